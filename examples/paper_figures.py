"""Draw the paper's figures with the exact model: energy maps, E_min / E_max vs size, comparison.

Writes PNG and SVG files to docs/figures/ (or --out): the Orthoglide, the paper's 30 x 60 mm
groove at 0.66 m/s, per-axis clipping (the default regeneration mode), paper timing law. The README's
3-D scenes come from examples/readme_scenes.py.

Usage: python examples/paper_figures.py [--out docs/figures] [--grid 41] [--workers N]
"""

from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from paper_table import PAPER, WIDTHS_MM, run_case

from placement import EvaluatorSettings, load_path, load_robot, optimize_placement
from placement.output.plots import draw_map, map_figure, save
from placement.search.sweep import sweep

EXAMPLE = Path(__file__).with_name("rect.yaml")


def panels(results, titles, suptitle):
    """Side-by-side maps sharing one colour scale."""
    feasible = np.concatenate([r.value[r.feasible] for r in results])
    color_range = (feasible.min(), feasible.max())
    figure, axes = plt.subplots(1, len(results), figsize=(4.2 * len(results), 4.0), constrained_layout=True,
                                squeeze=False)
    filled = None
    for ax, result, title in zip(axes[0], results, titles):
        filled = draw_map(ax, result, title=title, color_range=color_range) or filled
    figure.colorbar(filled, ax=axes[0].tolist(), label="electric energy (J)", shrink=0.9)
    figure.suptitle(suptitle)
    return figure


def comparison(robot, best, worst):
    """Bar charts of stroke, peak speed, peak motor torque and energy per actuator at E_min, E_max."""
    names = [a.joint for a in robot.actuators]
    quantities = [("stroke (mm)", lambda d: np.ptp(d.position, axis=0) * 1e3),
                  ("peak speed (m/s)", lambda d: np.abs(d.velocity).max(axis=0)),
                  ("peak motor torque (N m)", lambda d: np.abs(d.motor.torque_Nm).max(axis=0)),
                  ("energy (J)", lambda d: d.energy.per_actuator_J)]
    figure, axes = plt.subplots(1, 4, figsize=(14, 3.6), constrained_layout=True)
    index = np.arange(len(names))
    for ax, (label, value) in zip(axes, quantities):
        ax.bar(index - 0.2, value(best), 0.4, label="$E_{min}$ placement", color="tab:green")
        ax.bar(index + 0.2, value(worst), 0.4, label="$E_{max}$ placement", color="tab:red")
        ax.set_xticks(index, names)
        ax.set_title(label, fontsize=10)
    axes[0].legend(fontsize=8)
    figure.suptitle("30 mm x 60 mm path: actuators at the least- and most-energy placements")
    return figure


def size_figure(results):
    """E_min, E_max and the saving against the rectangle's width, ours beside the paper's."""
    rows = sorted(results, key=lambda r: r["width"])
    widths = [r["width"] for r in rows]
    figure, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    ax.plot(widths, [r["min"]["energy"] for r in rows], "o-", color="tab:green", label="$E_{min}$ (this model)")
    ax.plot(widths, [r["max"]["energy"] for r in rows], "o-", color="tab:red", label="$E_{max}$ (this model)")
    ax.plot(widths, [PAPER[w][0] for w in widths], "s--", color="tab:green", alpha=0.5, label="$E_{min}$ (paper)")
    ax.plot(widths, [PAPER[w][1] for w in widths], "s--", color="tab:red", alpha=0.5, label="$E_{max}$ (paper)")
    ax.set_xlabel("path width W (mm), L = 2W")
    ax.set_ylabel("electric energy (J)")
    saving = ax.twinx()
    saving.plot(widths, [r["gain"] * 100 for r in rows], "^-", color="tab:blue", label="saving (this model)")
    saving.plot(widths, [PAPER[w][2] for w in widths], "^--", color="tab:blue", alpha=0.5, label="saving (paper)")
    saving.set_ylabel("% saving", color="tab:blue")
    saving.set_ylim(0, 100)
    handles = ax.get_legend_handles_labels()[0] + saving.get_legend_handles_labels()[0]
    ax.legend(handles, [h.get_label() for h in handles], fontsize=7, loc="upper left")
    ax.set_title("$E_{min}$, $E_{max}$ and saving vs path size (paper timing, per-axis clipping)", fontsize=10)
    return figure


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/figures", help="folder for the PNG and SVG files")
    parser.add_argument("--grid", type=int, default=41, help="grid points per axis of the maps")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="worker processes")
    args = parser.parse_args()
    start = time.perf_counter()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    low, high = robot.workspace.min_m, robot.workspace.max_m
    xs, ys, zs = (np.linspace(low[k], high[k], args.grid) for k in range(3))
    phis = np.radians(np.linspace(-90, 90, 37))
    written = []

    def grid_sweep(axes, fixed):
        return sweep(robot, path, axes, fixed, evaluation=EvaluatorSettings(workers=args.workers))

    xy = grid_sweep({"x": xs, "y": ys}, {"z": 0.0, "phi": 0.0})
    written += save(map_figure(xy, "Energy vs $x_{Op}$ and $y_{Op}$ ($z_{Op}$ = 0, $\\phi$ = 0), 30 x 60 mm"),
                    out / "energy_xy")
    levels_y = (-0.060, -0.020, 0.020)
    xz = [grid_sweep({"x": xs, "z": zs}, {"y": y, "phi": 0.0}) for y in levels_y]
    written += save(panels(xz, [f"$y_{{Op}}$ = {y * 1e3:.0f} mm" for y in levels_y],
                           "Energy vs $x_{Op}$ and $z_{Op}$ ($\\phi$ = 0), 30 x 60 mm"), out / "energy_xz")
    x_phi = grid_sweep({"x": xs, "phi": phis}, {"y": 0.0, "z": 0.0})
    written += save(map_figure(x_phi, "Energy vs $x_{Op}$ and $\\phi$ ($y_{Op}$ = $z_{Op}$ = 0), 30 x 60 mm"),
                    out / "energy_x_phi")
    angles = (0, 30, 45, 60, 90)
    xy_phi = [grid_sweep({"x": xs, "y": ys}, {"z": 0.0, "phi": np.radians(a)}) for a in angles]
    written += save(panels(xy_phi, [f"$\\phi$ = {a}°" for a in angles],
                           "Energy vs $x_{Op}$ and $y_{Op}$ for several orientations ($z_{Op}$ = 0)"), out / "energy_xy_phi")
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        sizes = list(pool.map(run_case, WIDTHS_MM, ["paper"] * 7, ["clip"] * 7, [0.002] * 7))
    written += save(size_figure(sizes), out / "energy_vs_width")
    result = optimize_placement(robot, path)
    written += save(comparison(robot, result.best.detail, result.worst.detail), out / "emin_emax_comparison")
    print(f"wrote {len(written)} files to {out} in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
