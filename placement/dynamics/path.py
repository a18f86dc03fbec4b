"""Actuator efforts along a path, affine in the path motion: F(s) = A(s)·s̈ + B(s)·ṡ² + C(s).

Along a path p(s), every joint moves as q(s), so its velocity and acceleration are q'·ṡ and
q'·s̈ + q''·ṡ², and the projected RNEA (linear in the accelerations, quadratic in the velocities)
gives the efforts exactly in this form, from three batched calls (:func:`path_dynamics`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PathDynamics:
    """What limits the motion along the path of K placements, per sample, in the actuators' units.

    Attributes:
        velocity: (K, N, n_act) q' of the actuated joints (per metre of path).
        curvature: (K, N, n_act) q'' of the actuated joints (per metre² of path).
        inertia, centripetal, static: (K, N, n_act) A, B and C of the efforts (module docstring).
    """

    velocity: np.ndarray
    curvature: np.ndarray
    inertia: np.ndarray
    centripetal: np.ndarray
    static: np.ndarray

    def rows(self, index: np.ndarray) -> PathDynamics:
        """The same at some samples (an index into the sample axis)."""
        return PathDynamics(*(getattr(self, f.name)[:, index] for f in dataclasses.fields(PathDynamics)))

    def efforts(self, speed: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
        """(K, N, n_act) actuator efforts for ṡ and s̈ of shape (K, N)."""
        return (self.inertia * acceleration[..., None] + self.centripetal * speed[..., None] ** 2 + self.static)


