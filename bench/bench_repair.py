"""Recognition repair (Sec. IX-C2, docs/repair.md) on generated demonstrations.

For each of N generated scenarios (perception.world.generator, seeds 1000 ...,
nominal noise) the oracle's sequence — what a perfect eye recognizes under the
bundled rules — is repaired:

1. as it is: repair must leave it alone (a change here is a false repair);
2. with one slip injected, at up to ``PER_KIND`` places of each kind:
   ``carry-cut`` (a REACH-WITH-OBJ cut in two by a NO-OP over the table, the
   slip `lbw bench` shows at 4x noise), ``pick-as-touch`` (a PICK read as a
   NO-OP, its snapshots unchanged; issue #13's second example) and
   ``touch-before-place`` (a NO-OP over the table between a carry and its
   PLACE; issue #13's first example). Each is counted as repaired back to the
   oracle's sequence, left as recognized, or changed into something else.

The time of each repair call is recorded (median, max).

    .venv/bin/python -m bench repair             # 30 seeds
    .venv/bin/python -m bench.bench_repair 100   # 100 seeds
"""

from __future__ import annotations

import copy
import statistics
import sys
import time
from collections.abc import Callable
from typing import Any

SEED0, PER_KIND = 1000, 4
CARRY, TOUCH, TAKE = "REACH-WITH-OBJ", "NO-OP", "PICK"  # the bundled rules' words


def _still(name: str, operation: str, like: dict[str, Any], target: list[str],
           special: list[str]) -> dict[str, Any]:
    """A motion that changed nothing, with ``like``'s base and initial snapshot."""
    return {"name": name, "operation": operation, "motion": None, "base": like["base"],
            "target": target, "special": special, "fine": [],
            "initial_state": copy.deepcopy(like["initial_state"]),
            "final_state": copy.deepcopy(like["initial_state"])}


def carry_cut(ops: list[dict], k: int) -> list[dict]:
    """Operation k (a carry) as two carries with a NO-OP over the table between them."""
    first = dict(copy.deepcopy(ops[k]), name="slip-carry", target=["table"])
    cut = _still("slip-touch", TOUCH, ops[k], ["table"], ops[k]["special"])
    cut.pop("motion")
    return [*ops[:k], first, cut, *ops[k:]]


def pick_as_touch(ops: list[dict], k: int) -> list[dict]:
    """Operation k (a PICK) read as a NO-OP of the same object."""
    seen = _still("slip-touch", TOUCH, ops[k], ops[k]["target"], [])
    seen["motion"] = ops[k].get("motion")
    return [*ops[:k], seen, *ops[k + 1:]]


def touch_before_place(ops: list[dict], k: int) -> list[dict]:
    """A NO-OP over the table after operation k (a carry), before its PLACE."""
    touch = _still("slip-touch", TOUCH, ops[k], ["table"], ops[k]["special"])
    touch["initial_state"] = copy.deepcopy(ops[k]["final_state"])
    touch["final_state"] = copy.deepcopy(ops[k]["final_state"])
    touch.pop("motion")
    return [*ops[:k + 1], touch, *ops[k + 1:]]


SLIPS: dict[str, tuple[str, Callable[[list[dict], int], list[dict]]]] = {
    "carry-cut": (CARRY, carry_cut), "pick-as-touch": (TAKE, pick_as_touch),
    "touch-before-place": (CARRY, touch_before_place)}


def _places(ops: list[dict], operation: str) -> list[int]:
    """Up to PER_KIND indices of ``operation``, spread over the sequence."""
    found = [i for i, op in enumerate(ops) if op["operation"] == operation]
    step = max(1, len(found) // PER_KIND)
    return found[::step][:PER_KIND]


def main(argv: list[str]) -> dict[str, Any]:
    """Run the benchmark on ``argv[0]`` seeds (30); print and return the figures."""
    from lbw_engine.rules import load_rules
    from lbw_engine.see.actions import to_actions
    from lbw_engine.understand.repair import repair_actions
    from perception.world.generator import generate
    from perception.world.oracle import oracle_recognizer

    count = int(argv[0]) if argv else 30
    rules = load_rules()
    seconds: list[float] = []
    false_repairs, unchecked, left = [], [], []
    kinds = {k: {"injected": 0, "repaired": 0, "left": 0, "wrong": 0, "wrong_seeds": []}
             for k in SLIPS}

    def repaired(doc: dict) -> Any:
        clock = time.perf_counter()
        result = repair_actions(doc, rules)
        seconds.append(time.perf_counter() - clock)
        return result

    for seed in range(SEED0, SEED0 + count):
        truth = to_actions(oracle_recognizer(generate(seed).scenario(), rules))
        expected = [op["operation"] for op in truth["operations"]]
        plain = repaired(truth)
        if plain.repairs:
            false_repairs.append(seed)
        if not plain.checked:
            unchecked.append(seed)
        if plain.left:
            left.append(seed)
        for kind, (operation, slip) in SLIPS.items():
            for k in _places(truth["operations"], operation):
                doc = {**truth, "operations": slip(copy.deepcopy(truth["operations"]), k)}
                result = repaired(doc)
                tally = kinds[kind]
                tally["injected"] += 1
                if not result.repairs:
                    tally["left"] += 1
                elif result.operations == expected:
                    tally["repaired"] += 1
                else:
                    tally["wrong"] += 1
                    tally["wrong_seeds"].append(seed)
        print(f"   seed {seed}: {len(expected)} operations", flush=True)
    figures = {"seeds": count, "first_seed": SEED0, "false_repairs": false_repairs,
               "unchecked": unchecked, "inconsistent_as_recognized": left, "slips": kinds,
               "repair_seconds_median": statistics.median(seconds),
               "repair_seconds_max": max(seconds)}
    print(f"   correct sequences: {count}, changed by repair: {len(false_repairs)}, "
          f"inconsistent: {len(left)}")
    for kind, t in kinds.items():
        print(f"   {kind}: {t['injected']} injected, {t['repaired']} repaired to the oracle's "
              f"sequence, {t['left']} left, {t['wrong']} changed into something else")
    print(f"   repair time: median {figures['repair_seconds_median'] * 1000:.0f} ms, "
          f"max {figures['repair_seconds_max'] * 1000:.0f} ms")
    return figures


if __name__ == "__main__":
    main(sys.argv[1:])
