"""The seven-axis Panda: whole-path redundancy resolution against a local baseline and the locked arm.

Run: ``python benchmarks/redundancy.py [--paths circle contour] [--knots 1 2 3 5]``. For each path it prints
the least electric energy (J) and the search's wall time (s) of:

- ``locked``: the six-axis arm (``--lock panda_joint3=0``), its placement searched (6 variables);
- ``local``: at the locked optimum's placement, joint 3 resolved sample by sample by the classic local rule,
  gradient projection on the instantaneous power: from the locked posture, joint 3 moves at
  q̇3 = −k·dP/dq3, where P is the Joule power of the motor currents that hold the arm against gravity
  and dP/dq3 its derivative along the self-motion that keeps the tool's pose (the other joints follow by
  inverse kinematics), the best of a few gains k; the motion found is evaluated by the exact chain
  (its joint-3 trajectory prescribed, the others by inverse kinematics, RNEA, drives);
- ``knots@locked``: at the same placement, the whole-path profile of joint 3 (3 knots) searched;
- ``whole path``: placement and knots searched together (6 + knots variables), for each ``--knots``.

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
from placement.kinematics.base import solver_for
from placement.path import load_path
from placement.placing.transform import placed_task
from placement.robot.model import Robot
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from placement.workshop.load import edit_redundancy

EXAMPLES = Path(__file__).parent.parent / "examples"
GAINS = (0.0, 0.01, 0.03, 0.1, 0.3, 1.0)  # rad/(W·s): the local rule's gains tried
JOINT = "panda_joint3"


def search(robot: Robot, path_file: Path, fixed: dict[str, float] | None = None) -> tuple[float, np.ndarray, float]:
    """The least energy (J), its placement and the search's wall time (s)."""
    path = load_path(path_file)
    space = default_space(robot, fixed=fixed, half_turn=path.half_turn_symmetric())
    tic = time.perf_counter()
    best = optimize_placement(robot, path, space=space, settings=SearchSettings(seed=0, worst=False)).best
    assert best is not None, f"no feasible placement of {path_file.name}"
    return float(best.detail.value), best.detail.placement, time.perf_counter() - tic


def holding_power_W(robot: Robot, data: pin.Data, q: np.ndarray) -> float:
    """Joule power (W) of the motor currents that hold configuration ``q`` against gravity."""
    torque = pin.computeGeneralizedGravity(robot.model, data, q)[robot.actuated_v_indices]
    total = 0.0
    for effort, drive in zip(torque, robot.drives, strict=True):
        motor = drive.motor
        current = effort / drive.transmission.ratio / motor.torque_constant_Nm_per_A
        total += motor.phases * motor.resistance_ohm * current ** 2
    return total


def local_profile(robot: Robot, path_file: Path, placement: np.ndarray, gain: float) -> np.ndarray:
    """Joint 3 along the path by gradient projection on the holding power, from the locked posture (rad, per sample)."""
    evaluator = Evaluator(robot, load_path(path_file))
    samples = evaluator.samples
    start = evaluator.batch(np.append(placement, [0.0] * robot.profile_knots)[None])  # the locked posture, q3 = 0
    q = start.joints.q[0].copy()
    task, _ = placed_task(robot, samples, placement[None])
    model, data, frame = robot.model, robot.model.createData(), robot.end_effector_frame_id
    j3 = int(robot.redundant_q_indices[0])
    unit = np.zeros(model.nv)
    unit[j3] = 1.0
    limit = 0.5 * next(a.velocity_max for a in robot.actuators if a.joint == JOINT)
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
    """The exact chain's energy (J) of joint 3 moving as ``profile``, and its largest share of a joint speed limit."""
    evaluator = Evaluator(robot, load_path(path_file))
    samples = evaluator.samples
    task, force = placed_task(robot, samples, placement[None])
    velocity = np.gradient(profile, samples.t_s)
    task = dataclasses.replace(task, joint_position=profile[:, None], joint_velocity=velocity[:, None],
                               joint_acceleration=np.gradient(velocity, samples.t_s)[:, None])
    joints, reachable, reason = solver_for(robot).solve(task, 1)
    assert reachable.all(), reason
    act = robot.actuated_v_indices
    effort = actuator_efforts(robot, joints, force)
    trace = motor_trace(robot, effort, joints.v[:, act], joints.a[:, act])
    energy = electric_energy(robot, trace, samples.t_s, samples.piece).total_J
    speed = np.abs(joints.v[:, act]) / np.array([a.velocity_max for a in robot.actuators])
    return float(energy), float(speed.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paths", nargs="+", default=["circle", "contour"], help="example paths (default circle contour)")
    parser.add_argument("--knots", nargs="+", type=int, default=[1, 2, 3, 5], help="knot counts of the whole-path search")
    args = parser.parse_args()
    panda = load_robot("panda")
    locked = edit_redundancy(panda, {JOINT: 0.0})
    for name in args.paths:
        path_file = EXAMPLES / f"{name}.yaml"
        energy, placement, seconds = search(locked, path_file)
        print(f"{name}: locked            {energy:9.4f} J  {seconds:6.1f} s  (6 variables)")
        results = [(exact_energy(panda, path_file, placement, local_profile(panda, path_file, placement, gain)), gain)
                   for gain in GAINS]
        (local, speed), gain = min(results, key=lambda result: result[0][0])
        print(f"{name}: local             {local:9.4f} J  (gain {gain:g} rad/(W s); joint speeds up to {speed:.0%} of "
              f"their limits; gains tried {', '.join(f'{g:g}: {r[0]:.4f} J' for r, g in results)})")
        fixed = dict(zip(("x", "y", "z", "phi", "theta", "psi"), map(float, placement), strict=True))
        energy, _, seconds = search(panda, path_file, fixed)
        print(f"{name}: knots@locked      {energy:9.4f} J  {seconds:6.1f} s  (3 variables)")
        for knots in args.knots:
            robot = edit_redundancy(panda, {}, knots=knots)
            energy, found, seconds = search(robot, path_file)
            print(f"{name}: whole path, {knots} knot(s) {energy:9.4f} J  {seconds:6.1f} s  ({6 + knots} variables; "
                  f"joint 3 knots {np.degrees(found[6:]).round(1).tolist()} deg)")


if __name__ == "__main__":
    main()
