"""The search space: which placement variables are free, their bounds, and the others' values."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from placement.cell.cell_file import Region
from placement.exceptions import InfeasibleError, SettingsError
from placement.placing.profiles import SPIN, length_variables, redundant_bounds, redundant_defaults, redundant_variables
from placement.placing.transform import ANGLES, VARIABLES, plane_frame
from placement.placing.values import angle_variable
from placement.robot.model import Robot
from placement.robot.sidecar import PLANE_VARIABLES, Plane, Workspace

REPORTED_DECIMALS = 2  # a reported placement's decimals, in mm and degrees (placement.search.reporting)


@dataclass(frozen=True)
class PlacementSpace:
    """Which placement variables are free, their bounds, and the values of the fixed ones.

    Attributes:
        free: Names of the free variables, in ``names`` order.
        lower, upper: Bounds of the free variables (m, rad).
        fixed: Full placement vector whose fixed entries are used (m, rad).
        periods: Per free variable, the period of the objective along it (rad), or 0: an angle whose range
            is its whole turn (or half of it, by the path's half-turn symmetry) has no edge, and the search
            wraps it (:meth:`wrap`) rather than bounding it there.
        names: Every variable of a placement vector, in its order: VARIABLES, then a redundant robot's knots
            (:mod:`placement.placing.profiles`).
        lengths: The variables after the six that are lengths (a prismatic joint's knots); the others are angles.
    """

    free: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    fixed: np.ndarray
    periods: np.ndarray | None = None
    names: tuple[str, ...] = VARIABLES
    lengths: frozenset[str] = frozenset()

    def __post_init__(self) -> None:
        unknown = set(self.free) - set(self.names)
        if unknown:
            raise SettingsError(f"unknown placement variable(s) {sorted(unknown)}; expected some of {self.names}")
        if len(self.lower) != len(self.free) or np.any(np.asarray(self.lower) > np.asarray(self.upper)):
            raise SettingsError("placement bounds must give lower <= upper for every free variable")

    @property
    def period(self) -> np.ndarray:
        """The periods of the free variables (0 where a variable is not periodic)."""
        return np.zeros(len(self.free)) if self.periods is None else np.asarray(self.periods, dtype=float)

    def wrap(self, free_values: np.ndarray) -> np.ndarray:
        """Free values with every periodic variable brought into its range [lower, lower + period)."""
        values = np.array(free_values, dtype=float)
        period = self.period
        if not period.any():
            return values
        cyclic = period > 0
        shifted = values[..., cyclic] - self.lower[cyclic]
        values[..., cyclic] = self.lower[cyclic] + np.mod(shifted, period[cyclic])
        return values

    def difference(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """``a - b`` between free values, the shorter way round for a periodic variable."""
        difference = np.array(a, dtype=float) - b
        cyclic = self.period > 0
        difference[..., cyclic] -= self.period[cyclic] * np.round(difference[..., cyclic] / self.period[cyclic])
        return difference

    @property
    def angles(self) -> np.ndarray:
        """(len(names),) bool: which variables of a placement vector are angles (rad; deg on the command line), the
        others lengths (m; mm)."""
        return np.array([angle_variable(name, self.lengths) for name in self.names], dtype=bool)

    @property
    def indices(self) -> np.ndarray:
        """Positions of the free variables in the placement vector."""
        return np.array([self.names.index(name) for name in self.free], dtype=int)

    def full(self, free_values: np.ndarray) -> np.ndarray:
        """(K, len(names)) placements from (K, n_free) or (n_free,) free values."""
        values = np.atleast_2d(free_values)
        out = np.tile(self.fixed, (len(values), 1))
        out[:, self.indices] = values
        return out


def default_space(robot: Robot, free: tuple[str, ...] | None = None, fixed: dict[str, float] | None = None,
                  bounds: dict[str, tuple[float, float]] | None = None, half_turn: bool = False) -> PlacementSpace:
    """The placement space of a robot: by default the sidecar's ``placement`` section, else x, y, z
    within the workspace box and phi in ±180° (the tool axis staying along Z_b); a robot in a cell
    with a workpiece region keeps x, y, z within the region too. A robot with redundant joints adds
    their profiles' knots (:mod:`placement.placing.profiles`), free by default within the joints'
    ranges, and at the reference configuration's values when fixed without a value.

    Args:
        robot: The robot.
        free: Free variables (default: the sidecar's, else x, y, z, phi).
        fixed: Values of fixed variables (default 0); fixing a variable removes it from the default
            free set, and an explicitly free variable cannot be fixed.
        bounds: Bounds overriding the defaults (m, rad).
        half_turn: The path is unchanged by a half turn about its tool axis
            (:meth:`ToolPath.half_turn_symmetric`): phi then only needs ±90°.
    """
    defaults, plane = robot.placement_defaults, robot.plane
    knots = redundant_variables(robot)
    names = VARIABLES + knots
    if free is None:  # the default free set, less what the caller fixes
        default_free = (defaults.free if defaults and defaults.free is not None else PLANE_VARIABLES if plane
                        else ("x", "y", "z", "phi"))
        free = tuple(n for n in (*default_free, *knots) if n not in (fixed or {}))
    free = tuple(free)
    unknown = sorted(set(free) - set(names))
    if unknown:
        raise SettingsError(f"unknown placement variable(s) {unknown}; expected some of {', '.join(names)}")
    clash = sorted(set(free) & set(fixed or {}))
    if clash:
        raise SettingsError(f"{clash} cannot be both free and fixed")
    limits: dict[str, tuple[float, float]] = {name: bound for name, bound in (defaults.bounds if defaults else {}).items()}
    limits.update(redundant_bounds(robot))
    limits.update(bounds or {})
    if plane is not None:
        _check_in_plane(robot.name, plane, free, fixed or {})
    for axis, bound in _box_ranges(robot.workspace, plane).items():
        limits.setdefault(axis, bound)
    region = robot.cell.workpiece_region if robot.cell is not None else None
    for axis, (low, high) in _box_ranges(region, plane).items():  # the path's origin stays in the region
        bound = limits.get(axis, (low, high))
        limits[axis] = (max(bound[0], low), min(bound[1], high))
        if limits[axis][0] > limits[axis][1]:
            raise InfeasibleError(f"the cell's workpiece region ({axis} from {low * 1e3:.1f} to {high * 1e3:.1f} mm) "
                                  f"does not meet the placement bounds of robot '{robot.name}' ({axis} from "
                                  f"{bound[0] * 1e3:.1f} to {bound[1] * 1e3:.1f} mm)")
    limits.setdefault("phi", (-np.pi / 2, np.pi / 2) if half_turn else (-np.pi, np.pi))
    for angle in ("theta", "psi"):
        limits.setdefault(angle, (-np.pi, np.pi))
    missing = [name for name in free if name not in limits]
    if missing:
        raise SettingsError(_missing_bounds(robot.name, missing))
    values = {**redundant_defaults(robot), **(fixed or {})}
    fixed_vector = np.array([float(values.get(name, 0.0)) for name in names])
    chosen = tuple(n for n in names if n in free)
    if not chosen:
        raise SettingsError(f"robot '{robot.name}' leaves no placement variable free (its sidecar's placement.free is "
                            "empty, for the knots of its redundant joints, and none is profiled): free some with --free, "
                            "e.g. --free phi")
    lengths = length_variables(robot)
    periods = np.array([_period(n, limits[n], half_turn) for n in chosen], dtype=float)
    lower, upper = _printable(np.array([limits[n] for n in chosen], dtype=float).reshape(-1, 2),
                              np.array([angle_variable(n, lengths) for n in chosen], dtype=bool), periods)
    return PlacementSpace(free=chosen, lower=lower, upper=upper, fixed=fixed_vector, periods=periods, names=names,
                          lengths=lengths)


def printed(value: float, angle: bool) -> float:
    """A value (m or rad) as the report prints it, to REPORTED_DECIMALS of a mm or of a degree, read back."""
    if angle:
        return float(f"{np.degrees(value):.{REPORTED_DECIMALS}f}") * (np.pi / 180)
    return float(f"{value * 1e3:.{REPORTED_DECIMALS}f}") * 1e-3


def printed_steps(angles: np.ndarray) -> np.ndarray:
    """The printed grid's step (m or rad) of each variable: 10^-REPORTED_DECIMALS of a degree where ``angles``, else of
    a mm."""
    return np.where(angles, np.radians(10.0 ** -REPORTED_DECIMALS), 10.0 ** -REPORTED_DECIMALS * 1e-3)


def _printable(bounds: np.ndarray, angles: np.ndarray, periods: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) from (n, 2) bounds, each moved inwards onto the printed grid (by less than its step), where the
    range keeps a step: a reported placement is printed on that grid and must lie in the box, so that an optimum on
    a bound between two printed values (the UR5's tilt of ±0.35 rad, 20.0535°) would otherwise be reported a step
    inside it, 2.7e-5 of its energy above the optimum. A periodic variable keeps its range (it has no edge)."""
    lower, upper = bounds[:, 0].copy(), bounds[:, 1].copy()
    for k, (angle, step) in enumerate(zip(angles, printed_steps(angles), strict=True)):
        low = printed(np.ceil(lower[k] / step - 1e-6) * step, angle)
        high = printed(np.floor(upper[k] / step + 1e-6) * step, angle)
        if periods[k] == 0 and low < high:
            lower[k] = low if low >= bounds[k, 0] - 1e-12 else bounds[k, 0]
            upper[k] = high if high <= bounds[k, 1] + 1e-12 else bounds[k, 1]
    return lower, upper


def _period(name: str, bound: tuple[float, float], half_turn: bool) -> float:
    """The period of an angle whose range is exactly its whole turn, or, for phi on a path unchanged by a half
    turn, half of it (0 otherwise: the variable is bounded)."""
    if name not in (*ANGLES, SPIN):
        return 0.0
    width = bound[1] - bound[0]
    if np.isclose(width, 2 * np.pi, rtol=0, atol=1e-9):
        return 2 * np.pi
    if name == "phi" and half_turn and np.isclose(width, np.pi, rtol=0, atol=1e-9):
        return np.pi
    return 0.0


def _box_ranges(box: Workspace | Region | None, plane: Plane | None) -> dict[str, tuple[float, float]]:
    """The ranges of x, y, z over a box of the base frame (m): in the base frame, or in the plane's frame."""
    if box is None:
        return {}
    if plane is None:
        return {axis: (box.min_m[k], box.max_m[k]) for k, axis in enumerate("xyz")}
    turn, origin = plane_frame(plane)
    local = (box_corners(box.min_m, box.max_m) - origin) @ turn
    return {axis: (float(local[:, k].min()), float(local[:, k].max())) for k, axis in enumerate("xyz")}


def box_corners(low: Sequence[float] | np.ndarray, high: Sequence[float] | np.ndarray) -> np.ndarray:
    """(8, 3) corners of the axis-aligned box from ``low`` to ``high``: corner k takes ``high`` along x, y, z
    where bits 2, 1, 0 of k are set (so corners one bit apart share an edge)."""
    return np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])],
                    dtype=float)


def _check_in_plane(robot: str, plane: Plane, free: tuple[str, ...], fixed: dict[str, float]) -> None:
    """A planar robot's paths stay in its plane: only x, y and phi move, the other variables stay 0."""
    off = [name for name in free if name not in PLANE_VARIABLES]
    off += [name for name, value in fixed.items() if name not in PLANE_VARIABLES and value != 0.0]
    if off:
        raise SettingsError(f"robot '{robot}' moves in the plane of normal {list(plane.normal)} (sidecar "
                            f"placement.plane): paths stay in it, so only {', '.join(PLANE_VARIABLES)} may be free or "
                            f"fixed (x, y along the plane's own axes), got {', '.join(sorted(set(off)))}")


def _missing_bounds(robot: str, missing: list[str]) -> str:
    """What to do when free variables have no bounds: the command line's form and the sidecar's fields."""
    example = ",".join(f"{name}=MIN:MAX" for name in missing)
    return (f"robot '{robot}' declares no workspace, so {', '.join(missing)} {'has' if len(missing) == 1 else 'have'} "
            f"no bounds: give them on the command line as --free {example} (mm), or in the robot's sidecar as "
            f"workspace.min_m/max_m (a box, m) or placement.bounds (m, rad)")


