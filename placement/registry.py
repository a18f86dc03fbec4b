"""Registries of plug-in families: objectives, limits, motor models, regeneration policies,
transmissions, kinematics solvers and robots.

Each family has one :class:`Registry`, filled with the built-in members when their module is
imported (at the first look-up, for a registry that names that module) and with the members that
installed packages declare under the family's entry-point group (``placement.objectives``,
``placement.motor_models``, ...) the first time a name is looked up. Every process loads the same
entry points, so worker processes started by fork, forkserver or spawn see the same members; an
installed entry that fails to load makes only its own name unusable. Members registered at run
time with :meth:`Registry.register` live in one process only; :func:`runtime_members` and
:func:`restore_runtime_members` carry those a job uses to its worker process (they must then be
picklable, i.e. importable by name).
"""

from __future__ import annotations

import importlib
import threading
from importlib.metadata import entry_points
from typing import Generic, TypeVar

from placement.exceptions import PluginError, UnknownMemberError

Member = TypeVar("Member")
_REGISTRIES: dict[str, Registry] = {}


class Registry(Generic[Member]):
    """Named members of one plug-in family.

    Args:
        family: What a member is, for messages ("objective", "motor model", ...).
        group: The entry-point group whose entries are members: each entry's name is the member's
            name and its object the member.
        kind: What every member must be: an instance of this class (``instances=True``) or a
            subclass of it, checked as it is added, registered or loaded.
        instances: Whether members are instances (objectives, motor models) or classes (solvers).
        builtins: The module that adds the built-in members, imported at the first look-up, when the family's
            base lives below its members (the objectives and limits, whose bases are :mod:`placement.contract`).
    """

    def __init__(self, family: str, group: str, kind: type | None = None, instances: bool = True,
                 builtins: str | None = None) -> None:
        self.family = family
        self.group = group
        self.kind = kind
        self.instances = instances
        self.builtins = builtins
        self._members: dict[str, Member] = {}
        self._runtime: dict[str, Member] = {}
        self._broken: dict[str, str] = {}  # installed entries that failed to load: name -> why
        self._lock = threading.Lock()
        self._entry_points_loaded = False
        _REGISTRIES[group] = self

    def add(self, name: str, member: Member) -> Member:
        """Register a built-in member (at import of the module that defines it); returns it."""
        self._members[name] = self._checked(name, member)
        return member

    def register(self, name: str, member: Member) -> None:
        """Register a member at run time, in this process (see :func:`runtime_members`)."""
        self._members[name] = self._runtime[name] = self._checked(name, member)

    def get(self, name: str) -> Member:
        """The member called ``name``.

        Raises:
            UnknownMemberError: No member has that name (the message lists the known ones).
            PluginError: The installed package that declares it failed to load it.
        """
        self._load_entry_points()
        if name in self._broken:
            raise PluginError(self._broken[name])
        if name not in self._members:
            raise UnknownMemberError(self.family, name, self.names())
        return self._members[name]

    def names(self) -> list[str]:
        """Names of every usable member: built-in ones in the order they were added, then installed ones."""
        self._load_entry_points()
        return list(self._members)

    def __contains__(self, name: object) -> bool:
        self._load_entry_points()
        return name in self._members

    def _checked(self, name: str, member: Member) -> Member:
        if self.kind is None:
            return member
        fits = isinstance(member, self.kind) if self.instances else (isinstance(member, type)
                                                                     and issubclass(member, self.kind))
        if not fits:
            what = f"an instance of {self.kind.__name__}" if self.instances else f"a subclass of {self.kind.__name__}"
            raise PluginError(f"the {self.family} '{name}' must be {what}, got {type(member).__name__} "
                              f"{str(member)[:60]}")
        return member

    def _load_entry_points(self) -> None:
        if self._entry_points_loaded:
            return
        if self.builtins is not None:
            importlib.import_module(self.builtins)  # its members first, in the order it adds them
        with self._lock:
            if self._entry_points_loaded:
                return
            for entry in entry_points(group=self.group):
                if entry.name in self._members:
                    continue
                try:
                    self._members[entry.name] = self._checked(entry.name, entry.load())
                except Exception as error:  # an installed plug-in's own failure: only its name is unusable
                    self._broken[entry.name] = (f"the {self.family} '{entry.name}' installed as '{entry.value}' "
                                                f"failed to load: {type(error).__name__}: {str(error)[:200]}")
            self._entry_points_loaded = True


def runtime_members(used: dict[str, set[str]]) -> dict[str, dict[str, object]]:
    """The members registered at run time in this process that a job uses, to send to workers.

    Args:
        used: Names used, by entry-point group.
    """
    return {group: {name: _REGISTRIES[group]._runtime[name] for name in names if name in _REGISTRIES[group]._runtime}
            for group, names in used.items() if group in _REGISTRIES}


def restore_runtime_members(members: dict[str, dict[str, object]]) -> None:
    """Register, in a worker process, the members :func:`runtime_members` gave in the parent."""
    for group, named in members.items():
        for name, member in named.items():
            _REGISTRIES[group].register(name, member)
