"""The symbolic domain and the export know no rule names (issue #14 brief).

The domain's loader and its symbolic state get the interpreter's full check
(tests/engine/test_no_names.py). The export modules use libraries whose words
collide with event names (``str.join``, unified-planning's ``Task``), so for
them no string literal may be an operation, event, motion-class or relation name.
"""

import io
import tokenize
from pathlib import Path

import pytest

from lbw_engine.rules import load_rules
from tests.engine.test_no_names import ENGINE
from tests.engine.test_no_names import test_no_rule_names_in_engine as check_engine_file

RULES = load_rules()
NAMES = {*RULES.events, *RULES.motion_features.values(), *RULES.operations, *RULES.motions,
         *RULES.relations}
STRICT = [ENGINE / "rules" / "domain.py", ENGINE / "understand" / "domain.py"]
LITERALS = sorted([*ENGINE.glob("export/*.py"), ENGINE / "do" / "behaviour.py",
                   ENGINE / "cli" / "export.py"])


@pytest.mark.parametrize("path", STRICT, ids=lambda p: p.relative_to(ENGINE).as_posix())
def test_no_rule_names_in_domain(path: Path) -> None:
    check_engine_file(path)


@pytest.mark.parametrize("path", LITERALS, ids=lambda p: p.relative_to(ENGINE).as_posix())
def test_no_rule_names_as_literals(path: Path) -> None:
    hits = []
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type == tokenize.STRING and not tok.string.startswith(('"""', "'''")):
            words = tok.string.strip("\"'rfb").replace("{", " ").replace("}", " ").split()
            hits += [f"{path.name}:{tok.start[0]}: {w}" for w in words if w in NAMES]
    assert not hits, "rule names as literals:\n" + "\n".join(hits)
