"""Deprecated module path: second-order Taylor numbers live in :mod:`placement.kinematics.taylor`.

Closed-form kinematics plug-ins written for placement 0.1 import them from here; this path keeps
working, with a ``DeprecationWarning``, and will be removed in a later release.
"""

import warnings

from placement.kinematics.taylor import Taylor2, arctan2, sqrt

warnings.warn("placement.taylor is deprecated: import from placement.kinematics.taylor",
              DeprecationWarning, stacklevel=2)

__all__ = ["Taylor2", "arctan2", "sqrt"]
