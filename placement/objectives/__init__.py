"""Objectives: what placements are ranked by (a plug-in family, see :mod:`placement.objectives.base`)."""

from placement.objectives.base import OBJECTIVES, Objective, Wording, wording
from placement.objectives.energy import ElectricEnergy, MechanicalEnergy
from placement.objectives.motors import PeakTorque, RmsCurrent

__all__ = ["OBJECTIVES", "ElectricEnergy", "MechanicalEnergy", "Objective", "PeakTorque", "RmsCurrent", "Wording",
           "wording"]
