"""What the paper and realistic timing laws read of a path.

:class:`placement.path.toolpath.ToolPath` is such a path; it samples itself by calling the laws,
so the laws name what they need here instead of importing it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    import numpy as np

    from placement.path.path_file import Timing
    from placement.path.samples import PathSamples
    from placement.path.segments import Hold, Run, Segment


class TimedPath(Protocol):
    """A path's segments, feeds and timing bounds, and the sampling steps a timing law builds on."""

    @property
    def segments(self) -> tuple[Segment, ...]:
        """The segments, in order (m)."""

    @property
    def timing(self) -> Timing:
        """The timing law and its bounds."""

    @property
    def time_step_s(self) -> float:
        """The path file's sampling step (s)."""

    @property
    def holds(self) -> tuple[Hold, ...]:
        """Where the tool rests for a while (dwells), in order."""

    @property
    def oriented(self) -> bool:
        """Whether the path carries tool orientations."""

    def speed_m_s(self, segment: Segment) -> float:
        """The feed a segment is run at."""

    def motion(self, index: np.ndarray, s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray) -> dict[str, np.ndarray]:
        """Each sample's motion on its own segment ``index`` at arc length ``s`` from its start, all at once."""

    def runs(self, by_segment: bool = False) -> list[Run]:
        """The runs between stops, or each segment on its own."""

    def hold_parts(self, after: int, start_s: float, piece: int) -> tuple[list[dict[str, np.ndarray]], float, int]:
        """The samples of the holds (dwells) after segment ``after`` - 1, each a piece of its own."""

    def sample_counts(self, durations_s: list[float], step: float) -> list[int]:
        """Samples of each independently timed piece (and the checks of the sampling step)."""

    def assemble(self, parts: list[dict[str, np.ndarray]]) -> PathSamples:
        """Samples from their parts, with each sample's process force."""
