"""Object-finder on generated workspaces (Sec. III-B teach, Sec. VII-A execute): regressions.

Each row is a generated scenario's workspace (perception.world.generator) whose
initial state once broke a run, rendered through the simulated world at the
row's noise level. The finder must report every block once, with its shape,
its centre within 5 mm, and nothing else.
"""

import numpy as np
import pytest

from bench.bench_objects import score, truth_and_frame
from perception.vision.camera import default_cameras
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources

# (seed, workspace, noise level, expected block count, what used to go wrong)
ROWS = [
    (1051, "execute", "nominal", 7, "a cube behind a cube read 13 mm tall, named disc"),
    (1075, "teach", "nominal", 9, "a block behind a block read 20 mm tall: phantom disc"),
    (1016, "execute", "nominal", 7, "bricks in line: back one 7 mm, front one 89 mm tall"),
    (1022, "teach", "2x", 11, "a block behind a block: disc phantom on a 64 mm block"),
    (1027, "teach", "nominal", 6, "a cube's face cut by a neighbour's window: phantom brick"),
    (1076, "execute", "nominal", 9, "a disc before a beam: a near-tie check lifted it to 48 mm"),
    (1051, "execute", "4x", 7, "the pyramid case at four times the pixel noise"),
    (1075, "teach", "4x", 9, "the inverted-arch case at four times the pixel noise"),
    (1003, "execute", "2x", None, "a generated workspace that always worked"),
]


@pytest.mark.parametrize(("seed", "which", "level", "count", "why"), ROWS,
                         ids=[f"seed{r[0]}-{r[1]}-{r[2]}" for r in ROWS])
def test_generated_workspace_is_found_exactly(seed, which, level, count, why):
    truth, shapes, frame = truth_and_frame(seed, level, which)
    if count is not None:
        assert len(truth) == count, "the generator changed: update the table"
    res = VisionResources()
    found = ObjectFinder(default_cameras(), res).find(frame, shapes)
    misses, phantoms, wrong, errors = score(truth, found)
    assert (misses, phantoms, wrong) == (0, 0, 0), why
    assert max(errors) < 5.0, why
    assert sorted(f.shape for f in found) == sorted(s for s, _ in truth)
    assert res.in_use == 0


def test_the_score_counts_misses_phantoms_and_wrong_shapes():
    """The harness's matching itself: one of each failure is counted once."""

    class F:
        def __init__(self, shape, pos):
            self.shape, self.position = shape, pos

    truth = [("cube", (0, 0, 20)), ("brick", (100, 0, 25)), ("disc", (200, 0, 10))]
    found = [F("cube", (1, 0, 20)), F("cube", (100, 2, 25)), F("disc", (-200, 0, 10))]
    misses, phantoms, wrong, errors = score(truth, found)
    assert (misses, phantoms, wrong) == (1, 1, 1)
    assert np.allclose(sorted(errors), [1.0, 2.0])
