"""Throughput of the Orthoglide model, one core: closed-form and generic routes beside the lumped model.

Run: ``python benchmarks/throughput.py [--samples N] [--seconds S]``. Each line evaluates the
same end-effector trajectory (N samples, the paper's groove-milling load on the tool) and prints
samples per second; the lumped analytic model (legs massless, numpy only) is the reference that
the exact model is compared against, in the same run, together with the gap between them. The
generic batched kinematics (any URDF) runs beside the robot's closed-form plug-in, with the ratio
of their speeds and the largest difference of their joint motions.
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
from placement.cli.memory import keep_freed_memory  # noqa: E402
from placement.dynamics.inverse import inverse_dynamics  # noqa: E402
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings  # noqa: E402
from placement.kinematics import joint_trajectory  # noqa: E402
from placement.kinematics.trajectories import TaskTrajectory  # noqa: E402
from placement.path.load import load_path  # noqa: E402
from placement.path.path_file import Timing  # noqa: E402
from placement.search.sweep import sweep  # noqa: E402

closed_form = load_robot("orthoglide").plugin


def circle_task(samples: int) -> TaskTrajectory:
    """A 60 mm circle at 0.66 m/s (the paper's feed) in the X_b Y_b plane around C."""
    radius, speed = 0.03, 0.66
    w = speed / radius
    t = np.linspace(0.0, 2 * np.pi / w, samples)[:, None]
    ones = np.ones_like(t)
    position = np.hstack([radius * np.cos(w * t), radius * np.sin(w * t), 0 * t]) - 0.0268 * ones
    velocity = np.hstack([-radius * w * np.sin(w * t), radius * w * np.cos(w * t), 0 * t])
    acceleration = np.hstack([-radius * w**2 * np.cos(w * t), -radius * w**2 * np.sin(w * t), 0 * t])
    return TaskTrajectory(position, velocity, acceleration)


def best_seconds(function: Callable[[], object], seconds: float) -> float:
    """The shortest time (s) of repeated calls of ``function`` over about ``seconds``."""
    return alternated_best_seconds([function], seconds)[0]


def alternated_best_seconds(functions: list[Callable[[], object]], seconds: float) -> list[float]:
    """The shortest time (s) of each function, called in turn over about ``seconds`` (so that a change of the
    machine's load weighs on each alike)."""
    best = [np.inf] * len(functions)
    for function in functions:
        function()
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        for k, function in enumerate(functions):
            tic = time.perf_counter()
            function()
            best[k] = min(best[k], time.perf_counter() - tic)
    return best


def rate(function: Callable[[], object], samples: int, seconds: float) -> float:
    """Samples per second of ``function`` (which evaluates ``samples`` samples), best of repeats."""
    return samples / best_seconds(function, seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1000, help="samples per trajectory (default 1000)")
    parser.add_argument("--seconds", type=float, default=2.0, help="timing budget per line (default 2 s)")
    args = parser.parse_args()
    robot = load_robot("orthoglide")
    model = robot.model
    task = circle_task(args.samples)
    load = np.tile([-10.0, 215.0, 25.0], (args.samples, 1))
    length = closed_form.leg_length_m(model)
    platform_kg = model.inertias[model.getJointId("wrist_x")].mass
    slider_kg = model.inertias[model.getJointId("slider_x")].mass
    legs_kg = sum(model.inertias[model.getJointId(f"{b}_x")].mass for b in ("yoke", "bar1", "bar2", "far"))

    def lumped():
        return closed_form.lumped_actuator_forces(task.position_m, task.velocity_m_s, task.acceleration_m_s2,
                                                  length, platform_kg + 1.5 * legs_kg, slider_kg + 0.5 * legs_kg,
                                                  robot.actuators[0].reflected_inertia, model.gravity.linear, load)

    exact = inverse_dynamics(robot, task, load)
    gap = np.abs(lumped() - exact.effort).max()
    generic = joint_trajectory(robot, task, "numeric")
    closed = joint_trajectory(robot, task, "closed_form")
    route_gap = max(float(np.abs(getattr(generic, f) - getattr(closed, f)).max()) for f in ("q", "v", "a"))
    lines = [
        ("exact model, closed-form kinematics + projected RNEA", lambda: inverse_dynamics(robot, task, load),
         args.samples),
        ("  of which closed-form kinematics alone", lambda: joint_trajectory(robot, task, "closed_form"), args.samples),
        ("exact model, generic batched kinematics + projected RNEA",
         lambda: inverse_dynamics(robot, task, load, "numeric"), args.samples),
        ("  of which generic batched kinematics alone", lambda: joint_trajectory(robot, task, "numeric"), args.samples),
        ("lumped analytic model (reference, half leg mass at each end)", lumped, args.samples),
    ]
    print(f"Orthoglide inverse dynamics, {args.samples} samples per trajectory, one core")
    rates = {}
    for label, function, samples in lines:
        rates[label] = rate(function, samples, args.seconds)
        print(f"  {label:<62s} {rates[label]:>12,.0f} samples/s")
    ratio = rates[lines[0][0]] / rates[lines[2][0]]
    print(f"  closed-form / generic route: {ratio:.1f}x; largest joint position, rate or acceleration gap between "
          f"the routes: {route_gap:.1e}")
    print(f"  lumped - exact force gap on this path: {gap:.2f} N (exact peak {np.abs(exact.effort).max():.1f} N)")
    evaluator = Evaluator(robot, load_path(Path(__file__).parents[1] / "examples" / "rect.yaml"), EvaluatorSettings(threads=1))
    placements = np.random.default_rng(0).uniform([-0.1, -0.1, -0.1, -1.5, 0, 0], [0.05, 0.05, 0.05, 1.5, 0, 0],
                                                   (200, 6))
    optimal = Evaluator(robot, dataclasses.replace(evaluator.path, timing=Timing(mode="optimal")),
                        EvaluatorSettings(threads=1, workers=1))
    assert optimal.geometry is not None
    paper_s, optimal_s = alternated_best_seconds([lambda: evaluator.evaluate(placements),
                                                  lambda: optimal.evaluate(placements)], 2 * args.seconds)
    per_second, timed = len(placements) / paper_s, len(placements) / optimal_s
    print(f"  whole chain (energy and margins), 30 x 60 mm rectangle, {len(evaluator.samples)} samples: "
          f"{per_second:,.0f} placements/s ({per_second * len(evaluator.samples):,.0f} samples/s)")
    print(f"  the same under the optimal timing law (TOPP-RA on each of the 4 runs, {len(optimal.geometry)} path "
          f"samples), timed in turn with the line above: {timed:,.0f} placements/s, {100 * timed / per_second:.0f} % "
          "of the paper's timing's")
    workspace = robot.workspace
    axes = {axis: np.linspace(workspace.min_m[k], workspace.max_m[k], 41) for k, axis in enumerate("xy")}
    seconds = {}
    for workers in (1, 2):
        tic = time.perf_counter()
        sweep(robot, evaluator.path, axes, {"z": 0.0, "phi": 0.0}, evaluation=EvaluatorSettings(workers=workers))
        seconds[workers] = time.perf_counter() - tic
    print(f"41 x 41 (x, y) energy map of the 30 x 60 mm rectangle at z = 0, phi = 0: {seconds[1]:.2f} s with 1 worker, "
          f"{seconds[2]:.2f} s with 2 workers (speed-up {seconds[1] / seconds[2]:.2f}, process start-up included)")


if __name__ == "__main__":
    from results import recorded  # this run's section of benchmarks/RESULTS.md

    keep_freed_memory()  # as the command line does: the batches\' freed memory kept for the next ones
    with recorded("throughput"):
        main()
