"""Transmissions between a motor and its joint: a plug-in family.

A transmission is a sidecar schema (a strict pydantic model whose ``type`` field names it) with a
speed ratio: motor speed (rad/s) per unit joint speed (m/s or rad/s), and an efficiency. The
built-ins are ``ball_screw``, ``gear`` and ``rack_pinion``; a package adds one under the entry-point group
``placement.transmissions`` (the entry's object is the schema class).
"""

from __future__ import annotations

import builtins
import math
from typing import Annotated, Any

from pydantic import Field

from placement.registry import Registry
from placement.schema import Number, Tagged

Efficiency = Annotated[Number, Field(gt=0.0, le=1.0)]
Positive = Annotated[Number, Field(gt=0.0)]


class Transmission(Tagged):
    """Base of every transmission schema."""

    efficiency: Efficiency = 1.0

    @classmethod
    def schema_for(cls, value: Any) -> builtins.type[Transmission]:
        known = isinstance(value, dict) and value.get("type") in TRANSMISSIONS
        return TRANSMISSIONS.get(value["type"]) if known else cls

    @property
    def speed_ratio(self) -> float:
        """Motor speed per unit joint speed: rad per m (linear joint) or rad per rad (revolute)."""
        raise NotImplementedError

    def describe(self) -> str:
        """A few words for reports, e.g. 'ball screw 20 mm'."""
        return self.type


TRANSMISSIONS: Registry[type[Transmission]] = Registry("transmission", "placement.transmissions", Transmission,
                                                    instances=False)


class BallScrew(Transmission):
    """Ball screw: joint speed (m/s) = motor speed (rad/s) * lead_m / (2 pi)."""

    lead_m: Positive

    @property
    def speed_ratio(self) -> float:
        return 2 * math.pi / self.lead_m

    def describe(self) -> str:
        return f"ball screw {self.lead_m * 1e3:g} mm"


class Gear(Transmission):
    """Gearbox: joint speed (rad/s) = motor speed (rad/s) / ratio."""

    ratio: Positive

    @property
    def speed_ratio(self) -> float:
        return self.ratio

    def describe(self) -> str:
        return f"gear {self.ratio:g}:1"


class RackPinion(Transmission):
    """Rack and pinion behind a gearbox (a linear track's drive): joint speed (m/s) = motor speed (rad/s) / ratio *
    pinion_radius_m, the pinion's pitch radius (module x teeth / 2)."""

    ratio: Positive
    pinion_radius_m: Positive

    @property
    def speed_ratio(self) -> float:
        return self.ratio / self.pinion_radius_m

    def describe(self) -> str:
        return f"rack and pinion {self.pinion_radius_m * 1e3:g} mm, gear {self.ratio:g}:1"


TRANSMISSIONS.add("ball_screw", BallScrew)
TRANSMISSIONS.add("gear", Gear)
TRANSMISSIONS.add("rack_pinion", RackPinion)


def parse_transmission(value: Any) -> Transmission:
    """Validate a sidecar's ``transmission`` mapping with the schema its ``type`` names.

    Raises:
        ValueError: No ``type``, or an unknown one; pydantic's own errors, located under the field.
    """
    if isinstance(value, Transmission):
        return value
    if not isinstance(value, dict) or "type" not in value:
        raise ValueError(f"expected a mapping with a 'type', one of {', '.join(TRANSMISSIONS.names())}")
    if value["type"] not in TRANSMISSIONS:
        raise ValueError(f"unknown transmission type '{value['type']}', expected one of "
                         f"{', '.join(TRANSMISSIONS.names())}")
    return Transmission.schema_for(value).model_validate(value)
