"""Search for the best (and worst) placements by an objective, within every limit.

Best is the objective's better direction (least energy, by default) and worst the other one, so
that the gain of placing well can be reported. Strategy, per direction: a global search by
scipy's differential evolution over the free placement variables, with the limits as constraints
(a feasible placement always beats an infeasible one, and infeasible ones are ranked by how far
they break the limits, so they steer the search and never stop it), on the path sampled with
about ``search_samples`` samples, its first population half the best points of a Sobol scan of the box that is the
same for every seed (a small feasible region at the box's edge, the pocket's best, is otherwise found on some
seeds only), half a sample of the seed's; then the same local constrained polish (SLSQP) on the global search's
sampling from the best point of each of a few distinct regions the global search visited and, for a redundant
arm, from the best of where those end flipped onto the other branch of its self-motion (the branches are then
compared converged, not as the global search left them, which favours the branch its population gathered on);
then the polish of the best distinct ends (whether or not they keep every limit on the finer
sampling: the polish brings them back), on the path sampled at its own time step, which the reported values use, and
the best of them on across the objective's kinks (gradient sampling, :mod:`placement.search.kinks`: where the drives'
clipped power crosses zero, SLSQP stops short); the distinct polished optima are the basins, and those close to the
best are reported beside it (:mod:`placement.search.basins`).
An angle whose range is its whole turn (or half of it, by the path's half-turn symmetry) is
periodic: the objective wraps it, and the polish is free to cross the range's edge (no bound
cuts through a basin there).
The two directions run at once, in a process and on a core each, where the machine and this
process allow it (:func:`in_parallel`). The reported optima are re-evaluated with a four times
denser sampling (under the optimal timing law, keeping the timing found), and the difference is
reported.

A reported optimum is a placement as the report prints it, so that the printed numbers, entered
again, are the same placement: the best printed one near the search's optimum (a search of the printed lattice,
:mod:`placement.search.lattice`), and it keeps every limit, with the required margin
(:class:`EvaluatorSettings` ``margin``), both on the path's own samples and on the four times
denser ones (:mod:`placement.search.reporting`); failing that, the next of the polished and global
candidates that does is reported instead, and the optimum says so.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing
import os
import time
from collections.abc import Callable
from concurrent.futures import Executor, wait
from dataclasses import dataclass
from multiprocessing.sharedctypes import Synchronized

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution
from scipy.stats import qmc

from placement.dynamics.inverse import openmp_started
from placement.evaluation.evaluator import EvaluationJob, Evaluator, EvaluatorSettings, denser
from placement.evaluation.parallel import process_pool
from placement.evaluation.results import Evaluation, PlacementDetail
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.basins import (
    COARSE_POLISHES,
    RUNNER_UP_SHARE,
    Basin,
    converged_starts,
    distinct,
    has_branches,
    scaled_distance,
    unresolved,
)
from placement.search.coarse_guide import SearchModels, guide_value, search_models
from placement.search.kinks import across_kinks
from placement.search.local import BASIN_RADIUS, POLISH_STARTS, Problem, inward_until_feasible, polish_across, signed_objective
from placement.search.reporting import binding, reported_point
from placement.search.space import PlacementSpace, default_space
from placement.search.tolerance import ToleranceBox, tolerance_box

GIVE_UP_GENERATIONS = 25  # generations without any feasible placement after which the search stops
SCAN_FACTOR = 8  # the first population's best half comes from a seed-free Sobol scan this many times its size
RECHECK_DENSITY = 4  # the re-check samples the path this many times more densely
POLISH_EVALUATIONS = 30  # placement evaluations of a typical polish, for the duration estimate (gradients count n + 1)


@dataclass(frozen=True)
class SearchSettings:
    """What the search looks for, and the budget of the global search (differential evolution) and of the polish.

    Attributes:
        population: Placements per generation of the global search (at least 5 per free variable,
            rounded up to a power of 2, as its Sobol initialisation needs).
        max_generations: Upper bound on generations.
        tolerance: Relative spread of the population's objective values at which the search stops.
        seed: Random seed; the same seed gives the same result.
        search_samples: Samples of the path during the global search, at most (a coarser
            sampling than the path's own when the path has more; the polish and the reported
            energies use the path's own).
        best, worst: Which directions to search: the best placement by the objective, the worst.
        box_within: The share of the objective (0.01: 1 %) that the tolerance box around each optimum keeps
            (:mod:`placement.search.tolerance`, found on the polish's model right after its direction's search,
            in its process), or None for no box.
        basin_share: The share of the objective within which other basins (distinct local optima) are reported
            beside each optimum (0.05: those at most 5 % worse).
    """

    population: int = 48
    max_generations: int = 80
    tolerance: float = 1e-3
    seed: int = 0
    search_samples: int = 64
    best: bool = True
    worst: bool = True
    box_within: float | None = None
    basin_share: float = RUNNER_UP_SHARE


@dataclass(frozen=True)
class Optimum:
    """The placement found in one direction.

    Attributes:
        detail: Objective, energy, margins and trace of the placement (at the path's sampling).
        recheck_value: The objective at the same placement with 4x denser path sampling.
        recheck_margin: The tightest normalised margin of every limit on that denser sampling
            (≥ 0: every limit holds between the path's own samples too).
        recheck_limit: Which limit that is ("kind: where"; "reachability: path" where a denser
            sample has no configuration).
        evaluations: Placements evaluated by the search.
        note: Why the reported placement is not the search's own optimum (which failed to keep
            every limit, with the margin, once printed or on the denser sampling), else None.
        guide_value: When guides steered the search (:mod:`placement.search.coarse_guide`), the objective at the
            same placement on the polish's guide, else None.
        tolerance: The tolerance box around it, when the search was asked for one (``SearchSettings.box_within``).
        basins: The other distinct local optima the search found within ``SearchSettings.basin_share`` of it, as
            printed, best first (:mod:`placement.search.basins`).
        basin_share: That share (0.05: basins at most 5 % worse are listed).
    """

    detail: PlacementDetail
    recheck_value: float
    recheck_margin: float
    recheck_limit: str
    evaluations: int
    note: str | None = None
    guide_value: float | None = None
    tolerance: ToleranceBox | None = None
    basins: tuple[Basin, ...] = ()
    basin_share: float = RUNNER_UP_SHARE

    @property
    def unresolved(self) -> tuple[Basin, ...]:
        """The other basins within the 4x denser re-check's resolution of this optimum: their objective differs from
        this one's by less than either one changes on the denser sampling, so the sampling may decide the ranking."""
        return tuple(b for b in self.basins if unresolved(self.detail.value, self.recheck_value, b))

    @property
    def holds(self) -> bool:
        """Whether every limit keeps the required margin on the denser sampling too, with a finite objective."""
        return (self.detail.feasible and self.recheck_margin >= self.detail.required_margin
                and bool(np.isfinite(self.recheck_value)))

    def __repr__(self) -> str:
        """A short summary: the placement's detail and the 4x denser re-check."""
        return (f"Optimum({self.detail!r}, 4x denser: {self.recheck_value:.6g}, tightest {self.recheck_limit} "
                f"{self.recheck_margin:.3g}, {self.evaluations} evaluations)")

    @property
    def guide_gap(self) -> float | None:
        """Relative difference of the guide's objective from the exact one at this placement (None: no guide)."""
        if self.guide_value is None:
            return None
        return (self.guide_value - self.detail.value) / (abs(self.detail.value) or 1.0)

    @property
    def sampling_gap(self) -> float:
        """Relative change of the objective when the path is sampled 4x more densely (absolute at 0)."""
        return abs(self.recheck_value - self.detail.value) / (abs(self.detail.value) or 1.0)


@dataclass(frozen=True)
class PlacementResult:
    """Outcome of :func:`optimize_placement` (SI units: m, rad, J, ...).

    Attributes:
        best: The best feasible placement by the objective, if asked for and one exists.
        worst: The worst feasible placement by the objective, if asked for and one exists.
        space: Free variables, bounds and fixed values of the search.
        objective: The objective's name.
        regeneration: Regeneration policy of the energies.
        infeasible: Why no feasible placement was found (the binding limit), else None.
        guide: The models that steered the search when they were guides (:mod:`placement.search.coarse_guide`), else None.
    """

    best: Optimum | None
    worst: Optimum | None
    space: PlacementSpace
    objective: str
    regeneration: str
    infeasible: str | None = None
    guide: SearchModels | None = None

    def __repr__(self) -> str:
        """A short summary: the best and worst objective values and the gain."""
        found = {label: f"{optimum.detail.value:.6g}" for label, optimum in (("best", self.best), ("worst", self.worst))
                 if optimum is not None}
        text = ", ".join(f"{label} {value}" for label, value in found.items()) or f"infeasible: {self.infeasible}"
        gain = f", gain {self.gain:.1%}" if self.gain is not None else ""
        return f"PlacementResult({self.objective}: {text}{gain})"

    @property
    def gain(self) -> float | None:
        """|best − worst| over the larger of the two (for energy: (E_max − E_min)/E_max), when both were
        computed, both keep every limit on the denser sampling too (:attr:`Optimum.holds`), and one is not zero."""
        if self.best is None or self.worst is None or not (self.best.holds and self.worst.holds):
            return None
        best, worst = self.best.detail.value, self.worst.detail.value
        larger = max(abs(best), abs(worst))
        return float(abs(worst - best) / larger) if larger else None


def _search(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, sign: float, settings: SearchSettings,
            progress: Callable[[], None] | None) -> tuple[list[np.ndarray], Problem, list[np.ndarray]]:
    """Global search on the coarse sampling, polish on the fine one, from the best point of each of a few distinct
    regions the global search visited (:mod:`placement.search.basins`).

    Returns:
        The feasible candidates, best first (by objective, on the polish's model): the polished points and the
        global search's final population's feasible ones (empty if there is none); the problem that explains why
        there is none: the coarse one when the global search found nothing feasible, else the fine one; and the
        distinct polished optima (the basins), best first.
    """
    problem = Problem(coarse, space, sign)
    population = _global(problem, space, settings, progress)
    values, margins = problem.lookup(population)
    feasible = (margins >= 0).all(axis=1) & np.isfinite(values)
    if not feasible.any():
        return [], problem, []
    ranked = population[feasible][np.argsort(sign * values[feasible])]
    local = Problem(fine, space, sign)
    fine_margins = local.lookup(ranked)[1]  # one batch
    kept = ranked[(fine_margins >= 0).all(axis=1)]
    # A start may break a limit on the finer sampling (a best region's optimum often lies on a limit): the polish
    # brings it back, and only the polished points that keep every limit there are candidates.
    polished = _feasible([polish_across(local, start, space) for start in converged_starts(problem, space)], local)
    if not polished and len(kept):
        polished = [polish_across(local, kept[0], space)]
    if not polished:  # the finer sampling breaks a limit the coarse one missed: repair the closest
        closest = ranked[np.argmin(np.clip(-fine_margins, 0.0, None).sum(axis=1))]
        repaired = inward_until_feasible(local, polish_across(local, closest, space), space)
        return ([] if repaired is None else [repaired]), local, ([] if repaired is None else [repaired])
    signed = [sign * local.lookup(x)[0][0] for x in polished]
    polished = [polished[k] for k in np.argsort(signed, kind="stable")]
    polished[0] = across_kinks(local, polished[0], space)  # the best: the polish's SLSQP stops on a kink
    signed = sorted(sign * local.lookup(x)[0][0] for x in polished)
    basins = [polished[k] for k in distinct(polished, signed, space, BASIN_RADIUS)]
    candidates = polished + list(kept)  # by objective: a best that fails once printed gives way to the next best, most
    # often a point of its own basin from the final population, not the next basin's optimum
    order = np.argsort(sign * local.lookup(np.array(candidates))[0], kind="stable")
    return [candidates[k] for k in order], local, basins


def _feasible(points: list[np.ndarray], problem: Problem) -> list[np.ndarray]:
    """The points that keep every limit on the problem's model, with a finite objective."""
    if not points:
        return []
    return [p for p, value in zip(points, signed_objective(problem, np.array(points))) if np.isfinite(value)]


def _global(problem: Problem, space: PlacementSpace, settings: SearchSettings,
            progress: Callable[[], None] | None) -> np.ndarray:
    """The global search (differential evolution, the limits as constraints): its final population (free values)."""
    bounds = list(zip(space.lower, space.upper))  # a periodic variable's edge is wrapped by the polish
    n_limits = problem.margins(space.lower[:, None]).shape[0]
    constraint = NonlinearConstraint(problem.margins, np.zeros(n_limits), np.full(n_limits, np.inf))

    generations = [0]

    def generation_done(intermediate_result: object) -> bool:  # scipy passes the result by this name
        generations[0] += 1
        if progress is not None:
            progress()
        return problem.best_feasible is None and generations[0] >= GIVE_UP_GENERATIONS

    result = differential_evolution(
        problem.objective, bounds, constraints=constraint, vectorized=True, updating="deferred",
        popsize=_popsize(settings, len(bounds)), maxiter=settings.max_generations, tol=settings.tolerance,
        polish=False, init=_scanned_population(problem, space, settings), rng=np.random.default_rng(settings.seed),
        callback=generation_done)
    return space.wrap(np.asarray(result.population))


def _scanned_population(problem: Problem, space: PlacementSpace, settings: SearchSettings) -> np.ndarray:
    """The global search's first population: the best of SCAN_FACTOR times as many points of a Sobol sequence over the
    box, the same for every seed (feasible ones by objective, then the others by how far they break the limits), and
    the rest of a scrambled Sobol sample of the seed's."""
    free = len(space.free)
    size = 2 ** int(np.ceil(np.log2(_popsize(settings, free) * free)))
    scan = space.lower + qmc.Sobol(free, scramble=False).random(SCAN_FACTOR * size) * (space.upper - space.lower)
    values, margins = problem.lookup(scan)
    violation = np.clip(-margins, 0.0, None).sum(axis=1)
    rank = np.lexsort((np.where(np.isfinite(values), problem.sign * values, np.inf), violation))
    own = space.lower + qmc.Sobol(free, rng=np.random.default_rng(settings.seed)).random(size) * (space.upper - space.lower)
    return np.vstack([scan[rank[:size // 2]], own[:size - size // 2]])


def _popsize(settings: SearchSettings, free: int) -> int:
    """Differential evolution's population per free variable (its population then rounds up to a power of 2,
    as its Sobol initialisation needs)."""
    return max(5, settings.population // free)


def search_sampling(path: ToolPath, evaluation: EvaluatorSettings,
                    settings: SearchSettings) -> tuple[EvaluatorSettings, EvaluatorSettings]:
    """The evaluator settings of a search's global phase, on about ``settings.search_samples`` samples of the path
    (never finer than its own step), and of its polish and reported values, at the path's own step."""
    step = evaluation.time_step_s if evaluation.time_step_s is not None else path.time_step_s
    duration = float(path.sample(step).t_s[-1])
    fine = dataclasses.replace(evaluation, time_step_s=step)
    return dataclasses.replace(fine, time_step_s=max(step, duration / settings.search_samples)), fine


def optimize_placement(robot: Robot, path: ToolPath, *, space: PlacementSpace | None = None,
                       evaluation: EvaluatorSettings = EvaluatorSettings(), settings: SearchSettings = SearchSettings(),
                       progress: Callable[[], None] | None = None,
                       announce: Callable[[float], None] | None = None,
                       executor: Executor | None = None) -> PlacementResult:
    """Find the best (and worst) feasible placement of a path on a robot by an objective.

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path.
        space: Free variables and bounds (default: :func:`placement.search.space.default_space`).
        evaluation: How placements are evaluated: the objective (default: electric energy; the
            first ranks, when several are given), regeneration policy, the path's sampling step
            (the polish's and the reported values'; the global search's is coarser), and the
            workers: chunks per batch of placements for ``executor`` (default: every core).
        settings: Which directions to search, the search budget and seed.
        progress: Called once per generation of the global search (for a progress bar).
        announce: Called with the expected duration (s) before the search starts.
        executor: Runs the evaluations in chunks (a Dask cluster's, see :mod:`placement.evaluation.parallel`);
            default: this process (or a local pool for a solver that is not vectorised).

    Returns:
        The optima (None in a direction not asked for), or, when no placement is feasible, the
        reason with the binding limit.
    """
    space = space or default_space(robot, half_turn=path.half_turn_symmetric())
    models = search_models(path, *search_sampling(path, evaluation, settings))
    directions = settings.best + settings.worst

    def evaluators(threads: int | None) -> tuple[Evaluator, Evaluator, Evaluator | None]:
        """The global search's, the polish's and, if those are guides, the exact one (no worker process starts
        before an evaluation)."""
        coarse, fine, exact = (dataclasses.replace(each, threads=threads or evaluation.threads)
                               for each in (models.coarse, models.polish, models.exact))
        coarse = dataclasses.replace(coarse, feasibility_only=True)  # differential evolution reads violations only
        return (Evaluator(robot, models.coarse_path, coarse, executor),
                Evaluator(robot, models.polish_path, fine, executor),
                Evaluator(robot, path, exact, executor) if models.guided else None)

    coarse, fine, exact = evaluators(None)
    at_once = in_parallel(coarse, fine, directions)
    if at_once:  # each direction takes a core: this process keeps to one, and starts no OpenMP threads (it forks)
        coarse, fine, exact = evaluators(1)
    with coarse, fine, exact if exact is not None else contextlib.nullcontext():
        if announce is not None:
            announce(estimate(coarse, fine, space, settings, 1 if at_once else directions))
        result = search_evaluators(coarse, fine, space, settings, progress, exact)
    return dataclasses.replace(result, guide=models) if models.guided else result


def estimate(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, settings: SearchSettings,
             directions: int) -> float:
    """Expected duration (s) of a search (the first population's scan, every generation and typical polishes), from
    one evaluation of a population on the search's sampling and one of a placement on the path's own (after a first
    evaluation, which may load the kinematics)."""
    rng = np.random.default_rng(settings.seed)
    size = 2 ** int(np.ceil(np.log2(_popsize(settings, len(space.free)) * len(space.free))))  # Sobol's, as scipy's
    population = space.full(rng.uniform(space.lower, space.upper, (size, len(space.free))))
    fine.evaluate(population[:1])
    tic = time.perf_counter()
    coarse.evaluate(population)
    generation = time.perf_counter() - tic
    tic = time.perf_counter()
    fine.evaluate(population[1:2])
    placement = time.perf_counter() - tic
    polish = POLISH_STARTS * POLISH_EVALUATIONS * placement * (1 + len(space.free) / 2)
    converging = COARSE_POLISHES * POLISH_EVALUATIONS * generation / size * (1 + len(space.free) / 2) * has_branches(space)
    scan_and_generations = (settings.max_generations + SCAN_FACTOR) * generation  # the scan: SCAN_FACTOR populations
    return directions * (scan_and_generations + converging + polish)


@dataclass(frozen=True)
class _Outcome:
    """One direction's search: its best point (None if no placement is feasible), the placements it evaluated,
    when none is feasible, why (the binding limit), why the point is not the search's own optimum, if not, its
    4x denser re-check, when guides steered the search, the polish's guide's value there, its tolerance box
    if one was asked for, and the other basins within the search's share of it."""

    x: np.ndarray | None
    evaluations: int
    infeasible: str | None
    note: str | None = None
    check: Evaluation | None = None
    guide_value: float | None = None
    box: ToleranceBox | None = None
    basins: tuple[Basin, ...] = ()


@dataclass(frozen=True)
class _DirectionJob:
    """One direction's search, to run in another process with evaluators like this one's (picklable)."""

    coarse: EvaluationJob  # the global search's evaluator, as a job without placements
    fine: EvaluationJob  # the polish's
    space: PlacementSpace
    sign: float
    settings: SearchSettings
    exact: EvaluationJob | None = None  # the path's own sampling, when the others are guides


_generations: Synchronized | None = None  # in a direction's process: generations done, shared with the parent


def _share_generations(counter: Synchronized) -> None:
    global _generations
    _generations = counter


def _count_generation() -> None:
    assert _generations is not None  # set by _share_generations when the process starts
    with _generations.get_lock():
        _generations.value += 1


def _search_direction(job: _DirectionJob) -> _Outcome:
    """A direction's search in a process of its own, on one core."""
    with job.coarse.evaluator() as coarse, job.fine.evaluator() as fine:
        if job.exact is None:
            return _outcome(coarse, fine, job.space, job.sign, job.settings, _count_generation)
        with job.exact.evaluator() as exact:
            return _outcome(coarse, fine, job.space, job.sign, job.settings, _count_generation, exact)


def _outcome(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, sign: float, settings: SearchSettings,
             progress: Callable[[], None] | None, exact: Evaluator | None = None) -> _Outcome:
    """One direction's search: global and polish on ``coarse`` and ``fine``, the reported point on ``exact``
    (``fine`` when None; else ``fine`` is a guide, see :mod:`placement.search.coarse_guide`)."""
    reported = fine if exact is None else exact
    before = coarse.evaluations + fine.evaluations + reported.evaluations * (exact is not None)
    candidates, problem, optima = _search(coarse, fine, space, sign, settings, progress)
    if not candidates:
        return _Outcome(None, coarse.evaluations + fine.evaluations - before, _binding_limit(problem, problem.evaluator))
    with denser(reported, RECHECK_DENSITY) as dense:
        guide_model = None if exact is None else fine
        x, note, check = reported_point(candidates, reported, dense, space, sign, guide_model)
        others = _other_basins(optima, x, problem, space, sign, settings.basin_share)
        basins = tuple(_printed_basin(other, reported, dense, space, sign, guide_model) for other in others)
        guide = None if exact is None else guide_value(fine, space.full(x))
        evaluations = coarse.evaluations + fine.evaluations + reported.evaluations * (exact is not None)
        evaluations += dense.evaluations - before
    box = None if settings.box_within is None else _box_around(fine, space, x, sign, settings.box_within, exact is not None)
    return _Outcome(x, evaluations, None, note, check, guide, box, basins)


def _other_basins(optima: list[np.ndarray], x: np.ndarray, problem: Problem, space: PlacementSpace, sign: float,
                  share: float) -> list[np.ndarray]:
    """The polished optima of basins other than the reported point ``x``'s whose objective (on the polish's model)
    is within ``share`` of the reported point's, best first."""
    reference = problem.lookup(x)[0][0]
    return [o for o in optima if scaled_distance(o, x, space) > BASIN_RADIUS
            and sign * (problem.lookup(o)[0][0] - reference) <= share * abs(reference)]


def _printed_basin(x: np.ndarray, reported: Evaluator, dense: Evaluator, space: PlacementSpace, sign: float,
                   guide: Evaluator | None) -> Basin:
    """A runner-up basin's optimum as the report prints it (:func:`reported_point`), with its objective on the
    path's own sampling and the denser one."""
    printed, note, check = reported_point([x], reported, dense, space, sign, guide, walk=False)
    placement = space.full(printed)[0]
    value = float(reported.evaluate(placement[None]).value[0])
    recheck = float(check.value[0]) if check is not None else float("nan")
    return Basin(placement=placement, value=value, recheck_value=recheck, holds=note is None)


def _box_around(fine: Evaluator, space: PlacementSpace, x: np.ndarray, sign: float, within: float,
                guided: bool) -> ToleranceBox:
    """The tolerance box around a direction's optimum ``x`` (free values) on the polish's model, which it reads for
    feasibility and values only."""
    settings = dataclasses.replace(fine.settings, feasibility_only=True)
    with Evaluator(fine.robot, fine.path, settings, fine.executor) as evaluator:
        box = tolerance_box(evaluator, space, space.full(x)[0], lower_is_better=sign > 0, within=within)
    return dataclasses.replace(box, guided=guided)


def in_parallel(coarse: Evaluator, fine: Evaluator, directions: int) -> bool:
    """Whether both directions are searched at once, a process each: when both are asked for, this machine has
    two cores, the evaluations run in this process, which is no pool's worker (a study's searches share the
    cores already), and it may fork (:func:`placement.dynamics.inverse.openmp_started`)."""
    here = all(e.executor is None and e.workers == 1 for e in (coarse, fine))
    main = multiprocessing.parent_process() is None
    return directions == 2 and (os.cpu_count() or 1) >= 2 and here and main and not openmp_started()


def _outcomes(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, signs: list[float], settings: SearchSettings,
              progress: Callable[[], None] | None, exact: Evaluator | None = None) -> list[_Outcome]:
    """Each direction's search: one after the other, or at once (:func:`in_parallel`)."""
    if not in_parallel(coarse, fine, len(signs)):
        outcomes = []
        for sign in signs:
            outcomes.append(_outcome(coarse, fine, space, sign, settings, progress, exact))
            if outcomes[-1].x is None:  # the feasible set is the same in both directions
                break
        return outcomes
    none = np.zeros((0, 6))
    jobs = [_DirectionJob(coarse.job(none), fine.job(none), space, sign, settings,
                          None if exact is None else exact.job(none)) for sign in signs]
    counter = multiprocessing.Value("i", 0)
    with process_pool(len(jobs), _share_generations, (counter,)) as pool:
        futures = [pool.submit(_search_direction, job) for job in jobs]
        shown = 0
        while shown < counter.value or not all(future.done() for future in futures):
            wait(futures, timeout=0.1)
            for _ in range(counter.value - shown):
                if progress is not None:
                    progress()
                shown += 1
        return [future.result() for future in futures]


def search_evaluators(coarse: Evaluator, fine: Evaluator, space: PlacementSpace, settings: SearchSettings,
                      progress: Callable[[], None] | None = None, exact: Evaluator | None = None) -> PlacementResult:
    """Both directions' searches on evaluators built by the caller: the global search on ``coarse``, the polish on
    ``fine``, and each optimum's detail on ``exact`` (``fine`` when None) and its 4x denser re-check.

    :func:`optimize_placement` builds the evaluators from a robot and a path (see :func:`search_sampling` for the
    sampling of each); a caller that shares work between searches (examples/regeneration_modes.py) builds its own.
    """
    evaluator = fine if exact is None else exact
    better = evaluator.objective.sign
    directions = [(name, sign) for name, sign, wanted in (("best", better, settings.best),
                                                           ("worst", -better, settings.worst)) if wanted]
    outcomes = _outcomes(coarse, fine, space, [sign for _, sign in directions], settings, progress, exact)
    found: dict[str, Optimum | None] = {"best": None, "worst": None}
    infeasible = next((o.infeasible for o in outcomes if o.x is None), None)
    for (direction, _), outcome in zip(directions, outcomes):
        if infeasible is not None or outcome.x is None:
            break
        before = evaluator.evaluations
        placement = space.full(outcome.x)[0]
        check = outcome.check
        if check is None:
            with denser(evaluator, RECHECK_DENSITY) as dense:
                check = dense.recheck(placement[None], evaluator)
        tightest = binding(check)
        found[direction] = Optimum(detail=evaluator.detail(placement), recheck_value=float(check.value[0]),
                                   recheck_margin=float(check.margins[0, tightest]),
                                   recheck_limit=check.limits[tightest],
                                   evaluations=outcome.evaluations + evaluator.evaluations - before, note=outcome.note,
                                   guide_value=outcome.guide_value, tolerance=outcome.box, basins=outcome.basins,
                                   basin_share=settings.basin_share)
    return PlacementResult(best=found["best"], worst=found["worst"], space=space, objective=evaluator.objective_name,
                           regeneration=evaluator.settings.regeneration, infeasible=infeasible)


def _binding_limit(problem: Problem, evaluator: Evaluator) -> str:
    """Describe the limit that the least infeasible placement found breaks the most."""
    if problem.least_infeasible is None:
        return "no placement could be evaluated"
    point = problem.least_infeasible[2]
    detail = evaluator.detail(problem.space.full(point)[0])
    if not detail.reachable:
        return (f"the path leaves the robot's reach at every placement tried ({len(detail.unreachable_samples)} "
                f"of {len(detail.samples)} samples unreachable at the closest one)")
    worst = min(detail.margins, key=lambda m: m.margin)
    value = abs(worst.value) if worst.kind in ("joint speed", "motor torque", "motor speed") else worst.value
    return (f"{worst.kind} ({worst.where}) is exceeded even at the least infeasible placement found: "
            f"{value:.4g} {worst.unit} against a limit of {worst.limit:.4g} {worst.unit}")
