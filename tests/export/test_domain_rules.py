"""rules/domain.yaml: loads, and a table of broken copies, each refused with the
file and the line of the offending row (exit 2 from `lbw check`)."""

import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.errors import InputError
from lbw_engine.paths import default_rules_dir
from lbw_engine.rules import load_rules
from lbw_engine.rules.domain import load_domain

# (case id, file, old text, new text, marker on the expected line, message fragment)
BROKEN = [
    ("unknown-predicate", "domain.yaml", "add: [[hand-at, $hand, $object]]",
     "add: [[hand-near, $hand, $object]]", "hand-near", "predicate 'hand-near' does not exist"),
    ("wrong-arity", "domain.yaml", "pre: [[hand-empty, $hand], [hand-away, $hand]]",
     "pre: [[hand-empty, $hand, $object], [hand-away, $hand]]", "hand-empty, $hand, $object",
     "takes 1 arguments, got 2"),
    ("unbound-variable", "domain.yaml", "remove: [[hand-away, $hand]]\n    add: [[hand-at",
     "remove: [[hand-away, $hund]]\n    add: [[hand-at", "$hund", "parameter 'hund'"),
    ("wrong-type", "domain.yaml", "add: [[hand-at, $hand, $object]]",
     "add: [[hand-at, $object, $object]]", "hand-at, $object", "wants a agent there"),
    ("unknown-operation", "domain.yaml", "  WITHDRAW:", "  WITHDRAWS:", "WITHDRAWS",
     "operation (of operations.yaml) 'WITHDRAWS' does not exist"),
    ("unknown-relation", "domain.yaml", "  coplanar: [block, block]",
     "  coplanar: [block, block]\n  touching: [block, block]", "touching",
     "relation (of effects.yaml) 'touching' does not exist"),
    ("missing-relation", "domain.yaml", "  coplanar: [block, block]\n", "", "relations:",
     "relation 'coplanar' of effects.yaml has no argument types"),
    ("wildcard-outside-remove", "domain.yaml", "pre: [[holding, $hand, $object], [hand-away",
     "pre: [[holding, '*', $object], [hand-away", "'*', $object", "is not a parameter"),
    ("when-on-single", "domain.yaml", "when: {single: $from}", "when: {single: $object}",
     "single: $object", "needs a list parameter"),
    ("rebinds-effects-variable", "domain.yaml", "    params: {object: block, other: block,",
     "    bind: {object: base}\n    params: {object: block, other: block,", "bind: {object",
     "effects.yaml already binds $object"),
    ("effects-variable-not-a-parameter", "effects.yaml",
     "bind: {hand: base, object: special, support: target}\n    remove:",
     "bind: {hand: base, object: special, support: target, thing: target}\n    remove:\n"
     "      - [coplanar, $thing, $object]", "[coplanar, $thing, $object]",
     "variable $thing of PLACE-ON-TABLE is not a parameter"),
    ("place-relation-without-position", "effects.yaml",
     "      - [on, $object, $support, {wrt: $support}]\n  PLACE-ON-BLOCK",
     "      - [on, $object, $support]\n  PLACE-ON-BLOCK", "[on, $object, $support]",
     "records no position"),
]


def test_bundled_domain_loads():
    domain = load_domain()
    rules = load_rules()
    assert set(domain.relations) == set(rules.relations)
    assert set(domain.operations) <= rules.operations
    for name, op in domain.operations.items():
        effects = rules.effects.get(name)
        if effects is not None:  # effects.yaml's changes are the domain's, none lost
            assert len([a for a in op.add if a.pred in rules.relations]) == len(effects.add)


@pytest.mark.parametrize("case,file,old,new,marker,fragment", BROKEN, ids=[c[0] for c in BROKEN])
def test_broken_domain_is_refused(tmp_path: Path, case, file, old, new, marker, fragment):
    copy = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), copy)
    text = (copy / file).read_text()
    assert text.count(old) == 1, f"{case}: the edit does not apply once"
    (copy / file).write_text(text.replace(old, new))
    with pytest.raises(InputError) as err:
        load_domain(copy)
    line = next(i for i, t in enumerate((copy / file).read_text().splitlines(), 1) if marker in t)
    assert err.value.file.endswith(file)
    assert fragment in err.value.message
    assert err.value.line in (line, line - 1), f"{case}: line {err.value.line}, expected {line}"


def test_lbw_check_reads_the_domain(tmp_path: Path):
    copy = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), copy)
    text = (copy / "domain.yaml").read_text()
    (copy / "domain.yaml").write_text(text.replace("  WITHDRAW:", "  WITHDRAWS:"))
    assert main(["check", str(copy)]) == 2
