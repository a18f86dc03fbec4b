"""Collision distances of the UR5 with a spindle in examples/cell_ur5_table_wall.yaml (3 obstacles, a keep-out zone), one core.

Run: ``python benchmarks/collision.py [--configurations M] [--seconds S]``. Configurations are
drawn around the reference posture (each joint within ±0.6 rad, the tool above the table, as a
search visits them) and over the joints' whole ranges. Each line prints the time per configuration
and distances (pairs × configurations) per second: exact everywhere, then with the compiled lower
bounds' prefilter (:mod:`placement.collision.bounds`) at a few thresholds (with the share of pairs
computed exactly), and Pinocchio's own loop (``computeDistances``, every pair in C++, one
configuration per call) for comparison.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_variable] = "1"  # one core, before numpy loads

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
from throughput import best_seconds  # noqa: E402  (the benchmarks' folder is on the path when run)

from placement import Robot, load_robot  # noqa: E402
from placement.cell.cell_file import load_cell  # noqa: E402
from placement.collision.distances import CollisionScene  # noqa: E402

CELL = Path(__file__).parent.parent / "examples" / "cell_ur5_table_wall.yaml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configurations", type=int, default=2000, help="configurations per call (default 2000)")
    parser.add_argument("--seconds", type=float, default=3.0, help="time spent on each measurement (default 3 s)")
    args = parser.parse_args()
    robot = load_robot("ur5")
    tic = time.perf_counter()
    scene = CollisionScene(robot, load_cell(CELL))
    built = time.perf_counter() - tic
    shape_pairs = len(scene.geometry_model.collisionPairs)
    print(f"UR5 in {CELL.name}: {len(scene.bodies)} bodies, {len(scene.pairs)} pairs ({shape_pairs} shape pairs), "
          f"built in {built:.2f} s")
    rng = np.random.default_rng(0)
    low, high = (np.array([getattr(a, f) for a in robot.actuators]) for f in ("position_min", "position_max"))
    m = args.configurations
    sets = {"around the reference": robot.reference_q + rng.uniform(-0.6, 0.6, (m, robot.model.nq)),
            "over the joint ranges": low + (high - low) * rng.random((m, robot.model.nq))}
    for label, q in sets.items():
        print(f"\n{m} configurations {label}:")
        exact = scene.distances(q)
        seconds = best_seconds(lambda q=q: scene.distances(q), args.seconds)
        print(f"  exact:               {seconds / (m * shape_pairs) * 1e6:6.2f} us per shape-pair distance, "
              f"{m * len(scene.pairs) / seconds:10,.0f} distances/s")
        for threshold in (0.02, 0.05, 0.1):
            share = float((scene.distances(q, threshold) == exact).mean())
            seconds = best_seconds(lambda q=q, t=threshold: scene.distances(q, t), args.seconds)
            print(f"  threshold {threshold:4.2f} m:   {seconds / m * 1e6:7.1f} us per configuration, "
                  f"{m * len(scene.pairs) / seconds:10,.0f} distances/s ({share:.0%} of pairs exact)")
        seconds = best_seconds(lambda q=q: pinocchio_loop(robot, scene, q), args.seconds)
        print(f"  Pinocchio computeDistances loop: {seconds / (m * shape_pairs) * 1e6:6.2f} us per shape pair "
              "(results left in C++, not read; coal's warm start on)")


def pinocchio_loop(robot: Robot, scene: CollisionScene, q: np.ndarray) -> None:
    """Every shape pair's distance in configurations q (M, nq), by Pinocchio alone (its default settings)."""
    data, geometry_data = robot.model.createData(), pin.GeometryData(scene.geometry_model)
    for row in q:
        pin.computeDistances(robot.model, data, scene.geometry_model, geometry_data, row)


if __name__ == "__main__":
    from results import recorded  # this run's section of benchmarks/RESULTS.md

    with recorded("collision"):
        main()
