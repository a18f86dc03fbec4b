"""Long paths on the Orthoglide: a 100,000-point free-form contour, a 4,700-line surface-finishing program and a
60,000-line relief engraving.

Run: ``python benchmarks/long_paths.py [--out DIR] [--only contour|surface|relief] [--generate]``. It writes the
inputs (generated here, never stored), then searches each as ``python -m placement --robot orthoglide
--path FILE`` does (both directions, the tolerance boxes) and prints the wall time of each stage, the total
and the peak memory (the largest resident set of this process and its worker processes).

The inputs:

- ``contour.yaml``: a closed polyline of 100,000 points, as a CAM system exports a free-form contour
  (one point every 4 µm): r(θ) = 40 mm · (1 + 0.15 cos 3θ + 0.08 sin 5θ) in the X_p Y_p plane, about
  90 × 80 mm, inside the Orthoglide's 200 mm workspace cube at any turn phi; milled at 0.66 m/s with
  the paper's groove-milling forces and timing law (as ``examples/rect.yaml``).
- ``surface.nc`` and ``surface.yaml``: a ball-nose raster finishing pass over a 100 × 100 mm surface
  z = 25 mm · (1 + sin(πx/100)·cos(πy/100)) from z = 0 to 50 mm (a 100 × 100 × 50 mm part, the
  Orthoglide's cube is 200 mm): 47 passes along X, 1 mm apart in X and 2.17 mm in Y, zig-zag, at
  F3000 mm/min: 4,700 G1 lines of 3-D moves after a Fanuc-style header.
- ``relief.nc`` and ``relief.yaml``: the same surface engraved slowly, as CAMotics' tiger sample is (65,183
  segments, 4.3 h): 300 passes of 200 moves at F300, each stepover at F150, 60,300 G1 lines over 6,000 s; the
  feeds changing at every stepover, no chord merges two passes.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np

from placement import load_robot
from placement.cli.memory import keep_freed_memory
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.load import load_path
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot
from placement.search.coarse_guide import SearchModels, search_models
from placement.search.optimize import SearchSettings, optimize_placement, search_sampling
from placement.search.space import default_space

T = TypeVar("T")

CONTOUR_POINTS = 100_000
SURFACE_PASSES, SURFACE_MOVES = 47, 100  # raster passes along X, G1 moves per pass
RELIEF_PASSES, RELIEF_MOVES = 300, 200  # ... of the relief engraving


def contour_points_mm(count: int = CONTOUR_POINTS) -> np.ndarray:
    """(count, 2) points of the free-form closed contour (module docstring), mm."""
    theta = np.linspace(0.0, 2 * np.pi, count, endpoint=False)
    radius = 40.0 * (1 + 0.15 * np.cos(3 * theta) + 0.08 * np.sin(5 * theta))
    return np.column_stack([radius * np.cos(theta), radius * np.sin(theta)])


def write_contour(folder: Path, count: int = CONTOUR_POINTS) -> Path:
    """The contour's path file (a YAML polyline), written in ``folder``."""
    points = "\n".join(f"  - [{x:.4f}, {y:.4f}]" for x, y in contour_points_mm(count))
    file = folder / "contour.yaml"
    file.write_text(f"# A free-form contour of {count} points (benchmarks/long_paths.py)\n"
                    f"name: free-form contour, {count} points\nunits: mm\nfeed_m_s: 0.66\n"
                    "process_forces_N: {feed: 10, radial: 215, axial: 25}\n"
                    "timing: {mode: paper}\ntime_step_s: 0.001\n"
                    f"shape:\n  type: polyline\n  closed: true\n  points:\n{points}\n", encoding="utf-8")
    return file


def surface_height_mm(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The finished surface's height over the 100 × 100 mm part centred on the origin, 0 to 50 mm."""
    return 25.0 * (1 + np.sin(np.pi * x / 100) * np.cos(np.pi * y / 100))


def surface_program(passes: int = SURFACE_PASSES, moves: int = SURFACE_MOVES, feed_mm_min: float = 3000.0,
                    stepover_mm_min: float | None = None) -> str:
    """The raster finishing program (module docstring): header, passes of ``moves`` G1 lines at ``feed_mm_min``,
    each stepover at ``stepover_mm_min`` (default: the same feed), footer."""
    stepover = "" if stepover_mm_min is None else f" F{stepover_mm_min:g}"
    feed = "" if stepover_mm_min is None else f" F{feed_mm_min:g}"
    lines = ["%", "O0100 (SURFACE FINISH 100X100X50, D6 BALL NOSE)", "G21 G90 G17 G94", "G40 G49 G80",
             "T1 M6", "S18000 M3", "G54", "G43 H1 G0 Z60. M8"]
    x = np.linspace(-50.0, 50.0, moves + 1)
    for k, y in enumerate(np.linspace(-50.0, 50.0, passes)):
        along = x if k % 2 == 0 else x[::-1]
        z = surface_height_mm(along, np.full_like(along, y))
        if k == 0:
            lines += [f"G0 X{along[0]:.3f} Y{y:.3f}", f"G1 Z{z[0]:.3f} F{feed_mm_min:g}."]
        else:
            lines.append(f"G1 Y{y:.3f} Z{z[0]:.3f}{stepover}")  # the stepover, on the surface
        lines += [f"X{along[1]:.3f} Z{z[1]:.3f}{feed}"] + [f"X{a:.3f} Z{h:.3f}" for a, h in zip(along[2:], z[2:])]
    return "\n".join([*lines, "G0 Z60.", "M9", "M5", "M30", "%"]) + "\n"


def write_surface(folder: Path) -> Path:
    """The surface program and its path file, written in ``folder``; returns the path file."""
    (folder / "surface.nc").write_text(surface_program(), encoding="ascii")
    file = folder / "surface.yaml"
    file.write_text("# A ball-nose raster finishing program of a 100 x 100 x 50 mm part (benchmarks/long_paths.py)\n"
                    "name: surface finishing 100 x 100 x 50 mm\nshape: {type: gcode, file: surface.nc}\n"
                    "rapids: {mode: skip}\n"
                    "process_forces_N: {feed: 10, radial: 30, axial: 20}  # ESTIMATE: a light finishing cut\n"
                    "timing: {mode: paper}\n", encoding="utf-8")
    return file


def write_relief(folder: Path) -> Path:
    """The relief engraving and its path file, written in ``folder``; returns the path file."""
    (folder / "relief.nc").write_text(surface_program(RELIEF_PASSES, RELIEF_MOVES, 300.0, 150.0), encoding="ascii")
    file = folder / "relief.yaml"
    file.write_text("# A slow relief engraving of 60,300 lines (benchmarks/long_paths.py)\n"
                    "name: relief engraving 100 x 100 x 50 mm\nshape: {type: gcode, file: relief.nc}\n"
                    "rapids: {mode: skip}\ntiming: {mode: paper}\n", encoding="utf-8")
    return file


def peak_memory_mb() -> tuple[float, float]:
    """The largest resident set (MB) of this process and of its finished worker processes."""
    return (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)


def cpu_s() -> float:
    """Processor time (s) of this process and its finished worker processes: on a shared machine, what a stage
    costs, where the wall time also counts the other processes' share."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class Stages:
    """Wall and processor time of named stages."""

    def __init__(self) -> None:
        self.times: dict[str, tuple[float, float]] = {}

    def __call__(self, name: str, function: Callable[[], T]) -> T:
        wall, cpu = time.perf_counter(), cpu_s()
        value = function()
        self.times[name] = (time.perf_counter() - wall, cpu_s() - cpu)
        return value

    def print(self) -> None:
        for stage, (wall, cpu) in self.times.items():
            print(f"  {stage:<44} {wall:8.2f} s wall {cpu:8.2f} s CPU")
        own, children = peak_memory_mb()
        wall, cpu = (sum(times) for times in zip(*self.times.values()))
        print(f"  {'total':<44} {wall:8.2f} s wall {cpu:8.2f} s CPU; peak memory {own:.0f} MB here, "
              f"{children:.0f} MB in a worker")


def reference(robot: Robot, path: ToolPath, models: SearchModels) -> None:
    """The cost of one generation of the global search (a population of 64) and of one placement, on each model,
    measured here: what an unguided search would pay per generation and per polish step."""
    population = np.zeros((64, 6))
    population[:, 2] = np.linspace(-0.06, -0.02, 64)
    cases = [("global guide, 64 placements", models.coarse_path, models.coarse, population),
             ("polish guide, 1 placement", models.polish_path, models.polish, population[:1]),
             ("exact (path's own sampling), 1 placement", path, models.exact, population[:1])]
    costs = []
    for label, model, settings, placements in cases:
        evaluator = Evaluator(robot, model, dataclasses.replace(settings, threads=1, workers=1))
        evaluator.evaluate(placements[:1])
        tic = time.process_time()
        evaluator.evaluate(placements)
        costs.append(time.process_time() - tic)
        print(f"  {label:<44} {len(evaluator.samples):>8} samples {costs[-1]:8.3f} s CPU")
    generations = SearchSettings().max_generations
    print(f"  the global search's {generations} generations: {generations * costs[0]:.1f} s CPU on its guide, "
          f"{generations * 64 * costs[2]:.0f} s on the path's own sampling (a direction)")


def run(file: Path) -> None:
    """Search the path file as ``python -m placement --robot orthoglide --path FILE`` does, stage by stage."""
    stages = Stages()
    robot = stages("load robot", lambda: load_robot("orthoglide"))
    path = stages("load path", lambda: load_path(file))
    samples = stages("sample path", path.sample)
    print(f"{path.name}: {len(path.segments)} segments, {path.length_m * 1e3:.1f} mm, {len(samples)} samples")
    space = stages("half-turn symmetry", lambda: default_space(robot, half_turn=path.half_turn_symmetric()))
    evaluation, settings = EvaluatorSettings(), SearchSettings(box_within=0.01)  # the command line's 1 % boxes
    models = stages("guides", lambda: search_models(path, *search_sampling(path, evaluation, settings)))
    print(f"  guides: global {len(models.coarse_path.segments)} segments, polish {len(models.polish_path.segments)}")
    result = stages("search (both directions, re-check, detail, tolerance boxes)",
                    lambda: optimize_placement(robot, path, space=space, evaluation=evaluation, settings=settings))
    for label, optimum in (("best", result.best), ("worst", result.worst)):
        if optimum is not None:
            gap = "" if optimum.guide_gap is None else f", guide {optimum.guide_value:.6f} J ({optimum.guide_gap:+.4%})"
            print(f"  {label}: {optimum.detail.value:.6f} J exact (4x denser {optimum.recheck_value:.6f} J{gap}), "
                  f"{optimum.evaluations} evaluations{'; ' + optimum.note if optimum.note else ''}")
    stages.print()
    print("  reference, one evaluation on each model:")
    reference(robot, path, models)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, help="folder for the inputs (default: a temporary one)")
    parser.add_argument("--only", choices=("contour", "surface", "relief"), help="one of the three cases")
    parser.add_argument("--generate", action="store_true", help="write the inputs and stop")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = args.out or Path(temporary)
        folder.mkdir(parents=True, exist_ok=True)
        files = {"contour": write_contour(folder), "surface": write_surface(folder), "relief": write_relief(folder)}
        if args.generate:
            print("\n".join(str(f) for f in files.values()))
            return
        for name, file in files.items():
            if args.only in (None, name):
                run(file)
                sys.stdout.flush()


if __name__ == "__main__":
    from results import recorded  # this run's section of benchmarks/RESULTS.md

    keep_freed_memory()  # as the command line does: the batches\' freed memory kept for the next ones
    with recorded("long_paths"):
        main()
