"""Frames: the only thing the recognizer receives from the world (docs/architecture.md)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Frame:
    """One stereo frame: index, time in seconds, and the two uint8 gray views."""

    index: int
    t: float
    top: np.ndarray
    side: np.ndarray

    def view(self, name: str) -> np.ndarray:
        """The image of the camera called ``name`` ("top" or "side")."""
        if name == "top":
            return self.top
        if name == "side":
            return self.side
        raise KeyError(f"no view called {name!r}; a frame has 'top' and 'side'")
