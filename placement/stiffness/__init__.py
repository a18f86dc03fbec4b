"""Static stiffness: how far the tool yields under the process load, batched over samples.

- :mod:`placement.stiffness.compliance`: the springs of a robot (compliant actuators, declared passive springs) and
  the tool's Cartesian compliance C = T·K⁻¹·Tᵀ in actuator coordinates, for serial and closed-loop robots alike;
- :mod:`placement.stiffness.deflection`: the deflection δ = C·w of the tool point along a path, and its largest and
  RMS values;
- :mod:`placement.stiffness.loaded`: the loaded (complementary) correction, the tangent compliance under a finite
  load and the deflection at the nonlinear equilibrium it finds.
"""

from placement.stiffness.compliance import JointSprings, has_springs, joint_springs, tool_compliance, tool_deflection
from placement.stiffness.deflection import Deflection, DeflectionSummary, path_deflection
from placement.stiffness.loaded import complementary_stiffness, loaded_compliance, loaded_deflection

__all__ = ["Deflection", "DeflectionSummary", "JointSprings", "complementary_stiffness", "has_springs", "joint_springs",
           "loaded_compliance", "loaded_deflection", "path_deflection", "tool_compliance", "tool_deflection"]
