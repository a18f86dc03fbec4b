"""Every error placement raises for a user-facing reason derives from PlacementError, and is defined beside its
package's code in that package's ``exceptions`` module."""

import importlib
import pickle
import pkgutil
import types
import warnings

import placement
from placement.exceptions import PlacementError

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


def stray_errors(modules: list[types.ModuleType]) -> list[str]:
    """The errors defined outside the rule: not a PlacementError, or not in a module named ``exceptions``."""
    stray = []
    for module in modules:
        for cls in defined_errors(module):
            if not issubclass(cls, PlacementError):
                stray.append(f"{module.__name__}.{cls.__qualname__} does not derive from PlacementError")
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
        "TimingError": "placement.timing.exceptions"}.items()
    assert stray_errors(modules) == []


def test_the_walk_finds_an_error_defined_against_the_rule():
    module = types.ModuleType("placement.somewhere")
    exec("class FooError(ValueError):\n    pass\n\n"
         "class Holder:\n    class Inner(Exception):\n        pass\n\n"
         "class Fine(UserWarning):\n    pass\n", vars(module))
    assert stray_errors([module]) == [
        "placement.somewhere.FooError does not derive from PlacementError",
        "placement.somewhere.FooError is not defined in an exceptions module",
        "placement.somewhere.Holder.Inner does not derive from PlacementError",
        "placement.somewhere.Holder.Inner is not defined in an exceptions module"]


def test_the_public_errors_stay_importable_from_placement():
    public = [name for name in placement.__all__ if name.endswith("Error")]
    assert {"PlacementError", "InputFileError", "RobotFileError", "PathFileError", "UnknownRobotError",
            "UnreachableError", "UnknownMemberError"} <= set(public)
    assert all(issubclass(getattr(placement, name), PlacementError) for name in public)


def test_every_error_travels_between_processes_whole():
    """A worker's error reaches the caller as raised (PlacementError.__reduce__), whatever its constructor."""
    for cls in (cls for module in package_modules() for cls in defined_errors(module)):
        error = cls.__new__(cls)
        Exception.__init__(error, "what went wrong")
        error.__dict__.update(detail=[1, 2])
        copy = pickle.loads(pickle.dumps(error))
        assert type(copy) is cls and str(copy) == "what went wrong" and copy.__dict__ == {"detail": [1, 2]}
