"""The rules decide: no rule word is written in Python (issue #11, style.md).

Two checks, over the words the bundled rules define (events, Table IV values,
operations and their labels, motion classes, relations, Table V values):

* the generic interpreter (lbw_engine's top-level modules, see/, model/,
  rules/, the symbolic domain and recognition repair of understand/) names no
  event, motion value, operation or motion class anywhere — code, strings,
  comments or docstrings;
* no module of lbw_engine or perception holds a string literal that *is* a rule
  word (what a hard-coded oracle, a detector's value words or an ``if op ==``
  would need), relations and Table V values included.

Only the closed vocabularies design.md fixes are exempt: the scenario format's
keys and step kinds, the plan classes of plan.json, the reserved names table
and hand.
"""

import ast
import io
import re
import tokenize
from pathlib import Path

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.rules.analysis import PLAN_CLASSES

ROOT = Path(__file__).resolve().parents[2]
ENGINE = ROOT / "lbw_engine"
RULES = load_rules()

# design.md's closed vocabularies: scenario keys and step kinds, plan classes, reserved names.
DESIGN = {
    "name", "seed", "shapes", "noise", "pixel", "tremor", "speed", "teach", "objects",
    "demonstration", "pick", "place", "touch", "on", "at", "align", "with", "face", "execute",
    "faults", "during", "after", "kind", "drop", "displace", "remove", "object", "by",
    "north", "south", "east", "west", "table", "hand", "world", *PLAN_CLASSES,
    "block",  # also the scene's box kind (docs/architecture.md) and a generator shape
}
TEXT_WORDS = {*RULES.events, *RULES.motion_features.values(), *RULES.operations,
              *RULES.motions} - DESIGN
FEATURE_WORDS = {v for f in RULES.features.values() for v in f.values if isinstance(v, str)}
LABELS = {row.label for rows in RULES.classification.values() for row in rows if row.label}
LITERAL_WORDS = (TEXT_WORDS | set(RULES.relations) | FEATURE_WORDS | LABELS) - DESIGN


def _pattern(names, flags=0):
    alternatives = "|".join(sorted((re.escape(n) for n in names), key=len, reverse=True))
    return re.compile(r"(?<![\w-])(" + alternatives + r")(?![\w-])", flags)


def _files(*folders):
    return sorted(p for folder in folders for p in (ROOT / folder).rglob("*.py"))


CORE = sorted([*ENGINE.glob("*.py"), *_files("lbw_engine/see", "lbw_engine/model",
                                             "lbw_engine/rules"),
               ENGINE / "understand" / "domain.py", ENGINE / "understand" / "consistency.py",
               ENGINE / "understand" / "repair.py"])
EVERYTHING = _files("lbw_engine", "perception")
PATTERNS = [_pattern(TEXT_WORDS - set(RULES.motions), re.IGNORECASE), _pattern(RULES.motions)]


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


@pytest.mark.parametrize("path", CORE, ids=_rel)
def test_no_rule_names_in_the_interpreter(path):
    hits = []
    previous = None
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        after_dot, previous = previous == ".", tok.string
        if tok.type == tokenize.NAME and (tok.string == "True" or after_dot):
            continue  # Python's True; an attribute such as str.join is Python's too
        text = tok.string.replace("_", "-") if tok.type == tokenize.NAME else tok.string
        for pattern in PATTERNS:
            for match in pattern.finditer(text):
                if path.name in ("yamlio.py", "reader.py") and match.group(0).lower() == "true":
                    continue  # YAML's booleans
                hits.append(f"{_rel(path)}:{tok.start[0]}: {match.group(0)!r}")
    assert not hits, "rule names in the interpreter:\n" + "\n".join(hits)


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the string constants that are docstrings."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                out.add(id(body[0].value))
    return out


@pytest.mark.parametrize("path", EVERYTHING, ids=_rel)
def test_no_rule_word_literals(path):
    tree = ast.parse(path.read_text())
    docs = _docstrings(tree)
    hits = [f"{_rel(path)}:{node.lineno}: {node.value!r}" for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and id(node) not in docs and node.value in LITERAL_WORDS]
    assert not hits, "rule words written in Python:\n" + "\n".join(hits)


def test_the_word_lists_are_not_empty():
    assert {"near", "PICK", "on", "decreased"} <= LITERAL_WORDS | DESIGN
    assert len(CORE) >= 15 and len(EVERYTHING) >= 60
