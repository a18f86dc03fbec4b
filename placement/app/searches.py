"""The workbench's searches, each run in a process of its own: Optimise, Map and Front.

- **Optimise**: the command line's search of the best and/or worst placement; the optima become
  placements to go to, and are drawn in the scene as ghosts (:mod:`placement.app.ghosts`).
- **Map**: the ``map`` command's sweep through the current placement over two free variables,
  drawn as the command's figure, with its best cell to go to and the command line that gives
  the same map.
- **Front**: two objectives' Pareto front as ``--objectives`` searches it, drawn as its figure,
  each member to go to.
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from placement.app.evaluations import MAP_POINTS, shown_value
from placement.app.exceptions import NotReadyError
from placement.app.ghosts import Ghosts
from placement.app.heatmap import HeatMap
from placement.app.jobs import Job
from placement.app.numbers import number_html, readable
from placement.app.panels import Host, JobPanel, figure_image
from placement.contract.objective import OBJECTIVES, wording
from placement.evaluation.results import PlacementDetail
from placement.exceptions import SettingsError
from placement.placing.transform import VARIABLES
from placement.search.optimize import PlacementResult
from placement.search.pareto import ParetoFront
from placement.search.sweep import SweepResult

DIRECTIONS = ("best", "worst", "both")
BLANK = np.full((2, 2, 3), 255, dtype=np.uint8)  # an image not drawn yet


def _where(names: tuple[str, ...], placement: np.ndarray) -> str:
    """'x 12.50, phi 30.00' (mm, degrees) for the named variables of a placement."""
    return ", ".join(f"{name} {shown_value(name, placement[VARIABLES.index(name)]):.2f}" for name in names)


class OptimisePanel(JobPanel):
    """The best and/or worst placement under the page's choices; Go to best / Go to worst."""

    def __init__(self, host: Host) -> None:
        gui: Any = host.server.gui
        self.direction = gui.add_dropdown("direction", DIRECTIONS, initial_value="both")
        super().__init__(host, "Optimise", "search", "a search", "generations")
        self.optima: dict[str, PlacementDetail] = {}
        self.optima_html = gui.add_html("")
        self.buttons = {key: gui.add_button(f"Go to {key}", visible=False) for key in ("best", "worst")}
        for key, button in self.buttons.items():
            button.on_click(lambda _, key=key: host.guard(lambda: self.go_to(key)))
        self.ghosts = Ghosts(host.server, host.bench.robot)

    def launch(self) -> Job:
        direction = self.direction.value
        return self.host.bench.search(best=direction in ("best", "both"), worst=direction in ("worst", "both"))

    def finished(self, result: PlacementResult) -> None:
        words = wording(result.objective)
        unit = OBJECTIVES.get(result.objective).unit
        lines = []
        if result.infeasible:
            lines.append(f'<p style="color:#c00">no feasible placement: {html.escape(result.infeasible)}</p>')
        for key, optimum in (("best", result.best), ("worst", result.worst)):
            self.buttons[key].visible = optimum is not None
            self.ghosts.show(key, None if optimum is None else optimum.detail)
            if optimum is None:
                continue
            self.optima[key] = optimum.detail
            lines.append(f'<p>{key} ({html.escape(getattr(words, key))} {html.escape(words.subject)}): '
                         f'{number_html(f"{key}-value", optimum.detail.value, unit)}<br>'
                         f'<span id="{key}-placement">{_where(VARIABLES, optimum.detail.placement)}</span></p>')
        if result.gain is not None:
            lines.append(f'<p id="gain">gain {result.gain * 100:.1f} %</p>')
        self.optima_html.content = "".join(lines)
        self.say("done")

    def forget(self) -> None:
        """The choices changed: the optima found no longer answer them."""
        self.optima.clear()
        self.ghosts.clear()
        for button in self.buttons.values():
            button.visible = False
        self.optima_html.content = ""

    def go_to(self, key: str) -> None:
        """Go to the best or worst placement found."""
        if key not in self.optima:
            raise NotReadyError(f"no {key} placement yet: optimise first")
        self.host.set_placement(self.optima[key].placement, exact=True)
        self.host.frame_workpiece()


class MapPanel(JobPanel):
    """The objective over two free variables through the current placement, with its best cell to go to."""

    def __init__(self, host: Host) -> None:
        gui: Any = host.server.gui
        free = host.bench.space.free
        self.across = gui.add_dropdown("across", free, initial_value=free[0])
        self.up = gui.add_dropdown("up", free, initial_value=free[min(1, len(free) - 1)])
        self.points = gui.add_text("points per variable", "21", hint=f"a whole number from 2 to {MAP_POINTS}")
        super().__init__(host, "Map", "map", "a map", "placements")
        self.image = gui.add_image(BLANK, visible=False)
        self.best_html = gui.add_html("")
        self.go_button = gui.add_button("Go to the map's best", visible=False)
        self.go_button.on_click(lambda _: host.guard(self.go_to_best))
        self.best: np.ndarray | None = None
        self.command = ""
        self.through, self.plane = host.placement.copy(), ("", "")  # the placement the map went through, its axes
        self.heat_map = HeatMap(host.server, host.bench.robot.plane,
                                lambda placement: host.guard(lambda: host.set_placement(placement, exact=True)))

    def placement_moved(self, placement: np.ndarray) -> None:
        """Mark the map stale once the placement leaves its plane (a variable not mapped moved)."""
        self.heat_map.placement_moved(placement)
        off = [name for k, name in enumerate(VARIABLES) if name not in self.plane
               and abs(placement[k] - self.through[k]) > 1e-12]
        if off:
            self.mark_stale(f"the placement left the plane of this map ({', '.join(off)} moved)")

    def launch(self) -> Job:
        text = str(self.points.value).strip()
        try:
            points = float(text)
        except ValueError:
            points = float("nan")
        if not points.is_integer() or not 2 <= points <= MAP_POINTS:
            raise SettingsError(f"map: points per variable: expected a whole number from 2 to {MAP_POINTS}, "
                                f"got {text!r}")
        job, self.command = self.host.bench.map((self.across.value, self.up.value), int(points), self.host.placement)
        self.through, self.plane = self.host.placement.copy(), (self.across.value, self.up.value)
        return job

    def finished(self, result: SweepResult) -> None:
        words = wording(result.objective)
        unit = OBJECTIVES.get(result.objective).unit
        from placement.output.plots import map_figure  # the [viz] extra (matplotlib, meshcat): imported only here

        self.image.image = figure_image(map_figure(result, f"{result.path}: {words.subject} ({result.regeneration})"))
        self.image.visible = True
        in_scene = self.heat_map.show(result)
        self.heat_map.placement_moved(self.host.placement)
        index = result.best()
        self.best = None if index is None else result.placements()[index]
        self.go_button.visible = self.best is not None
        count = f"{int(result.feasible.sum())} of {result.feasible.size} placements feasible"
        best = "" if self.best is None else (
            f'<br>{html.escape(words.best)} {html.escape(words.subject)}: '
            f'{number_html("map-best-value", float(result.value.ravel()[index]), unit)} at '
            f'<span id="map-best-placement">{_where(result.variables, self.best)}</span>')
        scene = ("in the scene too: click a cell to go to it (best: black ball, current: magenta)" if in_scene
                 else "drawn here only: a map over an angle spans no plane of the scene")
        self.best_html.content = (f'<p>{count}{best}</p><p id="map-scene" style="font-size:11px">{scene}</p>'
                                  f'<p style="font-size:11px">the same map: '
                                  f'<code id="map-command">placement map --robot {html.escape(self.host.bench.robot.name)} '
                                  f'--path FILE {html.escape(self.command)}</code></p>')
        self.say("done")

    def go_to_best(self) -> None:
        """Go to the map's best placement."""
        if self.best is None:
            raise NotReadyError("no map with a feasible placement yet: map first")
        self.host.set_placement(self.best, exact=True)


class FrontPanel(JobPanel):
    """Two objectives' Pareto front, drawn, its members listed and each one to go to."""

    def __init__(self, host: Host) -> None:
        gui: Any = host.server.gui
        names = tuple(OBJECTIVES.names())
        self.first = gui.add_dropdown("first objective", names, initial_value="energy")
        self.second = gui.add_dropdown("second objective", names, initial_value="dexterity")
        super().__init__(host, "Search the front", "front", "a front", "generations")
        self.image = gui.add_image(BLANK, visible=False)
        self.table = gui.add_html("")
        self.member = gui.add_dropdown("member", ("none",), visible=False)
        self.go_button = gui.add_button("Go to member", visible=False)
        self.go_button.on_click(lambda _: host.guard(self.go_to_member))
        self.members: list[np.ndarray] = []

    def launch(self) -> Job:
        return self.host.bench.front((self.first.value, self.second.value))

    def finished(self, front: ParetoFront) -> None:
        from placement.output.plots import front_figure  # the [viz] extra (matplotlib, meshcat): imported only here

        if front.infeasible:
            self.say(f"no feasible placement: {front.infeasible}", error=True)
            return
        self.image.image = figure_image(front_figure(front, f"{self.host.bench.path.name} on {self.host.bench.robot.name}"))
        self.image.visible = True
        units = [OBJECTIVES.get(name).unit for name in front.objectives]
        head = "".join(f"<th>{html.escape(name)}{f' ({html.escape(u)})' if u else ''}</th>"
                       for name, u in zip(front.objectives, units))
        rows, labels = [], []
        for i, member in enumerate(front.members):
            knee = " (knee)" if i == front.knee else ""
            cells = "".join(f'<td>{number_html(f"front-{i}-{k}", float(v))}</td>' for k, v in enumerate(member.values))
            rows.append(f"<tr><td>{i}{knee}</td>{cells}</tr>")
            labels.append(f"{i}: " + ", ".join(f"{readable(float(v))} {u}".strip() for v, u in zip(member.values, units))
                          + knee)
        self.table.content = (f'<table id="front-table" style="font-size:11px"><tr><th>#</th>{head}</tr>'
                              + "".join(rows) + "</table>")
        self.members = [member.placement for member in front.members]
        self.member.options = tuple(labels)
        self.member.value = labels[front.knee if front.knee is not None else 0]
        self.member.visible = self.go_button.visible = True
        self.say(f"done: {len(labels)} members")

    def go_to_member(self) -> None:
        """Go to the member chosen."""
        if self.member.value not in self.member.options or not self.members:
            raise NotReadyError("no front yet: search the front first")
        self.host.set_placement(self.members[self.member.options.index(self.member.value)], exact=True)
