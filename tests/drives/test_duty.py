"""Duty cycle and the thermal limit: RMS torque by known integrals, the rest that keeps a motor within its rating,
and the Orthoglide example's RMS against scipy's trapezoid rule on the per-sample trace."""

import numpy as np
import pytest
from scipy.integrate import trapezoid

from placement import load_robot
from placement.contract.limit import LIMITS, margin_fields
from placement.energy.duty import SECONDS_PER_HOUR, duty_cycle, squared_torque_integral
from placement.energy.trace import Drives
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.load import load_path
from tests.support.paths import EXAMPLE


def unit_drives(rated: list[float]) -> Drives:
    """Direct drives (ratio 1, lossless, no friction nor rotor): motor torque = effort."""
    n = len(rated)
    one, zero = np.ones(n), np.zeros(n)
    return Drives(ratio=one, efficiency=one, coulomb_friction=zero, viscous_friction=zero, reflected_inertia=zero,
                  torque_constant_Nm_per_A=one, resistance_ohm=one, inductance_H=zero, back_emf_V_s_per_rad=one,
                  max_torque_Nm=np.full(n, 10.0), continuous_torque_Nm=np.array(rated), max_speed_rad_s=np.full(n, np.inf),
                  phase_voltage_limit_V=np.full(n, np.inf))


def test_rms_of_a_sine_is_its_amplitude_over_root_two():
    t = np.linspace(0.0, 2.0, 4001)  # two whole periods of 1 s
    torque = 3.0 * np.sin(2 * np.pi * t)[:, None]
    squared = squared_torque_integral(torque, np.diff(t))
    assert np.sqrt(squared[-1, 0] / 2.0) == pytest.approx(3.0 / np.sqrt(2), rel=1e-6)


def test_a_zero_width_interval_carries_nothing():
    torque = np.array([[1.0], [1.0], [5.0], [5.0]])
    squared = squared_torque_integral(torque, np.array([1.0, 0.0, 1.0]))  # a piece starts at sample 2
    assert squared[-1, 0] == pytest.approx(1.0 + 25.0)


def test_the_rest_needed_brings_the_period_rms_exactly_to_the_rating():
    """2 N m for 1 s against a 1 N m rating, holding 0.5 N m at rest: (4 + 0.25 r)/(1 + r) = 1 gives r = 4 s."""
    t = np.linspace(0.0, 1.0, 11)
    torque = np.column_stack([np.full(11, 2.0), np.full(11, 0.5)])
    duty = duty_cycle(unit_drives([1.0, 1.0]), torque, np.diff(t), np.array([0.5, 0.1]), rest_s=0.5)
    assert duty.limited_by == 0
    assert duty.cycles_per_hour == pytest.approx(SECONDS_PER_HOUR / 5.0)
    again = duty_cycle(unit_drives([1.0, 1.0]), torque, np.diff(t), np.array([0.5, 0.1]), rest_s=4.0)
    assert again.rms_torque_Nm[0] == pytest.approx(1.0) and again.limited_by is None
    assert again.cycles_per_hour == pytest.approx(duty.cycles_per_hour)
    assert again.ratio[1] == pytest.approx(np.sqrt((0.25 + 0.01 * 4) / 5))


def test_a_hold_torque_over_the_rating_allows_no_rest():
    t = np.linspace(0.0, 1.0, 11)
    torque = np.full((11, 1), 0.5)
    drives = unit_drives([1.0])
    assert duty_cycle(drives, torque, np.diff(t), np.array([1.2]), rest_s=0.0).cycles_per_hour == pytest.approx(3600)
    assert duty_cycle(drives, torque, np.diff(t), np.array([1.2]), rest_s=10.0).cycles_per_hour == 0.0
    unrated = duty_cycle(unit_drives([np.inf]), torque, np.diff(t), np.array([5.0]), rest_s=1.0)
    assert unrated.cycles_per_hour == pytest.approx(1800) and unrated.limited_by is None


def test_an_estimated_rating_is_reported_but_limits_nothing():
    """The UR5's ratings are EST (UR publishes none): no thermal limit; the Orthoglide's are DERIVED: one."""
    from placement.energy.duty import rating_status

    ur5, orthoglide = load_robot("ur5"), load_robot("orthoglide")
    assert set(rating_status(ur5)) == {"EST"} and not LIMITS.get("thermal").applies_to(ur5)
    assert set(rating_status(orthoglide)) == {"DERIVED"} and LIMITS.get("thermal").applies_to(orthoglide)
    assert np.isfinite(Drives.of(ur5).continuous_torque_Nm).all()


def test_orthoglide_example_rms_and_thermal_margin():
    """The RMS torque of the paper's rectangle is scipy's trapezoid of τ² over the trace, over the pass's time, and
    the thermal limit's margin is 1 − RMS/rating at the pass's end; gravity loads the vertical slider at rest."""
    robot = load_robot("orthoglide")
    assert "thermal" in LIMITS.names()
    evaluator = Evaluator(robot, load_path(EXAMPLE), EvaluatorSettings(workers=1))
    placement = np.array([-0.00255, 0.00352, -0.033, -0.0063, 0.0, 0.0])
    detail = evaluator.detail(placement)
    t = detail.samples.t_s
    piece = detail.samples.piece
    assert np.all(np.diff(t)[piece[1:] != piece[:-1]] == 0)  # a new piece repeats the time: scipy sees no interval
    rms = np.sqrt(trapezoid(detail.motor.torque_Nm**2, t, axis=0) / (t[-1] - t[0]))
    drives = Drives.of(robot)
    widths = np.where(piece[1:] == piece[:-1], np.diff(t), 0.0)
    duty = duty_cycle(drives, detail.motor.torque_Nm, widths, detail.hold_effort)
    np.testing.assert_allclose(duty.rms_torque_Nm, rms, rtol=1e-12)
    thermal = next(f for f in margin_fields(evaluator.batch(placement[None], exact=True)) if f.kind == "thermal (RMS)")
    np.testing.assert_allclose(thermal.margin[0, -1], 1 - rms / drives.continuous_torque_Nm, rtol=1e-9)
    assert np.all(np.diff(thermal.margin[0], axis=0) <= 1e-15)  # heat only accumulates
    # At rest only the vertical (z) slider carries weight; the horizontal ones only through the legs' tilt
    assert duty.hold_torque_Nm[2] > 5 * max(duty.hold_torque_Nm[:2])
