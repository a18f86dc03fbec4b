"""Motor-load objectives: peak motor torque, and RMS motor current (heating)."""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective


class PeakTorque(Objective):
    """Largest |motor torque| over the path and the motors: how close the job runs to the motors' peak."""

    title = "peak motor torque"
    unit = "N m"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return np.abs(batch.motor.torque_Nm).max(axis=(1, 2))


class RmsCurrent(Objective):
    """Largest RMS over the path of a motor's current I = τ/K_t: the hottest motor's copper losses."""

    title = "RMS motor current"
    unit = "A"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        squared = batch.motor.current_A**2
        dt = batch.widths_by_placement_s
        mean_square = np.einsum("kna,kn->ka", (squared[:, :-1] + squared[:, 1:]) / 2, dt) / dt.sum(axis=1)[:, None]
        return np.sqrt(mean_square).max(axis=1)


OBJECTIVES.add("peak_torque", PeakTorque())
OBJECTIVES.add("rms_current", RmsCurrent())
