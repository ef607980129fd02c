"""Rule edits reach every phase (issue #11): consistent renames in a copy of rules/.

A user renames words consistently in every rule file — every operation; or the
events, the Table IV and Table V values, the motion classes and the relations
together — and ``lbw run`` must still pass on the bundled scenarios: the
recognizer, the expected sequence (the oracle runs the same rules), the plan
analysis, the command expansion and the verification all read the words from
the rules. One row per (rename, scenario).
"""

import json
import re
import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.paths import default_rules_dir
from lbw_engine.rules import load_rules
from lbw_engine.rules.analysis import PLAN_CLASSES

ROOT = Path(__file__).resolve().parents[2]
RULES = load_rules()
SCENARIOS = sorted(p.stem for p in (ROOT / "scenarios").glob("*.yaml"))


def rename_copy(dest: Path, words: dict[str, str]) -> Path:
    """A copy of rules/ with each word replaced wherever it stands alone, in every file.

    Two exceptions keep the files' own vocabulary: the key ``on:`` (attention rows,
    moves) outside domain.yaml, whose ``on:`` keys are relations; and plan.json's
    classes in analysis.yaml (design.md), which share the word BUILD with Table V.
    """
    shutil.copytree(default_rules_dir(), dest)
    pattern = re.compile(r"(?<![\w-])(" + "|".join(
        sorted(map(re.escape, words), key=len, reverse=True)) + r")(?![\w-])")
    for f in sorted(dest.iterdir()):
        if f.suffix not in (".yaml", ".lark"):
            continue
        text = f.read_text()

        def sub(m: re.Match, text: str = text, name: str = f.name) -> str:
            word = m.group(1)
            if word == "on" and name != "domain.yaml" and text[m.end():m.end() + 1] == ":":
                return word
            if name == "analysis.yaml" and word in PLAN_CLASSES:
                return word
            return words[word]

        f.write_text(pattern.sub(sub, text))
    return dest


def operation_words() -> dict[str, str]:
    return {op: "OP-" + op.replace("-", "") for op in RULES.operations}


def other_words() -> dict[str, str]:
    words = {e: "ev-" + e for e in RULES.events if e != "true"}  # YAML's true stays quoted
    words.update({v: "val-" + v for v in RULES.motion_features.values()})
    words.update({v: "sd-" + v for f in RULES.features.values() for v in f.answers})
    words.update({m: "M" + m for m in RULES.motions})
    words.update({r: "rel-" + r for r in RULES.relations})
    return words


def every_word() -> dict[str, str]:
    return {**operation_words(), **other_words()}


RENAMES = {"operations": operation_words, "events-values-motions-relations": other_words,
           "every-word": every_word}
# Each run is a whole `lbw run` (~10 s): every word renamed at once on the scenarios that
# use between them every operation, ALIGN, a PACHIEVE and multi-support places; each of
# the two smaller renames on one more scenario.
CASES = [("every-word", s) for s in ("build-table", "inverted-arch", "place-and-align")] + \
    [("operations", "tower"), ("events-values-motions-relations", "arch")]


@pytest.fixture(scope="module")
def renamed(tmp_path_factory):
    copies: dict[str, Path] = {}

    def get(kind: str) -> Path:
        if kind not in copies:
            copies[kind] = rename_copy(tmp_path_factory.mktemp(kind) / "rules", RENAMES[kind]())
        return copies[kind]
    return get


@pytest.mark.parametrize("kind,scenario", CASES, ids=[f"{k}-{s}" for k, s in CASES])
def test_lbw_run_passes_with_renamed_rules(renamed, tmp_path, kind, scenario):
    rules = renamed(kind)
    assert main(["check", str(rules)]) == 0
    out = tmp_path / "out"
    assert main(["run", str(ROOT / "scenarios" / f"{scenario}.yaml"), "--out", str(out),
                 "--rules", str(rules)]) == 0
    actions = json.loads((out / "actions.json").read_text())
    verdict = json.loads((out / "execution.json").read_text())
    assert verdict["success"] is True and verdict["failure"] is None
    ops = {op["operation"] for op in actions["operations"]}
    if kind != "events-values-motions-relations":
        assert ops <= set(operation_words().values())
        assert "<op-" in (out / "commands.txt").read_text()
    if kind != "operations":
        motions = {op["motion"] for op in actions["operations"]}
        assert motions <= {"M" + m for m in RULES.motions}
        rels = {r[0] for op in actions["operations"] for r in op["final_state"]["relations"]}
        assert rels and all(r.startswith("rel-") for r in rels)
