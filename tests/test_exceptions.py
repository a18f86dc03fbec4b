"""Every error placement raises for a user-facing reason derives from PlacementError, and is defined beside its
package's code in that package's ``exceptions`` module; every warning it gives derives from PlacementWarning.

No error is raised as a bare PlacementError: each is of a named kind a caller can catch (an infeasible request, a
setting it cannot take, a broken plug-in, ...). The G-code reader's own errors are private and never leave it.
"""

import ast
import importlib
import pickle
import pkgutil
import types
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml

import placement
from placement.exceptions import InfeasibleError, PlacementError, PlacementWarning, PluginError, SettingsError

PACKAGE = Path(placement.__file__).parent

DEPRECATED = {"placement.batch", "placement.taylor"}  # old paths that only re-export, with a warning


def package_modules() -> list[types.ModuleType]:
    """Every module of the package, imported."""
    modules = [placement]
    for info in pkgutil.walk_packages(placement.__path__, "placement."):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            modules.append(importlib.import_module(info.name))
    return modules


def defined_errors(module: types.ModuleType) -> list[type[BaseException]]:
    """The exception classes (warnings aside) that ``module`` defines, at its top level or nested in its classes."""
    found, seen = [], set()
    pending = [value for value in vars(module).values() if isinstance(value, type)]
    while pending:
        cls = pending.pop()
        if cls in seen or cls.__module__ != module.__name__:
            continue
        seen.add(cls)
        if issubclass(cls, BaseException) and not issubclass(cls, Warning):
            found.append(cls)
        pending.extend(value for value in vars(cls).values() if isinstance(value, type))
    return sorted(found, key=lambda cls: cls.__qualname__)


def is_private(cls: type) -> bool:
    """A class its package keeps to itself (its name starts with ``_``)."""
    return cls.__name__.startswith("_")


def stray_errors(modules: list[types.ModuleType]) -> list[str]:
    """The errors defined outside the rule: not in a module named ``exceptions``; public and not a PlacementError, or
    private (kept inside its package, turned into a located public error there) and a PlacementError, which a caller
    catching PlacementError would then meet."""
    stray = []
    for module in modules:
        for cls in defined_errors(module):
            if not is_private(cls) and not issubclass(cls, PlacementError):
                stray.append(f"{module.__name__}.{cls.__qualname__} does not derive from PlacementError")
            if is_private(cls) and issubclass(cls, PlacementError):
                stray.append(f"{module.__name__}.{cls.__qualname__} is private but derives from PlacementError")
            if module.__name__.rpartition(".")[2] != "exceptions":
                stray.append(f"{module.__name__}.{cls.__qualname__} is not defined in an exceptions module")
    return stray


def test_every_error_of_the_package_is_a_placement_error_defined_in_an_exceptions_module():
    modules = package_modules()
    homes = {cls.__name__: module.__name__ for module in modules for cls in defined_errors(module)}
    assert homes.items() >= {
        "PlacementError": "placement.exceptions", "InputFileError": "placement.exceptions",
        "UnknownMemberError": "placement.exceptions", "PathFileError": "placement.path.exceptions",
        "GcodeError": "placement.path.exceptions", "PoseFileError": "placement.path.exceptions",
        "RobotFileError": "placement.robot.exceptions", "UnknownRobotError": "placement.robot.exceptions",
        "AssemblyError": "placement.robot.exceptions", "ExampleRobotError": "placement.robot.exceptions",
        "CellFileError": "placement.cell.exceptions", "UnreachableError": "placement.kinematics.exceptions",
        "LogFileError": "placement.workshop.exceptions", "UsageError": "placement.cli.exceptions",
        "TimingError": "placement.timing.exceptions", "SettingsError": "placement.exceptions",
        "InfeasibleError": "placement.exceptions", "PluginError": "placement.exceptions",
        "ClusterError": "placement.evaluation.exceptions", "CalibrationError": "placement.workshop.exceptions",
        "NotReadyError": "placement.app.exceptions", "KinematicsPluginError": "placement.robot.exceptions",
        "_ReaderError": "placement.path.exceptions", "_CycleError": "placement.path.exceptions",
        "_ExpressionError": "placement.path.exceptions", "_FlowError": "placement.path.exceptions"}.items()
    assert stray_errors(modules) == []


def test_the_kinds_sit_where_a_caller_looks_for_them():
    """A shallow tree: each kind directly under the root; the few errors of two kinds say so."""
    from placement.cli.exceptions import UsageError
    from placement.exceptions import InputFileError, UnknownMemberError
    from placement.kinematics.exceptions import UnreachableError
    from placement.robot.exceptions import KinematicsPluginError, RobotFileError

    for kind in (InputFileError, SettingsError, InfeasibleError, PluginError):
        assert kind.__bases__ == (PlacementError,)
    assert issubclass(UnreachableError, InfeasibleError)
    assert issubclass(UsageError, SettingsError) and issubclass(UnknownMemberError, SettingsError)
    assert not issubclass(UnknownMemberError, PluginError)  # a name the user gave: no plug-in is at fault
    assert KinematicsPluginError.__bases__ == (RobotFileError, PluginError)


def test_the_walk_finds_an_error_defined_against_the_rule():
    module = types.ModuleType("placement.somewhere")
    exec("from placement.exceptions import PlacementError\n\n"
         "class FooError(ValueError):\n    pass\n\n"
         "class Holder:\n    class Inner(Exception):\n        pass\n\n"
         "class _Kept(Exception):\n    pass\n\n"
         "class _Leaked(PlacementError):\n    pass\n\n"
         "class Fine(UserWarning):\n    pass\n", vars(module))
    assert stray_errors([module]) == [
        "placement.somewhere.FooError does not derive from PlacementError",
        "placement.somewhere.FooError is not defined in an exceptions module",
        "placement.somewhere.Holder.Inner does not derive from PlacementError",
        "placement.somewhere.Holder.Inner is not defined in an exceptions module",
        "placement.somewhere._Kept is not defined in an exceptions module",
        "placement.somewhere._Leaked is private but derives from PlacementError",
        "placement.somewhere._Leaked is not defined in an exceptions module"]


def test_the_public_errors_stay_importable_from_placement():
    public = [name for name in placement.__all__ if name.endswith("Error")]
    assert {"PlacementError", "InputFileError", "RobotFileError", "PathFileError", "UnknownRobotError",
            "UnreachableError", "UnknownMemberError", "SettingsError", "InfeasibleError", "PluginError",
            "MissingExtraError"} <= set(public)
    assert all(issubclass(getattr(placement, name), PlacementError) for name in public)
    assert "PlacementWarning" in placement.__all__ and placement.PlacementWarning is PlacementWarning


def test_every_error_travels_between_processes_whole():
    """A worker's error reaches the caller as raised (PlacementError.__reduce__), whatever its constructor (the
    private errors never leave their package, let alone their process)."""
    errors = [cls for module in package_modules() for cls in defined_errors(module) if not is_private(cls)]
    assert len(errors) >= 20
    for cls in errors:
        error = cls.__new__(cls)
        Exception.__init__(error, "what went wrong")
        error.__dict__.update(detail=[1, 2])
        copy = pickle.loads(pickle.dumps(error))
        assert type(copy) is cls and str(copy) == "what went wrong" and copy.__dict__ == {"detail": [1, 2]}


# --- warnings ----------------------------------------------------------------------------------------------

def defined_warnings(modules: list[types.ModuleType]) -> dict[str, type[Warning]]:
    """The warning classes the modules define, by qualified name."""
    return {f"{module.__name__}.{value.__qualname__}": value for module in modules for value in vars(module).values()
            if isinstance(value, type) and issubclass(value, Warning) and value.__module__ == module.__name__}


def warning_categories(file: Path) -> list[tuple[int, str]]:
    """The category of every ``warnings.warn`` / ``warnings.warn_explicit`` call in ``file``, as written ("" when the
    call leaves it out: a UserWarning)."""
    found = []
    for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in ("warn", "warn_explicit") \
                and isinstance(node.func.value, ast.Name) and node.func.value.id == "warnings":
            given = [k.value for k in node.keywords if k.arg == "category"] or node.args[1:2]
            found.append((node.lineno, ast.unparse(given[0]) if given else ""))
    return found


def test_every_warning_of_the_package_is_a_placement_warning():
    found = defined_warnings(package_modules())
    assert {"placement.exceptions.PlacementWarning", "placement.workshop.gepetto.EstimatesWarning",
            "placement.workshop.gepetto.StaleSidecarWarning",
            "placement.placing.transform.OrientationIgnoredWarning",
            "placement.path.exceptions.GcodeDialectWarning"} <= set(found)
    assert PlacementWarning.__bases__ == (UserWarning,)
    assert [name for name, cls in found.items() if not issubclass(cls, PlacementWarning)] == []


def test_every_warning_given_is_of_a_placement_warning_category():
    """Each ``warnings.warn`` names a PlacementWarning subclass the module defines or imports (none leaves it out)."""
    calls = 0
    for file in sorted(PACKAGE.rglob("*.py")):
        parts = file.relative_to(PACKAGE.parent).with_suffix("").parts
        module = importlib.import_module(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
        for line, category in warning_categories(file):
            calls += 1
            cls = getattr(module, category, None) if category.isidentifier() else None
            assert isinstance(cls, type) and issubclass(cls, PlacementWarning), f"{file}:{line}: category {category or '(none)'}"
    assert calls >= 3


def test_the_category_finder_sees_a_call_without_category(tmp_path):
    file = tmp_path / "module.py"
    file.write_text("import warnings\nwarnings.warn('a')\nwarnings.warn('b', category=FooWarning)\n"
                    "warnings.warn_explicit('c', BarWarning, 'f', 0)\n")
    assert warning_categories(file) == [(2, ""), (3, "FooWarning"), (4, "BarWarning")]


def test_the_command_line_shows_every_placement_warning_on_one_line():
    from placement.cli import _format_warning
    from placement.path.exceptions import GcodeDialectWarning
    from placement.placing.transform import OrientationIgnoredWarning
    from placement.workshop.gepetto import EstimatesWarning, StaleSidecarWarning

    for category in (PlacementWarning, EstimatesWarning, StaleSidecarWarning, OrientationIgnoredWarning,
                     GcodeDialectWarning):
        assert _format_warning(category("what was estimated"), category, "robot.yaml", 0) == "warning: what was estimated\n"
    assert _format_warning(UserWarning("other"), UserWarning, "x.py", 3).startswith("x.py:3: UserWarning: other")


# --- no bare PlacementError --------------------------------------------------------------------------------

def bare_placement_errors(file: Path, root: Path) -> list[str]:
    """Where ``file`` makes a PlacementError itself (``raise PlacementError(...)``, or one built to raise later)
    rather than an error of a named kind."""
    def is_root(node: ast.expr) -> bool:
        return isinstance(node, ast.Name | ast.Attribute) and ast.unparse(node).rpartition(".")[2] == "PlacementError"

    found = [node for node in ast.walk(ast.parse(file.read_text(encoding="utf-8")))
             if (isinstance(node, ast.Call) and is_root(node.func))
             or (isinstance(node, ast.Raise) and node.exc is not None and is_root(node.exc))]
    return [f"{file.relative_to(root)}:{node.lineno}: {ast.unparse(node)[:80]}" for node in sorted(found, key=lambda n: n.lineno)]


def test_no_error_is_raised_as_a_bare_placement_error():
    files = sorted(PACKAGE.rglob("*.py"))
    assert len(files) > 100
    bare = [where for file in files for where in bare_placement_errors(file, PACKAGE.parent)]
    assert bare == [], "raise an error of a named kind (placement/exceptions.py lists them):\n" + "\n".join(bare)


def test_the_bare_error_finder_finds_one(tmp_path):
    file = tmp_path / "module.py"
    file.write_text("from placement import exceptions\nfrom placement.exceptions import PlacementError, SettingsError\n"
                    "def f(x):\n    if x:\n        raise PlacementError(f'bad {x}')\n"
                    "    error = exceptions.PlacementError('later')\n    raise SettingsError('fine')\n\n"
                    "def g():\n    raise PlacementError\n")
    assert bare_placement_errors(file, tmp_path) == ["module.py:5: PlacementError(f'bad {x}')",
                                                     "module.py:6: exceptions.PlacementError('later')",
                                                     "module.py:10: raise PlacementError"]


# --- the G-code reader's private errors ----------------------------------------------------------------------

def test_the_reader_s_private_errors_are_named_only_inside_the_path_package():
    private = ("_ReaderError", "_CycleError", "_ExpressionError", "_FlowError")
    outside = [f"{file.relative_to(PACKAGE.parent)}: {name}" for file in sorted(PACKAGE.rglob("*.py"))
               if PACKAGE / "path" not in file.parents for name in private if name in file.read_text(encoding="utf-8")]
    assert outside == []


@pytest.mark.parametrize("program, located, private", [
    ("G0 X0 Y0 Z5\nG81 X1 Y1 R2 F100\n", "line 2, word 'G81': a canned cycle needs the bottom of the hole (Z)",
     "_CycleError"),
    ("G0 X0 Y0 Z0\nG1 X1 F100 (open\n", "line 2: the comment opened by '(' is not closed", "_ExpressionError"),  # read
    ("#1 = 0\nG0 X[1/#1] Y0 Z0\nG1 X1 F100\n", "line 2, word '/': division by zero", "_FlowError"),  # run
    ("G0 X0 Y0 Z0\nO100 if [1]\nG1 X1 F100\n", "line 2, word 'O100IF[1]': O100 if has no matching endif",
     "_FlowError"),
])
def test_a_program_the_reader_refuses_is_a_located_gcode_error(program, located, private, tmp_path):
    """Each private error of the reader becomes a GcodeError naming the file, line and word (its own is only the
    context of that one)."""
    from placement.path.exceptions import GcodeError
    from placement.path.gcode import read_program

    file = tmp_path / "part.nc"
    file.write_text(program)
    with pytest.raises(PlacementError) as caught:
        read_program(file)
    assert type(caught.value) is GcodeError and str(caught.value).startswith(f"{file}, {located}")
    assert type(caught.value.__context__).__name__ == private and caught.value.__suppress_context__


# --- a real bad input raises its kind ----------------------------------------------------------------------

def test_a_search_whose_path_cannot_be_placed_anywhere_is_infeasible(tmp_path):
    from placement.cell.cell_file import load_cell
    from placement.robot.equip import equip

    cell = tmp_path / "cell.yaml"
    cell.write_text(yaml.safe_dump({"workpiece_region": {"min_m": [5.0, 5.0, 5.0], "max_m": [6.0, 6.0, 6.0]}}))
    robot = equip(placement.load_robot("orthoglide"), load_cell(cell))
    with pytest.raises(InfeasibleError, match="the cell's workpiece region .* does not meet the placement bounds"):
        placement.optimize_placement(robot, placement.load_path("examples/rect.yaml"))


def test_a_path_out_of_reach_is_infeasible():
    robot = placement.load_robot("orthoglide")
    task = placement.TaskTrajectory(position_m=np.tile([5.0, 0.0, 0.0], (5, 1)), velocity_m_s=np.zeros((5, 3)),
                                    acceleration_m_s2=np.zeros((5, 3)))
    with pytest.raises(InfeasibleError, match="5 sample"):
        placement.joint_trajectory(robot, task)


def test_settings_a_search_cannot_take_are_a_settings_error():
    robot = placement.load_robot("orthoglide")
    with pytest.raises(SettingsError, match="the margin kept from every limit must be a share from 0 to 1, got 2"):
        placement.EvaluatorSettings(margin=2)
    with pytest.raises(SettingsError, match=r"unknown placement variable\(s\) \['w'\]"):
        placement.default_space(robot, free=("x", "w"))
    with pytest.raises(SettingsError, match="unknown objective 'energi'"):  # an UnknownMemberError
        placement.optimize_placement(robot, placement.load_path("examples/rect.yaml"),
                                     evaluation=placement.EvaluatorSettings(objective="energi"))


def test_a_member_of_the_wrong_type_is_a_plugin_error():
    with pytest.raises(PluginError, match="the objective 'not_an_objective' must be an instance of Objective, got"):
        placement.OBJECTIVES.register("not_an_objective", len)
    assert "not_an_objective" not in placement.OBJECTIVES


def test_a_kinematics_plugin_that_fails_is_a_located_plugin_error(tmp_path):
    from tests.support.robot_copies import edited_copy

    sidecar = edited_copy("orthoglide", tmp_path, lambda document: None)
    plugin = sidecar.parent / "closed_form.py"
    plugin.write_text("raise RuntimeError('no solver here')\n")
    with pytest.raises(PluginError) as caught:
        placement.load_robot(sidecar)
    assert isinstance(caught.value, placement.RobotFileError) and caught.value.path == plugin
    assert str(caught.value) == f"{plugin}: the kinematics plug-in failed to load: RuntimeError: no solver here"


def test_an_unreachable_scheduler_is_a_cluster_error(monkeypatch):
    """Dask's distributed package installed, the scheduler cannot be reached (without the package: a
    MissingExtraError naming the cluster extra, tests/test_extras.py)."""
    from placement.evaluation.exceptions import ClusterError
    from placement.evaluation.parallel import cluster

    monkeypatch.setattr("placement.evaluation.parallel.CONNECT_TIMEOUT_S", 1.0)
    with pytest.raises(ClusterError, match="Dask"), cluster("tcp://127.0.0.1:9"):
        pass


def test_a_log_that_cannot_determine_a_constant_is_a_calibration_error():
    from placement.workshop.calibration import MeasuredLog, calibrate
    from placement.workshop.exceptions import CalibrationError

    robot, t = placement.load_robot("orthoglide"), np.linspace(0.0, 1.0, 50)
    log = MeasuredLog(t, np.zeros((50, 3)), None, {"current": np.zeros((50, 3))})
    with pytest.raises(CalibrationError, match="resistance_ohm cannot be fitted to currents alone"):
        calibrate(robot, log, ["resistance_ohm"])
    with pytest.raises(SettingsError, match="constants to fit: expected some of"):
        calibrate(robot, log, ["colour"])


def test_a_workbench_action_before_its_result_is_not_ready():
    from placement.app.exceptions import NotReadyError
    from placement.app.searches import FrontPanel, MapPanel, OptimisePanel

    with pytest.raises(NotReadyError, match="no best placement yet: optimise first"):
        OptimisePanel.go_to(types.SimpleNamespace(optima={}), "best")
    with pytest.raises(NotReadyError, match="no map with a feasible placement yet: map first"):
        MapPanel.go_to_best(types.SimpleNamespace(best=None))
    with pytest.raises(NotReadyError, match="no front yet: search the front first"):
        FrontPanel.go_to_member(types.SimpleNamespace(member=types.SimpleNamespace(value=None, options=[]), members=[]))
