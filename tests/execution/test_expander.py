"""Table IX: every macro and sub-command row, expanded by the generic expander.

Each case starts the hand somewhere, expands one row of rules/commands.yaml
and compares the emitted primitives (world coordinates) with the row.
"""

import shutil
from pathlib import Path

import pytest

from lbw_engine.do.expander import Context, Expander
from lbw_engine.errors import InputError
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.paths import default_rules_dir
from lbw_engine.rules import load_rules
from lbw_engine.rules.commands import Step

RULESET = load_rules()
RULES = RULESET.commands
A = RULES.approach_height
P1 = (40.0, 120.0, 25.0)  # a brick's centre on the table
P2 = (-60.0, 200.0, 80.0)
P3 = (-30.0, 200.0, 80.0)
START = (150.0, 300.0, 150.0)  # the hand, away from P1 and below the approach height
W = 30.0 + RULES.margin


def _model(hand, held=None):
    model = EnvModel.measured(RULESET, {"b": Body("brick", (30.0, 30.0, 50.0), P1)}, hand)
    if held is not None:
        model.hold(held)
    return model


def _run(macro, args, hand=START, held=None):
    model = _model(hand, held)
    ex = Expander(RULES, model)
    cmds = ex.run((Step(macro, args),), Context(goal=None, width=W, where="test"),
                  scope={"p1": P1, "p2": P2, "p3": P3})
    out = [(c.name, c.world if c.world is not None else c.width) for c in cmds]
    return out, model


ROWS = [
    # Table IX: TRANSFER(pos1, pos2) -> amove(pos1), amove(pos2)
    ("TRANSFER", ("p1", "p2"), [("amove", P1), ("amove", P2)]),
    # PICK(pos1) -> open-hand, go-pickpos(pos1), close-hand, go-maxheight
    ("PICK", ("p1",), [("open-hand", W), ("amove", (P1[0], P1[1], START[2])), ("amove", P1),
                       ("close-hand", None), ("amove", (P1[0], P1[1], A))]),
    # PLACE(pos1) -> go-placepos(pos1), open-hand, go-maxheight
    ("PLACE", ("p1",), [("amove", (P1[0], P1[1], START[2])), ("amove", P1), ("open-hand", W),
                        ("amove", (P1[0], P1[1], A))]),
    # go-pickpos(pos1) -> z <- hand-pos z; amove(pos1 x, pos1 y, z); amove(pos1)
    ("go-pickpos", ("p1",), [("amove", (P1[0], P1[1], START[2])), ("amove", P1)]),
    ("go-placepos", ("p2",), [("amove", (P2[0], P2[1], START[2])), ("amove", P2)]),
    # go-maxheight: straight up to the approach height
    ("go-maxheight", (), [("amove", (START[0], START[1], A))]),
    # Ours (issue #12, docs/execution.md "Fine motion"): set down clear of a contact,
    # then slide into it holding the block ...
    ("SLIDE-PLACE", ("p1", "p2"), [("amove", (P1[0], P1[1], START[2])), ("amove", P1),
                                   ("amove", P2), ("open-hand", W), ("amove", (P2[0], P2[1], A))]),
    # ... or let go, close the jaws above it, come down beside it and push it in.
    ("PUSH-PLACE", ("p1", "p2", "p3"), [
        ("amove", (P1[0], P1[1], START[2])), ("amove", P1), ("open-hand", W),
        ("amove", (P1[0], P1[1], A)), ("close-hand", None), ("amove", (P2[0], P2[1], A)),
        ("amove", P2), ("push", P3), ("amove", (P3[0], P3[1], A))]),
]


@pytest.mark.parametrize("macro,args,want", ROWS, ids=[f"TableIX-{r[0]}" for r in ROWS])
def test_table_ix_row(macro, args, want):
    got, _ = _run(macro, args)
    assert [n for n, _ in got] == [n for n, _ in want]
    for (_, g), (_, w) in zip(got, want, strict=True):
        assert g == pytest.approx(w)


def test_pick_grasps_and_lifts_in_the_model():
    _, model = _run("PICK", ("p1",))
    assert model.holding() == "b"
    assert model.bodies["b"].position == pytest.approx((P1[0], P1[1], A))


def test_arm_coordinates_follow_the_configured_transform():
    model = _model(START)
    cmds = Expander(RULES, model).run((Step("amove", ("p1",)),), Context(None, W, "t"),
                                      {"p1": P1})
    assert cmds[0].arm == pytest.approx(RULES.arm_frame.to_arm(P1))
    assert RULES.arm_frame.to_world(cmds[0].arm) == pytest.approx(P1)
    assert cmds[0].arm != pytest.approx(P1)  # Fig. 24: arm and world frames differ


def test_fig24_goal_positions_map_to_the_printed_arm_x_y():
    # Fig. 24 prints GOAL-POSITION #f(-25.1 151.0 59.8) -> ARM #f(301.1 102.6 ...).
    arm = RULES.arm_frame.to_arm((-25.1, 151.0, 59.8))
    assert arm[:2] == pytest.approx((301.1, 102.6), abs=0.3)


def test_null_moves_are_not_emitted():
    got, _ = _run("go-pickpos", ("p1",), hand=(P1[0], P1[1], A))
    assert got == [("amove", P1)]


@pytest.mark.parametrize("angle,emitted", [(0.0, []), (90.0, ["turn-wrist 90.0"])],
                         ids=["jaws-along-x-already", "turn-to-y"])
def test_the_wrist_turns_only_when_the_grip_needs_it(angle, emitted):
    model = _model(START)
    ex = Expander(RULES, model)
    cmds = ex.run((Step("turn-wrist", ("wrist",)),),
                  Context(goal=None, width=W, where="test", wrist=angle))
    assert [c.text() for c in cmds] == emitted and model.wrist == angle


BAD = [
    ("unknown-key", "approach-height: 200.0", "approach-height: 200.0\nspeed: 3",
     "unknown key 'speed'"),
    ("unknown-macro", "      - [go-pickpos, pos1]", "      - [go-pikpos, pos1]",
     "unknown macro or primitive 'go-pikpos'"),
    ("recursion", "      - [amove, {xy: hand-pos, z: approach-height}]", "      - [PICK, hand-pos]",
     "recursive macro expansion"),
    ("arity", "      - [amove, pos1]\n      - [amove, pos2]", "      - [amove, pos1, pos2]",
     "'amove' takes 1 argument(s), got 2"),
    ("unknown-name", "      - [amove, pos2]", "      - [amove, pos3]", "unknown name 'pos3'"),
    ("bad-goal-source", "{goal: [object], steps: [[PICK", "{goal: [thing], steps: [[PICK",
     "unknown name 'thing'"),
    ("not-orthonormal", "    - [0.0, 0.0, -1.0]", "    - [0.0, 0.0, -0.5]", "orthonormal"),
    ("jaw-axis-z", "jaw-axes: [x, y]", "jaw-axes: [x, z]", "unknown name 'z'"),
    ("jaw-axes-twice", "jaw-axes: [x, y]", "jaw-axes: [x, x]", "each way the jaws close once"),
    ("max-opening-zero", "max-opening: 150.0", "max-opening: 0", "expected a number in [1, 1000]"),
    ("fine-relation-unknown", "relations: [coplanar]", "relations: [coplanr]",
     "unknown name 'coplanr'"),
    ("harmless-class-unknown", "harmless: [FAKE]", "harmless: [FAKES]", "unknown name 'FAKES'"),
    ("turn-wrist-arity", "[turn-wrist, wrist]", "[turn-wrist]", "'turn-wrist' takes 1 argument"),
    ("set-aside-unknown-name", "[PLACE, set-down]", "[PLACE, put-down]",
     "unknown name 'put-down'"),
]


@pytest.mark.parametrize("old,new,needle", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_commands_yaml_is_reported_with_file_and_line(tmp_path, old, new, needle):
    text = (Path(default_rules_dir()) / "commands.yaml").read_text()
    assert old in text
    bad = text.replace(old, new, 1)
    shutil.copytree(default_rules_dir(), tmp_path / "rules")
    path = tmp_path / "rules" / "commands.yaml"
    path.write_text(bad)
    with pytest.raises(InputError) as exc:
        load_rules(tmp_path / "rules")
    err = exc.value
    assert needle in err.message
    assert err.file == str(path) and err.line is not None
    pairs = zip(text.splitlines(), bad.splitlines(), strict=False)
    changed = next(i for i, (a, b) in enumerate(pairs, 1) if a != b)
    assert abs(err.line - changed) <= 3


# Issue #12 class 3: a 118 mm pillar gripped near its top hangs 88 mm below the grip centre;
# carried at the fixed approach height it swept over a standing pillar and knocked it down.
PILLAR = (17.0, 17.0, 118.0)
APPROACH_CASES = [  # (id, hand z, holds the pillar, expected approach height)
    ("empty-hand-over-pillar", 150.0, False, max(A, 118.0 + RULES.tip + 10.0)),
    ("carried-pillar-over-pillar", 148.0, True, max(A, 118.0 + (148.0 - 30.0) + 10.0)),
]


@pytest.mark.parametrize("hand_z,holds,expected", [c[1:] for c in APPROACH_CASES],
                         ids=[c[0] for c in APPROACH_CASES])
def test_the_approach_height_clears_the_tallest_object(hand_z, holds, expected):
    bodies = {"standing": Body("pillar", PILLAR, (0.0, 200.0, 59.0)),
              "carried": Body("pillar", PILLAR, (100.0, 100.0, 89.0))}  # foot at z = 30
    model = EnvModel.measured(RULESET, bodies, (100.0, 100.0, hand_z))
    if holds:
        model.hold("carried")
    assert Expander(RULES, model).approach_height() == pytest.approx(expected)
