import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from placement.robot import load_robot  # noqa: E402


@pytest.fixture
def orthoglide():
    """A freshly loaded Orthoglide (tests may modify its model)."""
    return load_robot("orthoglide")


@pytest.fixture
def fivebar():
    return load_robot("fivebar")
