"""Maps of an objective: evaluate a grid of placements, in parallel, and keep the result in a file.

A sweep varies any subset of the placement variables over a grid (the others fixed) and records,
for every grid point, the exact objective (electric energy by default), whether the placement is
feasible, and its tightest (or broken) limit. The grid is cut into chunks evaluated by worker
processes; any ``concurrent.futures.Executor`` can run them instead, such as a Dask client's
``get_executor(pure=False)`` or a Ray executor on a cluster, since each chunk carries its robot, path,
placements and the plug-in members registered at run time (all picklable).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from placement.contract.objective import OBJECTIVES
from placement.evaluation.evaluator import EvaluationJob, EvaluatorSettings, evaluate_job, members_used
from placement.evaluation.parallel import run_in_order
from placement.evaluation.results import Evaluation
from placement.exceptions import SettingsError
from placement.path.toolpath import ToolPath
from placement.placing.transform import VARIABLES
from placement.registry import runtime_members
from placement.robot.model import Robot

CHUNK_PLACEMENTS = 128  # placements per task


@dataclass(frozen=True)
class SweepResult:
    """A map of an objective over a grid of placements (SI units: m, rad, J, ...).

    Attributes:
        variables: Names of the swept variables, one per grid axis.
        axes: Values of each swept variable.
        fixed: (6,) values of the variables that are not swept.
        value: Grid of the objective (inf where a sample is unreachable).
        feasible: Grid of booleans: reachable and within every limit.
        tightest: Grid of indices into ``limits``: the tightest (or most broken) limit.
        limits: Labels of the limits ("kind: actuator or axis").
        robot, path, regeneration: What was swept.
        objective: The objective's name.
    """

    variables: tuple[str, ...]
    axes: tuple[np.ndarray, ...]
    fixed: np.ndarray
    value: np.ndarray
    feasible: np.ndarray
    tightest: np.ndarray
    limits: tuple[str, ...]
    robot: str
    path: str
    regeneration: str
    objective: str = "energy"

    def masked_value(self) -> np.ma.MaskedArray:
        """The objective with infeasible placements masked."""
        return np.ma.masked_array(np.where(self.feasible, self.value, 0.0), mask=~self.feasible)

    @property
    def label(self) -> str:
        """The objective with its unit, for axes and colour bars: 'electric energy (J)'."""
        objective = OBJECTIVES.get(self.objective)
        return f"{objective.title} ({objective.unit})"

    def best(self) -> int | None:
        """Index, in the grid's flattened order (:meth:`placements`), of the feasible placement best by the
        objective (the first of equals), or None when none is feasible."""
        if not self.feasible.any():
            return None
        signed = np.where(self.feasible, OBJECTIVES.get(self.objective).sign * self.value, np.inf).ravel()
        return int(np.argmin(signed))

    def placements(self) -> np.ndarray:
        """(n_points, 6) placement of every grid point, in the grid's flattened order."""
        mesh = np.meshgrid(*self.axes, indexing="ij")
        placements = np.tile(self.fixed, (mesh[0].size, 1))
        for name, coordinate in zip(self.variables, mesh, strict=True):
            placements[:, VARIABLES.index(name)] = coordinate.ravel()
        return placements

    def save(self, file: str | Path) -> None:
        """Write the map to an ``.npz`` file (reload with :meth:`load`)."""
        meta = {"variables": self.variables, "limits": self.limits, "robot": self.robot, "path": self.path,
                "regeneration": self.regeneration, "objective": self.objective}
        arrays = {"value": self.value, "feasible": self.feasible, "tightest": self.tightest, "fixed": self.fixed,
                  "meta": np.array(json.dumps(meta)), **{f"axis_{i}": axis for i, axis in enumerate(self.axes)}}
        np.savez_compressed(file, **arrays)  # type: ignore[arg-type]  # numpy's stub types **kwds as allow_pickle

    @classmethod
    def load(cls, file: str | Path) -> SweepResult:
        """Read a map written by :meth:`save`."""
        with np.load(file) as data:
            meta = json.loads(str(data["meta"]))
            return cls(variables=tuple(meta["variables"]),
                       axes=tuple(data[f"axis_{i}"] for i in range(len(meta["variables"]))),
                       fixed=data["fixed"], value=data["value" if "value" in data else "energy_J"],  # 0.1 maps: energy
                       feasible=data["feasible"], tightest=data["tightest"], limits=tuple(meta["limits"]),
                       robot=meta["robot"], path=meta["path"], regeneration=meta["regeneration"],
                       objective=meta.get("objective", "energy"))


def sweep(robot: Robot, path: ToolPath, axes: dict[str, np.ndarray], fixed: dict[str, float] | None = None, *,
          evaluation: EvaluatorSettings = EvaluatorSettings(), executor: Executor | None = None,
          progress: Callable[[int], None] | None = None) -> SweepResult:
    """Evaluate the exact objective over a grid of placements.

    Args:
        robot: The robot, as it is in memory (a plug-in module is re-loaded from its file).
        path: The tool path.
        axes: Swept variables and their values (m, rad), e.g. ``{"x": xs, "y": ys}``.
        fixed: Values of the other variables (default 0).
        evaluation: How placements are evaluated: one objective (default: electric energy),
            regeneration policy, path sampling step, ...; its workers are the worker processes of
            the default pool (default: every core; 1 runs in this process), each evaluating a
            chunk on one thread.
        executor: Any ``concurrent.futures.Executor`` to run the chunks instead of the default pool.
        progress: Called with the number of placements finished after each chunk.

    Returns:
        The map.
    """
    unknown = set(axes) - set(VARIABLES) | set(fixed or {}) - set(VARIABLES)
    if unknown:
        raise SettingsError(f"unknown placement variable(s) {sorted(unknown)}; expected some of {VARIABLES}")
    if len(evaluation.objectives) != 1:
        raise SettingsError(f"a sweep maps one objective, got {', '.join(evaluation.objectives)}")
    objective, regeneration = evaluation.objectives[0], evaluation.regeneration
    OBJECTIVES.get(objective)  # unknown names fail before any work
    variables = tuple(axes)
    values = tuple(np.asarray(axes[name], dtype=float) for name in variables)
    base = np.array([float((fixed or {}).get(name, 0.0)) for name in VARIABLES])
    grid = SweepResult(variables, values, base, np.zeros(0), np.zeros(0), np.zeros(0), (), robot.name, path.name,
                       regeneration, objective)
    placements = grid.placements()
    registered = runtime_members(members_used(robot, (objective,), regeneration, evaluation.method))
    jobs = [EvaluationJob(robot, path, evaluation, placements[i:i + CHUNK_PLACEMENTS], registered)
            for i in range(0, len(placements), CHUNK_PLACEMENTS)]
    results = run_in_order(evaluate_job, [(job,) for job in jobs], evaluation.workers or os.cpu_count() or 1, executor,
                           (lambda k: progress(len(jobs[k].placements))) if progress else None)
    shape = tuple(len(v) for v in values)
    evaluated = Evaluation.concatenate(results)
    return SweepResult(variables=variables, axes=values, fixed=base, value=evaluated.value.reshape(shape),
                       feasible=evaluated.feasible.reshape(shape),
                       tightest=evaluated.margins.argmin(axis=1).reshape(shape), limits=evaluated.limits,
                       robot=robot.name, path=path.name, regeneration=regeneration, objective=objective)

