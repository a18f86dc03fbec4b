"""The workbench's model, without a page: one path on one robot, evaluated live and exactly, and searched.

A :class:`Bench` holds the choices a user makes in the page (objective, regeneration policy,
timing law) and two evaluators built from them, as :func:`placement.search.optimize.optimize_placement`
builds them: the *live* one samples the path as coarsely as the search's global phase does (about
``SearchSettings.search_samples`` samples), for readings while a placement is dragged; the
*exact* one samples it at the path's own step, as ``--at`` does, so that its value is the number
``--at`` prints. A search runs in a process of its own (:class:`Search`): the page stays live,
its progress is reported per generation, and cancelling ends the process at once.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import queue
import threading
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.results import PlacementDetail
from placement.exceptions import PlacementError
from placement.limits.base import margin_fields, worst_margins
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.optimize import PlacementResult, SearchSettings, optimize_placement, search_sampling
from placement.search.space import PlacementSpace, default_space
from placement.timing.rules import check_timing, override_timing, timing_for


@dataclass(frozen=True)
class Reading:
    """One placement evaluated on the live (coarse) sampling.

    Attributes:
        placement: (6,) the placement (m, rad).
        value: The objective (inf where a sample is unreachable).
        feasible: Every sample reachable and every limit held.
        reachable: Every sample has a configuration.
        first_unreachable: The first sample without one (-1: none), and its time (s).
        tightest: The tightest limit's label ("kind: where") and its normalised margin.
        energy_per_actuator_J: (n_act,) electric energy of each actuator (NaN where unreachable).
        configuration: (N, nq) every joint at every live sample (the robot posed along the path).
        t_s: (N,) the live samples' times.
        tool_position_m: (N, 3) the placed path in the base frame.
    """

    placement: np.ndarray
    value: float
    feasible: bool
    reachable: bool
    first_unreachable: tuple[int, float]
    tightest: tuple[str, float]
    energy_per_actuator_J: np.ndarray
    configuration: np.ndarray
    t_s: np.ndarray
    tool_position_m: np.ndarray


@dataclass(frozen=True)
class Choices:
    """What the page lets the user choose: the objective, the regeneration policy and the timing law."""

    objective: str = "energy"
    regeneration: str = "clip"
    timing: str | None = None  # None: the path file's


class Bench:
    """One path on one robot: live and exact evaluations and searches under the user's choices.

    Args:
        robot: The robot.
        path: The path as loaded (its own timing law is the default).
        space: Free variables and bounds (default: the robot's, as the command line's).
        time_step_s: Sampling step of the exact evaluation (default: the path file's), as ``--time-step``.
        choices: The initial objective, regeneration and timing.
        search: The search's settings (seed, budget), as the command line's defaults.
    """

    def __init__(self, robot: Robot, path: ToolPath, space: PlacementSpace | None = None,
                 time_step_s: float | None = None, choices: Choices = Choices(),
                 search: SearchSettings = SearchSettings()) -> None:
        self.robot, self.source_path, self.time_step_s, self.search_settings = robot, path, time_step_s, search
        self.space = space or default_space(robot, half_turn=path.half_turn_symmetric())
        self.lock = threading.Lock()  # evaluators are not shared between threads
        self.note: str | None = None  # why the timing law is not the one chosen (an objective needs another)
        self.choose(choices)

    def choose(self, choices: Choices) -> None:
        """Rebuild the evaluators for new choices (a bad combination raises PlacementError and changes nothing)."""
        mode, self.note = timing_for([choices.objective], choices.timing, self.source_path)  # as the command line
        path = override_timing(self.source_path, mode)
        check_timing((choices.objective,), path)
        settings = EvaluatorSettings(objective=choices.objective, regeneration=choices.regeneration,
                                     time_step_s=self.time_step_s)
        exact = Evaluator(self.robot, path, settings)
        coarse, _ = search_sampling(path, settings, self.search_settings)
        live = Evaluator(self.robot, path, dataclasses.replace(coarse, workers=1))
        with self.lock:
            for old in (getattr(self, "live_evaluator", None), getattr(self, "exact_evaluator", None)):
                if old is not None:
                    old.close()
            self.choices, self.path, self.settings = choices, path, settings
            self.live_evaluator, self.exact_evaluator = live, exact

    def clamp(self, placement: np.ndarray) -> np.ndarray:
        """The placement with its free variables within their bounds and the others at their fixed values."""
        out = np.array(self.space.fixed, dtype=float)
        values = np.asarray(placement, dtype=float)
        out[self.space.indices] = np.clip(values[self.space.indices], self.space.lower, self.space.upper)
        return out

    def start(self) -> np.ndarray:
        """Where the page starts: the origin (the workspace's reference point) if the bounds hold it, else the
        middle of the bounds."""
        zero = self.clamp(np.zeros(6))
        if np.allclose(zero[self.space.indices], 0.0):
            return zero
        return self.clamp(self.space.full((self.space.lower + self.space.upper) / 2)[0])

    def live(self, placement: np.ndarray) -> Reading:
        """The placement on the live (coarse) sampling: objective, feasibility, tightest limit, energies, pose."""
        placement = _finite(placement)
        with self.lock:
            evaluator = self.live_evaluator
            batch = evaluator.batch(placement[None])
            margins, labels = worst_margins(margin_fields(batch))
            reachable = batch.reachable[0]
            value = float(evaluator.objective(batch)[0]) if reachable.all() else evaluator.objective.sign * np.inf
            energy = np.asarray(batch.energy.per_actuator_J[0], dtype=float)
        tight = int(np.argmin(margins[0])) if margins.shape[1] else -1
        missing = np.flatnonzero(~reachable)
        first = int(missing[0]) if len(missing) else -1
        t_s = evaluator.samples.t_s if batch.time_law is None else batch.time_law.timed_samples(evaluator.samples, 0).t_s
        return Reading(placement=placement, value=value, reachable=bool(reachable.all()),
                       feasible=bool(reachable.all() and (margins[0] >= 0).all()),
                       first_unreachable=(first, float(t_s[first]) if first >= 0 else float("nan")),
                       tightest=(labels[tight], float(margins[0, tight])) if tight >= 0 else ("", float("inf")),
                       energy_per_actuator_J=energy if reachable.all() else np.full(len(energy), np.nan),
                       configuration=batch.joints.q.reshape(len(t_s), -1), t_s=np.asarray(t_s),
                       tool_position_m=batch.tool_position_m[0])

    def exact(self, placement: np.ndarray) -> PlacementDetail:
        """The placement at the path's own sampling, every limit exact: the numbers ``--at`` prints."""
        placement = _finite(placement)
        with self.lock:
            return self.exact_evaluator.detail(placement)

    def search(self, best: bool, worst: bool) -> Search:
        """A search of the best and/or worst placement under the current choices, started in its own process."""
        settings = dataclasses.replace(self.search_settings, best=best, worst=worst)
        return Search(self.robot, self.path, self.space, self.settings, settings)

    def close(self) -> None:
        """Stop the evaluators' worker processes, if any."""
        with self.lock:
            self.live_evaluator.close()
            self.exact_evaluator.close()


def _finite(placement: np.ndarray) -> np.ndarray:
    values = np.asarray(placement, dtype=float).reshape(-1)
    if values.shape != (6,) or not np.isfinite(values).all():
        raise PlacementError("a placement is six finite numbers: x, y, z (m), phi, theta, psi (rad)")
    return values


class Search:
    """:func:`optimize_placement` in a process of its own (spawned: the page's threads are not copied).

    Its progress (generations done, of ``total``) and outcome are read with :meth:`poll`;
    :meth:`cancel` ends it at once.
    """

    def __init__(self, robot: Robot, path: ToolPath, space: PlacementSpace, evaluation: EvaluatorSettings,
                 settings: SearchSettings) -> None:
        context = multiprocessing.get_context("spawn")
        self.messages: multiprocessing.Queue = context.Queue()
        self.total = (settings.best + settings.worst) * settings.max_generations
        self.done = 0
        self.result: PlacementResult | None = None
        self.error: str | None = None
        self.process = context.Process(target=_run_search, args=(robot, path, space, evaluation, settings,
                                                                   self.messages), daemon=True)
        self.process.start()

    def poll(self, timeout_s: float = 0.2) -> bool:
        """Read what the search said; True once it has ended (with a result, an error or cancelled)."""
        try:
            while True:
                kind, payload = self.messages.get(timeout=timeout_s)
                timeout_s = 0.0
                if kind == "generation":
                    self.done += 1
                elif kind == "result":
                    self.result = payload
                elif kind == "error":
                    self.error = payload
        except queue.Empty:
            pass
        ended = self.result is not None or self.error is not None
        if not ended and not self.process.is_alive():
            self.error = self.error or "the search stopped"
            ended = True
        return ended

    def cancel(self) -> None:
        """End the search now."""
        if self.process.is_alive():
            self.process.terminate()
        self.process.join(timeout=10)
        self.error = self.error or "cancelled"

    def wait(self, on_progress: Callable[[int, int], None] | None = None) -> None:
        """Poll until the search ends, calling ``on_progress(done, total)`` as generations end."""
        while not self.poll():
            if on_progress is not None:
                on_progress(self.done, self.total)
        self.process.join(timeout=10)


def _run_search(robot: Robot, path: ToolPath, space: PlacementSpace, evaluation: EvaluatorSettings,
                settings: SearchSettings, messages: multiprocessing.Queue) -> None:
    """The search process: every generation and the outcome go to ``messages``."""
    try:
        result = optimize_placement(robot, path, space=space, evaluation=evaluation, settings=settings,
                                    progress=lambda: messages.put(("generation", None)))
        messages.put(("result", result))
    except PlacementError as error:
        messages.put(("error", str(error)))
    except Exception as error:  # the page says it; the server goes on
        messages.put(("error", f"unexpected {type(error).__name__}: {' '.join(str(error).split())[:300]}"))
