"""Placement of the path frame F_p in the robot's base frame F_b, and the space searched.

A placement is x = [x, y, z, phi, theta, psi] (m, rad): the origin of F_p in F_b and the
orientation R = Rz(phi)·Ry(theta)·Rx(psi), the paper's matrix bTp. Any subset of the six may be
free (searched within bounds) while the others stay fixed.

A planar mechanism declares its plane in the sidecar (``placement.plane``: a normal and a point).
The placement is then read in the plane's own frame F_pl (:func:`plane_frame`): its origin is the
plane's point, its z axis the normal, its x axis the base x axis projected on the plane (the base
y axis if the normal is within 8° of x) and its y axis completes a right-handed frame. So x and y
are the path origin's coordinates in the plane, phi turns the path about the normal, and z, theta
and psi stay 0, keeping the path in the plane: bTp = bT_pl·(the placement's transform).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from placement.cell.schema import Region
from placement.exceptions import PlacementError
from placement.kinematics.trajectories import TaskTrajectory
from placement.path import PathSamples
from placement.robot.model import Robot
from placement.robot.sidecar import PLANE_VARIABLES, Plane, Workspace

VARIABLES = ("x", "y", "z", "phi", "theta", "psi")
ANGLES = ("phi", "theta", "psi")
NORMAL_ALONG_X = np.cos(np.radians(8.0))  # |n·X_b| above this: the plane's x axis is taken from Y_b


def rotation_zyx(phi: np.ndarray, theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Rz(phi)·Ry(theta)·Rx(psi) for arrays of angles (rad), shape (..., 3, 3)."""
    cf, sf, ct, st, cp, sp = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    return np.stack([
        np.stack([cf * ct, cf * st * sp - sf * cp, cf * st * cp + sf * sp], axis=-1),
        np.stack([sf * ct, sf * st * sp + cf * cp, sf * st * cp - cf * sp], axis=-1),
        np.stack([-st, ct * sp, ct * cp], axis=-1),
    ], axis=-2)


def plane_frame(plane: Plane) -> tuple[np.ndarray, np.ndarray]:
    """The plane's own frame F_pl in the base frame (module docstring).

    Args:
        plane: The sidecar's ``placement.plane``.

    Returns:
        The rotation [u, v, n] (columns: the plane's x and y axes, its unit normal) and the origin (m).
    """
    normal = np.asarray(plane.normal, dtype=float) / np.linalg.norm(plane.normal)
    axis = np.eye(3)[1 if abs(normal[0]) > NORMAL_ALONG_X else 0]
    u = axis - (axis @ normal) * normal
    u /= np.linalg.norm(u)
    return np.column_stack([u, np.cross(normal, u), normal]), np.asarray(plane.point_m, dtype=float)


def robot_plane(robot: Robot) -> Plane | None:
    """The plane a planar robot declares in its sidecar, if any."""
    defaults = robot.sidecar.placement
    return defaults.plane if defaults is not None else None


def describe_plane(plane: Plane) -> dict[str, list[float]]:
    """The plane and the axes its placement coordinates x, y run along (base frame, JSON-ready)."""
    rotation, origin = plane_frame(plane)
    return {"normal": rotation[:, 2].tolist(), "point_m": origin.tolist(), "x_axis": rotation[:, 0].tolist(),
            "y_axis": rotation[:, 1].tolist()}


def placement_pose(placements: np.ndarray, plane: Plane | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The path frame's rotation (K, 3, 3) and origin (K, 3) (m) in the base frame, for (K, 6) placements.

    Args:
        placements: Placement vectors (m, rad), in the plane's frame when ``plane`` is given.
        plane: The robot's plane (module docstring), or None: placements are in the base frame.
    """
    x = np.atleast_2d(placements)
    rotation = rotation_zyx(x[:, 3], x[:, 4], x[:, 5])
    if plane is None:
        return rotation, x[:, :3]
    turn, origin = plane_frame(plane)
    return turn @ rotation, origin + x[:, :3] @ turn.T


def placed_task(robot: Robot, samples: PathSamples, placements: np.ndarray) -> tuple[TaskTrajectory, np.ndarray]:
    """The end-effector task and its external load for placed paths, as the robot's task needs.

    A position task follows the tool point (a pose list's orientations are ignored, with a warning
    once). A pose task also holds the end-effector frame at R_place·R_tool·R_ee, where R_place is
    the placement's rotation, R_tool the tool frame in the path frame (a pose list's orientation;
    the identity otherwise) and R_ee the sidecar's ``tool_rpy_in_path_rad``, which maps the tool
    frame to the end-effector frame. The angular velocity and acceleration in the base frame are
    R_place times the path frame's. The load is the process force on the tool from the workpiece,
    with a zero moment for a pose task.

    Args:
        robot: The robot.
        samples: The path sampled in its own frame (N samples).
        placements: (K, 6) placement vectors.

    Returns:
        The task (K·N samples, placement-major) and the load, (K·N, 3 or 6).
    """
    plane = robot_plane(robot)
    task, force = transform_path_to_base(samples, placements, plane)
    if robot.task == "position":
        if samples.rotation is not None:
            warnings.warn_explicit(f"robot '{robot.name}' has a position task: the pose list's orientations are "
                                   "ignored", OrientationIgnoredWarning, "placement.frames", 0, registry=_WARNED)
        return task, force
    rpy = robot.sidecar.end_effector.tool_rpy_in_path_rad or (0.0, 0.0, 0.0)
    end_effector = rotation_zyx(np.array(rpy[2]), np.array(rpy[1]), np.array(rpy[0]))
    path_rotation = placement_pose(placements, plane)[0]  # (K, 3, 3)
    if samples.rotation is None:
        rotation = np.repeat(path_rotation @ end_effector, len(samples), axis=0)
        still = np.zeros_like(task.position_m)
        angular_velocity, angular_acceleration = still, still
    else:
        assert samples.angular_velocity_rad_s is not None and samples.angular_acceleration_rad_s2 is not None
        rotation = (path_rotation[:, None] @ samples.rotation[None] @ end_effector).reshape(-1, 3, 3)
        angular_velocity = _turned(path_rotation, samples.angular_velocity_rad_s)
        angular_acceleration = _turned(path_rotation, samples.angular_acceleration_rad_s2)
    pose = TaskTrajectory(task.position_m, task.velocity_m_s, task.acceleration_m_s2, rotation, angular_velocity,
                          angular_acceleration)
    return pose, np.hstack([force, np.zeros_like(force)])


class OrientationIgnoredWarning(UserWarning):
    """A path's tool orientations meet a robot whose task is a position."""


_WARNED: dict = {}  # the warnings shown: once per message and process


def _turned(rotation: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """(K·N, 3) path-frame vectors (N, 3) turned by each placement's rotation (K, 3, 3), placement-major."""
    return np.einsum("kij,nj->kni", rotation, vectors).reshape(-1, 3)


def transform_path_to_base(samples: PathSamples, placements: np.ndarray,
                           plane: Plane | None = None) -> tuple[TaskTrajectory, np.ndarray]:
    """The sampled path seen in the base frame for each placement, stacked placement by placement.

    Args:
        samples: The path sampled in its own frame (N samples).
        placements: (K, 6) or (6,) placement vectors [x, y, z, phi, theta, psi] (m, rad).
        plane: A planar robot's plane, in whose frame the placements are read (module docstring).

    Returns:
        The task trajectory of the tool point (K·N samples, placement-major) and the process
        force on the tool in the base frame, (K·N, 3) N.
    """
    rotation, origin = placement_pose(placements, plane)  # (K, 3, 3), (K, 3)
    position = _turned(rotation, samples.position_m) + np.repeat(origin, len(samples), axis=0)
    task = TaskTrajectory(position, _turned(rotation, samples.velocity_m_s), _turned(rotation, samples.acceleration_m_s2))
    return task, _turned(rotation, samples.force_on_tool_N)


@dataclass(frozen=True)
class PlacementSpace:
    """Which placement variables are free, their bounds, and the values of the fixed ones.

    Attributes:
        free: Names of the free variables, in VARIABLES order.
        lower, upper: Bounds of the free variables (m, rad).
        fixed: Full 6-vector whose fixed entries are used (m, rad).
    """

    free: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    fixed: np.ndarray

    def __post_init__(self) -> None:
        unknown = set(self.free) - set(VARIABLES)
        if unknown:
            raise PlacementError(f"unknown placement variable(s) {sorted(unknown)}; expected some of {VARIABLES}")
        if len(self.lower) != len(self.free) or np.any(np.asarray(self.lower) > np.asarray(self.upper)):
            raise PlacementError("placement bounds must give lower <= upper for every free variable")

    @property
    def indices(self) -> np.ndarray:
        """Positions of the free variables in the 6-vector."""
        return np.array([VARIABLES.index(name) for name in self.free], dtype=int)

    def full(self, free_values: np.ndarray) -> np.ndarray:
        """(K, 6) placements from (K, n_free) or (n_free,) free values."""
        values = np.atleast_2d(free_values)
        out = np.tile(self.fixed, (len(values), 1))
        out[:, self.indices] = values
        return out


def default_space(robot: Robot, free: tuple[str, ...] | None = None, fixed: dict[str, float] | None = None,
                  bounds: dict[str, tuple[float, float]] | None = None, half_turn: bool = False) -> PlacementSpace:
    """The placement space of a robot: by default the sidecar's ``placement`` section, else x, y, z
    within the workspace box and phi in ±180° (the tool axis staying along Z_b); a robot in a cell
    with a workpiece region keeps x, y, z within the region too.

    Args:
        robot: The robot.
        free: Free variables (default: the sidecar's, else x, y, z, phi).
        fixed: Values of fixed variables (default 0); fixing a variable removes it from the default
            free set, and an explicitly free variable cannot be fixed.
        bounds: Bounds overriding the defaults (m, rad).
        half_turn: The path is unchanged by a half turn about its tool axis
            (:meth:`ToolPath.half_turn_symmetric`): phi then only needs ±90°.
    """
    defaults, plane = robot.sidecar.placement, robot_plane(robot)
    if free is None:  # the default free set, less what the caller fixes
        default_free = defaults.free if defaults and defaults.free else PLANE_VARIABLES if plane else ("x", "y", "z", "phi")
        free = tuple(n for n in default_free if n not in (fixed or {}))
    free = tuple(free)
    unknown = sorted(set(free) - set(VARIABLES))
    if unknown:
        raise PlacementError(f"unknown placement variable(s) {unknown}; expected some of {', '.join(VARIABLES)}")
    clash = sorted(set(free) & set(fixed or {}))
    if clash:
        raise PlacementError(f"{clash} cannot be both free and fixed")
    limits: dict[str, tuple[float, float]] = {name: bound for name, bound in (defaults.bounds if defaults else {}).items()}
    limits.update(bounds or {})
    if plane is not None:
        _check_in_plane(robot.name, plane, free, fixed or {})
    for axis, bound in _box_ranges(robot.sidecar.workspace, plane).items():
        limits.setdefault(axis, bound)
    region = robot.cell.workpiece_region if robot.cell is not None else None
    for axis, (low, high) in _box_ranges(region, plane).items():  # the path's origin stays in the region
        bound = limits.get(axis, (low, high))
        limits[axis] = (max(bound[0], low), min(bound[1], high))
        if limits[axis][0] > limits[axis][1]:
            raise PlacementError(f"the cell's workpiece region ({axis} from {low * 1e3:.1f} to {high * 1e3:.1f} mm) "
                                 f"does not meet the placement bounds of robot '{robot.name}' ({axis} from "
                                 f"{bound[0] * 1e3:.1f} to {bound[1] * 1e3:.1f} mm)")
    limits.setdefault("phi", (-np.pi / 2, np.pi / 2) if half_turn else (-np.pi, np.pi))
    for angle in ("theta", "psi"):
        limits.setdefault(angle, (-np.pi, np.pi))
    missing = [name for name in free if name not in limits]
    if missing:
        raise PlacementError(_missing_bounds(robot.name, missing))
    fixed_vector = np.array([float((fixed or {}).get(name, 0.0)) for name in VARIABLES])
    return PlacementSpace(free=tuple(n for n in VARIABLES if n in free),
                          lower=np.array([limits[n][0] for n in VARIABLES if n in free], dtype=float),
                          upper=np.array([limits[n][1] for n in VARIABLES if n in free], dtype=float),
                          fixed=fixed_vector)


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
        raise PlacementError(f"robot '{robot}' moves in the plane of normal {list(plane.normal)} (sidecar "
                             f"placement.plane): paths stay in it, so only {', '.join(PLANE_VARIABLES)} may be free or "
                             f"fixed (x, y along the plane's own axes), got {', '.join(sorted(set(off)))}")


def _missing_bounds(robot: str, missing: list[str]) -> str:
    """What to do when free variables have no bounds: the command line's form and the sidecar's fields."""
    example = ",".join(f"{name}=MIN:MAX" for name in missing)
    return (f"robot '{robot}' declares no workspace, so {', '.join(missing)} {'has' if len(missing) == 1 else 'have'} "
            f"no bounds: give them on the command line as --free {example} (mm), or in the robot's sidecar as "
            f"workspace.min_m/max_m (a box, m) or placement.bounds (m, rad)")
