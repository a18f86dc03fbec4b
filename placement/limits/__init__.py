"""The built-in limits, as margins (members of the family :mod:`placement.contract.limit`).

Importing this package registers them in :data:`placement.contract.limit.LIMITS`, which imports it at its first
look-up.
"""

from placement.limits import collision, joints, motors, stiffness, thermal, timing, workspace

__all__ = ["collision", "joints", "motors", "stiffness", "thermal", "timing", "workspace"]
