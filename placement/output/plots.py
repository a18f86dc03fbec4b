"""Figures of energy maps and placements (matplotlib): lengths in mm, angles in degrees.

Infeasible placements are masked: drawn in grey with hatching, never coloured as if they had an
energy.
"""

from __future__ import annotations

from placement.distribution import PLOTS, require

require(PLOTS)  # optional dependency: the [viz] extra; checked first, so that a missing one names the extra

import matplotlib  # noqa: E402

matplotlib.use("Agg")  # files only; no display needed

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402

from placement.contract.objective import OBJECTIVES  # noqa: E402
from placement.contract.objective import quantity as with_unit  # noqa: E402
from placement.evaluation.results import PlacementDetail  # noqa: E402
from placement.placing.profiles import is_closed, knot_shares, path_share, prismatic_joints  # noqa: E402
from placement.placing.transform import ANGLES  # noqa: E402
from placement.robot.model import Robot  # noqa: E402
from placement.search.feed import FeedStudy  # noqa: E402
from placement.search.pareto import ParetoFront  # noqa: E402
from placement.search.sweep import SweepResult  # noqa: E402
from placement.workshop.calibration import UNITS, Calibration  # noqa: E402

# Where a point's label may sit (points from the point), nearest first: diagonals, then the sides, farther and farther.
LABEL_OFFSETS_PT = [(sx * r, sy * r) for r in (5, 12, 22, 34, 48)
                    for sx, sy in ((1, 1), (1, -1), (-1, 1), (-1, -1), (1, 0), (-1, 0), (0, 1), (0, -1))]
LEADER = {"arrowstyle": "-", "color": "0.6", "linewidth": 0.5, "shrinkA": 0, "shrinkB": 3}  # to a label set apart
LABELS = {"x": "$x_{Op}$ (mm)", "y": "$y_{Op}$ (mm)", "z": "$z_{Op}$ (mm)", "phi": r"$\phi$ (deg)",
          "theta": r"$\theta$ (deg)", "psi": r"$\psi$ (deg)"}


def display_values(name: str, values: np.ndarray) -> np.ndarray:
    """SI values of a placement variable in display units (mm or degrees)."""
    return np.degrees(values) if name in ANGLES else np.asarray(values) * 1e3


def draw_map(ax: Axes, result: SweepResult, levels: int | np.ndarray = 12, title: str = "",
             color_range: tuple[float, float] | None = None):
    """Iso-contours of a two-variable map on ``ax``; returns the filled contour set (for a colour bar)."""
    if len(result.variables) != 2:
        raise ValueError("draw_map needs a map over two variables")
    (u_name, v_name), (u, v) = result.variables, result.axes
    uu, vv = np.meshgrid(display_values(u_name, u), display_values(v_name, v), indexing="ij")
    energy = result.masked_value()
    ax.set_facecolor("0.85")
    if (~result.feasible).any():
        ax.contourf(uu, vv, (~result.feasible).astype(float), levels=[0.5, 1.5], colors="none", hatches=["///"])
    filled = None
    if result.feasible.any():
        vmin, vmax = color_range or (energy.min(), energy.max())
        filled = ax.contourf(uu, vv, energy, levels=np.linspace(vmin, vmax, levels) if np.ndim(levels) == 0 else levels,
                             cmap="viridis", vmin=vmin, vmax=vmax, extend="both")
        lines = ax.contour(uu, vv, energy, levels=np.asarray(filled.levels)[::2], colors="k", linewidths=0.5)
        ax.clabel(lines, fmt=f"%.{label_decimals(np.asarray(lines.levels))}f", fontsize=7)
    ax.set_xlabel(LABELS[u_name])
    ax.set_ylabel(LABELS[v_name])
    ax.set_title(title, fontsize=10)
    return filled


def label_decimals(levels: np.ndarray) -> int:
    """Decimals that tell contour levels apart: one for levels a unit or more apart, more for closer ones."""
    steps = np.diff(levels)
    step = steps.min() if len(steps) and steps.min() > 0 else 1.0
    return max(1, int(np.ceil(-np.log10(step))) + 1)


def map_figure(result: SweepResult, title: str) -> Figure:
    """A one-panel figure of a two-variable map with its colour bar."""
    figure, ax = plt.subplots(figsize=(6.2, 5.0), constrained_layout=True)
    filled = draw_map(ax, result, title=title)
    if filled is not None:
        figure.colorbar(filled, ax=ax, label=result.label)
    figure.text(0.01, 0.005, "hatched: infeasible placements", fontsize=7, color="0.3", va="bottom")
    return figure


def calibration_figure(result: Calibration, actuators: list[str]) -> Figure:
    """Measured against predicted values over time, one panel per actuator and quantity; held-out part shaded."""
    panels = [(quantity, column, name) for quantity in sorted(result.measured) for column, name in enumerate(actuators)]
    columns = min(3, len(panels))
    rows = -(-len(panels) // columns)
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 2.8 * rows), squeeze=False,
                                constrained_layout=True)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    for ax, (quantity, column, name) in zip(axes.ravel(), panels, strict=False):
        ax.axvspan(result.t_s[result.split], result.t_s[-1], color="0.9", label="held out")
        ax.plot(result.t_s, result.measured[quantity][:, column], color="0.5", linewidth=0.8, label="measured")
        ax.plot(result.t_s, result.predicted[quantity][:, column], color="C0", linewidth=1.0, label="predicted")
        ax.set_title(f"{name}: {quantity}", fontsize=9)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"{quantity} ({UNITS[quantity]})")
    axes[0, 0].legend(fontsize=7)
    return figure


def feed_figure(study: FeedStudy, title: str) -> Figure:
    """Energy per part against time per part, one point per feed rate (labelled with the speed reached);
    broken limits hollow."""
    figure, ax = plt.subplots(figsize=(6.2, 4.4), constrained_layout=True)
    ax.plot(study.time_s, study.energy_J, color="0.6", linewidth=0.8)
    ax.scatter(study.time_s[study.feasible], study.energy_J[study.feasible], color="C0", zorder=3, label="limits hold")
    ax.scatter(study.time_s[~study.feasible], study.energy_J[~study.feasible], facecolors="none", edgecolors="C3",
               zorder=3, label="a limit is broken")
    ax.set_xlabel("time per part (s)")
    ax.set_ylabel("electric energy per part (J)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    labelled: dict[tuple[float, float], str] = {}
    for speed, t, e in zip(study.top_speed_m_s, study.time_s, study.energy_J, strict=True):
        if np.isfinite(e):  # feeds the timing law cannot reach give the same point: one label
            labelled.setdefault((round(float(t), 6), round(float(e), 6)), f"{speed:.2g} m/s")
    place_labels(ax, list(labelled), list(labelled.values()), ["black"] * len(labelled))
    return figure


def front_figure(front: ParetoFront, title: str) -> Figure:
    """The front, one panel per pair of objectives: members, the knee, and each objective's own optimum."""
    pairs = [(i, j) for i in range(len(front.objectives)) for j in range(i + 1, len(front.objectives))]
    figure, axes = plt.subplots(1, len(pairs), figsize=(6.2 * len(pairs), 4.6), constrained_layout=True, squeeze=False)
    values = np.array([member.values for member in front.members])
    labels = [_axis_label(name) for name in front.objectives]
    for ax, (i, j) in zip(axes[0], pairs):
        ax.plot(values[:, i], values[:, j], "o", color="C0", markersize=4, label="front (limits hold)")
        if front.knee is not None:
            ax.plot(*values[front.knee, [i, j]], "*", color="C1", markersize=14, label="knee")
        ends = [values[front.end(name)] for name in front.objectives]
        for k, (name, end) in enumerate(zip(front.objectives, ends, strict=True)):
            ax.plot(end[i], end[j], "s", markerfacecolor="none", markeredgecolor=f"C{k + 2}", markersize=11,
                    label=f"optimum of {name}")
        ax.set_xlabel(labels[i])
        ax.set_ylabel(labels[j])
        ax.legend(fontsize=8)
        place_labels(ax, [(end[i], end[j]) for end in ends],
                     [with_unit(front.optima[name], OBJECTIVES.get(name).unit) for name in front.objectives],
                     [f"C{k + 2}" for k in range(len(ends))])
    figure.suptitle(title, fontsize=10)
    return figure


def profiles_figure(robot: Robot, detail: PlacementDetail, title: str) -> Figure:
    """Each redundant joint's profile along the path (deg, or mm for a prismatic joint) against time, as the exact
    chain moved it, one panel per joint, its knots marked where they stand along the arc length."""
    joints = robot.redundant_joints
    figure, axes = plt.subplots(len(joints), 1, figsize=(6.4, 1.2 + 1.9 * len(joints)), sharex=True,
                                constrained_layout=True, squeeze=False)
    t = detail.samples.t_s
    share = path_share(detail.samples)[0]
    knot_t = np.interp(knot_shares(robot.profile_knots, is_closed(detail.samples)), share, t)
    prismatic = prismatic_joints(robot)
    for ax, joint, q in zip(axes[:, 0], joints, robot.redundant_q_indices, strict=True):
        scale, unit = (1e3, "mm") if joint in prismatic else (180 / np.pi, "deg")
        values = detail.configuration[:, q] * scale
        ax.plot(t, values, color="C0", linewidth=1.2)
        ax.plot(knot_t, np.interp(knot_t, t, values), "o", color="C1", markersize=5, label="knots")
        ax.set_ylabel(f"{joint} ({unit})")
        ax.grid(True, linewidth=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[-1, 0].set_xlabel("time along the path (s)")
    figure.suptitle(title, fontsize=10)
    return figure


def place_labels(ax: Axes, points: list[tuple[float, float]], texts: list[str], colors: list[str],
                 fontsize: float = 7) -> None:
    """Annotate points (data coordinates) so that no label overlaps another, the legend or a data point.

    Each label, in turn, takes the first of :data:`LABEL_OFFSETS_PT` around its point where its box,
    measured on the rendered figure, meets none of these and stays inside the axes; where none does,
    the first that stays clear of the other labels, else the farthest; a label set apart from its point
    has a thin line to it. Call it once the rest of the
    axes is drawn: the layout is settled first, and the labels take no part in it.
    """
    figure = ax.get_figure()
    assert isinstance(figure, Figure)
    figure.canvas.draw()  # settles the constrained layout: the boxes are measured where they will be drawn
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    frame = ax.get_window_extent(renderer)
    legend = ax.get_legend()
    marks = [Bbox.from_bounds(x - 3, y - 3, 6, 6) for x, y in ax.transData.transform(np.asarray(points).reshape(-1, 2))]
    taken: list[Bbox] = [legend.get_window_extent(renderer)] if legend is not None else []

    def label_at(point: tuple[float, float], text: str, color: str, offset: tuple[float, float]) -> Bbox:
        dx, dy = offset
        label = ax.annotate(text, point, textcoords="offset points", xytext=offset, fontsize=fontsize, color=color,
                            ha="left" if dx > 0 else "right" if dx < 0 else "center",
                            va="bottom" if dy > 0 else "top" if dy < 0 else "center",
                            arrowprops=None if max(abs(dx), abs(dy)) <= LABEL_OFFSETS_PT[0][0] else LEADER)
        label.set_in_layout(False)
        return label.get_window_extent(renderer)

    for point, text, color in zip(points, texts, colors, strict=True):
        fallback = None
        for offset in LABEL_OFFSETS_PT:
            box = label_at(point, text, color, offset)
            clear = not any(box.overlaps(other) for other in taken)
            if clear and _inside(box, frame) and not any(box.overlaps(mark) for mark in marks):
                break
            fallback = fallback or (offset if clear else None)
            ax.texts[-1].remove()
        else:
            box = label_at(point, text, color, fallback or LABEL_OFFSETS_PT[-1])
        taken.append(box)


def _inside(box: Bbox, frame: Bbox) -> bool:
    return frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1


def _axis_label(name: str) -> str:
    objective = OBJECTIVES.get(name)
    return f"{objective.title} ({objective.unit})" if objective.unit else objective.title


def save(figure: Figure, stem: str | object) -> list[str]:
    """Write ``stem``.png and ``stem``.svg; returns the file names."""
    names = [f"{stem}.png", f"{stem}.svg"]
    figure.savefig(names[0], dpi=130)
    figure.savefig(names[1])
    plt.close(figure)
    return names
