"""The main job with --objectives: the Pareto front of a path's placements, its report, JSON and plot."""

from __future__ import annotations

import argparse
import dataclasses
import sys

import numpy as np
from tqdm import tqdm

from placement.cli.exceptions import UsageError
from placement.contract.objective import OBJECTIVES, quantity
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.parallel import Cluster
from placement.evaluation.results import PlacementDetail
from placement.output.report import detail_json
from placement.path.toolpath import ToolPath
from placement.placing.values import angle_variable
from placement.robot.model import Robot
from placement.search.optimize import SearchSettings
from placement.search.pareto import ParetoFront, pareto_front
from placement.search.space import PlacementSpace


def parse_objectives(text: str) -> tuple[str, ...]:
    """The names given to --objectives: two or three known, different objectives."""
    names = _items(text)
    if not 2 <= len(names) <= 3 or len(set(names)) != len(names):
        raise UsageError(f"--objectives: expected two or three different objective names, e.g. energy,dexterity; "
                         f"got '{text}'")
    for name in names:
        OBJECTIVES.get(name)
    return names


def place_front(robot: Robot, path: ToolPath, space: PlacementSpace, args: argparse.Namespace,
                evaluation: EvaluatorSettings, settings: SearchSettings,
                remote: Cluster | None) -> tuple[dict, dict[str, PlacementDetail], str | None]:
    """Search the front of one path (on ``remote``, a Dask cluster, if given), print it, and return its JSON
    document and the members to draw; ``evaluation``'s objective is replaced by those of --objectives."""
    objectives = parse_objectives(args.objectives)
    evaluation = dataclasses.replace(evaluation, objective=objectives)
    searches = len(objectives) + 1  # each objective's optimum, then NSGA-II
    with tqdm(desc="searching the front", total=searches * settings.max_generations, unit=" generation",
              disable=args.quiet, file=sys.stderr, leave=False) as bar:
        front = pareto_front(robot, path, objectives, space=space, evaluation=evaluation, settings=settings,
                             progress=bar.update, executor=remote.executor if remote else None)
    document = {"objectives": list(objectives), "evaluations": front.evaluations}
    if front.infeasible:
        return document, {}, front.infeasible
    print("\n" + format_front(front))
    if args.png:
        from placement.output.plots import front_figure, save  # the [viz] extra (matplotlib, meshcat): imported only here

        names = save(front_figure(front, f"{path.name} on {robot.name}"), str(args.png).removesuffix(".png"))
        print(f"front plotted in {' and '.join(names)}")
    chosen = chosen_members(front, args.members)
    with Evaluator(robot, path, evaluation) as evaluator:
        details = {name: evaluator.detail(front.members[index].placement) for name, index in chosen.items()}
    document.update(front_json(front))
    document["drawn"] = {name: detail_json(robot, detail) for name, detail in details.items()}
    return document, details, None


def parse_members(text: str, objectives: tuple[str, ...]) -> tuple[str, ...]:
    """The names given to --members, checked before the search: knee, an objective of the front, or a number."""
    names = _items(text)
    for name in names:
        if not (name == "knee" or name in objectives or name.isdigit()):
            raise UsageError(f"--members: expected knee, an objective of the front ({', '.join(objectives)}) or a "
                             f"member number, got '{name[:40]}'")
    return names


def chosen_members(front: ParetoFront, text: str | None) -> dict[str, int]:
    """The members --members names ("knee", ends such as "energy", or indices), by label; default: knee and ends."""
    names = parse_members(text, front.objectives) if text else ("knee", *front.objectives)
    chosen = {}
    for name in names:
        if name == "knee" and front.knee is not None:
            chosen["knee"] = front.knee
        elif name in front.objectives:
            chosen[f"best {name}"] = front.end(name)
        elif name.isdigit() and int(name) < len(front.members):
            chosen[f"member {name}"] = int(name)
        else:
            raise UsageError(f"--members: expected knee, an objective of the front ({', '.join(front.objectives)}) "
                             f"or a member number below {len(front.members)}, got '{name}'")
    return chosen


def _items(text: str) -> tuple[str, ...]:
    return tuple(item.strip() for item in text.split(",") if item.strip())


def format_front(front: ParetoFront) -> str:
    """Text table of the front: every member's objectives and placement, the knee and the ends."""
    objectives = [OBJECTIVES.get(name) for name in front.objectives]
    free = front.space.free
    header = "  #  " + "".join(f"{name:>16s}" for name in front.objectives) + "".join(
        f"{name + (' deg' if angle_variable(name, front.space.lengths) else ' mm'):>12s}" for name in free) + "   margin"
    lines = [f"Pareto front: {len(front.members)} placements, none better than another on every objective "
             f"({front.evaluations:,} placements evaluated)", header]
    for index, member in enumerate(front.members):
        names = front.space.names
        shown = [np.degrees(member.placement[names.index(n)]) if angle_variable(n, front.space.lengths)
                 else member.placement[names.index(n)] * 1e3 for n in free]
        mark = "  knee" if index == front.knee else ""
        lines.append(f"  {index:<3d}" + "".join(f"{v:>16.4f}" for v in member.values)
                     + "".join(f"{v:>12.2f}" for v in shown) + f"   {member.margin * 100:5.1f} %{mark}")
    for name, objective in zip(front.objectives, objectives):
        end = front.members[front.end(name)].values[front.objectives.index(name)]
        gap = abs(end - front.optima[name]) / (abs(front.optima[name]) or 1.0)
        lines.append(f"  {name} end: member {front.end(name)}, {quantity(end, objective.unit)}; its own optimum "
                     f"{quantity(front.optima[name], objective.unit)} ({gap * 100:.3f} % apart)")
    dense = max(float(np.max(np.abs(m.recheck_values - m.values) / np.maximum(np.abs(m.values), 1e-300)))
                for m in front.members)
    lines.append(f"  4x denser sampling changes a member's objectives by at most {dense * 100:.3f} %")
    return "\n".join(lines)


def front_json(front: ParetoFront) -> dict:
    """JSON-ready front (SI units)."""
    return {"members": [{"placement": dict(zip(front.space.names, map(float, m.placement), strict=True)),
                         "values": dict(zip(front.objectives, map(float, m.values))),
                         "recheck_values": dict(zip(front.objectives, map(float, m.recheck_values))),
                         "margin": m.margin} for m in front.members],
            "knee": front.knee, "ends": {name: front.end(name) for name in front.objectives},
            "optima": {name: float(value) for name, value in front.optima.items()}}
