"""Videos that browsers play: H.264 MP4 through the ffmpeg that imageio-ffmpeg ships."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import cv2
import numpy as np


class VideoFile:
    """An H.264 MP4 written frame by frame through imageio-ffmpeg's ffmpeg; no-op without a path.

    Browsers play H.264 only in 4:2:0 (yuv420p) and start an MP4 before it has
    fully loaded only when its index (moov atom) comes first (+faststart);
    Chromium does not play OpenCV's mp4v codec (MPEG-4 Part 2) at all (issue #14).
    """

    BLOCK = 16  # H.264 codes 16x16 macroblocks: frames are padded to a multiple
    # imageio-ffmpeg's 0-10 scale; 4 is x264's CRF 30: the cameras' pixel noise is mostly
    # quantized away (a third of the size of CRF 20) while the monitor's text stays sharp.
    QUALITY = 4.0

    def __init__(self, path: str | Path | None, fps: float, quality: float = QUALITY) -> None:
        """Open lazily: the size is known at the first frame."""
        self.path, self.fps, self.quality = path, fps, quality
        self.writer: Any = None
        self.size: tuple[int, int] | None = None  # (width, height) after padding
        self.frames = 0

    def add(self, image: np.ndarray) -> None:
        """Append one BGR (or gray) frame, padded at the right and bottom with black."""
        if self.path is None:
            return
        if image.ndim == 2:
            image = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
        h, w = image.shape[:2]
        if self.writer is None:
            self.size = (-(-w // self.BLOCK) * self.BLOCK, -(-h // self.BLOCK) * self.BLOCK)
            self.writer = self._open()
        pw, ph = self.size
        if (w, h) != (pw, ph):
            image = cv2.copyMakeBorder(image, 0, max(0, ph - h), 0, max(0, pw - w),
                                       cv2.BORDER_CONSTANT, value=(0, 0, 0))[:ph, :pw]
        self.writer.send(np.ascontiguousarray(image, dtype=np.uint8))
        self.frames += 1

    def _open(self) -> Any:
        """Start ffmpeg reading raw BGR frames on its stdin."""
        import imageio_ffmpeg

        writer = imageio_ffmpeg.write_frames(
            str(self.path), self.size, pix_fmt_in="bgr24", pix_fmt_out="yuv420p",
            fps=self.fps, codec="libx264", quality=self.quality, macro_block_size=self.BLOCK,
            output_params=["-preset", "veryfast", "-movflags", "+faststart"])
        writer.send(None)  # the generator starts ffmpeg at its first send
        return writer

    def close(self) -> None:
        """Finish the file (ffmpeg writes the index and exits)."""
        if self.writer is not None:
            self.writer.close()
            self.writer = None
