"""The examples' own modules import as the examples import them: from the examples folder."""

import sys

from tests.support.paths import ROOT

sys.path.insert(0, str(ROOT / "examples"))
