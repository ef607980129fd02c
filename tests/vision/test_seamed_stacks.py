"""Object-finder: a stack of blocks of one footprint whose column is as tall as another
listed shape (helper round 17, u97, u98, u99, u73).

The column fits that shape, so nothing asked whether it was a stack. A seam crossing its
whole front face in the side view, with the front face above and below it, says it is:
each block's outline is drawn, and one block's front face has no line across it.
"""

import pytest

from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources
from perception.world.scene import Box

from .helpers import CAMS, Film


def _box(x, y, z, size):
    return Box("block", (x, y, z), tuple(map(float, size)))


C25, COL = (25, 25, 25), (25, 25, 50)
C40, P80 = (40, 40, 40), (40, 40, 80)
C30, P90 = (30, 30, 30), (30, 30, 90)

# (id, shapes, scene, expected sorted (shape, rounded z) pairs)
ROWS = [
    ("u97 two 25 mm cubes beside a 25x25x50 column", {"cube": C25, "col": COL},
     [_box(-100, 200, 12.5, C25), _box(-100, 200, 37.5, C25), _box(100, 300, 25, COL)],
     [("col", 25), ("cube", 12), ("cube", 38)]),
    ("u98 two 40 mm cubes beside a 40x40x80 pillar", {"cube": C40, "pillar": P80},
     [_box(0, 200, 20, C40), _box(0, 200, 60, C40), _box(120, 250, 40, P80)],
     [("cube", 20), ("cube", 60), ("pillar", 40)]),
    ("u73 three 30 mm cubes beside a 30x30x90 pillar", {"cube": C30, "pillar": P90},
     [_box(0, 150, 15, C30), _box(0, 150, 45, C30), _box(0, 150, 75, C30),
      _box(-120, 250, 45, P90)],
     [("cube", 15), ("cube", 45), ("cube", 75), ("pillar", 45)]),
    ("control: a column on a cube is two blocks, not three", {"cube": C25, "col": COL},
     [_box(0, 200, 12.5, C25), _box(0, 200, 50, COL)], [("col", 50), ("cube", 12)]),
    ("control: a cube in front of a column draws no seam on it", {"cube": C25, "col": COL},
     [_box(0, 250, 25, COL), _box(0, 224, 12.5, C25)], [("col", 25), ("cube", 12)]),
]


@pytest.mark.parametrize("noise", [2.0, 8.0])
@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("shapes, scene, expected", [r[1:] for r in ROWS],
                         ids=[r[0] for r in ROWS])
def test_a_seam_across_a_column_splits_it(shapes, scene, expected, noise, seed):
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=seed).shoot(scene), shapes)
    got = sorted((f.shape, f.position[2]) for f in found)
    assert [s for s, _ in got] == [s for s, _ in expected], got
    assert all(abs(z - e) <= 3.0 for (_, z), (_, e) in zip(got, expected, strict=True)), got


COLUMN = (40, 40, 80)


@pytest.mark.parametrize("noise", [2.0, 4.0, 8.0])
def test_a_stack_hidden_behind_a_column_is_read_as_the_cubes_a_task_needs(noise):
    """Generated twins 1271 (2x): two 40 mm cubes stacked 120 mm behind a 40 x 40 x 80
    column. The column hides their seam from the side camera, so the finder reads a
    second column; the plan needs two cubes, and the images allow the stack there."""
    shapes = {"cube": C40, "column": COLUMN}
    scene = [_box(239.7, 297.6, 20, C40), _box(239.7, 297.6, 60, C40),
             _box(234.5, 176.4, 40, COLUMN)]
    finder = ObjectFinder(CAMS, VisionResources())
    frame = Film(noise=noise, seed=1271).shoot(scene)
    found = finder.find(frame, shapes)
    assert sorted(f.shape for f in found) == ["column", "column"]
    again = finder.restack(frame, found, {"cube": 2, "column": 1}, shapes)
    got = sorted((f.shape, round(f.position[1]), round(f.position[2])) for f in again)
    assert [(s, y) for s, y, _ in got] == [("column", 176), ("cube", 298), ("cube", 298)], got
    assert [z for *_, z in got[1:]] == [20, 60], got


def test_a_column_in_full_view_is_not_read_as_a_stack_the_task_wants():
    """The control: the same needs, the back block a column the side camera sees whole,
    with no seam across it. It stays a column, and the lack stays for the matcher to
    report."""
    shapes = {"cube": C40, "column": COLUMN}
    scene = [_box(-100, 297.6, 40, COLUMN), _box(150, 176.4, 40, COLUMN)]
    finder = ObjectFinder(CAMS, VisionResources())
    frame = Film(noise=4.0, seed=1271).shoot(scene)
    found = finder.find(frame, shapes)
    again = finder.restack(frame, found, {"cube": 2, "column": 1}, shapes)
    assert sorted(f.shape for f in again) == ["column", "column"]
