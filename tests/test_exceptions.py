"""Every error placement raises for a user-facing reason derives from PlacementError, and is defined beside its
package's code in that package's ``exceptions`` module. The G-code reader's own errors are private (a leading ``_``),
no PlacementErrors, and never leave it."""

import importlib
import pickle
import pkgutil
import types
import warnings
from pathlib import Path

import pytest

import placement
from placement.exceptions import PlacementError

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
        "TimingError": "placement.timing.exceptions", "_ReaderError": "placement.path.exceptions",
        "_CycleError": "placement.path.exceptions", "_ExpressionError": "placement.path.exceptions",
        "_FlowError": "placement.path.exceptions"}.items()
    assert stray_errors(modules) == []


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
            "UnreachableError", "UnknownMemberError"} <= set(public)
    assert all(issubclass(getattr(placement, name), PlacementError) for name in public)


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
