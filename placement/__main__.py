"""``python -m placement``: the command line (see :mod:`placement.cli`)."""

import sys

from placement.cli import main

if __name__ == "__main__":
    sys.exit(main())
