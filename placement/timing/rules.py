"""Which timing law times a path: the one its objectives need, and the overrides of the path file's.

An objective may need a timing law (:attr:`placement.contract.objective.Objective.timing`): the cycle
time needs the optimal law, under which each placement is timed as fast as the robot allows, since
under the others every placement takes the same time. The rule is stated once here: the command
line times a path by the law its objectives need (:func:`timing_for`), and an evaluator refuses a
path timed otherwise (:func:`check_timing`). :func:`override_timing` applies the command line's
``--timing``, ``--max-acceleration`` and ``--max-jerk`` to a path.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from pydantic import ValidationError

from placement.contract.objective import OBJECTIVES
from placement.path.path_file import Timing
from placement.path.toolpath import ToolPath
from placement.timing.exceptions import TimingError

OPTIONS = {"mode": "--timing", "max_acceleration_m_s2": "--max-acceleration", "max_jerk_m_s3": "--max-jerk"}


def needed_timing(objectives: Sequence[str]) -> str | None:
    """The timing law the objectives need (cycle_time: optimal), or None when any law will do.

    Raises:
        UnknownMemberError: An objective's name is unknown.
        TimingError: Two objectives need different laws.
    """
    needs = {name: OBJECTIVES.get(name).timing for name in objectives}
    laws = sorted({law for law in needs.values() if law is not None})
    if len(laws) > 1:
        raise TimingError(f"{_needing(objectives)} need different timing laws ({', '.join(laws)}): rank by one of them")
    return laws[0] if laws else None


def timing_for(objectives: Sequence[str], requested: str | None, path: ToolPath) -> tuple[str | None, str | None]:
    """The timing law to time ``path`` by for ``objectives``, given the law requested (None: the path file's).

    Returns:
        The law (None: the path file's own stands) and, when the objectives need a law that the
        path file does not give and none was requested, why it is taken instead ("the objective
        cycle_time needs the optimal timing law"), else None.

    Raises:
        TimingError: The law requested is not the one the objectives need.
        UnknownMemberError: An objective's name is unknown.
    """
    needed = needed_timing(objectives)
    if needed is None or (requested or path.timing.mode) == needed:
        return requested, None
    if requested is not None:
        raise TimingError(f"--timing {requested}: {_needing(objectives)} needs --timing {needed}")
    return needed, f"{_needing(objectives)} needs the {needed} timing law"


def check_timing(objectives: Sequence[str], path: ToolPath) -> None:
    """Refuse a path that is not timed by the law its objectives need.

    Raises:
        TimingError: An objective needs another law than the path's (the message names the first).
        UnknownMemberError: An objective's name is unknown.
    """
    needed = needed_timing(objectives)
    if needed is not None and needed != path.timing.mode:
        name = next(name for name in objectives if OBJECTIVES.get(name).timing == needed)
        raise TimingError(f"the objective '{name}' needs the {needed} timing law (--timing {needed}, or timing: "
                          f"{{mode: {needed}}} in the path file); the path '{path.name}' is timed by the "
                          f"{path.timing.mode} law")


def override_timing(path: ToolPath, mode: str | None = None, max_acceleration_m_s2: float | None = None,
                    max_jerk_m_s3: float | None = None) -> ToolPath:
    """``path`` timed by ``mode`` with these bounds (the command line's ``--timing``, ``--max-acceleration`` and
    ``--max-jerk``); what is None stays the path file's.

    Raises:
        TimingError: The law that results is not valid (a realistic law without both bounds); the
            message names the command-line option at fault.
    """
    if mode is None and max_acceleration_m_s2 is None and max_jerk_m_s3 is None:
        return path
    timing = path.timing
    try:
        timing = Timing.model_validate({
            "mode": mode if mode is not None else timing.mode,
            "max_acceleration_m_s2": max_acceleration_m_s2 if max_acceleration_m_s2 is not None
            else timing.max_acceleration_m_s2,
            "max_jerk_m_s3": max_jerk_m_s3 if max_jerk_m_s3 is not None else timing.max_jerk_m_s3})
    except ValidationError as error:
        problem = error.errors()[0]
        option = OPTIONS.get(str(problem["loc"][0]) if problem["loc"] else "", "--timing")
        raise TimingError(f"{option}: {problem['msg'].removeprefix('Value error, ')}; the realistic timing law "
                          "needs --max-acceleration and --max-jerk > 0, or both in the path file") from None
    return dataclasses.replace(path, timing=timing)


def _needing(objectives: Sequence[str]) -> str:
    """The objectives that need a timing law, for a message ("the objective cycle_time")."""
    names = [name for name in objectives if OBJECTIVES.get(name).timing is not None]
    return f"the objective{'s' if len(names) > 1 else ''} {', '.join(names)}"
