"""Finished structures through the cameras: expected poses checked against the images.

The object-finder (objects.py) measures what it sees of each block's top face
and puts the block's bottom on the highest top face found under it, or on the
table. In a finished structure that reading is weak in two ways: a support may
be wholly hidden (the four legs under the plate of Fig. 20; the finder reports
one column from the table up to the plate's top), and two blocks one behind the
other on the side camera's line of sight may get each other's heights.

Verification and monitoring know where they expect every block, so they can
ask the images a narrower question (Sec. VIII, the executed structure against
the taught one): does the picture agree with this block standing there? Boxes
are drawn as silhouettes into both views and compared with the non-dark pixels
(as ``objects_match.SilhouetteCheck`` does for columns, here with real bottoms).
A found block whose top face lies where an expected block's does (same shape
footprint, same place) takes the expected pose when that explains the views at
least as well; an expected block nothing was found for is added when adding it
does not make the views worse (it is hidden, or the finder missed it). A block
that is not there adds its whole silhouette to the wrong pixels and is refused.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import networkx as nx
import numpy as np

from lbw_engine.model.geometry import footprints_meet
from perception.vision.camera import Camera
from perception.vision.vfd.objects import FoundObject
from perception.vision.vfd.objects_faces import (
    measure_tops,
    top_missing,
    tops_unseen,
    uncovered_or_part_seen,
)
from perception.vision.vfd.objects_nudged import nudged
from perception.vision.vfd.objects_pieces import (
    above,
    box_rect,
    images_of,
    meet,
    overlaps_images,
    pieces_of,
    reading_of,
    shifted,
    with_columns_under,
)
from perception.vision.vfd.silhouettes import Silhouettes

OUTLINE_SHARE = 0.05  # wrong pixels off the outline bands near posed blocks, per outline px
ABOVE_MM = 4.0  # a reading whose bottom is this near a block's top (or higher) lies on it
PASSES = 3  # passes over the expected blocks
WORSE_PX = 12  # more wrong pixels than this is evidence against a pose (edges, noise)

Expected = tuple[str, Sequence[float], Sequence[float]]  # shape, centre, size


def explain(cameras: Mapping[str, Camera], images: Mapping[str, np.ndarray],
            found: Sequence[FoundObject], expected: Mapping[str, Expected],
            most: Mapping[str, int] | None = None
            ) -> tuple[list[FoundObject], dict[str, int], list[str]]:
    """The finder's blocks with expected poses accepted where the views allow.

    Returns the blocks, the expected names given to some of them (index into
    the blocks) and the names added although the finder did not report them.
    A block may replace the finder's reading of it, or the pieces the finder
    made of it (a ring of a lower block around an upper one, Fig. 14).
    ``most`` bounds how many blocks of each shape the workspace holds (see
    ``_too_many``).
    """
    check = Silhouettes(cameras, images, [e[2] for e in expected.values()])
    boxes: list[FoundObject | None] = list(found)
    named: dict[str, int] = {}

    def cost() -> int:
        return check.wrong([(b.position, b.size) for b in boxes if b is not None])

    added: list[str] = []
    doubtful = []
    for g in _structures(expected, cameras):
        if _replace_whole(boxes, named, g, expected, check):
            continue
        # Blocks that merely overlap in an image (a plank behind two towers) need not stand
        # or fall together: each stack is tried on its own, so one misread stack does not
        # leave its neighbours to the finder's reading.
        stacks = _stacks(g, expected)
        if len(stacks) > 1:
            doubtful += [t for t in stacks if not _replace_whole(boxes, named, t, expected,
                                                                 check)]
        else:
            doubtful.append(g)
    # Whether the top view shows what is expected of a block's top beside the blocks
    # expected over it: it depends on the expected poses and the images only, so it is
    # worked out once per block, however many passes ask.
    shown: dict[str, bool] = {}

    def top_shown(name: str) -> bool:
        if name not in shown:
            shown[name] = uncovered_or_part_seen(name, expected, check)
        return shown[name]

    for _ in range(PASSES):  # a block's pose may only fit once its neighbours' do
        before = len(named)
        _add_hidden(boxes, named, added, expected, cost, top_shown, check)
        _replace(boxes, named, expected, cost, top_shown)
        if len(named) == before:
            break
    nudged(boxes, named, check, WORSE_PX)  # blocks under others slid a few mm
    for group in doubtful:  # posed one by one, a structure must still fit as a whole
        posed = [(boxes[named[n]].position, boxes[named[n]].size) for n in group if n in named]
        if posed and not _fits(check, boxes, posed, []):
            for n in [n for n in group if n in added]:  # the hidden ones are least sure
                boxes[named.pop(n)] = None
                added.remove(n)
    if named:
        shifted(boxes, named, found, cost, WORSE_PX, cameras["side"])
        _drop_unseen(boxes, named, cost)
    if most:
        _too_many(boxes, named, added, most, cost)
    measure_tops(boxes, named, check)
    keep = [i for i, b in enumerate(boxes) if b is not None]
    index = {i: k for k, i in enumerate(keep)}
    return [boxes[i] for i in keep], {n: index[i] for n, i in named.items()}, added


def _fits(check: Silhouettes, boxes: list, posed: list, replaced: list) -> bool:
    """Whether the views agree with the posed boxes near them (and near what they replace),
    off the one-pixel band around the drawn outlines, up to a small share of the outlines
    (pixel noise). A correct structure leaves no wrong pixel there; a block displaced by a
    few mm uncovers, or covers, strips wider than the band."""
    shown = [(b.position, b.size) for b in boxes if b is not None]
    wrong = check.wrong(shown, within=posed + replaced, edges=False)
    return wrong <= OUTLINE_SHARE * check.outline(posed)


def _structures(expected: Mapping[str, Expected], cameras: Mapping[str, Camera]
                ) -> list[list[str]]:
    """Expected blocks grouped by what the views can tell apart: blocks whose images
    overlap in either camera (one rests on, or hides, the other), transitively."""
    names = sorted(expected)
    rects = {n: [box_rect(cam, expected[n][1], expected[n][2]) for cam in cameras.values()]
             for n in names}
    return _components(names, lambda a, b: any(
        meet(ra, rb) for ra, rb in zip(rects[a], rects[b], strict=True)))


def _stacks(group: list[str], expected: Mapping[str, Expected]) -> list[list[str]]:
    """The group's blocks joined where their footprints overlap (one rests on, or over,
    the other), transitively: the stacks and bridges the group is made of."""
    return _components(group, lambda a, b: footprints_meet(*expected[a][1:], *expected[b][1:],
                                                           tol=0.0))


def _components(names: Sequence[str], joined: Callable[[str, str], bool]) -> list[list[str]]:
    """``names`` joined pairwise by ``joined``, transitively; each part sorted, the parts in
    the order of their first name."""
    graph = nx.Graph()
    graph.add_nodes_from(names)
    graph.add_edges_from((a, b) for i, a in enumerate(names) for b in names[i + 1:]
                         if joined(a, b))
    return [sorted(part) for part in nx.connected_components(graph)]


def _replace_whole(boxes: list, named: dict[str, int], group: list[str],
                   expected: Mapping[str, Expected], check: Silhouettes) -> bool:
    """The structure posed whole (``_replace_structure``), or else whole but for one block:
    the rest stands as expected and that block is gone or moved (a second-row cube taken
    from a pyramid, fault bench seed 7010; a leg taken from under a table top, 7003).
    Blocks whose top faces the top view does not show are tried first. The block left
    out is then looked for on its own."""
    unseen: list[str] = []
    if _replace_structure(boxes, named, group, expected, check, unseen):
        return True
    order = unseen + [n for n in group if n not in unseen]
    return len(group) > 2 and any(_replace_structure(
        boxes, named, [m for m in group if m != n], expected, check) for n in order)


def _replace_structure(boxes: list, named: dict[str, int], group: list[str],
                       expected: Mapping[str, Expected], check: Silhouettes,
                       unseen: list[str] | None = None) -> bool:
    """A whole structure at its expected pose, its uncovered blocks where the top view
    shows their faces, in place of what the finder made of it (a column, rings, swapped
    heights), where the views agree with it near its silhouettes nearly exactly (a
    hidden block that moved shows only there)."""
    parts = sorted({i for n in group for i in pieces_of(boxes, [
        i for i, b in enumerate(boxes) if b is not None and i not in named.values()],
        expected[n][1], expected[n][2], any_size=True, any_height=True,
        top_cam=check.cameras["top"])})
    parts = with_columns_under(boxes, parts, named)
    # Its uncovered blocks go where the top view shows their faces (a beam dropped 16 mm
    # off its goal onto its pillars, fault bench seed 5009: at its goal the structure did
    # not fit, and the pillars under it were reported gone).
    trial = [FoundObject(expected[n][0], tuple(map(float, expected[n][1])),
                         tuple(map(float, expected[n][2])), 0.0) for n in group]
    # A reading wholly above the group is no piece of it, but a block on it: the beam a
    # displaced top left over the towers it bridged, when the group is tried without it
    # (helper round 13, v80b, v80h). It stays, and may hide the group's tops.
    parts = [i for i in parts if not above(boxes[i], trial, ABOVE_MM)]
    was = {i: boxes[i] for i in parts}
    measure_tops(trial, {n: k for k, n in enumerate(group)}, check)
    posed = {n: (expected[n][0], trial[k].position, expected[n][2])
             for k, n in enumerate(group)}
    covers = [(b.position, b.size) for i, b in enumerate(boxes)
              if b is not None and i not in parts]
    missing = tops_unseen(group, posed, list(was.values()), check, covers)
    if missing:
        if unseen is not None:
            unseen += missing
        return False
    for i in parts:
        boxes[i] = None
    first = len(boxes)
    boxes.extend(trial)
    replaced = [(b.position, b.size) for b in was.values()]
    if not _fits(check, boxes, [(b.position, b.size) for b in trial], replaced):
        # one of its hidden blocks may have slid a few mm (a table's leg pushed 9 mm out
        # from under the top's front edge, fault bench seed 5008 at 4x: the whole did not
        # fit, the legs were left unnamed and reported gone)
        nudged(boxes, {n: first + k for k, n in enumerate(group)}, check, WORSE_PX)
        trial = boxes[first:]
    mine = [(b.position, b.size) for b in trial]
    stray: dict[int, FoundObject] = {}
    if not _fits(check, boxes, mine, replaced):
        # Other readings over the structure's images may be misreadings of it (a 6 mm
        # sliver of a tower's front face read 118 mm tall beside it, fault bench seed 7011
        # at 4x): without them, the views must agree near them too, so a real block is
        # not dropped.
        rects = [images_of(check.cameras, b) for b in trial]
        stray = {i: boxes[i] for i in range(first) if boxes[i] is not None
                 and i not in named.values() and overlaps_images(check.cameras, boxes[i], rects)}
        for i in stray:
            boxes[i] = None
        if not stray or not _fits(check, boxes, mine, replaced + [
                (b.position, b.size) for b in stray.values()]):
            return _undo(boxes, first, {**was, **stray})
    # and each block the views could see on its own must be seen: the whole's tolerance
    # is a share of all its outlines, more than a small block's image (``unshown``)
    gone = [n for k, n in enumerate(group) if check.unshown(mine[k], [
        (b.position, b.size) for j, b in enumerate(boxes) if b is not None and j != first + k])]
    if gone:
        if unseen is not None:
            unseen += [n for n in gone if n not in unseen]
        return _undo(boxes, first, {**was, **stray})
    named.update({n: first + k for k, n in enumerate(group)})
    return True


def _undo(boxes: list, first: int, was: Mapping[int, FoundObject]) -> bool:
    """Take back a trial pose: the boxes from ``first`` on go, the readings in ``was``
    return. False, for the caller to return."""
    del boxes[first:]
    for i, b in was.items():
        boxes[i] = b
    return False


def _add_hidden(boxes: list, named: dict[str, int], added: list[str],
                expected: Mapping[str, Expected], cost: Callable[[], int],
                top_shown: Callable[[str], bool], check: Silhouettes) -> None:
    """Expected blocks the finder saw nothing of, where adding them leaves the views as
    well explained (hidden from both cameras) or better, and the top view shows what is
    expected of their top faces beside the blocks over them (``top_shown``), or where
    nothing hides them from it (``top_missing``)."""
    base = cost()
    for name, (shape, center, size) in sorted(expected.items()):
        free = [i for i, b in enumerate(boxes) if b is not None and i not in named.values()]
        if name in named or pieces_of(boxes, free, center, size, any_size=True):
            continue  # the finder saw something there that is not this block
        if not top_shown(name) or top_missing(name, expected, boxes, check):
            continue
        boxes.append(FoundObject(shape, tuple(map(float, center)), tuple(map(float, size)), 0.0))
        trial = cost()
        others = [(b.position, b.size) for b in boxes[:-1] if b is not None]
        if trial <= base + WORSE_PX and not check.unshown((center, size), others):
            named[name], base = len(boxes) - 1, min(base, trial)
            added.append(name)
        else:
            boxes.pop()


def _drop_unseen(boxes: list, named: dict[str, int], cost: Callable[[], int]) -> None:
    """Readings no expected block took whose silhouettes the others cover in both views:
    nothing in the images shows them (the finder's guess of a column under a beam, between
    an arch's pillars). The converse of ``_add_hidden``; a spare block in sight changes
    the views when left out, and stays."""
    base = cost()
    for i, b in enumerate(boxes):
        if b is None or i in named.values():
            continue
        boxes[i] = None
        trial = cost()
        if trial <= base:
            base = trial
        else:
            boxes[i] = b


def _too_many(boxes: list, named: dict[str, int], added: list[str], most: Mapping[str, int],
              cost: Callable[[], int]) -> None:
    """No more blocks of a shape than the workspace holds: while there are, the one the
    views need least goes (named or not), if the views do not need it at all (leaving it
    out makes them no worse than WORSE_PX; a shape the finder gave a misread block is no
    reason to drop a real one). A block fallen off a tower leaves behind it a pose that
    other blocks' images can fill on the side camera's line of sight (a plank and a cube
    behind it), and the top face below looks the same from above: the block on the table
    is the one the images need."""
    for shape, limit in most.items():
        while True:
            mine = [i for i, b in enumerate(boxes) if b is not None and b.shape == shape]
            if len(mine) <= limit:
                break
            base, trials = cost(), {}
            for i in mine:
                b, boxes[i] = boxes[i], None
                trials[i] = cost()
                boxes[i] = b
            least = min(mine, key=lambda i: trials[i])
            if trials[least] > base + WORSE_PX:
                break
            boxes[least] = None
            for n in [n for n, i in named.items() if i == least]:
                del named[n]
                if n in added:
                    added.remove(n)


def _replace(boxes: list, named: dict[str, int], expected: Mapping[str, Expected],
             cost: Callable[[], int], top_shown: Callable[[str], bool]) -> None:
    """One pass: each unnamed expected block takes the place of the finder's reading of
    it, or of its pieces, where the views agree at least as well (and the top view shows
    its top face beside the blocks expected over it, ``top_shown``)."""
    base = cost()
    for name, (shape, center, size) in sorted(expected.items()):
        if name in named or not top_shown(name):
            continue
        posed = FoundObject(shape, tuple(map(float, center)), tuple(map(float, size)), 0.0)
        free = [i for i, b in enumerate(boxes) if b is not None and i not in named.values()]
        for parts in (reading_of(boxes, free, center, size), pieces_of(boxes, free, center, size)):
            if not parts:
                continue
            was = {i: boxes[i] for i in parts}
            for i in parts:
                boxes[i] = None
            boxes[parts[0]] = posed
            trial = cost()
            if trial <= base + WORSE_PX:
                named[name], base = parts[0], min(base, trial)
                break
            for i, b in was.items():  # the views disagree: keep the finder's reading
                boxes[i] = b


