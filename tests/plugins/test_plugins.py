"""Plug-in families: members from an installed distribution's entry points, seen by spawned workers.

``tests/plugin_demo`` holds a distribution as pip installs one (a module and its ``.dist-info``
with ``entry_points.txt``) that adds an objective and a motor model. A fresh interpreter with it
on its path runs a parallel map under the ``spawn`` start method, where every worker must find
both members by name, and checks the numbers against the same map in one process and against
independent physics.
"""

import os
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot, sweep
from placement.contract import OBJECTIVES
from placement.drives.motors import MOTOR_MODELS, Motor, MotorModel, PowerParts, register_motor_model
from placement.exceptions import UnknownMemberError
from placement.registry import runtime_members
from tests.support.paths import EXAMPLE, PLUGIN
from tests.support.robot_copies import edited_copy, orthoglide_motor

SCRIPT = r"""
import dataclasses, json, sys
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
import numpy as np, yaml
import placement
from placement.workshop.catalog import builtin_robots_dir

assert "peak_motor_speed" in placement.OBJECTIVES.names() and "standby_pmsm" in placement.MOTOR_MODELS.names()
import shutil
folder = Path(sys.argv[1]) / "orthoglide"
shutil.copytree(builtin_robots_dir() / "orthoglide", folder)
sidecar = yaml.safe_load((folder / "orthoglide.yaml").read_text())
motor = next(iter(sidecar["drives"].values()))["motor"]
motor["model"], motor["parameters"] = "standby_pmsm", {"standby_W": 7.0}
(folder / "orthoglide.yaml").write_text(yaml.safe_dump(sidecar))
robot = placement.load_robot(folder / "orthoglide.yaml")
path = placement.load_path(sys.argv[2])
axes = {"x": np.linspace(-0.04, 0.04, 3), "y": np.linspace(-0.04, 0.04, 3)}
out = {}
signed = placement.EvaluatorSettings(regeneration="signed", time_step_s=0.005)
with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
    for objective in ("peak_motor_speed", "energy"):
        settings = dataclasses.replace(signed, objective=objective)
        spawned = placement.sweep(robot, path, axes, evaluation=settings, executor=pool)
        here = placement.sweep(robot, path, axes, evaluation=dataclasses.replace(settings, workers=1))
        out[objective] = [spawned.value.tolist(), here.value.tolist()]
stock = placement.load_robot("orthoglide")
plain = placement.sweep(stock, path, axes, evaluation=dataclasses.replace(signed, workers=1))
evaluator = placement.Evaluator(stock, path, signed)
batch = evaluator.batch(plain.placements())
out["pmsm_energy"] = plain.value.tolist()
out["speed"] = np.abs(batch.motor.speed_rad_s).max(axis=(1, 2)).reshape(3, 3).tolist()
out["duration_s"] = float(batch.interval_widths_s.sum())
print(json.dumps(out))
"""


def test_installed_members_reach_spawned_workers(tmp_path):
    import json

    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(PLUGIN), *sys.path])}
    path = EXAMPLE
    result = subprocess.run([sys.executable, "-c", SCRIPT, str(tmp_path), str(path)], capture_output=True, text=True,
                            env=environment, cwd=tmp_path, timeout=600, check=False)
    assert result.returncode == 0, result.stderr[-3000:]
    out = json.loads(result.stdout.strip().splitlines()[-1])
    spawned, here = (np.array(v) for v in out["peak_motor_speed"])
    np.testing.assert_array_equal(spawned, here)
    np.testing.assert_allclose(spawned, out["speed"], rtol=1e-12)  # the objective is the motors' peak speed
    spawned, here = (np.array(v) for v in out["energy"])
    np.testing.assert_array_equal(spawned, here)
    # With full regeneration the standby power adds exactly 7 W per drive over the path's duration.
    np.testing.assert_allclose(spawned - np.array(out["pmsm_energy"]), 3 * 7.0 * out["duration_s"], rtol=1e-9)


LIMIT_SCRIPT = r"""
import json, sys
import numpy as np
from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.evaluation.evaluator import denser
from placement.timing.optimal import SAFETY

robot, path = load_robot("orthoglide"), load_path(sys.argv[1])
placement = np.array([0.0, 0.0, -0.033, 0.0, 0.0, 0.0])
with Evaluator(robot, path, EvaluatorSettings(time_step_s=0.004, workers=1)) as evaluator:
    detail = evaluator.detail(placement)
    recheck = denser(evaluator, 4).recheck(placement[None], evaluator)
top = np.array([a.velocity_max for a in robot.actuators])
column = [i for i, label in enumerate(recheck.limits) if label.startswith("half joint speed")]
print(json.dumps({"peak_share": float((np.abs(detail.velocity) / top).max()), "safety": SAFETY,
                  "cycle_time_s": detail.duration_s, "recheck_margin": float(recheck.margins[0, column].min()),
                  "recheck_feasible": bool(recheck.feasible[0])}))
"""


def test_an_installed_limit_bounds_the_optimal_timing_law(tmp_path):
    """The demo distribution's half-joint-speed limit, installed through its entry point: the optimal timing
    law runs every joint at exactly the limit's share of the bound it may use (SAFETY), no faster, and the
    timing holds it between the samples too (the 4x denser re-check)."""
    import json

    path = tmp_path / "rect.yaml"
    rect = (EXAMPLE).read_text(encoding="utf-8")
    path.write_text(rect.replace("mode: paper", "mode: optimal"), encoding="utf-8")
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(PLUGIN), *sys.path])}
    result = subprocess.run([sys.executable, "-c", LIMIT_SCRIPT, str(path)], capture_output=True, text=True,
                            env=environment, cwd=tmp_path, timeout=600, check=False)
    assert result.returncode == 0, result.stderr[-3000:]
    out = json.loads(result.stdout.strip().splitlines()[-1])
    assert out["peak_share"] == pytest.approx(0.5 * out["safety"], rel=1e-6)  # TOPP-RA stays ~1e-8 inside a bound
    assert out["recheck_feasible"] and out["recheck_margin"] >= 0
    robot = load_robot("orthoglide")
    with Evaluator(robot, load_path(path), EvaluatorSettings(time_step_s=0.004, workers=1)) as free:
        unbounded = free.detail(np.array([0.0, 0.0, -0.033, 0.0, 0.0, 0.0]))
    top = np.array([a.velocity_max for a in robot.actuators])
    assert (np.abs(unbounded.velocity) / top).max() > 0.6  # without the limit the feed (0.66 m/s) sets the pace
    assert out["cycle_time_s"] > 1.1 * unbounded.duration_s


def test_the_installed_members_are_not_in_a_process_without_the_distribution():
    assert "peak_motor_speed" not in OBJECTIVES and "standby_pmsm" not in MOTOR_MODELS
    with pytest.raises(UnknownMemberError, match="unknown objective 'peak_motor_speed': expected one of energy"):
        OBJECTIVES.get("peak_motor_speed")


class _Silent(MotorModel):
    """A motor that draws no power at all."""

    def interval_power(self, motor: Motor, speed_rad_s, current_A, dt_s):
        zero = np.zeros_like(speed_rad_s[..., 1:])
        return PowerParts(zero, zero, zero)


def test_members_registered_at_run_time_travel_to_spawned_workers(tmp_path):
    register_motor_model("silent_for_test", _Silent())
    carried = runtime_members({"placement.motor_models": {"silent_for_test", "pmsm"}, "placement.objectives": {"energy"}})
    assert isinstance(carried["placement.motor_models"]["silent_for_test"], _Silent)
    assert carried == {"placement.motor_models": carried["placement.motor_models"], "placement.objectives": {}}
    robot = load_robot(edited_copy("orthoglide", tmp_path, lambda d: orthoglide_motor(d).update(model="silent_for_test")))
    path = load_path(EXAMPLE)
    axes = {"x": np.array([-0.02, 0.0, 0.02])}
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        spawned = sweep(robot, path, axes, executor=pool, evaluation=EvaluatorSettings(time_step_s=0.01))
    assert spawned.feasible.all() and (spawned.value == 0.0).all()
    moving = sweep(load_robot("orthoglide"), path, axes, evaluation=EvaluatorSettings(time_step_s=0.01, workers=1))
    assert (moving.value > 1.0).all()  # the same map with the stock motor draws energy


def test_a_workers_error_reaches_the_caller_whole():
    import pickle

    from placement.kinematics.exceptions import UnreachableError
    from placement.robot.exceptions import RobotFileError

    for error in (UnknownMemberError("objective", "x", ["energy"]), RobotFileError("/r.yaml", "urdf", "not found"),
                  UnreachableError([3, 4], 2, "singular")):
        copy = pickle.loads(pickle.dumps(error))
        assert type(copy) is type(error) and str(copy) == str(error) and copy.__dict__ == error.__dict__


def test_a_broken_installed_entry_spoils_only_its_own_name(tmp_path):
    """One unloadable entry point: the family still works, and that name says why it cannot load."""
    import json

    dist = tmp_path / "broken_plugin-0.1.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: broken-plugin\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text("[placement.objectives]\naaa_broken = no_such_module:thing\n"
                                           "not_an_objective = json:dumps\n")
    script = ("import json, placement\n"
              "from placement.exceptions import UnknownMemberError\n"
              "names = placement.OBJECTIVES.names()\n"
              "errors = []\n"
              "for name in ('aaa_broken', 'not_an_objective'):\n"
              "    try:\n"
              "        placement.OBJECTIVES.get(name)\n"
              "    except placement.PlacementError as error:\n"
              "        errors.append([type(error).__name__, str(error)])\n"
              "print(json.dumps([names, errors]))\n")
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=environment,
                            cwd=tmp_path, timeout=300, check=False)
    assert result.returncode == 0, result.stderr[-2000:]
    names, errors = json.loads(result.stdout.strip().splitlines()[-1])
    assert set(names) == {"cycle_time", "deflection", "deflection_rms", "dexterity", "energy", "mechanical_energy",
                          "peak_torque", "rms_current", "shaking_force", "shaking_moment", "transmission"}
    assert [kind for kind, _ in errors] == ["PluginError", "PluginError"]
    assert "'aaa_broken' installed as 'no_such_module:thing' failed to load: ModuleNotFoundError" in errors[0][1]
    assert "must be an instance of Objective" in errors[1][1]
