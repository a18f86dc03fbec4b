"""Search for the placements of least (and most) electric energy that respect every limit.

Strategy, per direction (minimise, maximise): a global search by scipy's differential evolution
over the free placement variables, with the limits as constraints (a feasible placement always
beats an infeasible one, and infeasible ones are ranked by how far they break the limits, so they
steer the search and never stop it), on the path sampled with about ``search_samples`` samples;
then a local constrained polish (SLSQP) from the best few distinct candidates, on the path
sampled at its own time step, which the reported energies use. The reported optima are
re-evaluated with a four times denser sampling, and the difference is reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution, minimize

from placement.evaluation import Evaluation, Evaluator, PlacementDetail
from placement.exceptions import PlacementError
from placement.frames import VARIABLES, PlacementSpace
from placement.path import ToolPath
from placement.robot import Robot

POLISH_STARTS = 3  # distinct candidates polished locally
GIVE_UP_GENERATIONS = 25  # generations without any feasible placement after which the search stops
RECHECK_DENSITY = 4  # the re-check samples the path this many times more densely
GRADIENT_STEP = 1e-7  # forward-difference step of the polish, as a share of each variable's range


@dataclass(frozen=True)
class SearchSettings:
    """Budget of the global search (differential evolution) and of the polish.

    Attributes:
        population: Population size of the global search (at least 5 per free variable).
        max_generations: Upper bound on generations.
        tolerance: Relative spread of the population's energies at which the search stops.
        seed: Random seed; the same seed gives the same result.
        search_samples: Samples of the path during the global search, at most (a coarser
            sampling than the path's own when the path has more; the polish and the reported
            energies use the path's own).
    """

    population: int = 48
    max_generations: int = 80
    tolerance: float = 1e-3
    seed: int = 0
    search_samples: int = 64


@dataclass(frozen=True)
class Optimum:
    """The best placement found in one direction.

    Attributes:
        detail: Energy, margins and trace of the placement (at the search's sampling).
        recheck_energy_J: Energy of the same placement with 4x denser path sampling.
        evaluations: Placements evaluated by the search.
    """

    detail: PlacementDetail
    recheck_energy_J: float
    evaluations: int

    @property
    def sampling_gap(self) -> float:
        """Relative change of the energy when the path is sampled 4x more densely."""
        return abs(self.recheck_energy_J - self.detail.energy.total_J) / abs(self.detail.energy.total_J)


@dataclass(frozen=True)
class PlacementResult:
    """Outcome of :func:`optimize_placement` (SI units: m, rad, J).

    Attributes:
        best: The least-energy feasible placement, if minimisation was asked and one exists.
        worst: The most-energy feasible placement, if maximisation was asked and one exists.
        space: Free variables, bounds and fixed values of the search.
        regeneration: Regeneration mode of the energy.
        infeasible: Why no feasible placement was found (the binding limit), else None.
    """

    best: Optimum | None
    worst: Optimum | None
    space: PlacementSpace
    regeneration: str
    infeasible: str | None = None

    @property
    def gain(self) -> float | None:
        """(E_max − E_min)/E_max, when both were computed."""
        if self.best is None or self.worst is None:
            return None
        e_min, e_max = self.best.detail.energy.total_J, self.worst.detail.energy.total_J
        return float((e_max - e_min) / e_max)


def default_space(robot: Robot, free: tuple[str, ...] | None = None, fixed: dict[str, float] | None = None,
                  bounds: dict[str, tuple[float, float]] | None = None, half_turn: bool = False) -> PlacementSpace:
    """The placement space of a robot: by default the sidecar's ``placement`` section, else x, y, z
    within the workspace box and phi in ±180° (the tool axis staying along Z_b).

    Args:
        robot: The robot.
        free: Free variables (default: the sidecar's, else x, y, z, phi).
        fixed: Values of fixed variables (default 0); fixing a variable removes it from the default
            free set, and an explicitly free variable cannot be fixed.
        bounds: Bounds overriding the defaults (m, rad).
        half_turn: The path is unchanged by a half turn about its tool axis
            (:meth:`ToolPath.half_turn_symmetric`): phi then only needs ±90°.
    """
    defaults = robot.sidecar.placement
    if free is None:  # the default free set, less what the caller fixes
        free = tuple(n for n in (defaults.free if defaults else ("x", "y", "z", "phi")) if n not in (fixed or {}))
    free = tuple(free)
    unknown = sorted(set(free) - set(VARIABLES))
    if unknown:
        raise PlacementError(f"unknown placement variable(s) {unknown}; expected some of {', '.join(VARIABLES)}")
    clash = sorted(set(free) & set(fixed or {}))
    if clash:
        raise PlacementError(f"{clash} cannot be both free and fixed")
    limits = {**(defaults.bounds if defaults else {}), **(bounds or {})}
    workspace = robot.sidecar.workspace
    for k, axis in enumerate("xyz"):
        if workspace is not None:
            limits.setdefault(axis, (workspace.min_m[k], workspace.max_m[k]))
    limits.setdefault("phi", (-np.pi / 2, np.pi / 2) if half_turn else (-np.pi, np.pi))
    for angle in ("theta", "psi"):
        limits.setdefault(angle, (-np.pi, np.pi))
    missing = [name for name in free if name not in limits]
    if missing:
        raise PlacementError(f"robot '{robot.name}' declares no workspace: give bounds for {missing}")
    fixed_vector = np.array([float((fixed or {}).get(name, 0.0)) for name in VARIABLES])
    return PlacementSpace(free=tuple(n for n in VARIABLES if n in free),
                          lower=np.array([limits[n][0] for n in VARIABLES if n in free], dtype=float),
                          upper=np.array([limits[n][1] for n in VARIABLES if n in free], dtype=float),
                          fixed=fixed_vector)


class _Problem:
    """Objective and constraints over the free variables, sharing one evaluation per point."""

    def __init__(self, evaluator: Evaluator, space: PlacementSpace, sign: float) -> None:
        self.evaluator, self.space, self.sign = evaluator, space, sign
        self._cache: dict[bytes, tuple[float, np.ndarray]] = {}
        self.least_infeasible: tuple[float, np.ndarray, np.ndarray] | None = None  # (violation, x, margins)
        self.best_feasible: float | None = None  # signed energy of the best feasible point seen

    def _lookup(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        points = np.atleast_2d(points)
        todo = [p for p in points if p.tobytes() not in self._cache]
        if todo:
            evaluation = self.evaluator.evaluate(self.space.full(np.array(todo)))
            self._remember(np.array(todo), evaluation)
        values = [self._cache[p.tobytes()] for p in points]
        return np.array([v[0] for v in values]), np.array([v[1] for v in values])

    def _remember(self, points: np.ndarray, evaluation: Evaluation) -> None:
        if len(self._cache) > 200_000:
            self._cache.clear()
        for point, energy, margins in zip(points, evaluation.energy_J, evaluation.margins):
            self._cache[point.tobytes()] = (float(energy), margins)
            violation = float(np.clip(-margins, 0.0, None).sum())
            if violation > 0 and (self.least_infeasible is None or violation < self.least_infeasible[0]):
                self.least_infeasible = (violation, point, margins)
            elif violation == 0 and np.isfinite(energy):
                value = self.sign * float(energy)
                self.best_feasible = value if self.best_feasible is None else min(self.best_feasible, value)

    def objective(self, points: np.ndarray) -> np.ndarray:
        """Signed energy of (n_free, S) or (n_free,) points (scipy's layouts)."""
        energy, _ = self._lookup(np.asarray(points).T)
        return np.where(np.isfinite(energy), self.sign * energy, 1e30)

    def margins(self, points: np.ndarray) -> np.ndarray:
        """Tightest margin of every limit, (n_limits, S) or (n_limits,)."""
        _, margins = self._lookup(np.asarray(points).T)
        return margins.T if np.ndim(points) > 1 else margins[0]


def _search(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, sign: float, settings: SearchSettings,
            progress: Callable[[], None] | None) -> tuple[np.ndarray | None, _Problem]:
    """Global search on the coarse sampling, polish on the fine one.

    Returns:
        The best feasible point (None if there is none), and the problem that explains why not:
        the coarse one when the global search found nothing feasible, else the fine one.
    """
    problem = _Problem(coarse, space, sign)
    bounds = list(zip(space.lower, space.upper))
    n_limits = problem.margins(space.lower[:, None]).shape[0]
    constraint = NonlinearConstraint(problem.margins, np.zeros(n_limits), np.full(n_limits, np.inf))

    generations = [0]

    def generation_done(intermediate_result) -> bool:  # scipy passes the result by this name
        generations[0] += 1
        if progress is not None:
            progress()
        return problem.best_feasible is None and generations[0] >= GIVE_UP_GENERATIONS

    result = differential_evolution(
        problem.objective, bounds, constraints=constraint, vectorized=True, updating="deferred",
        popsize=max(5, settings.population // len(bounds)), maxiter=settings.max_generations, tol=settings.tolerance,
        polish=False, init="sobol", rng=np.random.default_rng(settings.seed), callback=generation_done)
    population = np.asarray(result.population)
    energies, margins = problem._lookup(population)
    feasible = (margins >= 0).all(axis=1) & np.isfinite(energies)
    if not feasible.any():
        return None, problem
    ranked = population[feasible][np.argsort(sign * energies[feasible])]
    local = _Problem(fine, space, sign)
    fine_margins = local._lookup(ranked)[1]  # one batch
    starts = ranked[(fine_margins >= 0).all(axis=1)]
    if not len(starts):  # the finer sampling breaks a limit the coarse one missed: repair the closest
        closest = ranked[np.argmin(np.clip(-fine_margins, 0.0, None).sum(axis=1))]
        repaired = _polish(local, closest, bounds)
        return (repaired if (local._lookup(repaired)[1] >= 0).all() else None), local
    best_x, best_value = None, np.inf
    for start in _distinct(starts, space):
        x = _polish(local, start, bounds)
        value, _ = local._lookup(x)
        if sign * value[0] < best_value:
            best_x, best_value = x, sign * value[0]
    return best_x, local


def _distinct(candidates: np.ndarray, space: PlacementSpace) -> list[np.ndarray]:
    """The best candidates, skipping any within 2 % of the box of one already kept."""
    scale = np.where(space.upper > space.lower, space.upper - space.lower, 1.0)
    kept: list[np.ndarray] = []
    for candidate in candidates:
        if all(np.abs((candidate - k) / scale).max() > 0.02 for k in kept):
            kept.append(candidate)
        if len(kept) == POLISH_STARTS:
            break
    return kept


def _polish(problem: _Problem, start: np.ndarray, bounds: list) -> np.ndarray:
    """SLSQP from ``start``; from a feasible start, returns a feasible point at least as good."""
    scale = np.array([hi - lo if hi > lo else 1.0 for lo, hi in bounds])  # search in box units

    def differences(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Forward-difference gradient of the objective and Jacobian of the margins, in one batch."""
        points = (u + np.vstack([np.zeros(len(u)), GRADIENT_STEP * np.eye(len(u))])) * scale
        energy, margins = problem._lookup(points)
        return (problem.sign * (energy[1:] - energy[0]) / GRADIENT_STEP,
                (margins[1:] - margins[0]).T / GRADIENT_STEP)

    result = minimize(lambda u: problem.objective(u * scale)[0], start / scale, method="SLSQP",
                      jac=lambda u: differences(u)[0],
                      bounds=[(lo / s, hi / s) for (lo, hi), s in zip(bounds, scale)],
                      constraints=[{"type": "ineq", "fun": lambda u: problem.margins(u * scale),
                                    "jac": lambda u: differences(u)[1]}],
                      options={"maxiter": 100, "ftol": 1e-10})
    polished = np.clip(result.x * scale, [b[0] for b in bounds], [b[1] for b in bounds])
    if not (problem._lookup(start)[1] >= 0).all():  # an infeasible start: take what SLSQP reached
        return polished
    polished = _feasible_towards(problem, start, polished)
    energy, _ = problem._lookup(polished)
    start_energy, _ = problem._lookup(start)
    return polished if problem.sign * energy[0] <= problem.sign * start_energy[0] else start


def _feasible_towards(problem: _Problem, feasible: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The point nearest ``target`` on the segment from ``feasible`` that keeps every limit.

    The local search ends on the limits, often a hair outside them; bisection brings it back.
    """
    if (problem._lookup(target)[1] >= 0).all():
        return target
    inside, outside = 0.0, 1.0
    for _ in range(40):
        middle = (inside + outside) / 2
        if (problem._lookup(feasible + middle * (target - feasible))[1] >= 0).all():
            inside = middle
        else:
            outside = middle
    return feasible + inside * (target - feasible)


def optimize_placement(robot: Robot, path: ToolPath, *, space: PlacementSpace | None = None,
                       regeneration: str = "clip", minimize_energy: bool = True, maximize_energy: bool = True,
                       time_step_s: float | None = None, settings: SearchSettings = SearchSettings(),
                       progress: Callable[[], None] | None = None) -> PlacementResult:
    """Find the least-energy (and most-energy) feasible placement of a path on a robot.

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path.
        space: Free variables and bounds (default: :func:`default_space`).
        regeneration: Regeneration mode, see :mod:`placement.energy`.
        minimize_energy, maximize_energy: Which searches to run.
        time_step_s: Path sampling step (default: the path file's).
        settings: Search budget and seed.
        progress: Called once per generation of the global search (for a progress bar).

    Returns:
        The optima (None in a direction not asked for), or, when no placement is feasible, the
        reason with the binding limit.
    """
    space = space or default_space(robot, half_turn=path.half_turn_symmetric())
    step = time_step_s if time_step_s is not None else path.time_step_s
    duration = float(path.sample(step).t_s[-1])
    with Evaluator(robot, path, regeneration, max(step, duration / settings.search_samples)) as coarse, \
            Evaluator(robot, path, regeneration, step) as evaluator:
        dense = Evaluator(robot, path, regeneration, step / RECHECK_DENSITY, workers=1)
        return _optimize(coarse, evaluator, dense, space, minimize_energy, maximize_energy, settings, progress)


def _optimize(coarse: Evaluator, evaluator: Evaluator, dense: Evaluator, space: PlacementSpace,
              minimize_energy: bool, maximize_energy: bool, settings: SearchSettings,
              progress: Callable[[], None] | None) -> PlacementResult:
    found: dict[float, Optimum | None] = {}
    infeasible = None
    for sign, wanted in ((1.0, minimize_energy), (-1.0, maximize_energy)):
        if not wanted:
            found[sign] = None
            continue
        before = evaluator.evaluations + coarse.evaluations
        x, problem = _search(coarse, evaluator, space, sign, settings, progress)
        if x is None:
            found[1.0] = found[-1.0] = None  # the feasible set is the same in both directions
            infeasible = _binding_limit(problem, problem.evaluator)
            break
        placement = space.full(x)[0]
        found[sign] = Optimum(detail=evaluator.detail(placement),
                              recheck_energy_J=float(dense.evaluate(placement[None]).energy_J[0]),
                              evaluations=evaluator.evaluations + coarse.evaluations - before)
    return PlacementResult(best=found[1.0], worst=found[-1.0], space=space, regeneration=evaluator.regeneration,
                           infeasible=infeasible)


def _binding_limit(problem: _Problem, evaluator: Evaluator) -> str:
    """Describe the limit that the least infeasible placement found breaks the most."""
    if problem.least_infeasible is None:
        return "no placement could be evaluated"
    _, point, _ = problem.least_infeasible
    detail = evaluator.detail(problem.space.full(point)[0])
    if not detail.reachable:
        return (f"the path leaves the robot's reach at every placement tried ({len(detail.unreachable_samples)} "
                f"of {len(detail.samples)} samples unreachable at the closest one)")
    worst = min(detail.margins, key=lambda m: m.margin)
    value = abs(worst.value) if worst.kind in ("joint speed", "motor torque", "motor speed") else worst.value
    return (f"{worst.kind} ({worst.where}) is exceeded even at the least infeasible placement found: "
            f"{value:.4g} {worst.unit} against a limit of {worst.limit:.4g} {worst.unit}")
