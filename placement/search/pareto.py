"""Pareto fronts: the placements that no other placement beats on every objective at once.

Energy is rarely the only thing a placement is judged by: a place that saves energy may sit near
a singularity (poor dexterity) or shake the machine. Given two or three objectives, the front is
the set of feasible placements where one objective can only improve at the cost of another.

Strategy:

1. Each objective's own optimum is searched first (:func:`placement.search.optimize.optimize_placement`,
   best direction only): the front's ends are then exact single-objective optima, not
   approximations of them.
2. NSGA-II (pymoo) evolves a population, seeded with those optima, over the free placement
   variables on the coarse search sampling, with every limit as a constraint. Every feasible
   placement it evaluates is archived.
3. The archive's non-dominated placements (at most ``FRONT_SIZE``, spread evenly along the
   front) are re-evaluated on the path's own sampling together with the optima, and the
   dominance is re-checked there; each member is then re-evaluated on a four times denser
   sampling, and the dominance is checked once more on those values.

The knee is the member nearest the ideal point (every objective at its best over the front)
once each objective is scaled to [0, 1] over the front.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np

from placement.contract.objective import OBJECTIVES
from placement.distribution import FRONTS, require
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings, denser
from placement.evaluation.results import Evaluation, PlacementDetail
from placement.exceptions import SettingsError
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.optimize import RECHECK_DENSITY, SearchSettings, optimize_placement, search_sampling
from placement.search.space import PlacementSpace, default_space

FRONT_SIZE = 24  # members reported at most, spread evenly along the front
UNREACHABLE_VALUE = 1e30  # what NSGA-II sees for an objective of an unreachable placement


@dataclass(frozen=True)
class FrontMember:
    """One placement of the front.

    Attributes:
        placement: (6,) placement vector (m, rad).
        values: (n_objectives,) the objectives on the path's own sampling.
        recheck_values: (n_objectives,) the same on a four times denser sampling.
        margin: The tightest normalised margin over every limit (≥ 0: feasible).
    """

    placement: np.ndarray
    values: np.ndarray
    recheck_values: np.ndarray
    margin: float


@dataclass(frozen=True)
class ParetoFront:
    """Outcome of :func:`pareto_front` (SI units).

    Attributes:
        objectives: The objectives' names.
        members: Mutually non-dominated feasible placements, by the first objective.
        optima: Each objective's own optimum (its single-objective search), by name.
        knee: Index into ``members`` of the knee (module docstring).
        space: Free variables, bounds and fixed values of the search.
        regeneration: Regeneration policy of the energies.
        evaluations: Placements evaluated in all.
        infeasible: Why no feasible placement was found, else None.
    """

    objectives: tuple[str, ...]
    members: tuple[FrontMember, ...]
    optima: dict[str, float]
    knee: int | None
    space: PlacementSpace
    regeneration: str
    evaluations: int
    infeasible: str | None = None

    def end(self, objective: str) -> int:
        """Index into ``members`` of the member best by ``objective`` (the front's end on its side)."""
        column = self.objectives.index(objective)
        sign = OBJECTIVES.get(objective).sign
        return int(np.argmin([sign * member.values[column] for member in self.members]))


def non_dominated(values: np.ndarray) -> np.ndarray:
    """Mask of the rows of ``values`` (to be minimised) that no other row dominates.

    A row dominates another when it is no worse in every column and better in one; of identical
    rows, the first is kept.
    """
    keep = np.ones(len(values), dtype=bool)
    for i, row in enumerate(values):
        others = np.delete(values, i, axis=0)
        dominated = ((others <= row).all(axis=1) & (others < row).any(axis=1)).any()
        duplicate = (values[:i] == row).all(axis=1).any()
        keep[i] = not dominated and not duplicate
    return keep


def knee_index(values: np.ndarray) -> int:
    """The row nearest the ideal point once each column (to be minimised) is scaled to [0, 1]."""
    low, high = values.min(axis=0), values.max(axis=0)
    scaled = (values - low) / np.where(high > low, high - low, 1.0)
    return int(np.argmin(np.linalg.norm(scaled, axis=1)))


def _front_problem(evaluator: Evaluator, space: PlacementSpace, signs: np.ndarray, n_limits: int) -> Any:
    """The objectives (signed to be minimised) and margins of placements, as a pymoo problem; its ``archive`` lists
    the (free values, signed objectives) of the feasible placements it evaluated."""
    require(FRONTS)
    from pymoo.core.problem import Problem  # optional dependency: the [pareto] extra

    class FrontProblem(Problem):
        """The problem pymoo solves, built here: pymoo's base class is imported only when a front is searched."""

        def __init__(self) -> None:
            super().__init__(n_var=len(space.free), n_obj=len(signs), n_ieq_constr=n_limits, xl=space.lower,
                             xu=space.upper)
            self.archive: list[tuple[np.ndarray, np.ndarray]] = []

        def _evaluate(self, x: np.ndarray, out: dict, *args: object, **kwargs: object) -> None:
            evaluation = evaluator.evaluate(space.full(x))
            signed = evaluation.values * signs
            out["F"] = np.where(np.isfinite(signed), signed, UNREACHABLE_VALUE)
            out["G"] = -evaluation.margins
            self.archive.extend(zip(x[evaluation.feasible], out["F"][evaluation.feasible]))

    return FrontProblem()


def pareto_front(robot: Robot, path: ToolPath, objectives: tuple[str, ...], *, space: PlacementSpace | None = None,
                 evaluation: EvaluatorSettings = EvaluatorSettings(), settings: SearchSettings = SearchSettings(),
                 progress: Callable[[], None] | None = None, executor: Executor | None = None) -> ParetoFront:
    """The Pareto front of feasible placements of a path on a robot for two or three objectives.

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path.
        objectives: Two or three objective names (see :mod:`placement.objectives`).
        space: Free variables and bounds (default: :func:`placement.search.space.default_space`).
        evaluation: How placements are evaluated (regeneration policy, the path's sampling step,
            workers: chunks per batch of placements for ``executor``, ...); the objectives are
            ``objectives``, so its own objective must be left at its default or be the same.
        settings: Budget and seed of the single-objective searches and of NSGA-II (its population
            and generations); the single-objective searches look for the best placement only.
        progress: Called once per generation of every search.
        executor: Runs the evaluations in chunks (a Dask cluster's, see :mod:`placement.evaluation.parallel`);
            default: this process.

    Returns:
        The front, or, when no placement is feasible, the reason.

    Raises:
        SettingsError: Not two or three different objectives, or evaluation settings naming others.
        MissingExtraError: pymoo (the ``pareto`` extra) is not installed; raised before any search.
    """
    if not 2 <= len(objectives) <= 3 or len(set(objectives)) != len(objectives):
        raise SettingsError(f"a Pareto front needs two or three different objectives, got {', '.join(objectives)}")
    if evaluation.objectives not in (EvaluatorSettings().objectives, tuple(objectives)):
        raise SettingsError(f"a Pareto front's objectives are given once, as objectives ({', '.join(objectives)}); "
                            f"the evaluation settings name {', '.join(evaluation.objectives)}")
    require(FRONTS)  # before the single-objective searches: NSGA-II is the [pareto] extra's
    signs = np.array([OBJECTIVES.get(name).sign for name in objectives])
    space = space or default_space(robot, half_turn=path.half_turn_symmetric())
    step = evaluation.time_step_s if evaluation.time_step_s is not None else path.time_step_s
    regeneration = evaluation.regeneration
    optima: dict[str, PlacementDetail] = {}
    evaluations = 0
    best_only = dataclasses.replace(settings, best=True, worst=False)
    for name in objectives:
        result = optimize_placement(robot, path, space=space,
                                    evaluation=dataclasses.replace(evaluation, objective=name, time_step_s=step),
                                    settings=best_only, progress=progress, executor=executor)
        if result.best is None:
            return ParetoFront(objectives, (), {}, None, space, regeneration, evaluations, result.infeasible)
        optima[name] = result.best.detail
        evaluations += result.best.evaluations
    seeds = np.array([detail.placement for detail in optima.values()])
    coarse, fine = search_sampling(path, dataclasses.replace(evaluation, objective=tuple(objectives)), settings)
    with Evaluator(robot, path, coarse, executor) as coarse_evaluator:
        candidates = _evolve(coarse_evaluator, space, signs, seeds[:, space.indices], settings, progress)
        evaluations += coarse_evaluator.evaluations
    with Evaluator(robot, path, fine, executor) as fine_evaluator, denser(fine_evaluator, RECHECK_DENSITY) as dense:
        members = _members(fine_evaluator, dense, signs, np.vstack([seeds, space.full(candidates)]))
        evaluations += fine_evaluator.evaluations + dense.evaluations
    knee = knee_index(np.array([m.values for m in members]) * signs)
    return ParetoFront(objectives, members, {name: detail.value for name, detail in optima.items()}, knee, space,
                       regeneration, evaluations)


def _evolve(evaluator: Evaluator, space: PlacementSpace, signs: np.ndarray, seeds: np.ndarray,
            settings: SearchSettings, progress: Callable[[], None] | None) -> np.ndarray:
    """NSGA-II from a population holding ``seeds``; the archive's non-dominated free values (coarse sampling)."""
    require(FRONTS)
    from pymoo.algorithms.moo.nsga2 import NSGA2  # optional dependency: the [pareto] extra
    from pymoo.optimize import minimize

    n_limits = evaluator.evaluate(space.full(space.lower)).margins.shape[1]
    problem = _front_problem(evaluator, space, signs, n_limits)
    rng = np.random.default_rng(settings.seed)
    population = max(settings.population, 2 * len(seeds))
    start = np.vstack([seeds, rng.uniform(space.lower, space.upper, (population - len(seeds), len(space.free)))])
    minimize(problem, NSGA2(pop_size=population, sampling=start), ("n_gen", settings.max_generations),
             seed=settings.seed, callback=lambda _: progress() if progress else None, verbose=False)
    if not problem.archive:
        return np.zeros((0, len(space.free)))
    points, values = (np.array(column) for column in zip(*problem.archive))
    front = non_dominated(values)
    points, values = points[front], values[front]
    order = np.argsort(values[:, 0])
    spread = np.unique(np.linspace(0, len(points) - 1, min(FRONT_SIZE, len(points))).round().astype(int))
    return points[order][spread]


def _members(fine: Evaluator, dense: Evaluator, signs: np.ndarray, placements: np.ndarray) -> tuple[FrontMember, ...]:
    """Placements re-evaluated on the path's sampling, then densely; those feasible and non-dominated on both (each
    placement once: an objective's own optimum seeds NSGA-II, and its archive may return it)."""
    placements = placements[np.sort(np.unique(placements, axis=0, return_index=True)[1])]
    evaluation = fine.evaluate(placements)
    kept = _feasible_front(evaluation, signs)
    recheck = dense.recheck(placements[kept], fine)
    still = _feasible_front(recheck, signs)
    chosen = np.flatnonzero(kept)[still]
    members = [FrontMember(placement=placements[i], values=evaluation.values[i], recheck_values=recheck.values[j],
                           margin=float(evaluation.margins[i].min()))
               for i, j in zip(chosen, np.flatnonzero(still))]
    return tuple(sorted(members, key=lambda m: signs[0] * m.values[0]))


def _feasible_front(evaluation: Evaluation, signs: np.ndarray) -> np.ndarray:
    """Mask of the feasible placements that no other feasible one dominates."""
    mask = evaluation.feasible.copy()
    mask[mask] = non_dominated(evaluation.values[mask] * signs)
    return mask
