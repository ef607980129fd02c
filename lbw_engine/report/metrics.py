"""Recognized sequence vs. ground truth, plan vs. true final relations (benchmark figures).

Operation names are compared as opaque strings: nothing here knows what any
operation means (the rules decide). One convention from perception.world.groundtruth:
the hand's leaving motion may be split by the recognizer (Fig. 12 shows two
closing operations where the demonstrator made one), so trailing repeats of a
sequence's last operation count as one (``collapse_tail``).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from typing import Any

# The two-sided 95% point of the standard normal distribution.
Z95 = statistics.NormalDist().inv_cdf(0.975)
# Figures that are a proportion of scenarios, each with its Wilson interval in the summary.
# ``exact_repaired``: exact after recognition repair (Sec. IX-C2, docs/repair.md).
# ``targets_exact``: exact, and every operation on the objects it really acted on.
RATES = {"exact_sequence_rate": "exact", "exact_repaired_rate": "exact_repaired",
         "targets_exact_rate": "targets_exact",
         "plan_correct_rate": "plan_correct", "execution_success_rate": "execution_success"}


def collapse_tail(ops: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Merge trailing repeats of the last operation into one spanning all of them."""
    if len(ops) < 2:
        return list(ops)
    last = ops[-1]["operation"]
    k = len(ops) - 1
    while k > 0 and ops[k - 1]["operation"] == last:
        k -= 1
    if k == len(ops) - 1:
        return list(ops)
    merged = dict(ops[k], t_end=ops[-1].get("t_end"))
    return [*ops[:k], merged]


def align(expected: Sequence[str], got: Sequence[str]) -> tuple[int, list[tuple[int, int]]]:
    """Levenshtein distance and the matched index pairs (equal names) of one optimal alignment."""
    n, m = len(expected), len(got)
    d = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n + 1):
        d[i][0] = i
    for j in range(m + 1):
        d[0][j] = j
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            cost = 0 if expected[i - 1] == got[j - 1] else 1
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost)
    pairs = []
    i, j = n, m
    while i > 0 and j > 0:
        if expected[i - 1] == got[j - 1] and d[i][j] == d[i - 1][j - 1]:
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
        elif d[i][j] == d[i - 1][j - 1] + 1:
            i, j = i - 1, j - 1
        elif d[i][j] == d[i - 1][j] + 1:
            i -= 1
        else:
            j -= 1
    return d[n][m], pairs[::-1]


def first_difference(expected: Sequence[str], got: Sequence[str]) -> str:
    """Where two sequences first differ, in words (for the benchmark's failure list)."""
    for k, (a, b) in enumerate(zip(expected, got, strict=False)):
        if a != b:
            return f"at #{k}: expected {a}, got {b}"
    if len(expected) != len(got):
        k = min(len(expected), len(got))
        more = f"missing {expected[k]}" if len(expected) > len(got) else f"extra {got[k]}"
        return f"at #{k}: {more} ({len(got)} operations instead of {len(expected)})"
    return "identical"


def compare_sequence(truth: list[dict[str, Any]], ops: list[dict[str, Any]]) -> dict[str, Any]:
    """Exactness, edit accuracy and boundary timing errors of recognized ``ops``.

    ``truth`` and ``ops`` are lists of {"operation", "t_start", "t_end"}. Timing
    errors (seconds) are those of the start and end of every operation matched
    by the alignment.
    """
    truth, ops = collapse_tail(truth), collapse_tail(ops)
    expected = [t["operation"] for t in truth]
    got = [o["operation"] for o in ops]
    dist, pairs = align(expected, got)
    errors = []
    for i, j in pairs:
        for key in ("t_start", "t_end"):
            if truth[i].get(key) is not None and ops[j].get(key) is not None:
                errors.append(abs(float(ops[j][key]) - float(truth[i][key])))
    return {"exact": expected == got, "edit_distance": dist,
            "accuracy": max(0.0, 1.0 - dist / max(1, len(expected))),
            "timing_errors": errors, "difference": first_difference(expected, got),
            "expected": len(expected), "recognized": len(got)}


def _norm(rel: Sequence[Any], support: Sequence[str], rename: dict[str, str]) -> tuple | None:
    """A support relation as (subject, sorted supports); None for other relation types.

    ``support`` names the support relations (rules/effects.yaml roles)."""
    if len(rel) < 3 or rel[0] not in support:
        return None
    obj = rel[2] if isinstance(rel[2], list) else [rel[2]]
    return (rename.get(rel[1], rel[1]), tuple(sorted(rename.get(o, o) for o in obj)))


def support_facts(relations: Sequence[Sequence[Any]], support: Sequence[str],
                  rename: dict[str, str] | None = None) -> set:
    """The support relations among ``relations`` as (subject, sorted supports)."""
    rename = rename or {}
    return {r for r in (_norm(rel, support, rename) for rel in relations) if r}


def plan_final_relations(plan: dict[str, Any], support: Sequence[str],
                         rename: dict[str, str] | None = None) -> set:
    """Support relations the plan's root achieves (its SC+), names mapped through ``rename``."""
    root = plan["operators"][plan["root"]]
    return support_facts(root.get("sc_plus", []), support, rename)


def fine_relations(rules: Any) -> set[str]:
    """The relations the effects of fine-motion operations add (the bundled rules: the one
    an ALIGN leaves, Sec. V-B5), read from rules/operations.yaml and effects.yaml."""
    fine = {m for m, spec in rules.motions.items() if spec.fine}
    ops = {row.operation for m in fine for row in rules.classification.get(m, ())}
    return {t.type for op in ops if op in rules.effects for t in rules.effects[op].add}


def plan_fine_pairs(plan: dict[str, Any], relations: set[str],
                    rename: dict[str, str] | None = None) -> set:
    """Unordered object pairs that the plan's root relates by one of ``relations``."""
    rename = rename or {}
    root = plan["operators"][plan["root"]]
    return {frozenset(rename.get(o, o) for o in rel[1:3]) for rel in root.get("sc_plus", [])
            if len(rel) >= 3 and rel[0] in relations and all(isinstance(o, str)
                                                             for o in rel[1:3])}


def percentile(values: Sequence[float], q: float) -> float | None:
    """The q-th percentile (linear interpolation), None for no values."""
    if not values:
        return None
    xs = sorted(values)
    pos = (len(xs) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson's score interval for a proportion of ``successes`` in ``n`` trials.

    Wilson (1927); method 3 of Newcombe (1998). Unlike the normal approximation it
    stays inside [0, 1] and is not empty at 0 or n successes, which is where the bench
    lives (100% at nominal noise). No interval is known from no trials: (0, 1).
    """
    if n <= 0:
        return 0.0, 1.0
    p, z2 = successes / n, z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def summarize(records: list[dict[str, Any]], levels: Sequence[str]) -> dict[str, dict]:
    """Per noise level: rates, accuracy, timing error percentiles, speed, pixels per frame."""
    out = {}
    for level in levels:
        rs = [r for r in records if r["level"] == level]
        if not rs:
            continue
        ok = [r for r in rs if "error" not in r]
        timing = [e for r in ok for e in r["timing_errors"]]
        placed = [e for r in ok for e in r.get("place_errors_mm", ())]

        out[level] = {
            "scenarios": len(rs), "crashed": len(rs) - len(ok),
            "exact_sequence_rate": _rate(rs, "exact"),
            "exact_repaired_rate": _rate(rs, "exact_repaired"),
            "targets_exact_rate": _rate(rs, "targets_exact"),
            "repairs": sum(r.get("repairs", 0) for r in ok),
            "edit_accuracy": statistics.fmean(r["accuracy"] for r in ok) if ok else 0.0,
            "timing_error_median_s": percentile(timing, 50),
            "timing_error_p95_s": percentile(timing, 95),
            # where each place measured its block against where it came to rest (x, y)
            "place_error_median_mm": percentile(placed, 50),
            "place_error_p95_mm": percentile(placed, 95),
            "plan_correct_rate": _rate(rs, "plan_correct"),
            "execution_success_rate": _rate(rs, "execution_success"),
            # issue #13: the cameras' verdict against the simulator's, where both were given
            "verdicts_agree_rate": _rate([r for r in ok if "verdicts_agree" in r],
                                         "verdicts_agree"),
            "realtime_factor_watch": _ratio(ok, "demo_seconds", "watch_seconds"),
            "realtime_factor_pipeline": _ratio(ok, "demo_seconds", "total_seconds"),
            "pixels_per_frame": statistics.fmean(r["pixels_per_frame"] for r in ok) if ok
            else None,
        }
        for figure, key in RATES.items():  # 95% intervals of the proportions
            out[level][figure.replace("_rate", "_ci95")] = \
                list(wilson(sum(1 for r in rs if r.get(key)), len(rs)))
    return out


def _rate(rs: list[dict], key: str) -> float:
    """Fraction of all records where ``key`` is true (a crashed run counts as a failure)."""
    return sum(1 for r in rs if r.get(key)) / max(1, len(rs))


def _ratio(rs: list[dict], num: str, den: str) -> float | None:
    """sum(num) / sum(den) over records (an aggregate real-time factor)."""
    d = sum(r[den] for r in rs)
    return sum(r[num] for r in rs) / d if d else None


def _with_ci(s: dict[str, Any], figure: str) -> str:
    """A rate and its 95% interval, e.g. ``94% (80-98)``."""
    lo, hi = s.get(figure.replace("_rate", "_ci95"), (None, None))
    rate = format(s[figure], ".0%")
    return rate if lo is None else f"{rate} ({lo * 100:.0f}-{hi * 100:.0f})"


def format_table(summary: dict[str, dict]) -> str:
    """The per-level figures as a plain text table; rates with their 95% Wilson intervals."""
    rows = [("level", "n", "exact", "exact rep", "targets", "edit-acc", "t-err med",
             "t-err p95",
             "plan ok", "exec ok", "cams=gt", "RTF watch", "RTF all", "px/frame")]

    def f(v: Any, fmt: str) -> str:
        """Format or dash."""
        return "-" if v is None else format(v, fmt)

    for level, s in summary.items():
        rows.append((level, str(s["scenarios"]), _with_ci(s, "exact_sequence_rate"),
                     _with_ci(s, "exact_repaired_rate"), _with_ci(s, "targets_exact_rate"),
                     f(s["edit_accuracy"], ".1%"),
                     f(s["timing_error_median_s"], ".2f"),
                     f(s["timing_error_p95_s"], ".2f"), _with_ci(s, "plan_correct_rate"),
                     _with_ci(s, "execution_success_rate"),
                     f(s.get("verdicts_agree_rate"), ".0%"), f(s["realtime_factor_watch"], ".1f"),
                     f(s["realtime_factor_pipeline"], ".1f"), f(s["pixels_per_frame"], ".0f")))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows)
