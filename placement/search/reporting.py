"""Which placement a search reports: one that keeps every limit as printed.

The report prints a placement to REPORTED_DECIMALS of a mm and of a degree; a user enters those
numbers again (``--at``) and must get the same verdict. So the optimum reported is a corner of
the printed grid's cell around the search's optimum (or a point pulled slightly inwards) that
keeps every limit, with the required margin, on the path's own samples and on the 4x denser
re-check; when the optimum cannot be, the next candidate that can, and the report says why.
"""

from __future__ import annotations

import numpy as np

from placement.evaluation.evaluator import Evaluator
from placement.evaluation.results import Evaluation
from placement.placing.transform import ANGLES, VARIABLES
from placement.search.space import PlacementSpace, printed, printed_steps

RETREAT_SHARES = np.array([0.0, 1e-5, 1e-4, 1e-3, 1e-2])  # a reported optimum's pulls, for rounding and re-check


REPORT_CANDIDATES = 20  # candidates tried, best first, when the optimum fails to keep its limits once printed


RECHECK_TRIES = 5  # printed placements near a candidate re-checked on the denser sampling, at most


BOUND_ROUND_OFF = 1e-12  # m or rad: a printed placement may pass a search bound by this much (its decimal digits)


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
                   sign: float, guide: Evaluator | None = None) -> tuple[np.ndarray, str | None, Evaluation | None]:
    """The first candidate that, printed, keeps every limit with the required margin on the path's samples and the
    denser ones.

    A candidate is printed (:func:`as_printed`) as the best of the corners of the printed grid's cell around it
    that keeps every limit on the path's samples, or else pulled inwards by the least of RETREAT_SHARES that does;
    at most RECHECK_TRIES of those are re-checked on the denser sampling, best first. With a ``guide`` (a cheaper
    model of the path, :mod:`placement.search.coarse_guide`), the corners and pulls are ranked and sifted on it, and each
    of those re-checked is evaluated on the path's samples first.

    Returns:
        The free variables of the placement to report, why it is not the first candidate (None if it is), and its
        re-check on the denser sampling. When no candidate does, the first one as printed, with why it fails, and
        no re-check.
    """
    centre = (space.lower + space.upper) / 2
    first_failure = ""
    for number, x in enumerate(candidates[:REPORT_CANDIDATES]):
        near = np.vstack([_grid_corners(space.full(x)[0], space.indices, space.angles),
                          space.full(x + RETREAT_SHARES[:, None] * (centre - x))])
        trials = near.copy()  # the free variables as printed, the fixed ones as the space fixes them
        trials[:, space.indices] = np.array([as_printed(p, space.angles) for p in near])[:, space.indices]
        fine_check = (fine if guide is None else guide).evaluate(trials)
        inside = (trials[:, space.indices] >= space.lower - BOUND_ROUND_OFF).all(axis=1) & (
            trials[:, space.indices] <= space.upper + BOUND_ROUND_OFF).all(axis=1)  # a corner may cross a bound
        usable = fine_check.feasible & inside
        corners = len(trials) - len(RETREAT_SHARES)
        order = [k for k in np.argsort(sign * fine_check.value[:corners], kind="stable") if usable[k]]
        order += [corners + k for k in np.flatnonzero(usable[corners:])]
        for k in order[:RECHECK_TRIES]:
            if guide is not None:
                exact = fine.evaluate(trials[k:k + 1])
                if not exact.feasible[0]:
                    if number == 0 and not first_failure:
                        first_failure = f"fails once printed ({_failure(exact)})"
                    continue
            check = dense.recheck(trials[k:k + 1], fine)
            if check.feasible[0] and np.isfinite(check.value[0]):
                if number == 0:
                    return trials[k][space.indices], None, check
                return trials[k][space.indices], (f"the search's optimum {first_failure}; reported: candidate "
                                                  f"{number + 1}, the best that keeps every limit there"), check
            if number == 0 and not first_failure:
                first_failure = f"fails the 4x denser re-check ({_failure(check)})"
        if number == 0 and not first_failure:
            first_failure = f"fails once printed ({_failure(fine_check)})"
    return (as_printed(space.full(candidates[0])[0], space.angles)[space.indices],
            f"no candidate keeps every limit once printed and on the 4x denser re-check: the search's optimum "
            f"{first_failure}", None)


def _grid_corners(placement: np.ndarray, free: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(2^n_free, width) the corners of the printed grid's cell (:func:`as_printed`) around ``placement`` (m, rad), the
    free variables rounded down or up, the others as they are (``angles``: which entries are angles)."""
    step = printed_steps(np.array(_angles(len(placement), angles), dtype=bool))
    low = np.floor(placement / step) * step
    corners = np.tile(placement, (2 ** len(free), 1))
    for bit, index in enumerate(free):
        up = (np.arange(len(corners)) >> bit) & 1
        corners[:, index] = low[index] + up * step[index]
    return corners


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


