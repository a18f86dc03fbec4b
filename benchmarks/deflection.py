"""Cost of the tool's deflection along the path against an energy evaluation, one core.

Run: ``python benchmarks/deflection.py [--placements K] [--repeats R]``. For each built-in robot with stiffness
(Orthoglide, UR5, Panda) it evaluates K placements of the paper's groove (examples/rect.yaml) near the robot's
workspace centre, and prints the best time of R runs of

- an energy evaluation (the whole exact chain: kinematics, dynamics, drives, the energy and every limit),
- the deflection alone on an evaluated batch (what the ``deflection`` objective adds to it: the process force
  turned into the base frame and δ = T·K⁻¹·Tᵀ·w at every sample),
- an evaluation of both objectives, energy and deflection,
- the deflection with the loaded correction (``--loaded-stiffness``: the nonlinear equilibrium, some 2·d + 2 more
  kinematics solves), where it covers the robot (not the Panda's seven axes),

and the ratios deflection / energy, (energy + deflection) / energy and loaded / energy. The goal (issue 37) is a
deflection costing at most 1.5 times an energy evaluation; the loaded correction is an option beyond it.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_variable] = "1"  # one core, before numpy loads

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from placement import load_robot  # noqa: E402
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings  # noqa: E402
from placement.path.load import load_path  # noqa: E402
from placement.path.toolpath import ToolPath  # noqa: E402

RECT = Path(__file__).resolve().parent.parent / "examples" / "rect.yaml"


def best_time_s(run: Callable[[], object], repeats: int) -> float:
    """The shortest wall time of ``repeats`` runs (after one warm-up run)."""
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def placements_near_centre(robot_name: str, count: int) -> np.ndarray:
    """``count`` placements within ±5 mm and ±5° of the workspace centre (no tilt)."""
    workspace = load_robot(robot_name).workspace
    assert workspace is not None
    centre = (np.array(workspace.min_m) + np.array(workspace.max_m)) / 2
    rng = np.random.default_rng(0)
    placements = np.zeros((count, 6))
    placements[:, :3] = centre + rng.uniform(-0.005, 0.005, (count, 3))
    placements[:, 3] = rng.uniform(-0.09, 0.09, count)
    return placements


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--placements", type=int, default=64)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    path = load_path(RECT)
    print(f"{'robot':<12s}{'samples':>9s}{'energy s':>11s}{'deflection s':>14s}{'both s':>9s}{'defl/energy':>13s}"
          f"{'both/energy':>13s}{'loaded/energy':>15s}")
    for name in ("orthoglide", "ur5", "panda"):
        print(row(name, path, args.placements, args.repeats))


def row(name: str, path: ToolPath, count: int, repeats: int) -> str:
    """One robot's line: samples, the three best times (s) and the two ratios."""
    robot = load_robot(name)
    placements = placements_near_centre(name, count)
    energy = Evaluator(robot, path, EvaluatorSettings(objective="energy", workers=1, threads=1))
    both = Evaluator(robot, path, EvaluatorSettings(objective=("energy", "deflection"), workers=1, threads=1))
    batch = energy.batch(placements)
    energy_s = best_time_s(lambda: energy.evaluate(placements), repeats)
    deflection_s = best_time_s(lambda: type(batch).deflection.func(batch), repeats)  # the cached property, uncached
    both_s = best_time_s(lambda: both.evaluate(placements), repeats)
    loaded = "n/a"
    if len(robot.actuators) == robot.task_dimension:
        loaded_batch = dataclasses.replace(batch, loaded_solver=energy.solver)
        loaded = f"{best_time_s(lambda: type(batch).deflection.func(loaded_batch), repeats) / energy_s:.3f}"
    return (f"{name:<12s}{len(placements) * len(energy.samples):>9d}{energy_s:>11.4f}{deflection_s:>14.4f}"
            f"{both_s:>9.4f}{deflection_s / energy_s:>13.3f}{both_s / energy_s:>13.3f}{loaded:>15s}")

if __name__ == "__main__":
    main()
