"""Sec. VI-B: the state-change formulas, one case per formula, on small relation sets."""

from __future__ import annotations

import pytest

from lbw_engine.understand import (
    RelationTable,
    focused_objects,
    gather_changes,
    leaf_changes,
    protected,
)

T = RelationTable(tolerance=1.0)
A = T.intern("on", "a", "table", [0.0, 0.0, 25.0], "table")
A2 = T.intern("on", "a", "b", [0.0, 0.0, 50.0], "b")
B = T.intern("on", "b", "table", [100.0, 0.0, 25.0], "table")
C = T.intern("on", "c", "a", [1.0, 2.0, 50.0], "a")
H = T.intern("holding", "hand", "a")
HB = T.intern("held-by", "a", "hand")
AGENTS, FIXED = frozenset({"hand"}), frozenset({"table"})


def fs(*rels):
    """A frozenset of relations."""
    return frozenset(rels)


LEAF = [  # (IS, FS) -> (SC+, SC-, SI)
    ("VI-B1-SCplus=FS-IS", (fs(A, B), fs(H, HB, B)), (fs(H, HB), fs(A), fs(B))),
    ("VI-B1-SCminus=IS-FS", (fs(H, HB, B), fs(A2, B)), (fs(A2), fs(H, HB), fs(B))),
    ("VI-B1-SI=IS^FS", (fs(B, C), fs(B, C)), (fs(), fs(), fs(B, C))),
]


@pytest.mark.parametrize("given,expected", [r[1:] for r in LEAF], ids=[r[0] for r in LEAF])
def test_leaf_formulas(given, expected):
    assert leaf_changes(*given) == expected


UPPER = [  # children (SC+, SC-, SI) -> (SC+, SC-, SI)
    ("VI-B1-SCplus=U(SC+)-U(SC-)",
     [(fs(H, HB), fs(A), fs()), (fs(A2), fs(H, HB), fs())], 0, fs(A2)),
    ("VI-B1-SCminus=U(SC-)-U(SC+)",
     [(fs(H, HB), fs(A), fs()), (fs(A2), fs(H, HB), fs())], 1, fs(A)),
    # SI = SI' - SC+' - SC-' + (SC+' ^ SC-'): B unchanged everywhere stays; C unchanged in one
    # child but established by another leaves SI; H, HB made and undone come back into SI.
    ("VI-B1-SI=SI'-SC+'-SC-'+(SC+'^SC-')",
     [(fs(H, HB), fs(A), fs(B)), (fs(A2, C), fs(H, HB), fs(B)), (fs(), fs(), fs(C))],
     2, fs(B, H, HB)),
]


@pytest.mark.parametrize("children,slot,expected", [r[1:] for r in UPPER],
                         ids=[r[0] for r in UPPER])
def test_upper_formulas(children, slot, expected):
    assert gather_changes(children)[slot] == expected


FOCUS = [  # (SC+, SC-) -> (base, target)
    ("VI-B2-base=obj+^obj-", fs(A2), fs(A), {"a"}, {"b"}),
    ("VI-B2-target=obj+-base", fs(A2, C), fs(A), {"a"}, {"b", "c"}),
    ("VI-B2-fixed-table-never-base", fs(T.intern("on", "a", "table", [5.0, 5.0, 25.0], "table")),
     fs(A), {"a"}, {"table"}),
    ("VI-B2-agent-left-out-FETCH-target=support", fs(H, HB), fs(A), {"a"}, {"table"}),
]


@pytest.mark.parametrize("plus,minus,base,target", [r[1:] for r in FOCUS],
                         ids=[r[0] for r in FOCUS])
def test_focused_objects(plus, minus, base, target):
    assert focused_objects(plus, minus, AGENTS, FIXED) == (frozenset(base), frozenset(target))


SP = [  # (SI, base) -> (SP, special)
    ("VI-B3-SP=SI^rel(base)", fs(B, C), {"a"}, fs(C), {"c"}),
    ("VI-B3-special=subjects(SP)-base", fs(A, C), {"a"}, fs(A, C), {"c"}),
    ("VI-B3-agent-relations-not-protected", fs(H, HB, B), {"a"}, fs(), set()),
]


@pytest.mark.parametrize("si,base,sp,special", [r[1:] for r in SP], ids=[r[0] for r in SP])
def test_protected(si, base, sp, special):
    assert protected(si, frozenset(base), AGENTS) == (sp, frozenset(special))


EQUALITY = [  # two measurements of a relation -> same set element?
    ("at-within-tolerance", ("on", "x", "y", [1.0, 2.0, 3.0], "y"),
     ("on", "x", "y", [1.4, 1.6, 3.9], "y"), True),
    ("at-beyond-tolerance", ("on", "x", "y", [1.0, 2.0, 3.0], "y"),
     ("on", "x", "y", [1.0, 3.5, 3.0], "y"), False),
    ("other-wrt", ("on", "x", "y", [1.0, 2.0, 3.0], "y"),
     ("on", "x", "y", [1.0, 2.0, 3.0], "table"), False),
    ("on-multiple-supports-are-a-set", ("on-multiple", "p", ["a", "b"], [0, 0, 60], None),
     ("on-multiple", "p", ["b", "a"], [0, 0, 60], None), True),
    ("no-at-vs-at", ("on", "x", "y", None, None), ("on", "x", "y", [0, 0, 0], "y"), False),
]


@pytest.mark.parametrize("one,two,same", [r[1:] for r in EQUALITY], ids=[r[0] for r in EQUALITY])
def test_relation_equality(one, two, same):
    table = RelationTable(tolerance=1.0)
    assert (table.intern(*one) is table.intern(*two)) is same
