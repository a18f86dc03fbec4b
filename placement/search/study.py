"""Studies: every path on every robot, searched one pair at a time, gathered in one table.

A production engineer choosing a machine for a family of parts asks, for each robot and each
part: can it be done at all, how little energy does it take at the best placement, how much does
placing it well save, and how long does a part take. Each (robot, path) pair is one independent
search (:func:`placement.search.optimize.optimize_placement`, best and worst), run on an executor: the
local process pool, or a Dask cluster (:mod:`placement.evaluation.parallel`). A pair that cannot be placed,
or whose search fails on an input error, becomes a row that says why; it does not stop the study.
"""

from __future__ import annotations

import dataclasses
import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import EvaluatorSettings
from placement.evaluation.parallel import run_in_order
from placement.exceptions import PlacementError
from placement.path.toolpath import ToolPath
from placement.placing.transform import VARIABLES
from placement.robot.model import Robot
from placement.search.optimize import Optimum, SearchSettings, optimize_placement


@dataclass(frozen=True)
class StudyRow:
    """One (robot, path) pair of a study (SI units; NaN where there is no value).

    Attributes:
        robot, path: Names.
        objective: The objective's name: what the best and worst placements are ranked by.
        feasible: Whether some placement keeps every limit.
        best_value, worst_value: The objective at the best and worst feasible placements (its unit).
        best_energy_J, worst_energy_J: Energy per pass at those placements.
        gain: |worst − best| of the objective over the larger of the two (for energy: (worst − best)/worst);
            NaN unless both keep every limit on the 4x denser re-check too.
        cycle_time_s: Time per pass at the best placement (the optimal timing law times each
            placement on its own; the others, every placement alike); for an infeasible pair, the
            path's time at its feed.
        fastest_cycle_time_s: Under the optimal timing law, the least time per pass of any
            feasible placement (a search of its own); NaN under the others.
        x_m, y_m, z_m, phi_rad, theta_rad, psi_rad: The best placement.
        evaluations: Placements evaluated.
        search_s: Wall time of the search.
        reason: Why the pair is infeasible or failed ("" otherwise).
    """

    robot: str
    path: str
    objective: str
    feasible: bool
    best_value: float
    worst_value: float
    best_energy_J: float
    worst_energy_J: float
    gain: float
    cycle_time_s: float
    fastest_cycle_time_s: float
    x_m: float
    y_m: float
    z_m: float
    phi_rad: float
    theta_rad: float
    psi_rad: float
    evaluations: int
    search_s: float
    reason: str


def study_pair(robot: Robot, path: ToolPath, evaluation: EvaluatorSettings, settings: SearchSettings) -> StudyRow:
    """Search one pair (in a worker) as ``evaluation`` says (objective, regeneration, time step): its row, infeasible
    or failed pairs included."""
    tic = time.perf_counter()
    cycle, fastest = float(path.sample(evaluation.time_step_s).t_s[-1]), np.nan
    try:
        result = optimize_placement(robot, path, evaluation=evaluation, settings=settings)
    except PlacementError as error:
        return _row(robot, path, evaluation, (cycle, fastest), (None, None), np.full(6, np.nan), 0,
                    time.perf_counter() - tic, str(error))
    best, worst = result.best, result.worst
    reason = result.infeasible or ""
    if path.timing.mode == "optimal" and best is not None:
        try:
            quickest = optimize_placement(robot, path, evaluation=dataclasses.replace(evaluation, objective="cycle_time"),
                                          settings=dataclasses.replace(settings, worst=False)).best
            fastest = np.nan if quickest is None else quickest.detail.value
        except PlacementError as error:  # the energy's row stands; the fastest time says why it is missing
            reason = f"fastest cycle time: {error}"
    placement = best.detail.placement if best else np.full(6, np.nan)
    cycle = best.detail.duration_s if best else cycle
    evaluations = sum(o.evaluations for o in (best, worst) if o is not None)
    return _row(robot, path, evaluation, (cycle, fastest), (best, worst), placement, evaluations,
                time.perf_counter() - tic, reason, result.gain)


def _row(robot: Robot, path: ToolPath, evaluation: EvaluatorSettings, cycle_s: tuple[float, float],
         optima: tuple[Optimum | None, Optimum | None], placement: np.ndarray, evaluations: int, seconds: float,
         reason: str, gain: float | None = None) -> StudyRow:
    values = [np.nan if o is None else float(o.detail.value) for o in optima]
    energies = [np.nan if o is None else float(o.detail.energy.total_J) for o in optima]
    pose = dict(zip([f"{n}_m" if n in "xyz" else f"{n}_rad" for n in VARIABLES], map(float, placement)))
    return StudyRow(robot=robot.name, path=path.name, objective=str(evaluation.objective),
                    feasible=optima[0] is not None,
                    best_value=values[0], worst_value=values[1], best_energy_J=energies[0], worst_energy_J=energies[1],
                    gain=np.nan if gain is None else gain, cycle_time_s=cycle_s[0],
                    fastest_cycle_time_s=float(cycle_s[1]), evaluations=evaluations,
                    search_s=seconds, reason=reason, **pose)


def run_study(robots: Sequence[Robot], paths: Sequence[ToolPath], *, evaluation: EvaluatorSettings | None = None,
              settings: SearchSettings | None = None, executor: Executor | None = None, workers: int | None = None,
              progress: Callable[[], None] | None = None) -> list[StudyRow]:
    """Search every path on every robot.

    Args:
        robots, paths: The robots and the paths; every pair is searched.
        evaluation: What each search ranks placements by and how it samples the paths (objective, regeneration
            policy, time step; default: :class:`EvaluatorSettings`'s).
        settings: Budget and seed of each search (default: :class:`SearchSettings`'s).
        executor: Runs the searches (a Dask cluster's, see :mod:`placement.evaluation.parallel`); default: a
            local pool of ``workers`` processes, or this process when ``workers`` is 1.
        workers: Processes of the local pool (default: every core).
        progress: Called once per finished pair.

    Returns:
        One row per pair, robots in the given order, then paths.
    """
    settings = settings or SearchSettings()
    pairs = [(robot, path) for robot in robots for path in paths]
    tasks = [(robot, path, evaluation or EvaluatorSettings(), settings) for robot, path in pairs]
    return run_in_order(study_pair, tasks, workers or os.cpu_count() or 1, executor,
                        (lambda _: progress()) if progress else None)

