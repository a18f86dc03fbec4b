"""A robot's drive arrays are built once, and never stand for another set of actuators."""

import dataclasses

import numpy as np
import pytest

from placement.energy.trace import Drives


def test_drives_are_built_once_per_set_of_actuators_and_follow_a_change(orthoglide):
    first = Drives.of(orthoglide)
    assert Drives.of(orthoglide) is first
    with pytest.raises(ValueError):  # shared, so read-only
        first.resistance_ohm[0] = 0.0
    changed = tuple(dataclasses.replace(a, drive=a.drive.model_copy(update={
        "motor": a.drive.motor.model_copy(update={"resistance_ohm": 2 * a.drive.motor.resistance_ohm})}))
        for a in orthoglide.actuators)
    other = dataclasses.replace(orthoglide, actuators=changed)
    assert np.array_equal(Drives.of(other).resistance_ohm, 2 * first.resistance_ohm)
    orthoglide.actuators = changed  # the same robot, given other actuators
    assert np.array_equal(Drives.of(orthoglide).resistance_ohm, 2 * first.resistance_ohm)
