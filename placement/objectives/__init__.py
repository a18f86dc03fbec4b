"""The built-in objectives: what placements are ranked by (members of the family :mod:`placement.contract.objective`).

Importing this package registers them in :data:`placement.contract.objective.OBJECTIVES`, which imports it at its
first look-up.
"""

from placement.objectives.energy import ElectricEnergy, MechanicalEnergy
from placement.objectives.kinetostatics import Dexterity, Transmission
from placement.objectives.motors import PeakTorque, RmsCurrent
from placement.objectives.shaking import ShakingForce, ShakingMoment
from placement.objectives.stiffness import LargestDeflection, RmsDeflection
from placement.objectives.timing import CycleTime

__all__ = ["CycleTime", "Dexterity", "ElectricEnergy", "LargestDeflection", "MechanicalEnergy", "PeakTorque", "RmsCurrent",
           "RmsDeflection", "ShakingForce", "ShakingMoment", "Transmission"]
