"""Balance along y, which the x-z engine cannot topple (design.md's 3-D reading).

pymunk tips a block whose load hangs past its supports along x. Along y it has no
dynamics, so a block kept its place however far it hung past a support's edge
(fault bench seed 7000: the middle cube of a pyramid row along y was slid off the
table, and the two cubes it carried stayed up, each on one neighbour, with their
centres 6 mm past that neighbour's edge; both cameras saw nothing wrong, and no
camera could have). After each world step every awake block that is not held is
checked: when the centre of mass of its load (itself and what it carries) lies
more than TIP_MM past the y-span where it touches its supports, the load slides off
that edge along y, riders and all, and falls in x-z; a block level with it in its
way stops it there (it leans on that block, wedged). A real block would also turn
about x as it went; the engine keeps a block's turn about y only, so it lands flat.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.model.geometry import TABLE, resting_on
from perception.world.layout import Layout

TIP_MM = 1.0  # how far past its supports' edge a load's centre may lie before it tips
CLEAR_MM = 0.5  # a tipped block ends this far past the edge it went over


def tip_along_y(world: Any) -> list[str]:
    """Slide every awake, unheld block whose load overhangs its supports along y off
    the edge it overhangs (with its riders); the names of the blocks that tipped."""
    shapes = world.shapes
    awake = sorted((n for n in world.names if not shapes[n].body.is_sleeping),
                   key=lambda n: shapes[n].bb.bottom)  # a lower load tips first
    if not awake:
        return []
    held: set[str] = set()
    for g in world.grippers:
        if g.holding is not None:
            held |= {g.holding, *g.riders}
    boxes = block_boxes(world)
    lay = None  # the layout of supports, built once a load overhangs (held blocks rest on
    # nothing: a block the hand still bears is no load on what it is lowered onto)
    tipped = []
    for name in awake:
        if name in held:
            continue
        # pymunk bears a block on any y-overlap at all, so a support is any block whose
        # footprint meets it (a tile set down 0.2 mm over its neighbour's edge stayed up
        # on it, 20 mm above the table, in x-z: helper round 17, u48)
        under = resting_on(name, boxes, overlap=0.0)
        if not under or TABLE in under:
            continue  # falling, held up by a hand, or on the table (all of y)
        lo, hi = world.extent(name, 1)
        spans = [(max(lo, a), min(hi, b)) for a, b in (world.extent(s, 1) for s in under)]
        edge_lo, edge_hi = min(s[0] for s in spans), max(s[1] for s in spans)
        if edge_lo <= lo and hi <= edge_hi:
            continue  # it lies wholly over its supports: so does what rides on it
        if lay is None:
            lay = Layout(world.positions(), dict(world.sizes),
                         {n: () if n in held else tuple(resting_on(n, boxes))
                          for n in world.names})
        riders = lay.carried(name)
        com = lay.centre_of_mass([name, *riders])[1]
        if com < edge_lo - TIP_MM:
            dy = edge_lo - CLEAR_MM - hi
        elif com > edge_hi + TIP_MM:
            dy = edge_hi + CLEAR_MM - lo
        else:
            continue
        moving = {name, *riders}  # a block level with it or with a rider stops it there
        for n in moving:
            dy = world.free_run_y(n, dy, moving)
        if abs(dy) < CLEAR_MM:
            continue  # wedged against that block: it leans on it
        world.shift_y(name, dy, riders)
        for n in (name, *riders):
            shapes[n].body.activate()
        boxes, lay = block_boxes(world), None
        tipped.append(name)
    return tipped


def block_boxes(world: Any) -> dict[str, tuple]:
    """Each block's box (centre, size) from its x-z bounds and its y-extent."""
    out = {}
    for name in world.names:
        bb = world.shapes[name].bb
        out[name] = (((bb.left + bb.right) / 2, world.y[name], (bb.bottom + bb.top) / 2),
                     (bb.right - bb.left, world.sizes[name][1], bb.top - bb.bottom))
    return out
