"""The tool's deflection along a path under the process load: per sample, and its largest and RMS values.

The deflection at a sample is δ(s) = C(s)·w(s) (:mod:`placement.stiffness.compliance`): the translation of the tool
point (m), and for a pose task the rotation of the end-effector frame (rad), both in the base frame, that the process
force on the tool (and no moment) causes in the robot's springs. Indices over a path read the translation alone
(a rotation is not mixed with a length): its largest norm, and its root mean square over the samples.

With the loaded correction (``loaded_stiffness`` in the path file, ``--loaded-stiffness``) the deflection is the
nonlinear equilibrium under the finite process force (:func:`placement.stiffness.loaded.loaded_deflection`) instead
of C·w, and its size is kept: the largest change it makes to the translation along the path, relative to the
largest linear deflection.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.kinematics.base import KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.stiffness.compliance import JointSprings, tool_deflection
from placement.stiffness.loaded import loaded_deflection


@dataclass(frozen=True)
class DeflectionSummary:
    """One placement's deflection along its path.

    Attributes:
        largest_m: The largest translation of the tool point (m).
        rms_m: The root mean square of its norm over the samples (m).
        sample: The sample of the largest.
        arc_length_m: How far along the path that sample lies (m).
        direction: (3,) the largest translation's unit direction in the base frame (zeros without load).
        translation_m: (N, 3) the tool point's translation at every sample, base frame (m).
        largest_rotation_rad: The largest rotation of the end-effector frame (rad), for a pose task; else None.
        loaded_correction: With the loaded correction, the largest change it makes to the translation along the path
            relative to the largest linear deflection; else None.
    """

    largest_m: float
    rms_m: float
    sample: int
    arc_length_m: float
    direction: np.ndarray
    translation_m: np.ndarray
    largest_rotation_rad: float | None = None
    loaded_correction: float | None = None


@dataclass(frozen=True)
class Deflection:
    """The tool's deflection at every sample of K placements.

    Attributes:
        translation_m: (K, N, 3) translation of the tool point, base frame.
        rotation_rad: (K, N, 3) rotation of the end-effector frame, base frame (pose tasks), else None.
        linear_translation_m: (K, N, 3) with the loaded correction, the linear model's translation C·w; else None.
    """

    translation_m: np.ndarray
    rotation_rad: np.ndarray | None = None
    linear_translation_m: np.ndarray | None = None

    @property
    def magnitude_m(self) -> np.ndarray:
        """(K, N) the translation's norm."""
        return np.sqrt(np.einsum("kni,kni->kn", self.translation_m, self.translation_m))

    @property
    def largest_m(self) -> np.ndarray:
        """(K,) the largest translation along the path."""
        return self.magnitude_m.max(axis=1)

    @property
    def rms_m(self) -> np.ndarray:
        """(K,) the root mean square of the translation's norm over the samples."""
        return np.sqrt(np.einsum("kni,kni->kn", self.translation_m, self.translation_m).mean(axis=1))

    @property
    def loaded_correction(self) -> np.ndarray | None:
        """(K,) with the loaded correction, the largest change it makes to the translation along the path, relative
        to the largest linear deflection (0 without load); else None."""
        if self.linear_translation_m is None:
            return None
        change = np.linalg.norm(self.translation_m - self.linear_translation_m, axis=2).max(axis=1)
        linear = np.linalg.norm(self.linear_translation_m, axis=2).max(axis=1)
        return np.divide(change, linear, out=np.zeros_like(change), where=linear > 0)

    def summary(self, placement: int, position_m: np.ndarray) -> DeflectionSummary:
        """The summary of one placement; ``position_m`` (N, 3) are the samples' tool points (m, any frame) that
        locate the largest one along the path (its arc length from the first sample)."""
        magnitude = self.magnitude_m[placement]
        sample = int(np.argmax(magnitude))
        largest = float(magnitude[sample])
        arc = float(np.linalg.norm(np.diff(position_m[: sample + 1], axis=0), axis=1).sum())
        direction = self.translation_m[placement, sample] / largest if largest > 0 else np.zeros(3)
        rotation = None if self.rotation_rad is None else float(np.linalg.norm(self.rotation_rad[placement], axis=1).max())
        correction = self.loaded_correction
        return DeflectionSummary(largest_m=largest, rms_m=float(self.rms_m[placement]), sample=sample, arc_length_m=arc,
                                 direction=direction, translation_m=self.translation_m[placement],
                                 largest_rotation_rad=rotation,
                                 loaded_correction=None if correction is None else float(correction[placement]))


def path_deflection(springs: JointSprings, joints: JointTrajectory, force_N: np.ndarray,
                    loaded: tuple[KinematicsSolver, TaskTrajectory] | None = None) -> Deflection:
    """The deflection at the samples of K placements.

    Args:
        springs: The robot's springs (:func:`placement.stiffness.compliance.joint_springs`).
        joints: Their motion, K·N rows (placement-major), with the task map of each sample.
        force_N: (K, N, 3) the process force on the tool from the workpiece, base frame (N); no moment.
        loaded: With the loaded correction, the robot's kinematics solver and the task of the K·N samples;
            else None: the linear model.

    Returns:
        The translation (and for a pose task the rotation) of the tool at every sample.

    Raises:
        SettingsError: The loaded correction does not cover the robot or its springs, or finds no equilibrium
            (:func:`placement.stiffness.loaded.loaded_deflection`).
    """
    k, n = force_N.shape[:2]
    force = force_N.reshape(k * n, 3)
    pose = joints.task_map.shape[1] == 6
    load = np.hstack([force, np.zeros_like(force)]) if pose else force
    linear = tool_deflection(springs, joints, load).reshape(k, n, -1)
    if loaded is None:
        return Deflection(translation_m=linear[..., :3], rotation_rad=linear[..., 3:] if pose else None)
    moved = loaded_deflection(springs, *loaded, joints, load).reshape(k, n, -1)
    return Deflection(translation_m=moved[..., :3], rotation_rad=moved[..., 3:] if pose else None,
                      linear_translation_m=linear[..., :3])
