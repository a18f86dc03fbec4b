"""The scene page's cameras: where a view looks from and how far, so that what it frames is all in sight.

Points are in the robot's base frame (Z up); the page's viewer (meshcat, three.js) has Y up (:func:`three_frame`).
"""

from __future__ import annotations

import numpy as np

from placement.search.space import box_corners

CAMERA_DIRECTION = np.array([-0.45, -0.45, 0.35]) / np.linalg.norm([-0.45, -0.45, 0.35])  # from the target
CAMERA_FOV_DEG = 75.0  # meshcat's default camera: PerspectiveCamera(75, aspect, 0.01, 100), vertical
CAMERA_MARGIN = 1.08  # every corner of the drawn box stays within 1/1.08 of the view's half-height and half-width
CAMERA_NEAR_M = 0.01  # meshcat's near clipping distance
CARRIED_TURN_DEG = 45.0  # a carried workpiece's view: from the robot's side of it, turned this much about the vertical

SWEEP_POINTS = 48  # the workpiece views frame a path on a moving workpiece at up to this many of its points ...
SWEEP_POSES = 48  # ... carried to up to this many of the workpiece's poses along the motion


def workpiece_direction(low_m: np.ndarray, high_m: np.ndarray, carried: bool = False) -> np.ndarray:
    """Where the workpiece view looks from (a unit vector from its box's centre, base frame), at the default view's
    elevation. A fixed workpiece is looked at from beyond it, away from the base frame's origin, so that an arm
    reaching out to it is behind it rather than in front of the camera. A workpiece carried by a chain of the robot
    (``carried``: a positioner's part, turned to a torch that works on the robot's side of it) is looked at from
    the robot's side, turned ``CARRIED_TURN_DEG`` about the vertical, so that the torch is not behind the part (the
    default view's direction for a part on the base frame's x axis). The default view's direction when the
    workpiece is over the base (as on a parallel machine, whose base frame is in its workspace)."""
    centre = (np.asarray(low_m, dtype=float) + np.asarray(high_m, dtype=float)) / 2
    away = centre[:2]
    if np.linalg.norm(away) <= float(np.max(np.subtract(high_m, low_m))) / 2:
        return CAMERA_DIRECTION
    horizontal = np.linalg.norm(CAMERA_DIRECTION[:2]) * away / np.linalg.norm(away)
    if carried:
        turn = np.radians(180.0 + CARRIED_TURN_DEG)
        horizontal = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]]) @ horizontal
    return np.array([*horizontal, CAMERA_DIRECTION[2]])


def framing(low_m: np.ndarray, high_m: np.ndarray,
            direction: np.ndarray = CAMERA_DIRECTION) -> tuple[np.ndarray, np.ndarray]:
    """A camera (target, position; m, base frame) on the centre of a box, as close as its 8 corners all stay in view.

    The view is taken square (meshcat's 75° vertical field both ways), the narrowest a window wider than tall
    gives; each corner keeps 1/``CAMERA_MARGIN`` of the half-view and is beyond the near plane.

    Args:
        low_m: The box's lowest corner (m).
        high_m: Its highest corner (m).
        direction: A unit vector from the box's centre towards the camera, not vertical.
    """
    low, high = np.asarray(low_m, dtype=float), np.asarray(high_m, dtype=float)
    centre = (low + high) / 2
    forward = -direction
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    offset = box_corners(low, high) - centre
    depth = offset @ forward  # beyond the centre (> 0) or before it, along the view
    half_view = np.tan(np.radians(CAMERA_FOV_DEG / 2)) / CAMERA_MARGIN
    across = np.maximum(np.abs(offset @ right), np.abs(offset @ up))
    distance = max(float(np.max(across / half_view - depth)), float(np.max(-depth)) + 2 * CAMERA_NEAR_M)
    return centre, centre + direction * distance


def three_frame(point_m: np.ndarray) -> list[float]:
    """A point of the scene (base frame, Z up) in three.js' world frame, Y up: meshcat turns its scene by -90° about X
    (x, y, z) -> (x, z, -y), and its camera node back, so that the camera's frame is three.js' world frame."""
    x, y, z = (float(v) for v in point_m)
    return [x, z, -y]


def swept(points_m: np.ndarray, rotation: np.ndarray, origin_m: np.ndarray) -> np.ndarray:
    """Where a moving frame carries points given in it (base frame, m): up to ``SWEEP_POINTS`` of ``points_m``
    (N, 3) at each of up to ``SWEEP_POSES`` of the frame's poses (rotations (M, 3, 3), origins (M, 3) m), both
    spread evenly from the first to the last."""
    def spread(count: int, most: int) -> np.ndarray:
        return np.unique(np.linspace(0, count - 1, min(count, most)).round().astype(int))

    points, poses = points_m[spread(len(points_m), SWEEP_POINTS)], spread(len(origin_m), SWEEP_POSES)
    return (points @ rotation[poses].transpose(0, 2, 1) + origin_m[poses, None, :]).reshape(-1, 3)
