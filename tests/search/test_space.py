"""The search box: its bounds lie on the printed grid, so that an optimum on a bound is reported where it is."""

import numpy as np
import pytest

from placement import load_robot
from placement.search.reporting import as_printed
from placement.search.space import default_space, printed_steps


@pytest.mark.parametrize("robot", ["ur5", "orthoglide", "ur5_track"])
def test_the_bounds_are_printed_values(robot):
    """Each bound, printed to 0.01 mm or 0.01° and read back, is itself (the Orthoglide's workspace box ends at
    -126.7949 mm and 73.2051 mm, the UR5's tilt at ±0.35 rad: moved inwards onto the grid)."""
    space = default_space(load_robot(robot), half_turn=True)
    for bound in (space.lower, space.upper):
        assert np.array_equal(as_printed(space.full(bound)[0], space.angles)[space.indices], bound)
    assert (space.upper - space.lower > printed_steps(space.angles[space.indices])).all()


def test_the_ur5s_tilt_bound_is_20_05_degrees_not_its_stated_0_35_rad():
    """The sidecar bounds theta and psi by ±0.35 rad (20.0535°); the UR5's best placement lies on theta's bound, which a
    report printed to 0.01° could only round inwards, 3.6e-4 J above the optimum (2.7e-5 of it)."""
    space = default_space(load_robot("ur5"))
    theta = space.free.index("theta")
    assert np.degrees(space.upper[theta]) == pytest.approx(20.05, abs=1e-12)
    assert np.degrees(space.lower[theta]) == pytest.approx(-20.05, abs=1e-12)
    assert 0.35 - space.upper[theta] < np.radians(0.01)


def test_a_periodic_angle_keeps_its_whole_range():
    space = default_space(load_robot("orthoglide"), half_turn=True)
    phi = space.free.index("phi")
    assert space.period[phi] == pytest.approx(np.pi)
    assert (space.lower[phi], space.upper[phi]) == (-np.pi / 2, np.pi / 2)
