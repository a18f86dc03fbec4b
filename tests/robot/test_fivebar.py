"""A second closed-loop mechanism, solved only by the generic machinery, checked independently.

Its dynamics (forward round trip, power balance, the lumped model of tests/fivebar_analytic.py with massless distal
links) are checked with every other robot's in tests/robot/test_contract.py.
"""

import numpy as np

from placement.kinematics import joint_trajectory
from tests.support import fivebar_analytic as analytic
from tests.support.trajectories import lissajous


def tip_path(t):
    return lissajous(t, center_m=(0.01, 0.30, 0.0), amplitude_m=(0.05, 0.04, 0.0), frequency_hz=(1.3, 0.8, 1.0),
                     phase_rad=(0.2, 0.9, 0.0))


def test_generic_kinematics_equal_the_analytic_inverse_kinematics(fivebar):
    task = tip_path(np.linspace(0.0, 2.0, 80))
    joints = joint_trajectory(fivebar, task)
    p, v, a = task.position_m, task.velocity_m_s, task.acceleration_m_s2
    expected = analytic.joint_angles(analytic.Taylor2(p[:, 0], v[:, 0], a[:, 0]),
                                     analytic.Taylor2(p[:, 1], v[:, 1], a[:, 1]))
    for name, value in expected.items():
        index = fivebar.model.joints[fivebar.model.getJointId(name)].idx_q
        np.testing.assert_allclose(joints.q[:, index], value.v, atol=1e-10, err_msg=name)
        np.testing.assert_allclose(joints.v[:, index], value.d1, atol=1e-10, err_msg=name)
        np.testing.assert_allclose(joints.a[:, index], value.d2, atol=1e-9, err_msg=name)
