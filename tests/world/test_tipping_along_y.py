"""Balance along y (perception/world/balance.py): a load tips whichever way it hangs.

pymunk tips a load hanging past its supports along x; balance.py does it along y.
Each row is a layout, what is taken away, and what the hanging block must rest on
once the world has settled. Every row runs twice: as written (the overhang along
y) and turned a quarter (along x, where pymunk decides), and both must agree.
"""

import pytest

from perception.world.physics import World
from perception.world.scenario import load_text

HEAD = """\
name: balance
shapes:
  post: [30, 30, 60]
  beam: [30, 150, 20]
  slab: [30, 90, 10]
  cube: [30, 30, 30]
teach:
  objects:
    t: {shape: cube, at: [250, 50]}
  demonstration:
    - pick: t
    - place: t
      on: table
      at: [250, 350]
execute:
  objects:
"""

# (id, objects as name: (shape, x, y, on), removed, block, what it must rest on)
ROWS = [
    ("beam across two posts, one removed: the beam falls",
     {"p": ("post", 0, 140, None), "q": ("post", 0, 260, None),
      "b": ("beam", 0, 200, ("p", "q"))}, "q", "b", ("table",)),
    ("beam across two posts, nothing removed: it stays",
     {"p": ("post", 0, 140, None), "q": ("post", 0, 260, None),
      "b": ("beam", 0, 200, ("p", "q"))}, None, "b", ("p", "q")),
    ("cube 10 mm past a cube's edge: its centre is over it, it stays",
     {"a": ("cube", 0, 200, None), "c": ("cube", 0, 210, ("a",))}, None, "c", ("a",)),
    ("cube on two cubes, the one under its centre removed: it tips off the other",
     {"a": ("cube", 0, 185, None), "b": ("cube", 0, 216, None),
      "c": ("cube", 0, 205, ("a", "b"))}, "b", "c", ("table",)),
    ("slab on two posts with a cube on its end, the post under the end removed: both tip",
     {"p": ("post", 0, 200, None), "q": ("post", 0, 240, None), "s": ("slab", 0, 210, ("p", "q")),
      "c": ("cube", 0, 240, ("s",))}, "q", "s", ("table",)),
    ("the same slab without the cube stays on the other post",
     {"p": ("post", 0, 200, None), "q": ("post", 0, 240, None),
      "s": ("slab", 0, 210, ("p", "q"))}, "q", "s", ("p",)),
]


def _scenario(objects: dict, turned: bool) -> str:
    """The layout as execute.objects lines; ``turned`` swaps x and y (about (0, 200)), and
    each shape's x and y sizes with them."""
    head = HEAD
    if turned:
        for shape, (sx, sy, sz) in {"beam": (30, 150, 20), "slab": (30, 90, 10)}.items():
            head = head.replace(f"{shape}: [{sx}, {sy}, {sz}]", f"{shape}: [{sy}, {sx}, {sz}]")
    lines = []
    for name, (shape, x, y, on) in objects.items():
        if turned:
            x, y = y - 200, x + 200
        where = "" if on is None else f", on: [{', '.join(on)}]"
        lines.append(f"    {name}: {{shape: {shape}, at: [{x}, {y}]{where}}}\n")
    return head + "".join(lines)


@pytest.mark.parametrize("turned", [False, True], ids=["along y", "along x"])
@pytest.mark.parametrize("objects,removed,block,rests_on", [r[1:] for r in ROWS],
                         ids=[r[0] for r in ROWS])
def test_a_load_past_its_supports_tips(objects, removed, block, rests_on, turned):
    sc = load_text(_scenario(objects, turned), "balance.yaml")
    world = World(sc.execute.objects.values())
    world.settle(0.3)
    if removed:
        world.remove_block(removed)
    world.settle(2.0)
    assert world.supports()[block] == rests_on


def test_two_loads_tipping_into_one_gap_do_not_pass_through_each_other():
    """Two cubes each hanging 20 mm into the gap a removed cube left (a pyramid row
    along y, fault bench seed 7000) meet there: neither passes into the other."""
    objects = {"a": ("cube", 0, 140, None), "m": ("cube", 0, 170, None),
               "b": ("cube", 0, 200, None), "l": ("cube", 0, 155, ("a", "m")),
               "r": ("cube", 0, 185, ("m", "b"))}
    world = World(load_text(_scenario(objects, False), "balance.yaml").execute.objects.values())
    world.settle(0.3)
    world.remove_block("m")
    world.settle(2.0)
    lo_l, hi_l = world.extent("l", 1)
    lo_r, hi_r = world.extent("r", 1)
    pos = world.positions()
    level = abs(pos["l"][2] - pos["r"][2]) < 30.0
    assert not level or min(hi_l, hi_r) - max(lo_l, lo_r) <= 0.5
