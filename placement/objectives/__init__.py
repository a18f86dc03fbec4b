"""Objectives: what placements are ranked by (a plug-in family, see :mod:`placement.objectives.base`)."""

from placement.objectives.base import OBJECTIVES, Objective, Wording, quantity, wording
from placement.objectives.energy import ElectricEnergy, MechanicalEnergy
from placement.objectives.kinetostatics import Dexterity, Transmission
from placement.objectives.motors import PeakTorque, RmsCurrent
from placement.objectives.shaking import ShakingForce, ShakingMoment
from placement.objectives.timing import CycleTime

__all__ = ["OBJECTIVES", "CycleTime", "Dexterity", "ElectricEnergy", "MechanicalEnergy", "Objective", "PeakTorque", "RmsCurrent",
           "ShakingForce", "ShakingMoment", "Transmission", "Wording", "quantity",
           "wording"]
