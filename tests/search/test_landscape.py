"""The paper's headline landscape on the Orthoglide, from a free search over x, y, z and phi.

Least energy near the isotropic point O_b with the rectangle's sides along the axes (phi ≈ 0°, or
90° by the machine's symmetry); most energy against the three faces of the cube that meet at Q⁻,
with the rectangle turned by about 45°.
"""

import numpy as np
import pytest

from placement import EvaluatorSettings, SearchSettings, load_path, load_robot, optimize_placement
from tests.support.paths import EXAMPLE


@pytest.fixture(scope="module")
def result():
    return optimize_placement(load_robot("orthoglide"), load_path(EXAMPLE), evaluation=EvaluatorSettings(time_step_s=0.004),
                              settings=SearchSettings(seed=1))


def test_least_energy_near_the_isotropic_point_with_the_sides_along_the_axes(result):
    x, y, z, phi = result.best.detail.placement[:4]
    assert np.hypot(x, y) < 0.010  # O_b is the origin; energy hardly depends on z (the paper's finding)
    assert min(abs(np.degrees(phi)) % 90, 90 - abs(np.degrees(phi)) % 90) < 5


def test_most_energy_against_the_faces_at_q_minus_turned_by_45_degrees(result):
    robot = load_robot("orthoglide")
    q_minus = np.array(robot.workspace.points_m["Q_minus"])
    x, y, z, phi = result.worst.detail.placement[:4]
    # The turned 30 x 60 mm rectangle reaches (15 + 30)/√2 = 31.8 mm from its centre along x and y.
    reach = (0.015 + 0.030) / np.sqrt(2)
    assert np.all(np.abs(np.array([x, y]) - q_minus[:2] - reach) < 0.005)
    assert abs(z - q_minus[2]) < 0.005
    assert abs(abs(np.degrees(phi)) - 45) < 5
