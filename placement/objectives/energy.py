"""Energy objectives: electric energy under the regeneration policy, and mechanical shaft energy."""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective


class ElectricEnergy(Objective):
    """Electric energy the drives draw along the path, under the regeneration policy (the paper's)."""

    title = "electric energy"
    unit = "J"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return batch.energy.total_J


class MechanicalEnergy(Objective):
    """Work the motor shafts deliver, Σ_i ∫ max(0, τ_i·ω_i) dt: motors do not take work back."""

    title = "mechanical energy"
    unit = "J"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        shaft = batch.motor.torque_Nm * batch.motor.speed_rad_s  # (K, N, n_act)
        interval = np.maximum((shaft[:, :-1] + shaft[:, 1:]) / 2, 0.0).sum(axis=-1)  # as electric power is clipped
        return (interval * batch.widths_by_placement_s).sum(axis=-1)


OBJECTIVES.add("energy", ElectricEnergy())
OBJECTIVES.add("mechanical_energy", MechanicalEnergy())
