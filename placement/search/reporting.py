"""Which placement a search reports: one that keeps every limit as printed.

The report prints a placement to REPORTED_DECIMALS of a mm and of a degree; a user enters those
numbers again (``--at``) and must get the same verdict. So the optimum reported is the best printed
placement near the search's optimum, found by a search of the printed lattice
(:mod:`placement.search.lattice`), or the optimum pulled slightly inwards, as printed, that keeps
every limit, with the required margin, on the path's own samples and on the 4x denser re-check;
when the optimum cannot be, the next candidate that can, and the report says why.
"""

from __future__ import annotations

import numpy as np

from placement.evaluation.evaluator import Evaluator
from placement.evaluation.results import Evaluation
from placement.placing.transform import ANGLES, VARIABLES
from placement.search.lattice import Model, inside, lattice_search
from placement.search.space import PlacementSpace, printed

RETREAT_SHARES = np.array([0.0, 1e-5, 1e-4, 1e-3, 1e-2])  # a reported optimum's pulls, for rounding and re-check


REPORT_CANDIDATES = 20  # candidates tried, best first, when the optimum fails to keep its limits once printed


RECHECK_TRIES = 5  # the lattice's best points re-checked on the denser sampling, at most, before the pulled ones


def as_printed(placement: np.ndarray, angles: np.ndarray | None = None) -> np.ndarray:
    """A placement vector (m, rad) rounded as the report prints it, REPORTED_DECIMALS of a mm and of a degree, and
    read back as the command line reads it (so the printed numbers, entered again, are this very placement).

    Args:
        placement: The placement vector (m, rad).
        angles: Which of its entries are angles (:attr:`PlacementSpace.angles`); by default phi, theta, psi and every
            variable after the six (a revolute joint's knots, the spin).
    """
    return np.array([printed(value, angle) for angle, value in zip(_angles(len(placement), angles), placement,
                                                                    strict=True)])


def _angles(width: int, angles: np.ndarray | None) -> list[bool]:
    """Which entries of a placement vector of ``width`` are angles: ``angles`` where given, else phi, theta, psi and
    every entry after the six."""
    if angles is not None:
        return [bool(angle) for angle in angles]
    return [k >= len(VARIABLES) or VARIABLES[k] in ANGLES for k in range(width)]


def reported_point(candidates: list[np.ndarray], fine: Evaluator, dense: Evaluator, space: PlacementSpace,
                   sign: float, guide: Evaluator | None = None,
                   walk: bool = True) -> tuple[np.ndarray, str | None, Evaluation | None]:
    """The first candidate that, printed, keeps every limit with the required margin on the path's samples and the
    denser ones.

    A candidate is printed as the best printed placements near it that keep every limit on the path's samples, found
    by a search of the printed lattice (:mod:`placement.search.lattice`), at most RECHECK_TRIES of them, then as
    pulled inwards by each of RETREAT_SHARES that does; those are re-checked on the denser sampling in that order.
    When none holds there (the lattice's best lies on a limit that the denser samples break, and a pull towards the
    box's centre may bind it harder), the lattice is searched again on the denser samples. With a ``guide`` (a
    cheaper model of the path, :mod:`placement.search.coarse_guide`), the lattice is searched on it, and each point
    re-checked is evaluated on the path's samples first. Without ``walk`` (a runner-up basin's point, listed, not
    reported), only the corners of the printed cell around a candidate are tried.

    Returns:
        The free variables of the placement to report, why it is not the first candidate (None if it is), and its
        re-check on the denser sampling. When no candidate does, the first one as printed, with why it fails, and
        no re-check.
    """
    first_failure = ""
    models: list[Model] = [fine] if guide is None else [guide]
    if guide is None and walk:
        models.append(_Rechecked(dense, fine))
    for number, x in enumerate(candidates[:REPORT_CANDIDATES]):
        for model in models:
            trials = _printed_near(model, space.full(x)[0], space, sign, walk)
            trial, check, failure = _first_holding([] if isinstance(trials, str) else list(trials), fine, dense, guide)
            if number == 0 and not first_failure:
                first_failure = trials if isinstance(trials, str) else failure
            if trial is not None:
                note = None if number == 0 else (f"the search's optimum {first_failure}; reported: candidate "
                                                 f"{number + 1}, the best that keeps every limit there")
                return trial[space.indices], note, check
    return (as_printed(space.full(candidates[0])[0], space.angles)[space.indices],
            f"no candidate keeps every limit once printed and on the 4x denser re-check: the search's optimum "
            f"{first_failure}", None)


def _first_holding(trials: list[np.ndarray], fine: Evaluator, dense: Evaluator, guide: Evaluator | None
                   ) -> tuple[np.ndarray | None, Evaluation | None, str]:
    """The first of ``trials`` (placements) that keeps every limit on the path's samples (evaluated there when the
    trials come from a ``guide``) and on the denser ones, with its re-check; else None and why the first fails."""
    failure = ""
    for trial in trials:
        if guide is not None:
            exact = fine.evaluate(trial[None])
            if not exact.feasible[0]:
                failure = failure or f"fails once printed ({_failure(exact)})"
                continue
        check = dense.recheck(trial[None], fine)
        if check.feasible[0] and np.isfinite(check.value[0]):
            return trial, check, failure
        failure = failure or f"fails the 4x denser re-check ({_failure(check)})"
    return None, None, failure


class _Rechecked:
    """The denser re-check as a model the lattice search evaluates (:meth:`Evaluator.recheck`)."""

    def __init__(self, dense: Evaluator, fine: Evaluator) -> None:
        self.dense, self.fine = dense, fine

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        return self.dense.recheck(placements, self.fine)


def _printed_near(model: Model, placement: np.ndarray, space: PlacementSpace, sign: float,
                  walk: bool) -> np.ndarray | str:
    """(K, width) printed placements near ``placement`` (m, rad) that keep every limit on ``model``, in the box: the
    lattice search's best RECHECK_TRIES (:func:`placement.search.lattice.lattice_search`, with ``walk``), then the
    placement pulled towards the box's centre by each of RETREAT_SHARES, as printed; or why none does: "fails once
    printed (the limit)" or "lies outside the box once printed"."""
    search = lattice_search(model, placement, space, sign, walk)
    x = placement[space.indices]
    pulled = space.full(x + RETREAT_SHARES[:, None] * ((space.lower + space.upper) / 2 - x))
    pulled[:, space.indices] = np.array([as_printed(p, space.angles) for p in pulled])[:, space.indices]
    check = model.evaluate(pulled)
    usable = check.feasible & np.isfinite(check.value) & inside(pulled[:, space.indices], space)
    trials = np.vstack([search.placements[search.usable][:RECHECK_TRIES], pulled[usable]])
    if len(trials):
        return trials
    if search.first is None:
        return "lies outside the box once printed"
    return f"fails once printed ({_failure(search.first)})"


def _failure(check: Evaluation) -> str:
    """The limit that binds most at the first placement of ``check``: "kind: where, margin M %"."""
    tightest = binding(check)
    return f"{check.limits[tightest]}, margin {check.margins[0, tightest] * 100:.4f} %"


def binding(check: Evaluation, placement: int = 0) -> int:
    """The column of the limit that binds most at a placement of ``check``: reachability where a sample has no
    configuration (every margin is then at most -1, the workspace's first side included), else the tightest."""
    if not check.reachable[placement]:
        return check.limits.index("reachability: path")
    return int(np.argmin(check.margins[placement]))


