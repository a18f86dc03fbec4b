"""The five-bar exported as Gepetto's 5bar_linkage is (tests/data/gepetto_fivebar_weld), assembled."""

import shutil
import warnings
from pathlib import Path

from placement.__main__ import main
from placement.workshop.gepetto import EstimatesWarning
from tests.support.paths import DATA

WELD_DATA = DATA / "gepetto_fivebar_weld"


def assembled_weld_fivebar(folder: Path) -> Path:
    """A copy of the export in ``folder``, through ``assemble --write``: its pins locked, in the x-z plane."""
    copy = folder / "gepetto_fivebar_weld"
    shutil.copytree(WELD_DATA, copy)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EstimatesWarning)
        if main(["assemble", str(copy), "--write"]) != 0:
            raise AssertionError("assemble --write failed on the weld five-bar")
    return copy
