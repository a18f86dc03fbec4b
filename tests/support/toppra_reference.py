"""The time-optimal timing of one run by the ``toppra`` package itself: the reference that the compiled passes
(:mod:`placement.timing.topp`) are checked against."""

from __future__ import annotations

import logging

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint

logging.getLogger("toppra").setLevel(logging.ERROR)  # an infeasible run is an answer


class Given(toppra.constraint.LinearConstraint):
    """Constraint rows a·s̈ + b·ṡ² + c ≤ 0 and bounds on ṡ², computed beforehand for one run."""

    def __init__(self, a: np.ndarray | None, b: np.ndarray | None, c: np.ndarray | None, x_max: np.ndarray) -> None:
        super().__init__()
        self.set_discretization_type(toppra.constraint.DiscretizationType.Interpolation)
        self.identical = True
        self._rows = (a, b, c)
        self._x_max = x_max

    def compute_constraint_params(self, path: object, gridpoints: np.ndarray, *args: object, **kwargs: object) -> tuple:
        a, b, c = self._rows
        xbound = np.column_stack([np.zeros(len(gridpoints)), self._x_max])
        if a is None:
            return None, None, None, None, None, None, xbound
        rows = a.shape[1]
        a, b, c, F, g, _, _ = toppra.constraint.canlinear_colloc_to_interpolate(
            a, b, c, np.eye(rows), np.zeros(rows), None, None, gridpoints, identical=True)
        return a, b, c, F, g, None, xbound


class Interval:
    """The path interval of one run (what TOPP-RA asks of a path when the constraints are given)."""

    def __init__(self, length_m: float) -> None:
        self.path_interval = np.array([0.0, length_m])


def toppra_run(arc_m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
               x_max: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """ṡ at each sample and s̈ after it (the one before, at the end) of one run, rest to rest, by toppra's TOPPRA
    with its seidel solver, or None when no timing exists."""
    constraints = [Given(None, None, None, x_max), Given(a, b, c, x_max)]
    solver = toppra.algorithm.TOPPRA(constraints, Interval(float(arc_m[-1])), gridpoints=arc_m, solver_wrapper="seidel")
    s_ddot, s_dot, _ = solver.compute_parameterization(0.0, 0.0)
    if s_dot is None or s_ddot is None or not np.isfinite(s_dot).all():
        return None
    return s_dot, np.append(s_ddot, s_ddot[-1])
