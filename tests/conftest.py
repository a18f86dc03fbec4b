
import pytest

from placement.robot import load_robot


@pytest.fixture
def orthoglide():
    """A freshly loaded Orthoglide (tests may modify its model)."""
    return load_robot("orthoglide")


@pytest.fixture
def fivebar():
    return load_robot("fivebar")
