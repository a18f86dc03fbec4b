"""What happens to braking (negative) power: regeneration policies, a plug-in family.

A policy says what each drive draws from its power, interval by interval, and what the supply
delivers from the sum of the drives. The built-ins:

    clip      per-axis clipping: braking energy is burnt in each drive (default)
    bus       shared DC bus: axes exchange power, the sum is clipped
    signed    full regeneration: negative power is given back
    absolute  braking costs as much as driving

and always E_absolute ≥ E_clip ≥ E_bus ≥ E_signed. A package adds a policy (an instance of a
:class:`RegenerationPolicy` subclass) under the entry-point group ``placement.regeneration``.
"""

from __future__ import annotations

import numpy as np

from placement.registry import Registry


class RegenerationPolicy:
    """Turns signed drive power into drawn power.

    Attributes:
        description: A few words for reports.
    """

    description: str = ""

    def axis_power(self, power_W: np.ndarray) -> np.ndarray:
        """What each drive draws, (..., n_act), from its signed power (default: the power itself)."""
        return power_W

    def supply_power(self, pooled_W: np.ndarray) -> np.ndarray:
        """What the supply delivers, (...), from the sum of the drawn powers (default: the sum)."""
        return pooled_W


class Clip(RegenerationPolicy):
    description = "per-axis clipping (braking energy is not recovered)"

    def axis_power(self, power_W: np.ndarray) -> np.ndarray:
        return np.maximum(power_W, 0.0)


class Bus(RegenerationPolicy):
    description = "shared DC bus (axes exchange braking energy)"

    def supply_power(self, pooled_W: np.ndarray) -> np.ndarray:
        return np.maximum(pooled_W, 0.0)


class Signed(RegenerationPolicy):
    description = "full regeneration (braking energy is given back)"


class Absolute(RegenerationPolicy):
    description = "absolute (braking costs as much as driving)"

    def axis_power(self, power_W: np.ndarray) -> np.ndarray:
        return np.abs(power_W)


REGENERATION: Registry[RegenerationPolicy] = Registry("regeneration mode", "placement.regeneration", RegenerationPolicy)
for _name, _policy in (("clip", Clip()), ("bus", Bus()), ("signed", Signed()), ("absolute", Absolute())):
    REGENERATION.add(_name, _policy)
