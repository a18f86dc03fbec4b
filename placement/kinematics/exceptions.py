"""Errors of the kinematics: samples of a trajectory that no robot configuration reaches."""

from __future__ import annotations

from placement.exceptions import InfeasibleError


class UnreachableError(InfeasibleError):
    """Some samples of a task-space trajectory have no valid robot configuration (at this placement, nothing
    reaches them: an :class:`~placement.exceptions.InfeasibleError`).

    Attributes:
        sample_indices: Indices of the unreachable samples (at most the first 20 are kept).
        n_unreachable: How many samples are unreachable.
        reason: Why the first one failed.
    """

    def __init__(self, sample_indices: list[int], n_unreachable: int, reason: str) -> None:
        self.sample_indices = sample_indices[:20]
        self.n_unreachable = n_unreachable
        self.reason = reason
        super().__init__(
            f"{n_unreachable} sample(s) unreachable, first at index {sample_indices[0]}: {reason}"
        )
