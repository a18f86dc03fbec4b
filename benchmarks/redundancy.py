"""Redundant robots: whole-path resolution against a local baseline and the locked robot.

Run: ``python benchmarks/redundancy.py [--robots panda ur5_track] [--paths ...] [--knots 1 2 3 5]``. The seven-axis
Panda (its joint 3 redundant) is run on the circle and the contour, the UR5 on its track (the track redundant) on
the long weld seam. For each path it prints the least electric energy (J) and the search's wall time (s) of:

- ``locked``: the redundant joint held at 0 (``--lock panda_joint3=0``, ``--lock track=0``), the placement searched;
  none on the long seam, which the UR5 cannot reach from one place;
- ``whole path``: placement and knots searched together, for each ``--knots``;
- ``local``: the classic local rule, gradient projection on the instantaneous power, at the locked optimum's
  placement, or, where the locked robot reaches nothing, at the whole-path optimum's (its default knots): from the
  locked posture (or the whole-path profile's first value), the redundant joint moves at q̇ = −k·dP/dq, where P is
  the Joule power of the motor currents that hold the robot against gravity and dP/dq its derivative along the
  self-motion that keeps the tool's pose (the other joints follow by inverse kinematics), the best of a few gains
  k; the motion found is evaluated by the exact chain (its trajectory prescribed, the others by inverse
  kinematics, RNEA, drives);
- ``knots@locked``: at the locked optimum's placement, the whole-path profile (3 knots) searched.

Numbers on a shared 2-core machine vary by some 30 % in time; the energies are reproducible (seed 0).
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from placement import load_robot
from placement.dynamics.inverse import actuator_efforts
from placement.energy.integration import electric_energy
from placement.energy.trace import motor_trace
from placement.evaluation.evaluator import Evaluator
from placement.exceptions import InfeasibleError
from placement.kinematics.base import solver_for
from placement.path import load_path
from placement.placing.transform import placed_task
from placement.robot.model import Robot
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from placement.workshop.load import edit_redundancy

EXAMPLES = Path(__file__).parent.parent / "examples"
CASES = {  # robot: its redundant joint, the paths, the local rule's gains tried (rad/(W·s), or m/(W·s) for a track)
    "panda": ("panda_joint3", ("circle", "contour"), (0.0, 0.01, 0.03, 0.1, 0.3, 1.0)),
    "ur5_track": ("track", ("long_seam",), (0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0)),
}
VARIABLES = ("x", "y", "z", "phi", "theta", "psi")


def search(robot: Robot, path_file: Path,
           fixed: dict[str, float] | None = None) -> tuple[float, np.ndarray | None, float]:
    """The least energy (J, inf where no placement is feasible), its placement (or None) and the search's wall time (s)."""
    path = load_path(path_file)
    space = default_space(robot, fixed=fixed, half_turn=path.half_turn_symmetric())
    tic = time.perf_counter()
    try:
        best = optimize_placement(robot, path, space=space, settings=SearchSettings(seed=0, worst=False)).best
    except InfeasibleError:
        best = None
    if best is None:
        return float("inf"), None, time.perf_counter() - tic
    return float(best.detail.value), best.detail.placement, time.perf_counter() - tic


def holding_power_W(robot: Robot, data: pin.Data, q: np.ndarray) -> float:
    """Joule power (W) of the motor currents that hold configuration ``q`` against gravity."""
    torque = pin.computeGeneralizedGravity(robot.model, data, q)[robot.actuated_v_indices]
    total = 0.0
    for effort, drive in zip(torque, robot.drives, strict=True):
        motor = drive.motor
        current = effort / drive.transmission.speed_ratio / motor.torque_constant_Nm_per_A
        total += motor.phases * motor.resistance_ohm * current ** 2
    return total


def local_profile(robot: Robot, path_file: Path, placement: np.ndarray, start: np.ndarray, gain: float) -> np.ndarray:
    """The redundant joint along the path by gradient projection on the holding power, from the first posture of the
    placement vector ``start`` (m or rad, per sample)."""
    evaluator = Evaluator(robot, load_path(path_file))
    samples = evaluator.samples
    first = evaluator.batch(start[None])  # the starting posture: its first sample's
    assert np.all(first.reachable), "the local rule's start is out of reach"
    q = first.joints.q[0].copy()
    task, _ = placed_task(robot, samples, placement[None])
    model, data, frame = robot.model, robot.model.createData(), robot.end_effector_frame_id
    j3 = int(robot.redundant_q_indices[0])
    unit = np.zeros(model.nv)
    unit[j3] = 1.0
    limit = 0.5 * next(a.velocity_max for a in robot.actuators if a.joint == robot.redundant_joints[0])
    profile = np.empty(len(samples))
    for k in range(len(samples)):
        for _ in range(20):  # Newton on the pose with joint 3 held at its value
            pin.framesForwardKinematics(model, data, q)
            pose = data.oMf[frame]
            error = np.concatenate([pose.translation - task.position_m[k], pin.log3(pose.rotation @ task.rotation[k].T)])
            if np.linalg.norm(error) < 1e-12:
                break
            jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
            q = q - np.linalg.solve(np.vstack([jacobian, unit]), np.append(error, 0.0))
        profile[k] = q[j3]
        if k + 1 == len(samples):
            break
        jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        direction = np.linalg.solve(np.vstack([jacobian, unit]), np.append(np.zeros(6), 1.0))  # self-motion per rad
        step = 1e-5
        slope = (holding_power_W(robot, data, q + step * direction)
                 - holding_power_W(robot, data, q - step * direction)) / (2 * step)
        rate = float(np.clip(-gain * slope, -limit, limit))
        q = q + (samples.t_s[k + 1] - samples.t_s[k]) * rate * direction
    return profile


def exact_energy(robot: Robot, path_file: Path, placement: np.ndarray, profile: np.ndarray) -> tuple[float, float]:
    """The exact chain's energy (J) of the redundant joint moving as ``profile``, and the largest share of a joint
    speed limit (inf and nan where the motion leaves the reach)."""
    evaluator = Evaluator(robot, load_path(path_file))
    samples = evaluator.samples
    task, force = placed_task(robot, samples, placement[None])
    velocity = np.gradient(profile, samples.t_s)
    task = dataclasses.replace(task, joint_position=profile[:, None], joint_velocity=velocity[:, None],
                               joint_acceleration=np.gradient(velocity, samples.t_s)[:, None])
    joints, reachable, _ = solver_for(robot).solve(task, 1)
    if not reachable.all():
        return float("inf"), float("nan")
    act = robot.actuated_v_indices
    effort = actuator_efforts(robot, joints, force)
    trace = motor_trace(robot, effort, joints.v[:, act], joints.a[:, act])
    energy = electric_energy(robot, trace, samples.t_s, samples.piece).total_J
    speed = np.abs(joints.v[:, act]) / np.array([a.velocity_max for a in robot.actuators])
    return float(energy), float(speed.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=list(CASES), choices=list(CASES), help="robots (default: both)")
    parser.add_argument("--paths", nargs="+", help="example paths (default: each robot's)")
    parser.add_argument("--knots", nargs="+", type=int, default=[1, 2, 3, 5], help="knot counts of the whole-path search")
    args = parser.parse_args()
    for name in args.robots:
        joint, paths, gains = CASES[name]
        for path in args.paths or paths:
            compare(load_robot(name), joint, EXAMPLES / f"{path}.yaml", gains, args.knots)


def compare(robot: Robot, joint: str, path_file: Path, gains: tuple[float, ...], knot_counts: list[int]) -> None:
    """Print the locked robot's, the whole-path searches', the local rule's and the knots at the locked optimum's
    energies on one path."""
    name = f"{robot.name} {path_file.stem}"
    unit, scale = ("mm", 1e3) if joint == "track" else ("deg", 180 / np.pi)
    locked = edit_redundancy(robot, {joint: 0.0})
    energy, placement, seconds = search(locked, path_file)
    print(f"{name}: locked            {energy:9.4f} J  {seconds:6.1f} s  ({len(default_space(locked).free)} variables)")
    wholes = {}
    for knots in knot_counts:
        resolved = edit_redundancy(robot, {}, knots=knots)
        energy, found, seconds = search(resolved, path_file)
        wholes[knots] = found
        shown = "none" if found is None else (found[6:] * scale).round(1).tolist()
        print(f"{name}: whole path, {knots} knot(s) {energy:9.4f} J  {seconds:6.1f} s  "
              f"({len(default_space(resolved).free)} variables; {joint} knots {shown} {unit})")
    anchor = wholes.get(robot.profile_knots)
    if placement is not None:  # from the locked posture
        at, start, where = placement[:6], np.append(placement[:6], [0.0] * robot.profile_knots), "the locked optimum"
    elif anchor is not None:  # from the whole-path optimum's first posture
        at, start, where = anchor[:6], anchor, "the whole-path optimum"
    else:
        print(f"{name}: local             not run (no placement of the locked or the whole-path search)")
        return
    results = [(exact_energy(robot, path_file, at, local_profile(robot, path_file, at, start, gain)), gain)
               for gain in gains]
    (local, speed), gain = min(results, key=lambda result: result[0][0])
    print(f"{name}: local             {local:9.4f} J  (at {where}, gain {gain:g}; joint speeds up to {speed:.0%} of "
          f"their limits; gains tried {', '.join(f'{g:g}: {r[0]:.4f} J' for r, g in results)})")
    if placement is not None:
        fixed = dict(zip(VARIABLES, map(float, placement), strict=True))
        energy, _, seconds = search(robot, path_file, fixed)
        print(f"{name}: knots@locked      {energy:9.4f} J  {seconds:6.1f} s  ({robot.profile_knots} variables)")


if __name__ == "__main__":
    main()
