"""The printed lattice: the placement reported is the best printed one near the search's optimum.

The report prints a placement to REPORTED_DECIMALS of a mm and of a degree (:func:`placement.search.space.printed`),
and a user enters those numbers again: what is reported is a point of the lattice of those steps, not the search's
continuous optimum. Rounding the optimum to the best corner of its cell loses what the energy rises over a step, and
how much depends on where in its cell the optimum fell, so on the seed: on the paper's groove the energy rises on
either side of a crease ten and more times faster than along it, and two optima 2e-8 apart printed 3.3e-7 apart; the
pocket's optimum lies on a limit, where only the corners on its feasible side can be printed, and which of them lies
nearest the limit changed with the cell (1.4e-6 over seeds 0-9).

So the lattice itself is searched, in batches: the corners of the optimum's cell and the neighbours of the optimum
rounded, then, from the best of them that keeps every limit, its neighbours, and from the best again while one is
better (a pattern search on the lattice). A neighbour is one step (of the printed digits) along one variable or along
two at once: a crease is seldom along an axis, and on the groove and the UR5 the diagonal steps of three and more
variables (3^n - 1 neighbours in all) ended on the same lattice points at 1.6 to 6 times the evaluations. The
search ends on a printed point that no neighbour improves: a minimum of the lattice, which starts near one another
reach alike (seeds 0-9 of the pocket end on one, those of the groove on two, 1.45e-7 apart, near the crease's two
lowest points, where the cells' best corners were 3.5e-7 apart). A periodic variable's points are wrapped into its
range, and a point outside the box is not evaluated.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from placement.evaluation.results import Evaluation
from placement.search.space import PlacementSpace, printed, printed_steps

LATTICE_MOVES = 40  # moves of the lattice search, at most
LATTICE_CHANGES = 2  # a neighbour on the lattice differs along this many variables at most (module docstring)
BOUND_ROUND_OFF = 1e-12  # m or rad: a printed placement may pass a search bound by this much (its decimal digits)


class Model(Protocol):
    """What the lattice search evaluates placements on: an :class:`~placement.evaluation.evaluator.Evaluator`, or a
    re-check on denser samples."""

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        """The objective and every limit's margin at (K, width) placements."""
        ...


@dataclass(frozen=True)
class LatticeSearch:
    """The printed points a lattice search evaluated.

    Attributes:
        placements: (K, width) the printed placements (m, rad), those that keep every limit first, by objective (the
            lattice's best first), then the rest.
        usable: (K,) whether each lies in the box and keeps every limit, with a finite objective.
        first: The evaluation of the first points in the box (why none is usable, if so), or None when none lies in
            the box.
        moves: Moves the search made from the best of the first points.
    """

    placements: np.ndarray
    usable: np.ndarray
    first: Evaluation | None
    moves: int


def lattice_search(model: Model, placement: np.ndarray, space: PlacementSpace, sign: float,
                   walk: bool = True) -> LatticeSearch:
    """The best printed placement near ``placement`` by a pattern search on the printed lattice (module docstring).

    Args:
        model: Evaluates placements (the objective and every limit).
        placement: (width,) the search's optimum (m, rad); its fixed entries are kept.
        space: The search space (free variables, bounds, periods).
        sign: +1 when lower objective values are better, -1 when higher ones are.
        walk: Whether to search; else only the 2^n corners of the printed cell around ``placement`` are evaluated
            (a runner-up basin's, which is listed, not reported).

    Returns:
        The points evaluated, the lattice's best first.
    """
    lattice = _Lattice(model, placement, space, sign)
    n = len(space.indices)
    index = placement[space.indices] / lattice.step  # the placement in lattice units
    corners = np.floor(index) + np.array(list(itertools.product((0, 1), repeat=n)))
    neighbours = neighbour_offsets(n)
    first = lattice.visit(np.vstack([corners, np.round(index) + neighbours]) if walk else corners)
    moves = 0
    best = lattice.best()
    while walk and best is not None and moves < LATTICE_MOVES:
        lattice.visit(np.array(best) + neighbours)
        better = lattice.best()
        if better == best:
            break
        best, moves = better, moves + 1
    return lattice.search(first, moves)


def neighbour_offsets(n: int) -> np.ndarray:
    """(m, n) the lattice offsets of a point and its neighbours: every step of -1, 0 or +1 along at most LATTICE_CHANGES
    of n variables (the zero offset first)."""
    offsets = np.array(list(itertools.product((0, -1, 1), repeat=n)))
    return offsets[np.count_nonzero(offsets, axis=1) <= LATTICE_CHANGES]


class _Lattice:
    """The printed lattice around a placement: its points evaluated (once each), by lattice index."""

    def __init__(self, model: Model, placement: np.ndarray, space: PlacementSpace, sign: float) -> None:
        self.model, self.placement, self.space, self.sign = model, placement, space, sign
        self.step = printed_steps(space.angles)[space.indices]
        self.seen: dict[tuple[int, ...], int] = {}  # lattice index -> row of the points evaluated
        self.rows: list[np.ndarray] = []
        self.signed: list[float] = []  # the signed objective of each (+inf where it is not usable)
        self.usable: list[bool] = []

    def visit(self, indices: np.ndarray) -> Evaluation | None:
        """Evaluate the points of lattice ``indices`` (m, n) not evaluated yet that lie in the box, in one batch: their
        evaluation (None when none does)."""
        new = [k for k in dict.fromkeys(tuple(int(i) for i in k) for k in indices) if k not in self.seen]
        points = _printed_points(np.array(new, dtype=float).reshape(-1, len(self.step)) * self.step, self.placement,
                                 self.space)
        in_box = inside(points[:, self.space.indices], self.space)
        evaluation = self.model.evaluate(points[in_box]) if in_box.any() else None
        usable = np.zeros(len(new), dtype=bool)
        if evaluation is not None:
            usable[in_box] = evaluation.feasible & np.isfinite(evaluation.value)
        signed = np.full(len(new), np.inf)
        if evaluation is not None:
            signed[in_box] = np.where(usable[in_box], self.sign * evaluation.value, np.inf)
        for k, point, good, value in zip(new, points, usable.tolist(), signed.tolist(), strict=True):
            self.seen[k] = len(self.rows)
            self.rows.append(point)
            self.usable.append(good)
            self.signed.append(value)
        return evaluation

    def best(self) -> tuple[int, ...] | None:
        """The lattice index of the best usable point evaluated (the first evaluated of equals), None if none is."""
        if not self.seen:
            return None
        best = min(self.seen, key=lambda k: (self.signed[self.seen[k]], self.seen[k]))
        return best if np.isfinite(self.signed[self.seen[best]]) else None

    def search(self, first: Evaluation | None, moves: int) -> LatticeSearch:
        """The points evaluated, usable ones first by objective (the first evaluated of equals)."""
        order = np.lexsort((np.arange(len(self.rows)), np.array(self.signed)))
        return LatticeSearch(np.array(self.rows).reshape(-1, len(self.placement))[order], np.array(self.usable)[order],
                             first, moves)


def _printed_points(free_values: np.ndarray, placement: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """(m, width) placements: ``placement`` with its free entries set to (m, n) ``free_values`` (periodic ones wrapped
    into their range) as printed (:func:`placement.search.space.printed`)."""
    points = np.tile(placement, (len(free_values), 1))
    wrapped = space.wrap(free_values)
    for column, index in enumerate(space.indices):
        angle = bool(space.angles[index])
        points[:, index] = [printed(value, angle) for value in wrapped[:, column]]
    return points


def inside(free_values: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """(m,) whether each row of free values lies in the box (up to the printed digits' round-off)."""
    above = (free_values >= space.lower - BOUND_ROUND_OFF).all(axis=1)
    return np.asarray(above & (free_values <= space.upper + BOUND_ROUND_OFF).all(axis=1))
