"""The interpreter knows no operation, event or motion-class name: they all come
from rules/ (issue #2, "Done when"). Every word of every lbw_engine/*.py file
(code, strings, comments, docstrings) is checked against the names the bundled
rules define. Python's own ``True`` keyword is not an event name."""

import io
import re
import tokenize
from pathlib import Path

import pytest

from lbw_engine.rules import load_rules

ENGINE = Path(__file__).resolve().parents[2] / "lbw_engine"
RULES = load_rules()
NAMES = {*RULES.events, *RULES.motion_features.values(), *RULES.operations}


def _pattern(names, flags=0):
    alternatives = "|".join(sorted((re.escape(n) for n in names), key=len, reverse=True))
    return re.compile(r"(?<![\w-])(" + alternatives + r")(?![\w-])", flags)


PATTERNS = [_pattern(NAMES, re.IGNORECASE), _pattern(RULES.motions)]


INTERPRETER = sorted([*ENGINE.glob("*.py"), *ENGINE.glob("see/*.py"), *ENGINE.glob("model/*.py"),
                      *(ENGINE / "rules" / f for f in ("__init__.py", "files.py", "check.py",
                                                      "reader.py"))])


@pytest.mark.parametrize("path", INTERPRETER, ids=lambda p: p.relative_to(ENGINE).as_posix())
def test_no_rule_names_in_engine(path):
    hits = []
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type == tokenize.NAME and tok.string == "True":
            continue
        text = tok.string
        if tok.type == tokenize.NAME:
            text = text.replace("_", "-")
        for pattern in PATTERNS:
            for match in pattern.finditer(text):
                if path.name == "yamlio.py" and match.group(0).lower() == "true":
                    continue
                hits.append(f"{path.name}:{tok.start[0]}: {match.group(0)!r}")
    assert not hits, "rule names in the interpreter:\n" + "\n".join(hits)
