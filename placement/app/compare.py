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


def tightest_words(detail: PlacementDetail) -> str:
    """The tightest limit ("kind where"), or why there is none."""
    if not detail.reachable:
        return "unreachable"
    tight = min(detail.margins, key=lambda m: m.margin, default=None)
    return "none" if tight is None else f"{tight.kind} {tight.where}"


class ComparePanel:
    """Pin a placement; its numbers beside the current placement's, and the difference (current - pinned), to twelve
    significant digits."""

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
        rows = ["<tr><th></th><th>pinned</th><th>current</th><th>difference</th></tr>"]
        for (key, label, before), (_, _, now) in zip(numbers(pinned, self.joints), numbers(current, self.joints)):
            cells = (f'<td id="compare-{key}-{column}">{value:.12g}</td>' if np.isfinite(value) else
                     f'<td id="compare-{key}-{column}">-</td>'
                     for column, value in (("pinned", before), ("current", now), ("difference", now - before)))
            rows.append(f"<tr><td>{html.escape(label)}</td>{''.join(cells)}</tr>")
        rows.append(f'<tr style="white-space:normal"><td>tightest</td><td>{html.escape(tightest_words(pinned))}</td>'
                    f"<td>{html.escape(tightest_words(current))}</td><td></td></tr>")
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
