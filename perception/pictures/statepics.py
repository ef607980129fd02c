"""Pictures of the execution's initial and final state: expected boxes over measured images.

``lbw_engine.cli.execute`` renders the execution workspace through the same two
cameras before the robot starts and after the world has settled
(``ExecutionResult.views``), and execution.json says what was measured and
what was expected. Here each box is projected with the camera models
(``perception.vision.camera``) and its 12 edges are drawn over both views:

| picture | boxes drawn                                                           |
|---------|-----------------------------------------------------------------------|
| initial | what the object-finder measured (Sec. VII-A 3), named by the plan object matched to it |
| final   | where the plan expects each object, and where it was measured          |
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from perception.vision.camera import Camera, default_cameras

EXPECTED_COLOR, MEASURED_COLOR = (0, 200, 255), (255, 170, 40)  # BGR: amber, light blue
FONT = cv2.FONT_HERSHEY_SIMPLEX
# The 12 edges of a box, as pairs of corner indices (corner k has bit i set on axis i's + side).
EDGES = [(a, a | 1 << i) for a in range(8) for i in range(3) if not a & 1 << i]


@dataclass(frozen=True)
class Box:
    """A box to draw: its label, centre and size (mm), and its colour (BGR)."""

    label: str
    center: tuple[float, float, float]
    size: tuple[float, float, float]
    color: tuple[int, int, int]
    right: bool = True  # label at the box's right (else at its left): two sets stay apart


def corners(center: Sequence[float], size: Sequence[float]) -> np.ndarray:
    """The 8 corners of an axis-aligned box (corner k: + side on axis i when bit i is set)."""
    c, h = np.asarray(center, float), np.asarray(size, float) / 2.0
    return np.array([c + h * [1 if k & 1 << i else -1 for i in range(3)] for k in range(8)])


def draw_boxes(views: Mapping[str, np.ndarray], boxes: Sequence[Box],
               cameras: Mapping[str, Camera] | None = None, scale: int = 2) -> np.ndarray:
    """Top and side views side by side (scaled), each box's edges projected onto both."""
    cams = dict(cameras or default_cameras())
    tiles = []
    for name in ("top", "side"):
        img = views[name]
        img = cv2.cvtColor(img, cv2.COLOR_GRAY2BGR) if img.ndim == 2 else img.copy()
        img = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
        for box in boxes:
            uv = cams[name].project(corners(box.center, box.size)) * scale
            pts = [tuple(int(round(c)) for c in p) for p in uv]
            for a, b in EDGES:
                cv2.line(img, pts[a], pts[b], box.color, 1, cv2.LINE_AA)
            _label(img, box, uv)
        cv2.putText(img, name, (6, 18), FONT, 0.5, (235, 235, 235), 1, cv2.LINE_AA)
        tiles.append(img)
    gap = np.full((tiles[0].shape[0], 4, 3), 90, np.uint8)
    return np.hstack([tiles[0], gap, tiles[1]])


def _label(img: np.ndarray, box: Box, uv: np.ndarray) -> None:
    """Write the box's label beside its projection, at mid height."""
    (w, _), _ = cv2.getTextSize(box.label, FONT, 0.4, 1)
    v = int(uv[:, 1].mean()) + 4
    u = int(uv[:, 0].max()) + 4 if box.right else int(uv[:, 0].min()) - 4 - w
    cv2.putText(img, box.label, (u, v), FONT, 0.4, box.color, 1, cv2.LINE_AA)


def initial_boxes(report: Mapping[str, Any]) -> list[Box]:
    """The object-finder's measurements, labelled with the plan object matched to each."""
    state = report.get("initial_state") or {}
    matching = state.get("matching") or {}
    out = []
    for m in state.get("measured") or []:
        pos = tuple(float(c) for c in m["position"])
        name = next((n for n, p in matching.items() if math.dist(p, pos) < 0.5), None)
        label = name or f"{m['shape']} (not in the plan)"
        out.append(Box(label, pos, tuple(float(c) for c in m["size"]), MEASURED_COLOR))
    return out


def final_boxes(report: Mapping[str, Any], sizes: Mapping[str, Sequence[float]]) -> list[Box]:
    """Expected final positions (execution.json ``expected``) and measured ones (``positions``)."""
    expected = (report.get("expected") or {}).get("positions") or {}
    measured = report.get("positions") or {}
    out = []
    for positions, color, right in ((measured, MEASURED_COLOR, False),
                                    (expected, EXPECTED_COLOR, True)):
        for name, pos in sorted(positions.items()):  # expected drawn last: on top
            if name in sizes:
                out.append(Box(name, tuple(float(c) for c in pos),
                               tuple(float(c) for c in sizes[name]), color, right))
    return out


def state_pictures(views: Mapping[str, Mapping[str, np.ndarray]], report: Mapping[str, Any],
                   sizes: Mapping[str, Sequence[float]], scale: int = 2
                   ) -> list[tuple[str, str, np.ndarray]]:
    """(key, caption, image) for the initial and the final state, where the views exist."""
    source = report.get("final_state_source", "unknown source")
    shots = (("execution-initial", "initial state: boxes the object-finder measured in these "
              "images, named by the plan object matched to each", initial_boxes(report)),
             ("execution-final", "final state: expected by the plan (amber) against measured "
              f"({source}, blue)", final_boxes(report, sizes)))
    return [(key, caption, draw_boxes(views[key], boxes, scale=scale))
            for key, caption, boxes in shots if key in views]
