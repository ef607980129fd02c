"""Vision resource manager: hands out image windows, at most 32 at once (Sec. II-B2, III-A).

The paper's MWVS hardware processes up to 32 rectangular windows in parallel;
an MFD asks the manager for windows when it is created and gets an error when
none are left. Every read of a window goes through ``Window.read``, which
counts the pixels read in the current frame (the benchmark's cost measure).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

MAX_WINDOWS = 32


class ResourceExhausted(RuntimeError):
    """No window is left in the vision hardware (the MWVS has 32)."""


@dataclass
class Window:
    """A rectangular window on one camera's image, read every ``step`` pixels."""

    view: str
    x0: int
    y0: int
    x1: int
    y1: int
    step: int = 1
    manager: VisionResources | None = field(default=None, repr=False)
    wid: int = -1

    def move_to(self, cx: float, cy: float, w: int, h: int, size: tuple[int, int]) -> None:
        """Centre the window at (cx, cy) with size w x h, clipped to an image of ``size``."""
        # Conditional expressions instead of min/max calls: trackers move windows ~10
        # times a frame.
        x0 = int(round(cx - w / 2.0))
        y0 = int(round(cy - h / 2.0))
        sw, sh = size
        a = x0 if x0 < sw - 1 else sw - 1
        b = y0 if y0 < sh - 1 else sh - 1
        self.x0 = a = a if a > 0 else 0
        self.y0 = b = b if b > 0 else 0
        e, f = x0 + w, y0 + h
        e = e if e < sw else sw
        f = f if f < sh else sh
        self.x1 = e if e > a + 1 else a + 1
        self.y1 = f if f > b + 1 else b + 1

    def set_rect(self, rect: tuple[int, int, int, int]) -> None:
        """Set the window to the pixel rectangle (x0, y0, x1, y1)."""
        self.x0, self.y0, self.x1, self.y1 = (int(v) for v in rect)

    @property
    def center(self) -> tuple[float, float]:
        """Window centre in image pixels."""
        return (self.x0 + self.x1) / 2.0, (self.y0 + self.y1) / 2.0

    def read(self, image: np.ndarray) -> np.ndarray:
        """The window's (subsampled) pixels of ``image``; counted as read this frame."""
        sub = image[self.y0:self.y1:self.step, self.x0:self.x1:self.step]
        if self.manager is not None:
            self.manager.pixels_read += sub.size
        return sub


class VisionResources:
    """Allocate and free windows; count the pixels all windows read per frame."""

    def __init__(self, max_windows: int = MAX_WINDOWS) -> None:
        """A pool of ``max_windows`` windows (the MWVS had 32)."""
        self.max_windows = max_windows
        self._live: dict[int, Window] = {}
        self._next = 0
        self.pixels_read = 0  # in the current frame
        self.history: list[int] = []  # pixels read in each finished frame

    @property
    def in_use(self) -> int:
        """Number of windows currently allocated."""
        return len(self._live)

    def allocate(self, view: str, rect: tuple[int, int, int, int] = (0, 0, 1, 1),
                 step: int = 1) -> Window:
        """A new window on ``view``; raises ResourceExhausted when all are in use."""
        if len(self._live) >= self.max_windows:
            raise ResourceExhausted(
                f"all {self.max_windows} vision windows are in use; free a detector first")
        win = Window(view, *rect, step=step, manager=self, wid=self._next)
        self._live[self._next] = win
        self._next += 1
        return win

    def free(self, window: Window) -> None:
        """Return ``window`` to the pool (freeing twice is harmless)."""
        self._live.pop(window.wid, None)
        window.manager = None

    def end_frame(self) -> int:
        """Close the current frame's pixel count and return it."""
        n, self.pixels_read = self.pixels_read, 0
        self.history.append(n)
        return n
