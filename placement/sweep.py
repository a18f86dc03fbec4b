"""Energy maps: evaluate a grid of placements, in parallel, and keep the result in a file.

A sweep varies any subset of the placement variables over a grid (the others fixed) and records,
for every grid point, the exact energy, whether the placement is feasible, and its tightest (or
broken) limit. The grid is cut into chunks evaluated by worker processes; any
``concurrent.futures.Executor`` can run them instead, such as a Dask client's ``get_executor()``
or a Ray executor on a cluster, since each chunk carries its robot, path and placements (all
picklable) and returns plain arrays.
"""

from __future__ import annotations

import json
import os
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from placement.evaluation import evaluate_in_worker, single_threaded_rnea
from placement.exceptions import PlacementError
from placement.frames import VARIABLES
from placement.path import ToolPath
from placement.robot import Robot

CHUNK_PLACEMENTS = 128  # placements per task


@dataclass(frozen=True)
class SweepResult:
    """An energy map over a grid of placements (SI units: m, rad, J).

    Attributes:
        variables: Names of the swept variables, one per grid axis.
        axes: Values of each swept variable.
        fixed: (6,) values of the variables that are not swept.
        energy_J: Grid of energies (inf where a sample is unreachable).
        feasible: Grid of booleans: reachable and within every limit.
        tightest: Grid of indices into ``limits``: the tightest (or most broken) limit.
        limits: Labels of the limits ("kind: actuator or axis").
        robot, path, regeneration: What was swept.
    """

    variables: tuple[str, ...]
    axes: tuple[np.ndarray, ...]
    fixed: np.ndarray
    energy_J: np.ndarray
    feasible: np.ndarray
    tightest: np.ndarray
    limits: tuple[str, ...]
    robot: str
    path: str
    regeneration: str

    def masked_energy(self) -> np.ma.MaskedArray:
        """Energies with infeasible placements masked."""
        return np.ma.masked_array(np.where(self.feasible, self.energy_J, 0.0), mask=~self.feasible)

    def save(self, file: str | Path) -> None:
        """Write the map to an ``.npz`` file (reload with :meth:`load`)."""
        meta = {"variables": self.variables, "limits": self.limits, "robot": self.robot, "path": self.path,
                "regeneration": self.regeneration}
        np.savez_compressed(file, energy_J=self.energy_J, feasible=self.feasible, tightest=self.tightest,
                            fixed=self.fixed, meta=json.dumps(meta),
                            **{f"axis_{i}": axis for i, axis in enumerate(self.axes)})

    @classmethod
    def load(cls, file: str | Path) -> SweepResult:
        """Read a map written by :meth:`save`."""
        with np.load(file) as data:
            meta = json.loads(str(data["meta"]))
            return cls(variables=tuple(meta["variables"]),
                       axes=tuple(data[f"axis_{i}"] for i in range(len(meta["variables"]))),
                       fixed=data["fixed"], energy_J=data["energy_J"], feasible=data["feasible"],
                       tightest=data["tightest"], limits=tuple(meta["limits"]), robot=meta["robot"],
                       path=meta["path"], regeneration=meta["regeneration"])


def evaluate_chunk(robot: Robot, path: ToolPath, regeneration: str, time_step_s: float | None,
                   placements: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]:
    """Evaluate a chunk of placements (runs in a worker, with the robot as it is in memory).

    Returns:
        Energies, feasibility, index of the tightest limit, and the limit labels.
    """
    evaluation = evaluate_in_worker(robot, path, regeneration, time_step_s, "auto", placements)
    return evaluation.energy_J, evaluation.feasible, evaluation.margins.argmin(axis=1), evaluation.limits


def sweep(robot: Robot, path: ToolPath, axes: dict[str, np.ndarray], fixed: dict[str, float] | None = None,
          regeneration: str = "clip", time_step_s: float | None = None, workers: int | None = None,
          executor: Executor | None = None, progress: Callable[[int], None] | None = None) -> SweepResult:
    """Evaluate the exact energy over a grid of placements.

    Args:
        robot: The robot, as it is in memory (a plug-in module is re-loaded from its file).
        path: The tool path.
        axes: Swept variables and their values (m, rad), e.g. ``{"x": xs, "y": ys}``.
        fixed: Values of the other variables (default 0).
        regeneration: Regeneration mode, see :mod:`placement.energy`.
        time_step_s: Path sampling step (default: the path file's).
        workers: Worker processes of the default pool (default: every core; 1 runs in this process).
        executor: Any ``concurrent.futures.Executor`` to run the chunks instead of the default pool.
        progress: Called with the number of placements finished after each chunk.

    Returns:
        The map.
    """
    unknown = set(axes) - set(VARIABLES) | set(fixed or {}) - set(VARIABLES)
    if unknown:
        raise PlacementError(f"unknown placement variable(s) {sorted(unknown)}; expected some of {VARIABLES}")
    variables = tuple(axes)
    values = [np.asarray(axes[name], dtype=float) for name in variables]
    base = np.array([float((fixed or {}).get(name, 0.0)) for name in VARIABLES])
    mesh = np.meshgrid(*values, indexing="ij")
    placements = np.tile(base, (mesh[0].size, 1))
    for name, coordinate in zip(variables, mesh):
        placements[:, VARIABLES.index(name)] = coordinate.ravel()
    chunks = [placements[i:i + CHUNK_PLACEMENTS] for i in range(0, len(placements), CHUNK_PLACEMENTS)]
    jobs = [(robot, path, regeneration, time_step_s, chunk) for chunk in chunks]
    workers = workers or os.cpu_count() or 1
    if executor is None and workers == 1:
        results = []
        for job in jobs:
            results.append(evaluate_chunk(*job))
            if progress:
                progress(len(job[-1]))
    else:
        own = executor is None
        pool = executor or ProcessPoolExecutor(max_workers=workers, initializer=single_threaded_rnea)
        try:
            futures = {pool.submit(evaluate_chunk, *job): k for k, job in enumerate(jobs)}
            results = [None] * len(jobs)
            for future in as_completed(futures):
                results[futures[future]] = future.result()
                if progress:
                    progress(len(jobs[futures[future]][-1]))
        finally:
            if own:
                pool.shutdown()
    shape = tuple(len(v) for v in values)
    return SweepResult(variables=variables, axes=tuple(values), fixed=base,
                       energy_J=np.concatenate([r[0] for r in results]).reshape(shape),
                       feasible=np.concatenate([r[1] for r in results]).reshape(shape),
                       tightest=np.concatenate([r[2] for r in results]).reshape(shape),
                       limits=results[0][3], robot=robot.name, path=path.name, regeneration=regeneration)
