"""The workbench's long computations, each in a process of its own: searches, maps and Pareto fronts.

A :class:`Job` runs one of this module's tasks (:func:`search_task`, :func:`map_task`,
:func:`front_task`: the command line's own functions, ``optimize_placement``, ``sweep`` and
``pareto_front``) in a spawned process, so that the page stays live; its stage (what it does
before its first step: the process starting, the kernels loading or compiling, a first
evaluation timed), its progress (generations or placements done, of ``total``) and its outcome
are read with :meth:`Job.poll`, and :meth:`Job.cancel` ends it at once.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import queue
from collections.abc import Callable
from typing import Any

import numpy as np

from placement.evaluation.evaluator import EvaluatorSettings
from placement.exceptions import PlacementError
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.optimize import PlacementResult, SearchSettings, optimize_placement
from placement.search.pareto import ParetoFront, pareto_front
from placement.search.space import PlacementSpace
from placement.search.sweep import SweepResult, sweep

Progress = Callable[[int], None]  # called with the steps just done
Stage = Callable[[str], None]  # called with what the task does now, before its steps count
STARTING = "starting its process (Python, the robot)"
WARMING = "loading the compiled kernels (compiling them on first use) and timing a first evaluation"

LAST_WORDS_S = 0.5  # how long an ended task's last message is awaited


class Job:
    """A task in a process of its own (spawned: the page's threads are not copied).

    Args:
        task: A module-level function taking ``*args`` and a ``progress`` keyword (steps done).
        args: Its arguments (picklable).
        total: Steps of the whole task, for a progress bar.
    """

    def __init__(self, task: Callable[..., Any], args: tuple, total: int) -> None:
        context = multiprocessing.get_context("spawn")
        self.messages: multiprocessing.Queue = context.Queue()
        self.total, self.done = total, 0
        self.stage = STARTING  # what the task does before its first step
        self.result: Any = None
        self.error: str | None = None
        self.closed = False
        self.process = context.Process(target=_run, args=(task, args, self.messages), daemon=True)
        self.process.start()

    def poll(self, timeout_s: float = 0.2) -> bool:
        """Read what the task said; True once it has ended (with a result, an error or cancelled)."""
        self._read(timeout_s)
        ended = self.result is not None or self.error is not None
        if not ended and not self.process.is_alive():
            self._read(LAST_WORDS_S)  # what it said just before it ended may still be in the pipe
            if self.result is None and self.error is None:
                self.error = "the computation stopped"
            ended = True
        return ended

    def _read(self, timeout_s: float) -> None:
        """Take every message waiting (the first within ``timeout_s``); none once the queue is closed."""
        if self.closed:
            return
        try:
            while True:
                kind, payload = self.messages.get(timeout=timeout_s)
                timeout_s = 0.0
                if kind == "progress":
                    self.done += payload
                elif kind == "stage":
                    self.stage = payload
                elif kind == "result":
                    self.result = payload
                elif kind == "error":
                    self.error = payload
        except queue.Empty:
            pass

    def cancel(self) -> None:
        """End the task now."""
        self.error = self.error or "cancelled"
        if self.process.is_alive():
            self.process.terminate()
        self.process.join(timeout=10)
        self._close()

    def _close(self) -> None:
        """Release the queue's pipe and feeder thread."""
        self.closed = True
        self.messages.close()
        self.messages.join_thread()

    def wait(self, on_progress: Callable[[int, int], None] | None = None) -> None:
        """Poll until the task ends, calling ``on_progress(done, total)`` meanwhile."""
        while not self.poll():
            if on_progress is not None:
                on_progress(self.done, self.total)
        self.process.join(timeout=10)
        self._close()


def _run(task: Callable[..., Any], args: tuple, messages: multiprocessing.Queue) -> None:
    """The job's process: its progress and outcome go to ``messages``."""
    try:
        result = task(*args, progress=lambda steps: messages.put(("progress", steps)),
                      stage=lambda text: messages.put(("stage", text)))
        messages.put(("result", result))
    except PlacementError as error:
        messages.put(("error", str(error)))
    except Exception as error:  # the page says it; the server goes on
        messages.put(("error", f"unexpected {type(error).__name__}: {' '.join(str(error).split())[:300]}"))


def search_task(robot: Robot, path: ToolPath, space: PlacementSpace, evaluation: EvaluatorSettings,
                settings: SearchSettings, *, progress: Progress, stage: Stage) -> PlacementResult:
    """The command line's search (:func:`optimize_placement`), on the threads the command line's takes; progress:
    one step per generation; stage: the kernels warming, then the first population's scan with the time expected.

    Asked for both directions on a machine of two cores or more, the command line searches them at once, each in
    a process of its own on one core (:func:`placement.search.optimize.in_parallel`); this job's process is no
    main process, so it searches them one after the other, here too on one core each: the batched kinematics
    split a batch of placements among threads, and how it is split changes the last digits of each placement's
    numbers, and so the search's way (the UR5's best differed from the command line's by 3e-7 J and 1.3 mm).
    """
    if settings.best and settings.worst and (os.cpu_count() or 1) >= 2:
        evaluation = dataclasses.replace(evaluation, threads=1)
    stage(WARMING)
    return optimize_placement(robot, path, space=space, evaluation=evaluation, settings=settings,
                              progress=lambda: progress(1),
                              announce=lambda s: stage(f"scanning the first population (about {s:.0f} s in all)"))


def map_task(robot: Robot, path: ToolPath, axes: dict[str, np.ndarray], fixed: dict[str, float],
             evaluation: EvaluatorSettings, *, progress: Progress, stage: Stage) -> SweepResult:
    """The ``map`` command's sweep, in this one process; progress: placements evaluated; stage: the kernels
    warming."""
    stage(WARMING.split(" and ")[0])
    return sweep(robot, path, axes, fixed, evaluation=dataclasses.replace(evaluation, workers=1), progress=progress)


def front_task(robot: Robot, path: ToolPath, objectives: tuple[str, ...], space: PlacementSpace,
               evaluation: EvaluatorSettings, settings: SearchSettings, *, progress: Progress,
               stage: Stage) -> ParetoFront:
    """The Pareto front as ``--objectives`` searches it (:func:`pareto_front`); progress: one step per generation;
    stage: the kernels warming and the first generation."""
    stage(WARMING.split(" and ")[0] + ", then the first generation")
    return pareto_front(robot, path, objectives, space=space, evaluation=dataclasses.replace(evaluation, objective=objectives),
                        settings=settings, progress=lambda: progress(1))
