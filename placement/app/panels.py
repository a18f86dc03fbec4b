"""What the workbench's panels share: the page they live in, a long computation's controls, figures as images.

A panel is built inside the page's current GUI folder from a :class:`Host` (the page: its bench,
its server, the current placement, how to go to another and how to answer an action), so that no
panel knows the page's own class.
"""

from __future__ import annotations

import html
import threading
from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np
import viser  # optional dependency: the [app] extra, checked by placement.app
from matplotlib.figure import Figure  # optional dependency: the [app] extra, checked by placement.app

from placement.app.evaluations import Bench
from placement.app.exceptions import NotReadyError
from placement.app.jobs import Job


class Host(Protocol):
    """The page, as its panels use it."""

    bench: Bench
    server: viser.ViserServer
    placement: np.ndarray

    def guard(self, action: Callable[[], None], beside: JobPanel | None = None) -> None:
        """Run a page action; what goes wrong is said in the page (in ``beside``'s state line if given)."""

    def acted(self, event: object, action: Callable[[], None], beside: JobPanel | None = None) -> None:
        """Run a tab's action on the texts its fields show (read from the tab first)."""

    def set_placement(self, placement: np.ndarray, exact: bool, move_gizmo: bool = True) -> None:
        """Go to a placement (m, rad)."""

    def frame_workpiece(self) -> None:
        """Every tab's camera on the placed path."""


class JobPanel(ABC):
    """A start button, Cancel, a progress bar and a state line (``id="KEY-state"``) around one job at a time.

    Args:
        host: The page.
        start_label: The start button's text.
        key: The state line's id prefix.
        what: The computation, as a message names it ("a map").
        steps: What its steps are ("generations"), as its state line counts them.
    """

    def __init__(self, host: Host, start_label: str, key: str, what: str, steps: str) -> None:
        gui: Any = host.server.gui
        self.host, self.key, self.what, self.steps = host, key, what, steps
        self.job: Job | None = None
        self.start_label = start_label
        self.has_result = False  # a result is shown (it may have gone stale)
        self.start_button = gui.add_button(start_label)
        self.cancel_button = gui.add_button(f"Cancel {key}", disabled=True, hint=f"stop {what} at once")
        self.progress = gui.add_progress_bar(0.0, visible=False)
        self.state = gui.add_html("")
        self.start_button.on_click(lambda event: host.acted(event, self._start, beside=self))
        self.cancel_button.on_click(lambda _: host.guard(self.cancel))

    @abstractmethod
    def launch(self) -> Job:
        """Start the job from the panel's fields (a PlacementError if they are not valid)."""

    @abstractmethod
    def finished(self, result: Any) -> None:
        """Show the job's result."""

    def say(self, text: str, error: bool = False, stale: bool = False) -> None:
        """The state line (red for an error, amber for a stale result)."""
        style = ' style="color:#c00"' if error else ' style="color:#b36b00"' if stale else ""
        self.state.content = f'<p id="{self.key}-state"{style}>{html.escape(text)}</p>'

    def mark_stale(self, reason: str) -> None:
        """The result shown no longer answers the page: said on its state line (the result stays visible)."""
        if self.has_result and self.job is None:
            self.say(f"stale: {reason}; {self.start_label} again for an answer", stale=True)

    def _start(self) -> None:
        if self.job is not None:
            raise NotReadyError(f"{self.what} is being computed: wait for it or cancel it")
        job = self.job = self.launch()
        self.start_button.disabled, self.cancel_button.disabled = True, False
        self.progress.value, self.progress.visible = 0.0, True
        self.say(f"{job.stage}...")
        threading.Thread(target=self._follow, args=(job,), daemon=True).start()

    def _follow(self, job: Job) -> None:
        said = [""]

        def shown(done: int, total: int) -> None:
            """The progress bar, and the state line: what the job does before its first step (never a silent 0 %),
            then its steps counted."""
            self.progress.value = 100.0 * min(done, total) / max(total, 1)
            text = f"{job.stage}..." if done == 0 else f"{min(done, total)} of {total} {self.steps} done"
            if text != said[0]:
                said[0] = text
                self.say(text)

        job.wait(shown)
        self.job = None
        self.start_button.disabled, self.cancel_button.disabled = False, True
        self.progress.visible = False
        if job.result is None:
            self.say(job.error or "no result", error=True)
            return
        def show() -> None:
            self.finished(job.result)
            self.has_result = True

        self.host.guard(show, beside=self)

    def cancel(self) -> None:
        """End the running job, if any."""
        if self.job is not None:
            self.job.cancel()


def figure_image(figure: Figure) -> np.ndarray:
    """A matplotlib figure as an (H, W, 3) RGB image, for the page; the figure is closed."""
    import matplotlib.pyplot as plt  # optional dependency: the [app] extra, checked by placement.app

    figure.canvas.draw()
    image = np.asarray(figure.canvas.buffer_rgba())[..., :3].copy()  # type: ignore[attr-defined]
    plt.close(figure)
    return image
