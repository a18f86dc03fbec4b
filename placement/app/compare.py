"""The workbench's Compare and Export panels: a pinned placement beside the current one; the current one as JSON.

- **Compare**: *Pin* keeps the current placement's exact numbers (the objective, the energy and
  each actuator's, the tightest limit and its margin, the cycle time); they are shown beside the
  current placement's, with the difference, each time the current one changes.
- **Export**: the document ``--json`` writes with ``--at`` at the current placement (the very
  function the command line uses), shown in the page and sent to the browser as a download.
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from placement.app.numbers import number_html
from placement.app.panels import Host
from placement.contract.objective import OBJECTIVES
from placement.evaluation.results import PlacementDetail
from placement.output.report import json_text

EXPORT_FILE = "placement.json"


def numbers(detail: PlacementDetail, joints: list[str]) -> list[tuple[str, str, float]]:
    """(key, label with unit, value) of the numbers compared; NaN where the placement is unreachable."""
    reachable = detail.reachable
    rows = []
    if detail.objective != "energy":
        objective = OBJECTIVES.get(detail.objective)
        rows.append(("objective", f"{detail.objective} ({objective.unit})", float(detail.value)))
    rows.append(("energy", "energy (J)", float(detail.energy.total_J) if reachable else np.nan))
    for joint, energy in zip(joints, np.asarray(detail.energy.per_actuator_J, dtype=float)):
        rows.append((f"energy-{joint}", f"  {joint} (J)", float(energy) if reachable else np.nan))
    tight = min(detail.margins, key=lambda m: m.margin, default=None) if reachable else None
    rows.append(("margin", "margin (%)", tight.margin * 100 if tight is not None else np.nan))
    rows.append(("cycle-time", "cycle (s)", float(detail.duration_s) if reachable else np.nan))
    return rows


def relative_change_percent(before: float, now: float) -> float:
    """``now`` against ``before`` in % of ``before`` (NaN when ``before`` is 0 or either is not finite)."""
    if not (np.isfinite(before) and np.isfinite(now)) or before == 0.0:
        return float("nan")
    return 100.0 * (now - before) / abs(before)


def tightest_words(detail: PlacementDetail) -> str:
    """The tightest limit ("kind where"), or why there is none."""
    if not detail.reachable:
        return "unreachable"
    tight = min(detail.margins, key=lambda m: m.margin, default=None)
    return "none" if tight is None else f"{tight.kind} {tight.where}"


class ComparePanel:
    """Pin a placement; its numbers beside the current placement's, the difference (current - pinned) and that
    difference in % of the pinned value (for the margin, already a %: in points), each to five significant digits
    (in full in each cell's ``data-value``)."""

    def __init__(self, host: Host) -> None:
        gui: Any = host.server.gui
        self.host = host
        self.joints = [actuator.joint for actuator in host.bench.robot.actuators]
        self.pin_button = gui.add_button("Pin this placement")
        self.table = gui.add_html('<p style="font-size:12px">pin a placement to compare others with it</p>')
        self.pinned: PlacementDetail | None = None
        self.current: PlacementDetail | None = None
        self.pin_button.on_click(lambda _: host.guard(self.pin))

    def pin(self) -> None:
        """Keep the current placement's exact numbers."""
        self.pinned = self.host.bench.exact(self.host.placement)
        self.show(self.current or self.pinned)

    def forget(self) -> None:
        """The choices changed: the pinned numbers no longer answer them."""
        self.pinned = None
        self.table.content = '<p style="font-size:12px">pin a placement to compare others with it</p>'

    def show(self, current: PlacementDetail) -> None:
        """The current placement's numbers beside the pinned one's (nothing until one is pinned)."""
        self.current = current
        pinned = self.pinned
        if pinned is None:
            return
        rows = ["<tr><th></th><th>pinned</th><th>current</th><th>difference</th><th>%</th></tr>"]
        for (key, label, before), (_, _, now) in zip(numbers(pinned, self.joints), numbers(current, self.joints)):
            change = now - before if key == "margin" else relative_change_percent(before, now)
            cells = [number_html(f"compare-{key}-{column}", value) for column, value in
                     (("pinned", before), ("current", now), ("difference", now - before))]
            cells.append(number_html(f"compare-{key}-percent", change, "pts" if key == "margin" else "", digits=3))
            rows.append(f"<tr><td>{html.escape(label)}</td>{''.join(f'<td>{cell}</td>' for cell in cells)}</tr>")
        rows.append(f'<tr style="white-space:normal"><td>tightest</td><td>{html.escape(tightest_words(pinned))}</td>'
                    f"<td>{html.escape(tightest_words(current))}</td><td></td><td></td></tr>")
        self.table.content = f'<table id="compare" style="font-size:10px;white-space:nowrap">{"".join(rows)}</table>'


class ExportPanel:
    """The current placement's ``--json --at`` document, shown and downloaded."""

    def __init__(self, host: Host) -> None:
        gui: Any = host.server.gui
        self.host = host
        self.button = gui.add_button("Export JSON")
        self.text = gui.add_html("")
        self.document = ""
        self.button.on_click(lambda _: host.guard(self.export))

    def export(self) -> None:
        """Show the document and send it to every browser on the page as a download."""
        bench = self.host.bench
        self.document = json_text(bench.document(bench.exact(self.host.placement)))
        self.text.content = (f'<p style="font-size:11px">as <code>--json FILE --at ...</code> writes it; downloaded as '
                             f'{EXPORT_FILE}</p><pre id="export-json" style="max-height:220px;overflow:auto;'
                             f'font-size:10px">{html.escape(self.document)}</pre>')
        self.host.server.send_file_download(EXPORT_FILE, self.document.encode("utf-8"), save_immediately=True)
