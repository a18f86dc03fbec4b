"""Registries of plug-in families: objectives, limits, motor models, regeneration policies,
transmissions, kinematics solvers and robots.

Each family has one :class:`Registry`, filled with the built-in members when its module is
imported and with the members that installed packages declare under the family's entry-point
group (``placement.objectives``, ``placement.motor_models``, ...) the first time a name is looked
up. Every process loads the same entry points, so worker processes started by fork, forkserver or
spawn see the same members. Members registered at run time with :meth:`Registry.register` live in
one process only; :func:`runtime_members` and :func:`restore_runtime_members` carry them to worker
processes (the members must be picklable, i.e. importable by name).
"""

from __future__ import annotations

from collections.abc import Iterator
from importlib.metadata import entry_points
from typing import Generic, TypeVar

from placement.exceptions import PlacementError

Member = TypeVar("Member")
_REGISTRIES: dict[str, Registry] = {}


class UnknownMemberError(PlacementError):
    """A name that no member of a family has; the message lists the known names."""

    def __init__(self, family: str, name: str, known: list[str]) -> None:
        self.family, self.name, self.known = family, name, known
        super().__init__(f"unknown {family} '{name}': expected one of {', '.join(known) or '(none registered)'}")


class Registry(Generic[Member]):
    """Named members of one plug-in family.

    Args:
        family: What a member is, for messages ("objective", "motor model", ...).
        group: The entry-point group whose entries are members: each entry's name is the member's
            name and its object the member.
    """

    def __init__(self, family: str, group: str) -> None:
        self.family = family
        self.group = group
        self._members: dict[str, Member] = {}
        self._runtime: dict[str, Member] = {}
        self._entry_points_loaded = False
        _REGISTRIES[group] = self

    def add(self, name: str, member: Member) -> Member:
        """Register a built-in member (at import of the module that defines it); returns it."""
        self._members[name] = member
        return member

    def register(self, name: str, member: Member) -> None:
        """Register a member at run time, in this process (see :func:`runtime_members`)."""
        self._members[name] = member
        self._runtime[name] = member

    def get(self, name: str) -> Member:
        """The member called ``name``.

        Raises:
            UnknownMemberError: No member has that name (the message lists the known ones).
        """
        self._load_entry_points()
        if name not in self._members:
            raise UnknownMemberError(self.family, name, self.names())
        return self._members[name]

    def names(self) -> list[str]:
        """Names of every member: built-in ones in the order they were added, then installed ones."""
        self._load_entry_points()
        return list(self._members)

    def __contains__(self, name: object) -> bool:
        self._load_entry_points()
        return name in self._members

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def _load_entry_points(self) -> None:
        if self._entry_points_loaded:
            return
        self._entry_points_loaded = True
        for entry in entry_points(group=self.group):
            if entry.name not in self._members:
                try:
                    self._members[entry.name] = entry.load()
                except Exception as error:  # an installed plug-in's own failure
                    raise PlacementError(f"the {self.family} '{entry.name}' installed as '{entry.value}' failed to "
                                         f"load: {type(error).__name__}: {error}") from None


def runtime_members() -> dict[str, dict[str, object]]:
    """Members registered at run time in this process, by entry-point group (to send to workers)."""
    return {group: dict(registry._runtime) for group, registry in _REGISTRIES.items() if registry._runtime}


def restore_runtime_members(members: dict[str, dict[str, object]]) -> None:
    """Register, in a worker process, the members :func:`runtime_members` gave in the parent."""
    for group, named in members.items():
        for name, member in named.items():
            _REGISTRIES[group].register(name, member)
