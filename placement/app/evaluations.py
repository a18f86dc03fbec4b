"""The workbench's model, without a page: one path on one robot, evaluated live and exactly, and searched.

A :class:`Bench` holds the choices a user makes in the page (objective, regeneration policy,
timing law) and two evaluators built from them, as :func:`placement.search.optimize.optimize_placement`
builds them: the *live* one samples the path as coarsely as the search's global phase does (about
``SearchSettings.search_samples`` samples), for readings while a placement is dragged; the
*exact* one samples it at the path's own step, as ``--at`` does, so that its value is the number
``--at`` prints. A search, a map or a Pareto front runs in a process of its own
(:class:`placement.app.jobs.Job`): the page stays live, its progress is reported, and cancelling
ends the process at once.
"""

from __future__ import annotations

import dataclasses
import threading
from dataclasses import dataclass

import numpy as np

from placement.app.jobs import Job, front_task, map_task, search_task
from placement.contract.limit import margin_fields, worst_margins
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.results import PlacementDetail
from placement.exceptions import SettingsError
from placement.output.report import detail_json, job_document
from placement.path.toolpath import ToolPath
from placement.placing.transform import ANGLES, VARIABLES
from placement.robot.model import Robot
from placement.search.optimize import SearchSettings, search_sampling
from placement.search.space import PlacementSpace, default_space
from placement.timing.rules import check_timing, override_timing, timing_for

MAP_POINTS = 101  # values per variable of a map, at most


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
        tightest_sample: The live sample where the tightest limit is tightest (-1: that limit is no sample's,
            such as a motor's RMS over the pass, or there is none).
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
    tightest_sample: int = -1


@dataclass(frozen=True)
class Choices:
    """What the page lets the user choose: the objective, the regeneration policy and the timing law."""

    objective: str = "energy"
    regeneration: str = "clip"
    timing: str | None = None  # None: the path file's


class Bench:
    """One path on one robot: live and exact evaluations, searches, maps and fronts under the user's choices.

    Args:
        robot: The robot.
        path: The path as loaded (its own timing law is the default).
        space: Free variables and bounds (default: the robot's, as the command line's).
        time_step_s: Sampling step of the exact evaluation (default: the path file's), as ``--time-step``.
        choices: The initial objective, regeneration and timing.
        search: The search's settings (seed, budget), as the command line's defaults.
        margin: The share (0 to 1) of every limit a feasible placement keeps free, as ``--margin`` / 100.
    """

    def __init__(self, robot: Robot, path: ToolPath, space: PlacementSpace | None = None,
                 time_step_s: float | None = None, choices: Choices = Choices(),
                 search: SearchSettings = SearchSettings(), margin: float = 0.0) -> None:
        self.robot, self.source_path, self.time_step_s, self.search_settings = robot, path, time_step_s, search
        self.margin = margin
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
                                     time_step_s=self.time_step_s, margin=self.margin)
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
        """The placement with its free variables within their bounds and the others at their fixed values; a
        placement of the six variables only takes a redundant robot's knots and spin from the space's fixed values
        (the page edits the six)."""
        out = np.array(self.space.fixed, dtype=float)
        values = np.asarray(placement, dtype=float)
        values = np.concatenate([values, out[len(values):]])
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
        """The placement on the live (coarse) sampling: objective, feasibility (keeping the margin), tightest limit,
        energies, pose."""
        placement = _finite(placement)
        with self.lock:
            evaluator = self.live_evaluator
            batch = evaluator.batch(placement[None])
            fields = margin_fields(batch)
            margins, labels = worst_margins(fields)
            reachable = batch.reachable[0]
            value = float(evaluator.objective(batch)[0]) if reachable.all() else evaluator.objective.sign * np.inf
            energy = np.asarray(batch.energy.per_actuator_J[0], dtype=float)
        tight = int(np.argmin(margins[0])) if margins.shape[1] else -1
        missing = np.flatnonzero(~reachable)
        first = int(missing[0]) if len(missing) else -1
        t_s = evaluator.samples.t_s if batch.time_law is None else batch.time_law.timed_samples(evaluator.samples, 0).t_s
        return Reading(placement=placement, value=value, reachable=bool(reachable.all()),
                       feasible=bool(reachable.all() and (margins[0] >= self.margin).all()),
                       first_unreachable=(first, float(t_s[first]) if first >= 0 else float("nan")),
                       tightest=(labels[tight], float(margins[0, tight])) if tight >= 0 else ("", float("inf")),
                       energy_per_actuator_J=energy if reachable.all() else np.full(len(energy), np.nan),
                       configuration=batch.joints.q.reshape(len(t_s), -1), t_s=np.asarray(t_s),
                       tool_position_m=batch.tool_position_m[0], tightest_sample=_sample_of(fields, tight, len(t_s)))

    def exact(self, placement: np.ndarray) -> PlacementDetail:
        """The placement at the path's own sampling, every limit exact: the numbers ``--at`` prints."""
        placement = _finite(placement)
        with self.lock:
            return self.exact_evaluator.detail(placement)

    def document(self, detail: PlacementDetail) -> dict:
        """The JSON document ``--json`` writes with ``--at`` at the detail's placement."""
        document = job_document(self.robot, self.path, self.settings, len(self.path.sample(self.time_step_s)))
        document["at"] = detail_json(self.robot, detail)
        return document

    def search(self, best: bool, worst: bool) -> Job:
        """A search of the best and/or worst placement under the current choices, started in its own process;
        its steps are generations."""
        settings = dataclasses.replace(self.search_settings, best=best, worst=worst)
        return Job(search_task, (self.robot, self.path, self.space, self.settings, settings),
                   (best + worst) * settings.max_generations)

    def map(self, variables: tuple[str, str], points: int, placement: np.ndarray) -> tuple[Job, str]:
        """A map of the objective through ``placement`` over two free variables, their bounds cut in ``points``
        values each, started in its own process (steps: placements); also its grid as ``map`` takes it
        (``--grid ... --fix ...``)."""
        u, v = variables
        free = self.space.free
        if u == v or u not in free or v not in free:
            raise SettingsError(f"map: choose two different free variables ({', '.join(free)}), got {u} and {v}")
        if not 2 <= points <= MAP_POINTS:
            raise SettingsError(f"map: points per variable: expected a whole number from 2 to {MAP_POINTS}, got {points}")
        placement = _finite(placement)
        axes, grid = {}, []
        for name in variables:
            k = free.index(name)
            low, high = shown_value(name, self.space.lower[k]), shown_value(name, self.space.upper[k])
            axes[name] = np.linspace(low, high, points) * (np.pi / 180 if name in ANGLES else 1e-3)  # as --grid reads it
            grid.append(f"{name}={low!r}:{high!r}:{points}")
        fixed = {name: float(placement[k]) for k, name in enumerate(VARIABLES) if name not in variables}
        fix = ",".join(f"{name}={value!r}{'rad' if name in ANGLES else 'm'}" for name, value in fixed.items())
        job = Job(map_task, (self.robot, self.path, axes, fixed, self.settings), points * points)
        options = [f"--grid {','.join(grid)}", f"--fix {fix}", f"--objective {self.choices.objective}",
                   f"--regen {self.choices.regeneration}"]
        options += [f"--timing {self.path.timing.mode}"] if self.path is not self.source_path else []
        options += [f"--time-step {self.time_step_s!r}"] if self.time_step_s is not None else []
        options += [f"--margin {self.margin * 100!r}"] if self.margin else []
        return job, " ".join(options)

    def front(self, objectives: tuple[str, str]) -> Job:
        """The Pareto front of two objectives, as ``--objectives`` searches it, started in its own process (steps:
        generations); the path timed by the law they need."""
        if len(set(objectives)) != 2:
            raise SettingsError(f"front: choose two different objectives, got {' and '.join(objectives)}")
        mode, _ = timing_for(objectives, self.choices.timing, self.source_path)
        path = override_timing(self.source_path, mode)
        settings = dataclasses.replace(self.settings, objective=objectives)
        return Job(front_task, (self.robot, path, objectives, self.space, settings, self.search_settings),
                   (len(objectives) + 1) * self.search_settings.max_generations)

    def close(self) -> None:
        """Stop the evaluators' worker processes, if any."""
        with self.lock:
            self.live_evaluator.close()
            self.exact_evaluator.close()


def shown_value(name: str, value: float) -> float:
    """A placement variable (m, rad) as the page and the command line show it (mm, degrees)."""
    return float(np.degrees(value)) if name in ANGLES else float(value) * 1e3


def si_value(name: str, shown: float) -> float:
    """A value typed in the page (mm, degrees) in SI units (m, rad)."""
    return float(np.radians(shown)) if name in ANGLES else float(shown) / 1e3


def _sample_of(fields: list, column: int, samples: int) -> int:
    """The sample where the margin in ``column`` of :func:`worst_margins` is least for the first placement (-1: the
    column is no sample's, or there is none)."""
    if column < 0:
        return -1
    for field in fields:
        margin = np.asarray(field.margin)
        if column < margin.shape[2]:
            return int(np.argmin(margin[0, :, column])) if margin.shape[1] == samples else -1
        column -= margin.shape[2]
    return -1


def _finite(placement: np.ndarray) -> np.ndarray:
    values = np.asarray(placement, dtype=float).reshape(-1)
    if values.shape != (6,) or not np.isfinite(values).all():
        raise SettingsError("a placement is six finite numbers: x, y, z (m), phi, theta, psi (rad)")
    return values
