"""Recognition repair (Sec. IX-C2): one inconsistent step, one change that fits, or none.

The paper leaves failure treatment as future work and proposes to check what
was recognized against each operation's preconditions and effects. After
recognition the sequence runs through rules/domain.yaml (``consistency``). At
its first inconsistent step p, every single change at or before p is tried:

* delete: operation k goes (the eye saw a motion the hand did not make);
* narrow: a slot of k that names several objects names one of them;
* delete and rejoin: k goes, and the operations on both sides of it, the same
  operation with the same base and special, become one (a spurious local
  motion cut one motion in two; Table VII: a motion ends where the next begins);
* replace: k becomes another operation of its motion class (a feature of
  Table V was misread); its slots stay, its final relations follow effects.yaml.

A change is a candidate when its run has no inconsistency at or before p and
none the sequence did not have (it fixes p and breaks nothing). Of the
candidates, those leaving the fewest inconsistencies count; the change is made
only when exactly one is left. Zero or several leave the sequence as
recognized, and the inconsistency is reported. Then the next one is treated
(after one left as recognized, too).
Nothing is inserted: a change needs a recognized motion to act on. Every change
is recorded in actions.json ``repairs`` (design.md): ``at`` (where ``now``
starts in the repaired ``operations``), ``was``, ``now`` (whole operation
records) and ``why``. No operation is named here; docs/repair.md.
"""

from __future__ import annotations

import copy
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.rules import RuleSet, Template
from lbw_engine.rules.domain import FILE, WILDCARD
from lbw_engine.understand.consistency import (
    Binder,
    Finding,
    Run,
    Start,
    relation_objects,
    run_sequence,
    slot_values,
    start_state,
)


@dataclass(eq=False)
class Entry:
    """An operation record of the sequence being repaired, and where it came from."""

    record: dict[str, Any]
    origin: int  # its index in the recognized sequence (a rejoined one: the later part's)


@dataclass(frozen=True)
class Change:
    """One candidate change: ``count`` entries from ``at`` give way to ``now``."""

    at: int
    count: int
    now: tuple[dict[str, Any], ...]
    words: str  # the change, for ``why``
    origin: int  # of the new entries

    def applied(self, entries: list[Entry]) -> list[Entry]:
        """The sequence with this change made."""
        new = [Entry(r, self.origin) for r in self.now]
        return [*entries[:self.at], *new, *entries[self.at + self.count:]]


@dataclass
class Repaired:
    """What repair made of a recognized sequence."""

    actions: dict[str, Any]  # the document, with ``repairs`` when any change was made
    repairs: list[dict[str, Any]] = field(default_factory=list)
    left: list[str] = field(default_factory=list)  # inconsistencies no single change fixed
    checked: bool = True  # False: an operation has no entry in domain.yaml

    @property
    def operations(self) -> list[str]:
        """The operation names of the repaired sequence."""
        return [op["operation"] for op in self.actions["operations"]]


def repair_actions(doc: dict[str, Any], rules: RuleSet) -> Repaired:
    """Run a recognized sequence (an actions.json document) through the domain and
    repair what exactly one single change can (module docstring)."""
    ops = doc["operations"]
    start = start_state(ops, doc.get("objects") or {}, rules)
    binder = Binder(start)
    entries = [Entry(op, i) for i, op in enumerate(ops)]
    run = run_sequence(start, ops, binder)
    if any(binder.static(op).op is None for op in ops):
        return Repaired(doc, left=[str(f) for f in run.findings], checked=False)
    made: list[tuple[Change, list[Entry], Entry | None, str]] = []
    notes: dict[str, str] = {}  # finding -> why it stayed
    skipped: set[int] = set()  # where no single change fits (origins): passed over
    while len(made) + len(skipped) < len(ops):
        todo = [f for f in run.findings if entries[f.index].origin not in skipped]
        if not todo:
            break
        chosen = _choose(rules, start, binder, entries, run, todo[0], skipped, notes)
        if chosen is None:
            skipped.add(entries[todo[0].index].origin)
            continue
        change, trial, why = chosen
        after = entries[change.at + change.count] if change.at + change.count < len(entries) \
            else None
        made.append((change, entries[change.at:change.at + change.count], after, why))
        entries = trial
        run = run_sequence(start, [e.record for e in entries], binder)
    left = [f"{f}: {notes[str(f)]}" if str(f) in notes else str(f) for f in run.findings]
    if not made:
        return Repaired(doc, left=left)
    out = {**doc, "operations": [e.record for e in entries]}
    out["repairs"] = [_record(entries, *m) for m in made]
    return Repaired(out, out["repairs"], left)


def _record(entries: list[Entry], change: Change, was: list[Entry], after: Entry | None,
            why: str) -> dict[str, Any]:
    """One ``repairs`` entry; ``at`` is where its ``now`` starts in the final sequence."""
    position = {id(e.record): i for i, e in enumerate(entries)}
    anchor = change.now[0] if change.now else (after.record if after else None)
    at = position.get(id(anchor), len(entries)) if anchor is not None else len(entries)
    return {"at": at, "was": [copy.deepcopy(e.record) for e in was],
            "now": [copy.deepcopy(r) for r in change.now], "why": why}


SLOTS = ("base", "target", "special")  # actions.json's slots of an operation (design.md)


def _choose(rules: RuleSet, start: Start, binder: Binder, entries: list[Entry], run: Run,
            first: Finding, skipped: set[int], notes: dict[str, str]
            ) -> tuple[Change, list[Entry], str] | None:
    """The one change that fixes ``first`` and breaks nothing, or None.

    Findings before ``first`` are ones no single change fixed (``skipped``);
    a change may leave them, as it may leave the later ones.
    """
    p_origin = entries[first.index].origin
    current = {entries[f.index].origin for f in run.findings}
    scored: list[tuple[int, Change, list[Entry]]] = []
    for change in _changes(rules, entries, first.index):
        trial = change.applied(entries)

        def useless(f: Finding, trial: list[Entry] = trial) -> bool:
            origin = trial[f.index].origin
            return origin not in current or origin == p_origin or \
                (origin < p_origin and origin not in skipped)

        tried = run_sequence(start, [e.record for e in trial], binder, stop=useless)
        if not any(useless(f) for f in tried.findings):
            scored.append((len(tried.findings), change, trial))
    if not scored:
        notes[str(first)] = f"no single change makes it consistent with {FILE}"
        return None
    fewest = min(n for n, _, _ in scored)
    best = [(c, t) for n, c, t in scored if n == fewest]
    if len(best) > 1:
        notes[str(first)] = (f"{len(best)} changes fit equally ("
                             + "; ".join(c.words for c, _ in best) + "), none is made")
        return None
    change, trial = best[0]
    return change, trial, (f"{first}; {change.words} is the only single change that makes "
                           f"this step consistent with {FILE} and breaks no other")


def _changes(rules: RuleSet, entries: list[Entry], p: int) -> Iterator[Change]:
    """Every single change at or before step ``p`` (the list of the module docstring).

    No change undoes what an operation's snapshots recorded: only an operation
    that changed no relation may go, and another reading must make at least the
    changes recorded (it may make more, that the steps after it need).
    """
    names = {e.record.get("name") for e in entries}
    for k in range(p + 1):
        rec = entries[k].record
        name = rec.get("name") or f"#{k}"
        recorded = _difference(rec)
        if not any(recorded):
            yield Change(k, 1, (), f"deleting {name}", entries[k].origin)
            # ... or it acted on one of the several objects a slot names (a carried beam
            # brought down onto one pillar reached the next one's edge: helper round 20,
            # r07, whose touch was deleted; with both readings, no change is made)
            for slot in SLOTS:
                several = rec.get(slot) or []
                for one in several if len(several) > 1 else []:
                    yield Change(k, 1, ({**copy.deepcopy(rec), slot: [one]},),
                                 f"reading {name}'s {slot} as {one} alone", entries[k].origin)
            if 0 < k < len(entries) - 1 and _same_motion(entries[k - 1].record,
                                                        entries[k + 1].record):
                a, b = entries[k - 1].record, entries[k + 1].record
                yield Change(k - 1, 3, (_rejoined(a, b),),
                             f"deleting {name} and taking {a.get('name')} and "
                             f"{b.get('name')} as the one motion it cut in two",
                             entries[k + 1].origin)
        for motion, other in _alternatives(rules, rec):
            new = _replaced(rules, rec, motion, other, names)
            if new is not None and all(r <= n for r, n in zip(recorded, _difference(new),
                                                              strict=True)):
                yield Change(k, 1, (new,), f"reading {name} as {other}", entries[k].origin)


def _difference(rec: dict[str, Any]) -> tuple[set[tuple], set[tuple]]:
    """The relations an operation's snapshots show it adding and removing (positions aside:
    two measurements of one relation differ by noise)."""
    def keys(state: str) -> set[tuple]:
        return {(r[0], r[1], frozenset(relation_objects(r)))
                for r in rec.get(state, {}).get("relations", [])}

    before, after = keys("initial_state"), keys("final_state")
    return after - before, before - after


def _same_motion(a: dict[str, Any], b: dict[str, Any]) -> bool:
    """Two operations that may be one motion: the same operation, base and special."""
    return all(a.get(key) == b.get(key) for key in ("operation", "base", "special"))


def _rejoined(a: dict[str, Any], b: dict[str, Any]) -> dict[str, Any]:
    """One motion from its two parts: ``a``'s start, ``b``'s end and where it came to.

    A snapshot holds the relations of its operation's nodes. The joined motion ends
    with ``b``'s nodes, so it starts with ``b``'s relations too (neither part changed
    any): ``a``'s would leave the relations of the blocks it came to looking added by
    the carry. The positions at the start are ``a``'s, with ``b``'s for nodes ``a`` had not.
    """
    out = copy.deepcopy(a)
    for key in ("t_end", "final_event", "target", "final_state"):
        if key in b:
            out[key] = copy.deepcopy(b[key])
    if "initial_state" in b:
        start = copy.deepcopy(b["initial_state"])
        start["positions"] = {**start.get("positions", {}),
                              **copy.deepcopy(a.get("initial_state", {}).get("positions", {}))}
        out["initial_state"] = start
    if "fine" in a or "fine" in b:
        out["fine"] = [*a.get("fine", []), *b.get("fine", [])]
    return out


def _alternatives(rules: RuleSet, rec: dict[str, Any]) -> list[tuple[str, str]]:
    """(motion class, operation): the other operations of the record's class (Table V)."""
    op = rec["operation"]
    classes = [rec["motion"]] if rec.get("motion") in rules.classification else \
        [m for m, rows in rules.classification.items() if any(r.operation == op for r in rows)]
    out: list[tuple[str, str]] = []
    for motion in classes:
        for row in rules.classification[motion]:
            if row.operation != op and row.operation in rules.domain.operations \
                    and row.operation not in (o for _, o in out):
                out.append((motion, row.operation))
    return out


def _replaced(rules: RuleSet, rec: dict[str, Any], motion: str, other: str,
              names: set[Any]) -> dict[str, Any] | None:
    """``rec`` read as ``other``: a new name, final relations from effects.yaml (None when
    effects.yaml adds a position the record did not measure: nothing is made up)."""
    final = _effect_on(rules, other, rec)
    if final is None:
        return None
    label, n = rules.label(motion, other), 1
    while f"{label}{n:02d}" in names:
        n += 1
    out = copy.deepcopy(rec)
    out.update(operation=other, name=f"{label}{n:02d}")
    out["final_state"] = {**out.get("final_state", {}), "relations": final}
    return out


def _effect_on(rules: RuleSet, op: str, rec: dict[str, Any]) -> list[Any] | None:
    """The record's initial relations changed by ``op``'s effects.yaml rule (Sec. V-B4)."""
    before = copy.deepcopy(rec["initial_state"]["relations"])
    rule = rules.effects.get(op)
    if rule is None:
        return before
    binds = {var: slot_values(src, rec) or () for var, src in rule.bind.items()}

    def names(term: str) -> tuple[str, ...] | None:
        return None if term == WILDCARD else tuple(binds.get(term[1:].rstrip("*"), ()))

    kept = [r for r in before if not any(_matches(r, t, names) for t in rule.remove)]
    measured = rec.get("final_state", {}).get("relations", [])
    for tpl in rule.add:
        if tpl.when is not None and (tpl.when[0] == "single") != (
                len(names(tpl.when[1]) or ()) == 1):
            continue
        made = _instances(tpl, names, measured)
        if made is None:
            return None
        kept += made
    return kept


def _matches(rel: list[Any], tpl: Template, names) -> bool:
    """Does a relation match a removal template (``*`` matches anything)?"""
    if rel[0] != tpl.type:
        return False
    subj, obj = names(tpl.subject), names(tpl.object)
    if subj is not None and rel[1] not in subj:
        return False
    return obj is None or set(relation_objects(rel)) <= set(obj)


def _instances(tpl: Template, names, measured: list[Any]) -> list[Any] | None:
    """The relations an add template makes; one with a position must have been measured."""
    subjects, objs = names(tpl.subject) or (), names(tpl.object) or ()
    if not subjects or not objs:
        return None
    obj: Any = objs[0] if len(objs) == 1 else list(objs)
    out = []
    for subject in subjects if tpl.subject.endswith("*") else subjects[:1]:
        rel = [tpl.type, subject, obj]
        if tpl.wrt is not None:
            seen = [m for m in measured if m[0] == tpl.type and m[1] == subject
                    and set(relation_objects(m)) == set(objs)]
            if not seen:
                return None
            rel = copy.deepcopy(seen[0])
        out.append(rel)
    return out
