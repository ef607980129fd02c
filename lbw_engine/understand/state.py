"""Operators and their state changes (Sec. VI-B).

The formulas, one function each, so the conformance table can test them alone:

* ``leaf_changes``: SC⁺ = FS − IS, SC⁻ = IS − FS, SI = IS ∩ FS (Sec. VI-B1).
* ``gather_changes``: an upper operator from its plot's operators:
  SC⁺' = ∪SC⁺ⱼ, SC⁻' = ∪SC⁻ⱼ, SI' = ∪SIⱼ; SC⁺ = SC⁺' − SC⁻', SC⁻ = SC⁻' − SC⁺',
  SI = SI' − SC⁺' − SC⁻' + (SC⁺' ∩ SC⁻').
* ``focused_objects``: base = obj⁺ ∩ obj⁻, target = obj⁺ − base (Sec. VI-B2).
* ``protected``: SP = SI ∩ {rel(x, y) | x ∈ base ∨ y ∈ base},
  special = {x | rel(x, y) ∈ SP} − base (Sec. VI-B3).

Decisions where the paper is silent (docs/analysis.md): agents (the hand) are
left out of obj⁺/obj⁻ and their relations are never protected; fixed objects
(the table) are never a base; an operator whose only new relations are with the
agent (a FETCH) takes as target the objects it leaves (obj⁻ − base), i.e. the
support the object was picked from.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Union

from lbw_engine.understand.actions import Operation
from lbw_engine.understand.relations import Rel

Changes = tuple[frozenset[Rel], frozenset[Rel], frozenset[Rel]]  # (SC⁺, SC⁻, SI)


def leaf_changes(initial: frozenset[Rel], final: frozenset[Rel]) -> Changes:
    """SC⁺, SC⁻ and SI of a recognized operation from its IS and FS snapshots."""
    return final - initial, initial - final, initial & final


def gather_changes(parts: Iterable[Changes]) -> Changes:
    """SC⁺, SC⁻ and SI of an upper operator from those of its plot's operators."""
    plus_u: set[Rel] = set()
    minus_u: set[Rel] = set()
    si_u: set[Rel] = set()
    for plus, minus, si in parts:
        plus_u |= plus
        minus_u |= minus
        si_u |= si
    sc_plus = frozenset(plus_u - minus_u)
    sc_minus = frozenset(minus_u - plus_u)
    si = frozenset((si_u - plus_u - minus_u) | (plus_u & minus_u))
    return sc_plus, sc_minus, si


def _objects(rels: Iterable[Rel], agents: frozenset[str]) -> set[str]:
    """The objects a set of relations talks about, agents left out."""
    return {name for rel in rels for name in rel.names()} - agents


def focused_objects(
    sc_plus: frozenset[Rel],
    sc_minus: frozenset[Rel],
    agents: frozenset[str],
    fixed: frozenset[str],
) -> tuple[frozenset[str], frozenset[str]]:
    """(base, target): base = obj⁺ ∩ obj⁻ − fixed, target = obj⁺ − base (or obj⁻ − base)."""
    obj_plus = _objects(sc_plus, agents)
    obj_minus = _objects(sc_minus, agents)
    base = (obj_plus & obj_minus) - fixed
    target = obj_plus - base
    if not target:
        # Only relations with the agent were made (a FETCH): name what was left.
        target = obj_minus - base
    return frozenset(base), frozenset(target)


def protected(
    si: frozenset[Rel], base: frozenset[str], agents: frozenset[str]
) -> tuple[frozenset[Rel], frozenset[str]]:
    """(SP, special): unchanged relations touching the base, and their other objects."""
    sp = frozenset(
        rel
        for rel in si
        if not agents.intersection(rel.names()) and base.intersection(rel.names())
    )
    special = frozenset(rel.subject for rel in sp) - base
    return sp, special


# A plot is ("$sequence" | "$parallel", item, ...) or a single member; a member
# is an Operator or a recognized Operation (a leaf, written ($action name)).
Member = Union["Operator", Operation]
Plot = Union[tuple, "Operator", Operation]


@dataclass(eq=False)
class Operator:
    """A plan operator: class, plot, state changes and focused objects (Fig. 14)."""

    cls: str
    plot: Plot
    members: tuple[Member, ...]
    sc_plus: frozenset[Rel]
    sc_minus: frozenset[Rel]
    si: frozenset[Rel]
    sp: frozenset[Rel]
    base: frozenset[str]
    target: frozenset[str]
    special: frozenset[str]
    lo: int  # first and last recognized operation covered (demonstration order)
    hi: int
    name: str = ""
    next: list[Member] = field(default_factory=list)

    def changes(self) -> Changes:
        """(SC⁺, SC⁻, SI)."""
        return self.sc_plus, self.sc_minus, self.si


def member_changes(member: Member) -> Changes:
    """State changes of a plot member (an Operation's are computed from IS and FS)."""
    if isinstance(member, Operation):
        return leaf_changes(member.initial, member.final)
    return member.changes()


def span(member: Member) -> tuple[int, int]:
    """First and last recognized operation a member covers."""
    if isinstance(member, Operation):
        return member.index, member.index
    return member.lo, member.hi


def make_operator(
    cls: str, plot: Plot, members: Sequence[Member], agents: frozenset[str],
    fixed: frozenset[str],
) -> Operator:
    """Build an upper operator from its plot, gathering state and focused objects."""
    sc_plus, sc_minus, si = gather_changes(member_changes(m) for m in members)
    base, target = focused_objects(sc_plus, sc_minus, agents, fixed)
    sp, special = protected(si, base, agents)
    spans = [span(m) for m in members]
    return Operator(
        cls, plot, tuple(members), sc_plus, sc_minus, si, sp, base, target, special,
        min(s[0] for s in spans), max(s[1] for s in spans),
    )
