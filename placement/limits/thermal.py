"""The thermal limit: each motor's RMS torque over the cycle within its rated continuous torque.

Where a drive gives ``continuous_torque_Nm`` from a source other than an estimate, the path run back
to back (no rest, the strictest duty) must keep sqrt(∫τ² dt / T) ≤ τ_c (:mod:`placement.energy.duty`).
A rating whose source is EST (a maker that publishes none, a rule of thumb) is reported against in
the duty cycle but rejects no placement: a guess should not decide feasibility. A user who enters
the datasheet's figure (status CATALOG, or no source) makes it a limit. The margin at a sample is
(τ_c − τ_rms(t))/τ_c with τ_rms(t) = sqrt(∫₀ᵗ τ² dt / T), the heat accumulated so far over the whole
cycle's time: it only falls along the path, and at the last sample it is the cycle's RMS torque.
An RMS is not a quantity of one sample, so this limit puts no bound on the optimal timing law's
rows (its :meth:`path_bounds` are none): a timing law faster than the feed may break it, and the
margins then say so.
"""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField
from placement.energy.duty import rating_status, squared_torque_integral
from placement.energy.trace import Drives
from placement.robot.model import Robot


class Thermal(Limit):
    """RMS motor torque over the cycle within continuous_torque_Nm, for the drives that give one."""

    def applies_to(self, robot: Robot) -> bool:
        return len(_bounded(robot)) > 0

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        rated = Drives.of(batch.robot).continuous_torque_Nm
        bounded = _bounded(batch.robot)
        widths = batch.widths_by_placement_s
        squared = squared_torque_integral(batch.motor.torque_Nm[..., bounded], widths)
        last = None if batch.exact else np.array([len(batch.samples) - 1])  # the margin only falls along the path
        if last is not None:
            squared = squared[:, last]
        cycle = widths.sum(axis=-1)[:, None, None]
        rms = np.sqrt(squared / np.where(cycle > 0, cycle, np.inf))
        names = tuple(batch.robot.actuators[i].joint for i in bounded)
        return [MarginField("thermal (RMS)", (rated[bounded] - rms) / rated[bounded], rms,
                            np.broadcast_to(rated[bounded], rms.shape), names, ("N m",) * len(names), last)]


def _bounded(robot: Robot) -> np.ndarray:
    """The actuators whose drive gives a continuous torque from a source other than an estimate."""
    rated = np.isfinite(Drives.of(robot).continuous_torque_Nm)
    return np.flatnonzero(rated & (np.array(rating_status(robot)) != "EST"))


LIMITS.add("thermal", Thermal())
