"""Scenario validation, row by row: a bad scenario -> the error's key path and message."""

import pytest

from lbw_engine.errors import InputError
from lbw_engine.rules import load_rules
from perception.world.scenario import load_text

RULES = load_rules()

GOOD = """\
name: t
shapes:
  brick: [30, 30, 50]
  plank: [160, 60, 20]
teach:
  objects:
    a: {shape: brick, at: [-100, 100]}
    b: {shape: brick, at: [100, 100]}
    p: {shape: plank, at: [0, 300]}
    c: {shape: brick, at: [-40, 300], on: p}
  demonstration:
    - pick: a
    - place: a
      on: table
      at: [0, 150]
"""


def _with(old: str, new: str) -> str:
    """GOOD with one text replacement (the replaced text must exist)."""
    assert old in GOOD
    return GOOD.replace(old, new)


def _steps(text: str) -> str:
    """GOOD with its demonstration replaced."""
    head = GOOD.split("  demonstration:\n")[0]
    return head + "  demonstration:\n" + text


# (case id, scenario text, expected line, key path, message fragment)
ROWS = [
    ("unknown-top-key", GOOD + "colour: red\n", 16, "colour", "unknown key 'colour'"),
    ("missing-name", _with("name: t\n", ""), None, "name", "missing required key 'name'"),
    ("bad-seed", GOOD + "seed: -3\n", 16, "seed", "non-negative integer"),
    ("shape-too-small", _with("[30, 30, 50]", "[5, 30, 50]"), 3, "shapes.brick[0]",
     "outside 10-200 mm"),
    ("shape-too-big", _with("[160, 60, 20]", "[160, 260, 20]"), 4, "shapes.plank[1]",
     "outside 10-200 mm"),
    ("shape-not-a-vector", _with("[30, 30, 50]", "[30, 30]"), 3, "shapes.brick",
     "list of 3 numbers"),
    ("bad-object-name", _with("    a: {shape", "    A: {shape").replace("pick: a", "pick: A"),
     7, "teach.objects.A", "names match"),
    ("reserved-name", _with("    b: {shape", "    hand: {shape"), 8, "teach.objects.hand",
     "reserved"),
    ("unknown-shape", _with("b: {shape: brick", "b: {shape: cube"), 8, "teach.objects.b.shape",
     "unknown shape 'cube'"),
    ("unknown-object-key", _with("b: {shape: brick, at: [100, 100]}",
                                 "b: {shape: brick, at: [100, 100], colour: 3}"), 8,
     "teach.objects.b.colour", "unknown key 'colour'"),
    ("object-off-table-x", _with("[100, 100]", "[290, 100]"), 8, "teach.objects.b",
     "off the table"),
    ("object-off-table-y", _with("[100, 100]", "[100, 390]"), 8, "teach.objects.b",
     "off the table"),
    ("objects-overlap", _with("[100, 100]", "[-80, 110]"), 8, "teach.objects.b",
     "overlap 'a'"),
    ("rests-on-unknown", _with("on: p}", "on: q}"), 10, "teach.objects.c.on",
     "unknown object 'q'"),
    ("rests-off-support", _with("[-40, 300], on: p", "[-120, 300], on: p"), 10,
     "teach.objects.c", "does not rest on 'p'"),
    # its footprint meets the plank's, its centre is 10 mm beyond the end (round 11, 108)
    ("rests-beyond-support", _with("[-40, 300], on: p", "[-90, 300], on: p"), 10,
     "teach.objects.c", "would tip off 'p'"),
    # each block's centre is over its support, but the brick on the plank's end tips
    # the plank off the brick under it (a load a world started at rest would keep up)
    ("load-beyond-support", _with("on: p}\n", "on: p}\n    e: {shape: plank, at: [110, 100], "
                                  "on: b}\n    f: {shape: brick, at: [180, 100], on: e}\n"),
     11, "teach.objects.e", "would tip off 'b' under what rests on it"),
    # the brick put on the plank's end tips the plank off the brick under it
    ("placed-load-beyond-support",
     _with("on: p}\n", "on: p}\n    e: {shape: plank, at: [110, 100], on: b}\n").replace(
         "on: table\n      at: [0, 150]", "on: e\n      at: [180, 100]"),
     16, "teach.demonstration[1].at", "would tip off 'b' under what rests on it"),
    ("placed-beyond-support", _steps("    - pick: a\n    - place: a\n      on: p\n"
                                     "      at: [-85, 300]\n"), 15,
     "teach.demonstration[1].at", "would tip off 'p'"),
    ("noise-unknown-key", GOOD + "noise: {blur: 1}\n", 16, "noise.blur", "unknown key"),
    ("noise-negative", GOOD + "noise: {tremor: -1}\n", 16, "noise.tremor", "not be negative"),
    ("noise-speed-order", GOOD + "noise: {speed: [1.2, 0.8]}\n", 16, "noise.speed",
     "0 < low <= high"),
    ("step-two-kinds", _steps("    - pick: a\n      touch: b\n"), 12, "teach.demonstration[0]",
     "exactly one of pick, place, touch"),
    ("step-unknown-object", _steps("    - pick: z\n"), 12, "teach.demonstration[0].pick",
     "unknown object 'z'"),
    ("step-unknown-key", _steps("    - pick: a\n      at: [0, 0]\n"), 13,
     "teach.demonstration[0].at", "unknown key 'at'"),
    ("pick-while-holding", _steps("    - pick: a\n    - pick: b\n"), 13,
     "teach.demonstration[1].pick", "while holding 'a'"),
    ("place-not-held", _steps("    - place: a\n      on: table\n      at: [0, 150]\n"), 12,
     "teach.demonstration[0].place", "the hand holds nothing"),
    ("place-other-than-held", _steps("    - pick: a\n    - place: b\n      on: table\n"
                                     "      at: [0, 150]\n"), 13,
     "teach.demonstration[1].place", "the hand holds 'a'"),
    ("place-on-absent", _steps("    - pick: a\n    - place: a\n      on: q\n"), 14,
     "teach.demonstration[1].on", "unknown object 'q'"),
    ("place-on-carried", _steps("    - pick: p\n    - place: p\n      on: c\n"), 14,
     "teach.demonstration[1].on", "rides on 'p'"),
    ("place-table-needs-at", _steps("    - pick: a\n    - place: a\n      on: table\n"), 13,
     "teach.demonstration[1].at", "needs 'at'"),
    ("place-overlap", _steps("    - pick: a\n    - place: a\n      on: table\n"
                             "      at: [100, 110]\n"), 15,
     "teach.demonstration[1].at", "overlap 'b'"),
    ("place-off-table", _steps("    - pick: a\n    - place: a\n      on: table\n"
                               "      at: [0, -30]\n"), 15,
     "teach.demonstration[1].at", "off the table"),
    ("supports-differ", _steps("    - pick: a\n    - place: a\n      on: [b, p]\n"
                               "      at: [0, 0]\n"), 14,
     "teach.demonstration[1].on", "differ in height"),
    ("touch-held", _steps("    - pick: a\n    - touch: a\n"), 13,
     "teach.demonstration[1].touch", "in the hand"),
    ("align-unknown-face", _steps("    - pick: a\n    - place: a\n      on: table\n"
                                  "      at: [60, 100]\n      align: {with: b, face: up}\n"),
     16, "teach.demonstration[1].align.face", "unknown face 'up'"),
    ("execute-unknown-shape", GOOD + "execute:\n  objects:\n    x: {shape: cube, at: [0, 0]}\n",
     18, "execute.objects.x.shape", "unknown shape 'cube'"),
]


@pytest.mark.parametrize("text,line,where,fragment", [r[1:] for r in ROWS],
                         ids=[f"errors-row{i + 1}-{r[0]}" for i, r in enumerate(ROWS)])
def test_bad_scenario_is_reported_with_place(text, line, where, fragment):
    with pytest.raises(InputError) as info:
        load_text(text, "bad.yaml")
    err = info.value
    assert err.file == "bad.yaml"
    assert err.where == where
    assert fragment in err.message
    if line is not None:
        assert err.line == line
    assert str(err).startswith("bad.yaml")


def test_good_scenario_loads_with_defaults():
    sc = load_text(GOOD)
    assert sc.seed == 0 and sc.noise.pixel == 2.0 and sc.noise.tremor == 1.0
    assert sc.noise.speed == (0.8, 1.2)
    assert sc.teach.objects["c"].center == (-40.0, 300.0, 45.0)  # on the 20 mm plank
    assert sc.demonstration[1].dest == (0.0, 150.0, 25.0)


def test_bare_on_key_is_a_string_and_riders_move_with_their_carrier():
    sc = load_text(_steps("    - pick: p\n    - place: p\n      on: table\n      at: [0, 250]\n"))
    assert sc.states[-1].center["c"] == (-40.0, 250.0, 45.0)
    assert ["on", "c", "p"] in sc.states[-1].relations(RULES.roles)
