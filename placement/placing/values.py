"""Placement values as people type them: lengths in mm and angles in degrees, unless a value ends in m or rad.

The command line's ``--at``, ``--fix`` and ``--free`` and the workbench's fields read this syntax
(``x=10,phi=30``, ``y=-40:40``), and return SI values (m, rad). A redundant robot's knots
(``panda_joint3@1``, ``track@0``, :mod:`placement.placing.profiles`) and the tool's ``spin`` are named through
``extra``: angles, but for those named in ``lengths`` too (a prismatic joint's knots,
:func:`placement.placing.profiles.length_variables`), which are lengths.
"""

from __future__ import annotations

from collections.abc import Collection

import numpy as np

from placement.exceptions import SettingsError
from placement.placing.profiles import KNOT_SEPARATOR, SPIN
from placement.placing.transform import ANGLES, VARIABLES


def parse_names(text: str, option: str, extra: tuple[str, ...] = ()) -> tuple[str, ...]:
    """'x,y,phi' -> placement variable names (of VARIABLES and ``extra``), each once, at least one."""
    known = VARIABLES + extra
    names = tuple(name.strip() for name in text.split(",") if name.strip())
    unknown = [name[:40] for name in names if name not in known]
    if not names or unknown:
        raise SettingsError(f"{option}: {f'unknown placement variable(s) {unknown}; ' if unknown else ''}expected names "
                         f"from {', '.join(known)}, got '{text[:40]}'")
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise SettingsError(f"{option}: {', '.join(twice)} is given twice")
    return names


def parse_values(text: str, option: str, extra: tuple[str, ...] = (),
                 lengths: Collection[str] = ()) -> dict[str, float]:
    """'x=10,phi=30' -> SI values; lengths in mm and angles in deg unless suffixed m / rad; names from VARIABLES
    and ``extra`` (a redundant robot's variables: angles, but for the lengths named in ``lengths``)."""
    values: dict[str, float] = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, raw = item.partition("=")
        name = name.strip()
        if name not in VARIABLES + extra or not raw:
            raise SettingsError(f"{option}: expected name=value with names from {', '.join(VARIABLES + extra)}, "
                             f"got '{item[:40]}'")
        if name in values:
            raise SettingsError(f"{option}: {name} is given twice")
        value = _quantity(raw, name, lengths)
        if value is None:
            raise SettingsError(f"{option}: '{raw[:40]}' is not a number for {name}")
        if not np.isfinite(value):
            raise SettingsError(f"{option}: {name} must be a finite number, got '{raw[:40]}'")
        values[name] = value
    return values


def unsuffixed_lengths(text: str, lengths: Collection[str] = ()) -> dict[str, float]:
    """The lengths of a 'x=10,phi=30' option given without a unit (read as mm), in mm, by name (``lengths``: the
    redundant variables that are lengths); call after :func:`parse_values` has accepted ``text``."""
    items = (item.partition("=") for item in filter(None, (part.strip() for part in text.split(","))))
    return {name.strip(): float(raw) for name, _, raw in items
            if not angle_variable(name.strip(), lengths) and _quantity(raw, name.strip(), lengths) is not None
            and not raw.strip().endswith("m")}


def parse_free(text: str, option: str, extra: tuple[str, ...] = (),
               lengths: Collection[str] = ()) -> tuple[tuple[str, ...], dict[str, tuple[float, float]]]:
    """'y=-40:40,x,phi=-90:90' -> the free variables and the bounds given (SI).

    Bounds are in mm and deg unless a number ends in m or rad, as for --fix; a variable without
    bounds keeps the sidecar's or the workspace's. ``extra`` and ``lengths``: as for :func:`parse_values`.

    Returns:
        The names, each once, and {name: (lower, upper)} (m, rad) for those given bounds.

    Raises:
        SettingsError: An unknown or repeated name, or bounds that are not two finite numbers MIN < MAX.
    """
    items = [item.strip() for item in text.split(",") if item.strip()]
    if any(not item.partition("=")[0].strip() for item in items):
        raise SettingsError(f"{option}: expected name or name=MIN:MAX for each variable, got '{text[:40]}'")
    names = parse_names(",".join(item.partition("=")[0] for item in items), option, extra)
    bounds = {}
    for item in items:
        name, equals, spec = (part.strip() for part in item.partition("="))
        if equals:
            bounds[name] = _bounds(name, spec, item, option, lengths)
    return names, bounds


def _bounds(name: str, spec: str, item: str, option: str, lengths: Collection[str]) -> tuple[float, float]:
    """'-40:40' -> (lower, upper) of ``name`` in SI, lower < upper."""
    unit, example = ("deg", f"{name}=-90:90") if angle_variable(name, lengths) else ("mm", f"{name}=-40:40")
    parts = spec.split(":")
    numbers = [value for value in (_quantity(part, name, lengths) for part in parts)
               if value is not None and np.isfinite(value)]
    if len(parts) != 2 or len(numbers) != 2:
        raise SettingsError(f"{option}: expected name or name=MIN:MAX with two finite numbers ({unit}), e.g. {example}, "
                         f"got '{item[:40]}'")
    low, high = numbers
    if not low < high:
        raise SettingsError(f"{option}: expected MIN below MAX in name=MIN:MAX ({unit}), e.g. {example}, "
                         f"got '{item[:40]}' (--fix gives a single value)")
    return low, high


def _quantity(raw: str, name: str, lengths: Collection[str]) -> float | None:
    """A value of variable ``name`` in SI: mm and deg unless suffixed m / rad; None if not a number."""
    angle = angle_variable(name, lengths)
    units = {"rad": 1.0, "deg": np.pi / 180} if angle else {"mm": 1e-3, "m": 1.0}
    text = raw.strip()
    unit = next((u for u in sorted(units, key=len, reverse=True) if text.endswith(u)), None)
    number = text[: -len(unit)] if unit else text
    try:
        return float(number) * units[unit or ("deg" if angle else "mm")]
    except ValueError:
        return None


def angle_variable(name: str, lengths: Collection[str] = ()) -> bool:
    """Whether a placement variable is an angle: phi, theta, psi, the tool's spin, or a knot of a redundant joint but
    those named in ``lengths`` (a prismatic joint's knots, :func:`placement.placing.profiles.length_variables`)."""
    return name in ANGLES or name == SPIN or (KNOT_SEPARATOR in name and name not in lengths)
