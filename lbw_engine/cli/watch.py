"""``lbw watch SCENARIO --out DIR [--rules DIR]``: recognize a demonstration from images.

lbw_engine.pipeline.watch renders the demonstration frame by frame and the
recognizer reads only those frames (docs/seeing.md). Writes ``actions.json``:
the recognized sequence after recognition repair (Sec. IX-C2, docs/repair.md),
with every change in ``repairs`` and printed, one line each.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lbw_engine.guard import MAX_FPS, Place, number
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.watch import repair, slide_notes, watch
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions

HELP = "watch a scenario's demonstration through the two cameras; writes actions.json"
EXIT_CODES = ("0 recognized as demonstrated (after recognition repair); 1 recognition failed "
              "or differs from the demonstration (actions.json is still written); 2 bad input "
              "(one line: file, place, what is wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """SCENARIO, --out, --rules and --fps."""
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")
    parser.add_argument("--fps", type=float, metavar="N", default=30.0,
                        help="frames per second (30)")


def run(args: argparse.Namespace) -> int:
    """Watch the demonstration and publish actions.json; exit 1 if recognition failed or
    does not verify against the scenario's demonstration."""
    from perception.world.scenario import load

    number(args.fps, Place(where="--fps"), 0, MAX_FPS, above=True, unit="frames per second")
    rules = load_rules(args.rules)
    scenario = load(Path(args.scenario))
    inputs = [args.scenario, *([args.rules] if args.rules else [])]
    with OutputDir(args.out, inputs=inputs) as out:  # a bad --out is refused before watching
        recognizer, _ = watch(scenario, rules, fps=args.fps)
        raw = to_actions(recognizer)
        repaired = repair(raw, rules)  # Sec. IX-C2; every change is in actions.json `repairs`
        actions = repaired.actions
        path = out.write_json("actions.json", actions)
    ops = [op["operation"] for op in actions["operations"]]
    print(f"lbw watch: {len(actions['objects'])} objects, {len(ops)} operations -> {path}")
    from lbw_engine.pipeline.run import repair_lines

    for line in repair_lines(actions):
        print(f"lbw watch: {line}")
    for line in slide_notes(scenario, rules):
        print(f"lbw watch: {line}", file=sys.stderr)
    problems = []
    if not actions["objects"]:
        problems.append("no objects were located")
    if not ops:
        problems.append("no operations were recognized")
    elif any(op is None for op in ops):
        problems.append("some motions could not be classified")
    else:  # evaluation only: the scenario says what was demonstrated
        from lbw_engine.pipeline.run import compare_with_truth, with_repair

        same = with_repair(compare_with_truth(scenario, raw, rules), repaired, rules)["repair"]
        if not same["exact"]:
            problems.append(f"the sequence is not the demonstrated one ({same['difference']})")
    if problems:
        print(f"lbw watch: recognition failed: {'; '.join(problems)}", file=sys.stderr)
        return 1
    return 0
