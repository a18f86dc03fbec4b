"""Searches of one path under several regeneration modes, sharing the exact chain (for examples/paper_table.py).

A regeneration mode (:mod:`placement.energy.regeneration`) only decides how braking power is counted: the
kinematics, dynamics, drives and limits of a placement are the same under every mode. :func:`optimize_modes`
runs each mode's search as :func:`placement.search.optimize.optimize_placement` would (the same global search,
polish, reported point and re-check, with the same seed: each mode's optimum is its own search's), but the chain
runs once per placement for every mode (:class:`SharedChain`): a placement that one mode's search evaluated
costs the others nothing. The global search's first generation is the same under every mode, and a mode whose
objective equals another's at every placement its search meets (``bus`` and ``signed`` when the drives' summed
power never turns negative) has its whole search for free.

The modes are searched in this process, one direction after the other.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings, batch_margins, batch_values
from placement.evaluation.results import Evaluation
from placement.exceptions import SettingsError
from placement.path.time_law import TimeLaw
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.coarse_guide import search_models
from placement.search.optimize import PlacementResult, SearchSettings, search_evaluators, search_sampling
from placement.search.space import PlacementSpace, default_space
from placement.timing.exceptions import TimingError


class SharedChain:
    """The objectives and margins of placements of one sampled path under several regeneration modes, each
    placement through the chain once.

    Args:
        chain: Evaluates the chain (its settings' sampling, objectives and margin; its regeneration mode is
            not used); in this process, without the optimal timing law.
        modes: The regeneration modes' names.
    """

    def __init__(self, chain: Evaluator, modes: Sequence[str]) -> None:
        if chain.geometry is not None:
            raise TimingError("a shared chain needs a timing law that times every placement alike, not 'optimal'")
        self.chain, self.modes = chain, tuple(modes)
        self.limits: tuple[str, ...] | None = None
        # placement bytes -> ((n_modes, n_objectives) values, (n_limits,) margins, reachable)
        self._rows: dict[bytes, tuple[np.ndarray, np.ndarray, bool]] = {}

    @property
    def evaluations(self) -> int:
        """Placements that went through the chain."""
        return self.chain.evaluations

    def evaluate(self, placements: np.ndarray, mode: str) -> Evaluation:
        """Objectives under ``mode`` and tightest margins of (K, 6) placements, as :meth:`Evaluator.evaluate`
        with that mode gives them; placements not met before go through the chain, in one batch."""
        index = self.modes.index(mode)
        keys = [placement.tobytes() for placement in placements]
        new = {key: placement for key, placement in zip(keys, placements) if key not in self._rows}
        if new:
            self._run(np.array(list(new.values())), list(new))
        assert self.limits is not None  # set by the first run
        rows = [self._rows[key] for key in keys]
        settings = self.chain.settings
        return Evaluation(placements=placements, objectives=settings.objectives,
                          values=np.array([values[index] for values, _, _ in rows]),
                          margins=np.array([margins for _, margins, _ in rows]), limits=self.limits,
                          reachable=np.array([reachable for *_, reachable in rows]), required_margin=settings.margin)

    def _run(self, placements: np.ndarray, keys: list[bytes]) -> None:
        """The chain once for ``placements``; every mode's objectives from its motor trace."""
        batch = self.chain.batch(placements)
        margins, self.limits, reachable = batch_margins(batch)
        by_placement = np.stack([batch_values(batch.under(mode), self.chain.objectives, reachable)
                                 for mode in self.modes], axis=1)  # (K, n_modes, n_objectives)
        for key, value, margin, ok in zip(keys, by_placement, margins, reachable, strict=True):
            self._rows[key] = (value, margin, bool(ok))


class ModeEvaluator(Evaluator):
    """An :class:`Evaluator` of one regeneration mode whose searches' evaluations go through a :class:`SharedChain`
    (its details and re-checks are its own)."""

    def __init__(self, robot: Robot, path: ToolPath, settings: EvaluatorSettings, shared: SharedChain) -> None:
        super().__init__(robot, path, settings)
        self.shared = shared

    def _evaluate_batch(self, placements: np.ndarray, law: TimeLaw | None = None) -> Evaluation:
        self.evaluations += len(placements)  # as asked for: the evaluations of the mode's own search
        return self.shared.evaluate(placements, self.settings.regeneration)


def optimize_modes(robot: Robot, path: ToolPath, modes: Sequence[str], *, space: PlacementSpace | None = None,
                   evaluation: EvaluatorSettings = EvaluatorSettings(),
                   settings: SearchSettings = SearchSettings()) -> dict[str, PlacementResult]:
    """Each regeneration mode's best (and worst) placement, as :func:`optimize_placement` finds it for that mode,
    with the chain shared among the modes (module docstring).

    Args:
        robot: The robot (its actuators need drives).
        path: The tool path, under a timing law that times every placement alike (not "optimal"), and short
            enough to be searched on itself (:mod:`placement.search.coarse_guide`).
        modes: The regeneration modes' names (``evaluation``'s own is not used).
        space: Free variables and bounds (default: :func:`placement.search.space.default_space`).
        evaluation: The objective, the path's sampling step and the threads, as for :func:`optimize_placement`;
            the evaluations run in this process.
        settings: Which directions to search, the search budget and seed.

    Returns:
        Each mode's result, by name.

    Raises:
        TimingError: The optimal timing law.
        SettingsError: A path searched on guides.
    """
    space = space or default_space(robot, half_turn=path.half_turn_symmetric())
    coarse, fine = (dataclasses.replace(each, workers=1) for each in search_sampling(path, evaluation, settings))
    coarse = dataclasses.replace(coarse, feasibility_only=True)  # differential evolution reads violations only
    if search_models(path, coarse, fine).guided:
        raise SettingsError(f"{path.name}: a path searched on guides cannot share its chain among modes")
    shared = [SharedChain(Evaluator(robot, path, each), modes) for each in (coarse, fine)]
    views = {mode: [ModeEvaluator(robot, path, dataclasses.replace(each, regeneration=mode), chain)
                    for each, chain in zip((coarse, fine), shared)] for mode in modes}
    found: dict[str, dict[str, PlacementResult]] = {mode: {} for mode in modes}
    for direction in ("best", "worst"):
        if not getattr(settings, direction):
            continue
        one_way = dataclasses.replace(settings, best=direction == "best", worst=direction == "worst")
        for mode in modes:
            global_search, polish = views[mode]
            found[mode][direction] = search_evaluators(global_search, polish, space, one_way)
    return {mode: _merged(results) for mode, results in found.items()}


def _merged(results: dict[str, PlacementResult]) -> PlacementResult:
    """One result from a mode's searches in each direction (the worst's added to the best's)."""
    best, worst = results.get("best"), results.get("worst")
    if best is None or worst is None:
        first = best or worst
        assert first is not None  # a direction at least was searched
        return first
    return dataclasses.replace(best, worst=worst.worst, infeasible=best.infeasible or worst.infeasible)
