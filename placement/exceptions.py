"""Exceptions raised by placement: the root of every error and of every warning, and those every package shares.

Every error a user can cause derives from :class:`PlacementError`, so a caller (or the command
line) can catch one type and report its message, which always says what was wrong and where.
The kinds every package shares are defined here, each directly under the root:

- :class:`InputFileError`: an input file is missing, malformed or inconsistent (located: file, field);
  the packages define its subclasses;
- :class:`SettingsError`: a setting, an option or an argument has a value it cannot take;
  :class:`UnknownMemberError` (a name no member of a plug-in family has, :mod:`placement.registry`)
  is one;
- :class:`InfeasibleError`: the request is sound but nothing satisfies it (no placement within the
  bounds, no feed profile within the limits, samples no configuration reaches);
- :class:`PluginError`: a plug-in fails to load or breaks its family's contract.
- :class:`MissingExtraError`: a feature asked for needs an extra that is not installed (also an
  ``ImportError``; :mod:`placement.distribution`).

Each package defines its own errors beside its code, in its ``exceptions`` module:

- :mod:`placement.path.exceptions`: path files, G-code programs, pose lists;
- :mod:`placement.timing.exceptions`: timing laws the objectives or the path cannot take;
- :mod:`placement.robot.exceptions`: robot files (their kinematics plug-in files too), robot names,
  assembly, example-robot-data arms;
- :mod:`placement.kinematics.exceptions`: unreachable samples (an :class:`InfeasibleError`);
- :mod:`placement.evaluation.exceptions`: a Dask cluster that cannot be used;
- :mod:`placement.workshop.exceptions`: measured logs, calibrations they cannot determine;
- :mod:`placement.cell.exceptions`: cell files;
- :mod:`placement.output.exceptions`: result files, controller exports;
- :mod:`placement.app.exceptions`: workbench actions that come too early;
- :mod:`placement.cli.exceptions`: command-line options (a :class:`SettingsError`).

Every warning placement gives for a user-facing reason derives from :class:`PlacementWarning` (a
``UserWarning``), so ``warnings.filterwarnings("ignore", category=PlacementWarning)`` silences them
all; each is defined beside the code that gives it (``EstimatesWarning`` and ``StaleSidecarWarning``
in :mod:`placement.workshop.gepetto`, ``OrientationIgnoredWarning`` in :mod:`placement.placing.transform`,
``MasslessWarning`` in :mod:`placement.robot.plausibility`, ``GcodeDialectWarning`` in
:mod:`placement.path.exceptions`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any


class PlacementError(Exception):
    """Base class of every error raised by placement for a user-facing reason.

    Errors travel between processes whole (a worker's error reaches the caller as raised).
    """

    def __reduce__(self) -> tuple[Any, ...]:
        return _rebuild, (type(self), str(self), self.__dict__)


def _rebuild(cls: type[PlacementError], message: str, attributes: dict[str, Any]) -> PlacementError:
    """An error as pickled by :meth:`PlacementError.__reduce__`, without calling its constructor."""
    error = cls.__new__(cls)
    Exception.__init__(error, message)
    error.__dict__.update(attributes)
    return error


class InputFileError(PlacementError):
    """An input file is missing, malformed or inconsistent.

    Attributes:
        path: The file at fault.
        field: Dotted path of the offending field inside the file ("" for the whole file).
        problem: What is wrong, including what was expected.
    """

    def __init__(self, path: str | Path, field: str, problem: str) -> None:
        self.path = Path(path)
        self.field = field
        self.problem = problem
        where = f"{self.path}" + (f", field '{field}'" if field else "")
        super().__init__(f"{where}: {problem}")


class SettingsError(PlacementError):
    """A setting, an option or an argument has a value it cannot take (a placement value, a bound, a name, a count,
    a shape), alone or with the others given."""


class InfeasibleError(PlacementError):
    """The request is sound, but nothing satisfies it: no placement within the bounds, no feed profile within the
    limits, samples that no configuration reaches.

    A search that finds no feasible placement among the bounds returns its result with the reason
    (``PlacementResult.infeasible``) rather than raising; this is raised where nothing can be returned.
    """


class PluginError(PlacementError):
    """A plug-in fails to load or breaks its family's contract: an installed entry point that cannot be imported,
    a member of the wrong type, a kinematics plug-in that fails or answers what its robot does not have."""


class UnknownMemberError(SettingsError):
    """A name that no member of a family has; the message lists the known names.

    A :class:`SettingsError`, not a :class:`PluginError`: the name is one the user gave (an objective, a limit, a
    solver), and no plug-in is at fault.
    """

    def __init__(self, family: str, name: str, known: list[str]) -> None:
        self.family, self.name, self.known = family, name, known
        super().__init__(f"unknown {family} '{name}': expected one of {', '.join(known) or '(none registered)'}")


class PlacementWarning(UserWarning):
    """Base class of every warning placement gives for a user-facing reason (an estimate, a stale file, a value
    ignored); the command line shows each as a ``warning: ...`` line."""


class MissingExtraError(PlacementError, ImportError):
    """A feature needs an optional package that is not installed; the message names the extra that brings it.

    Also an :class:`ImportError`, as the import it stands for (see :mod:`placement.distribution`).

    Attributes:
        feature: The feature, in the user's words (e.g. "the 3-D scene (--html, --show)").
        extra: The extra that installs what it needs (e.g. "viz").
        missing: The module that could not be imported.
    """

    def __init__(self, feature: str, extra: str, missing: str, distribution: str, reason: str) -> None:
        self.feature, self.extra, self.missing = feature, extra, missing
        super().__init__(f"{feature} needs the '{extra}' extra: pip install '{distribution}[{extra}]' ({reason})",
                         name=missing)


def listed(items: Sequence[object], most: int) -> str:
    """How a message lists names, folders or lines: up to ``most`` of them, comma-separated, then "and N more"."""
    shown = ", ".join(str(item) for item in items[:most])
    return shown + (f" and {len(items) - most} more" if len(items) > most else "")
