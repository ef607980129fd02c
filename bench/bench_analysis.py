"""Plan analysis (Sec. VI) on synthetic demonstrations of growing size.

Towers, arches and tables are built side by side, one after another, as a
demonstrator would: every ACHIEVE is REACH, PICK, REACH-WITH-OBJ, PLACE with
IS/FS snapshots like the recognizer's, and now and then a touch (a FAKE outside
any ACHIEVE). We time ``analyze`` (templates, state algebra, closures, naming,
plan.json) for 10 ... 10,000 ACHIEVEs and fit the growth exponent of time vs.
size on a log-log scale.

    .venv/bin/python -m bench analysis          # all sizes, figures to bench/results/
    .venv/bin/python -m bench.bench_analysis 1000 10000
"""

from __future__ import annotations

import math
import sys
import time
from typing import Any

HAND, TABLE = "hand", "table"
SIZES = (10, 100, 1000, 10000)


def on(subject: str, support: str | list[str], at: list[float], wrt: str | None = None) -> list:
    """An `on` (one support) or `on-multiple` relation with coordinates."""
    if isinstance(support, list):
        return ["on-multiple", subject, support, {"at": at, "wrt": wrt or TABLE}]
    return ["on", subject, support, {"at": at, "wrt": wrt or support}]


def _op(name: str, operation: str, target: list[str], special: list[str],
        initial: list, final: list) -> dict[str, Any]:
    """One actions.json operation entry."""
    return {"name": name, "operation": operation, "base": [HAND], "target": target,
            "special": special, "initial_state": {"relations": initial},
            "final_state": {"relations": final}}


class TaskWriter:
    """Writes an actions.json document one pick-and-place (or touch) at a time."""

    def __init__(self) -> None:
        self.ops: list[dict[str, Any]] = []
        self.counts: dict[str, int] = {}

    def _name(self, operation: str) -> str:
        """Fig. 12 style names: pick01, place-on-block02 ..."""
        self.counts[operation] = self.counts.get(operation, 0) + 1
        return f"{operation.lower()}{self.counts[operation]:02d}"

    def add(self, operation: str, target: list[str], special: list[str], initial: list,
            final: list) -> None:
        """Append one operation."""
        self.ops.append(_op(self._name(operation), operation, target, special, initial, final))

    def achieve(self, obj: str, start: list, goal: list[list], context: list | None = None,
                riding: list | None = None) -> None:
        """FETCH + PUT of ``obj`` from its ``start`` relation to the ``goal`` relations.

        ``context``: unchanged relations of the target seen in the PLACE snapshots;
        ``riding``: relations of objects resting on ``obj`` (carried along).
        """
        context, riding = context or [], riding or []
        hold = [["holding", HAND, obj], ["held-by", obj, HAND]]
        support = goal[0][2] if isinstance(goal[0][2], list) else [goal[0][2]]
        table_goal = support == [TABLE]
        self.add("REACH", [obj], [], [start, *riding], [start, *riding])
        self.add("PICK", [obj], [], [start, *riding], [*hold, *riding])
        self.add("REACH-WITH-OBJ", support, [obj], [*hold, *riding, *context],
                 [*hold, *riding, *context])
        self.add("PLACE-ON-TABLE" if table_goal else "PLACE-ON-BLOCK", support, [obj],
                 [*hold, *riding, *context], [*goal, *riding, *context])

    def touch(self, obj: str, rel: list) -> None:
        """REACH then NO-OP: the hand comes down to ``obj`` and leaves (a FAKE)."""
        self.add("REACH", [obj], [], [rel], [rel])
        self.add("NO-OP", [obj], [], [rel], [rel])

    def withdraw(self) -> None:
        """The hand leaves."""
        self.add("WITHDRAW", [], [], [], [])

    def document(self) -> dict[str, Any]:
        """The actions.json document."""
        return {"operations": self.ops}


def _tower(w: TaskWriter, tag: str, x: float, n: int) -> None:
    """A tower of ``n`` bricks at ``x``."""
    below = None
    for k in range(n):
        b = f"{tag}b{k}"
        start = on(b, TABLE, [x, 350.0 + k * 0.1, 25.0])
        goal = (on(b, TABLE, [x, 100.0, 25.0]) if below is None
                else on(b, below, [0.0, 0.0, 50.0]))
        w.achieve(b, start, [goal])
        below = b


def _arch(w: TaskWriter, tag: str, x: float, n: int) -> None:
    """Two pillars and a lintel on both (on-multiple, co-support as Fig. 21)."""
    pillars = [f"{tag}p0", f"{tag}p1"][: max(0, min(n, 2))]
    placed = []
    for k, p in enumerate(pillars):
        goal = on(p, TABLE, [x + 40.0 * k, 100.0, 25.0])
        w.achieve(p, on(p, TABLE, [x, 360.0 + k, 25.0]), [goal])
        placed.append(goal)
    if n >= 3:
        lintel = f"{tag}l"
        goal = [on(lintel, pillars, [x + 20.0, 100.0, 55.0])]
        goal += [["co-support", p, lintel, {"at": [40.0 * k - 20.0, 0.0, -30.0], "wrt": lintel}]
                 for k, p in enumerate(pillars)]
        w.achieve(lintel, on(lintel, TABLE, [x, 380.0, 5.0]), goal, context=placed)


def _table(w: TaskWriter, tag: str, x: float, n: int) -> None:
    """Four legs and a plate on them (Fig. 18)."""
    legs = [f"{tag}g{k}" for k in range(min(n, 4))]
    placed = []
    for k, g in enumerate(legs):
        goal = on(g, TABLE, [x + 30.0 * (k % 2), 100.0 + 30.0 * (k // 2), 25.0])
        w.achieve(g, on(g, TABLE, [x, 300.0 + k, 25.0]), [goal])
        placed.append(goal)
    if n >= 5:
        plate = f"{tag}t"
        w.achieve(plate, on(plate, TABLE, [x, 390.0, 5.0]),
                  [on(plate, legs, [x + 15.0, 115.0, 55.0])], context=placed)


BUILDERS = ((_tower, 3), (_arch, 3), (_table, 5))


def synthetic_task(achieves: int) -> dict[str, Any]:
    """An actions.json document with exactly ``achieves`` ACHIEVEs, structures side by side."""
    w = TaskWriter()
    left, k = achieves, 0
    while left > 0:
        build, size = BUILDERS[k % len(BUILDERS)]
        n = min(size, left)
        build(w, f"s{k}-", 1000.0 * k, n)
        if k % 7 == 3:  # now and then a hesitant touch: removed as redundant
            w.touch(f"s{k}-x", on(f"s{k}-x", TABLE, [1000.0 * k, 20.0, 25.0]))
        left -= n
        k += 1
    w.withdraw()
    return w.document()


def run_once(achieves: int) -> dict[str, float]:
    """Analyse one synthetic task; return the timings in seconds."""
    from lbw_engine.rules import load_rules
    from lbw_engine.understand import RelationTable, analyze, parse_actions

    rules = load_rules().analysis
    doc = synthetic_task(achieves)
    t0 = time.perf_counter()
    seq = parse_actions(doc, RelationTable(rules.tolerance), "<synthetic>")
    t1 = time.perf_counter()
    result = analyze(seq, rules)
    t2 = time.perf_counter()
    n_ach = sum(1 for op in result.operators.values() if op.cls == "ACHIEVE")
    assert n_ach == achieves, (n_ach, achieves)
    return {"operations": len(doc["operations"]), "load_s": t1 - t0, "analyze_s": t2 - t1,
            "operators": len(result.operators)}


def growth_exponent(sizes: list[int], times: list[float]) -> float:
    """Least-squares slope of log(time) against log(size)."""
    xs, ys = [math.log(s) for s in sizes], [math.log(t) for t in times]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True)) / sum(
        (x - mx) ** 2 for x in xs)


def main(argv: list[str]) -> dict:
    """Time analysis per size (best of 3, 1 run for 10,000) and fit the exponent."""
    sizes = [int(a) for a in argv] or list(SIZES)
    run_once(10)  # warm up: grammar compilation is cached
    rows = []
    print(f"{'ACHIEVEs':>9} {'operations':>10} {'operators':>9} {'load s':>8} {'analyze s':>9}")
    for n in sizes:
        runs = [run_once(n) for _ in range(1 if n >= 10000 else 3)]
        best = min(runs, key=lambda r: r["analyze_s"])
        rows.append({"achieves": n, **best})
        print(f"{n:>9} {best['operations']:>10} {best['operators']:>9} "
              f"{best['load_s']:>8.4f} {best['analyze_s']:>9.4f}")
    fit = [r for r in rows if r["achieves"] >= 100] or rows
    exponent = growth_exponent([r["achieves"] for r in fit], [r["analyze_s"] for r in fit])
    print(f"growth exponent (time ~ n^k, n >= 100): k = {exponent:.2f}")
    return {"rows": rows, "growth_exponent": exponent}


if __name__ == "__main__":
    main(sys.argv[1:])
