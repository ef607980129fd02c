"""lbw export on every bundled scenario (issue #14, "Done when"):

* PDDL: unified-planning reads the files back, pyperplan solves the problem, the
  plan becomes an executable plan (ACHIEVEs at the learned places), it is
  expanded into Table IX commands, executed in the simulator, and verifies;
* `lbw execute --via bt` verifies;
* HDDL parses back, one task and method per operator, `$parallel` unordered;
* plan.dot parses (pydot) and names every operator and leaf.

The learned plans are cached in tests/data/SCENARIO.plan.json (`lbw run` output;
test_fresh_plan_round_trip learns one anew), so no test watches a
demonstration but that one.
"""

import json
from pathlib import Path

import pydot
import pytest
from unified_planning.io import PDDLReader

from lbw_engine import export
from lbw_engine.cli import main
from lbw_engine.do import plan as planmod
from lbw_engine.export.leaves import bind_leaves
from lbw_engine.paths import default_rules_dir
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from lbw_engine.understand.domain import run
from perception.world import scenario as scenario_mod

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = sorted((ROOT / "scenarios").glob("*.yaml"))
RULES = export.load(default_rules_dir())


def cached_plan(scenario: Path) -> Path:
    return ROOT / "tests" / "data" / f"{scenario.stem}.plan.json"


def round_trip(plan_file: Path, scenario: Path, out: Path) -> dict:
    """Export PDDL, solve it, execute the planner's plan; the execution report."""
    assert main(["export", str(plan_file), "--to", "pddl", "--out", str(out)]) == 0
    actions = export.solve(out / "domain.pddl", out / "problem.pddl")
    assert actions, "the planner found no plan"
    plan = planmod.load(plan_file)
    doc = export.replan_doc(plan, RULES, actions, "ACHIEVE")
    result = execute_plan(planmod.parse(doc, "<replanned>"), scenario_mod.load(scenario),
                          load_rules())
    assert result.success, result.message
    return doc


def test_every_scenario_has_a_cached_plan():
    assert [s.stem for s in SCENARIOS if not cached_plan(s).exists()] == []


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
def test_pddl_round_trip_verifies(scenario: Path, tmp_path: Path):
    doc = round_trip(cached_plan(scenario), scenario, tmp_path)
    learned = planmod.load(cached_plan(scenario))
    placed = {r.subject for r in learned.operators[learned.root].sc_plus
              if r.type in RULES.domain.support_relations}
    assert len(doc["operators"]) == len(placed) + 1  # one ACHIEVE per placed object, a BUILD


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
def test_execute_via_bt_verifies(scenario: Path, tmp_path: Path):
    assert main(["execute", str(cached_plan(scenario)), str(scenario), "--out", str(tmp_path),
                 "--via", "bt"]) == 0
    report = json.loads((tmp_path / "execution.json").read_text())
    assert report["success"] and report["via"] == "bt" and report["ticks"] >= 1


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
def test_hddl_parses_back(scenario: Path, tmp_path: Path):
    plan = planmod.load(cached_plan(scenario))
    assert main(["export", str(cached_plan(scenario)), "--to", "hddl", "--out",
                 str(tmp_path)]) == 0
    htn = PDDLReader().parse_problem(str(tmp_path / "domain.hddl"),
                                     str(tmp_path / "problem.hddl"))
    assert {t.name for t in htn.tasks} == set(plan.operators)
    methods = {m.name: m for m in htn.methods}
    for name, op in plan.operators.items():
        method = methods[f"m-{name}"]
        assert len(method.subtasks) == len(planmod.action_names(op.plot))
        if op.plot[0] == "$parallel":
            assert method.total_order() is None or len(method.subtasks) == 1
            assert not method.partial_order()
        if op.plot[0] == "$sequence" and all(p[0] == "$action" for p in op.plot[1:]):
            assert method.total_order() is not None
    assert [s.task.name for s in htn.task_network.subtasks] == [plan.root]


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
def test_dot_names_every_operator_and_leaf(scenario: Path, tmp_path: Path):
    plan = planmod.load(cached_plan(scenario))
    assert main(["export", str(cached_plan(scenario)), "--to", "dot", "--out",
                 str(tmp_path)]) == 0
    (graph,) = pydot.graph_from_dot_data((tmp_path / "plan.dot").read_text())
    names = {n.get_name().strip('"') for n in graph.get_nodes()}
    assert set(plan.operators) | set(plan.leaf_operations) <= names


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
def test_learned_leaves_run_through_the_domain(scenario: Path):
    """The learned plan, leaf by leaf, meets every precondition and reaches its goal,
    except relations made by fine motions, which plan.json does not keep."""
    plan = planmod.load(cached_plan(scenario))
    sp = export.symbolic(plan, RULES)
    steps = bind_leaves(plan, sp, RULES.commands)
    final, problems = run(sp.init, [(RULES.domain.operations[s.operation], s.bindings)
                                    for s in steps])
    assert problems == []
    assert {f[0] for f in sp.goal - final} <= {"coplanar"}


def test_fresh_plan_round_trip(tmp_path: Path):
    scenario = ROOT / "scenarios" / "place-and-align.yaml"
    assert main(["run", str(scenario), "--out", str(tmp_path / "run")]) == 0
    doc = round_trip(tmp_path / "run" / "plan.json", scenario, tmp_path / "export")
    leaves = [n for op in doc["operators"].values() for n in planmod.action_names(op["plot"])
              if n not in doc["operators"]]
    assert any(n.startswith("align") for n in leaves)  # the planner aligns (Table V ALIGN)


def test_tree_yaml_is_the_plan(tmp_path: Path):
    from lbw_engine.yamlio import load_file

    plan_file = cached_plan(ROOT / "scenarios" / "inverted-arch.yaml")
    assert main(["export", str(plan_file), "--to", "bt", "--out", str(tmp_path)]) == 0
    tree = load_file(tmp_path / "tree.yaml")
    kinds: dict[str, int] = {}

    def walk(node):
        kinds[node["kind"]] = kinds.get(node["kind"], 0) + 1
        for child in node.get("children", []):
            walk(child)

    walk(tree["tree"])
    plan = planmod.load(plan_file)
    assert kinds["action"] == len(plan.leaf_operations)
    assert kinds["parallel"] == 1  # Fig. 17: the two bricks on the plank


@pytest.mark.parametrize("edit,fragment", [
    (lambda d: d.update(root="nowhere"), "root operator 'nowhere'"),
    (lambda d: d["operators"][d["root"]]["sc_plus"].append(["touching", "a", "b"]),
     "relation 'touching' is not a relation of effects.yaml"),
], ids=["bad-root", "unknown-relation"])
def test_bad_plan_is_exit_2_and_no_files(tmp_path: Path, capsys, edit, fragment):
    doc = json.loads(cached_plan(ROOT / "scenarios" / "arch.yaml").read_text())
    edit(doc)
    bad = tmp_path / "plan.json"
    bad.write_text(json.dumps(doc))
    out = tmp_path / "out"
    assert main(["export", str(bad), "--to", "pddl", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert fragment in err and len(err.strip().splitlines()) == 1
    assert not out.exists() or not any(out.iterdir())


def test_docs_export_commands_run_as_written(tmp_path: Path, monkeypatch):
    """The commands at the top of docs/export.md, run from the repository root."""
    import re
    import shlex

    text = (ROOT / "docs" / "export.md").read_text()
    block = re.search(r"```sh\n(.*?)```", text, re.S).group(1)
    monkeypatch.chdir(ROOT)
    for line in block.splitlines():
        words = shlex.split(line.split("#")[0])
        assert words[0] == ".venv/bin/lbw"
        words = [str(tmp_path / w) if w.startswith("out/") else w for w in words[1:]]
        assert main(words) == 0, line
    assert (tmp_path / "out" / "bt-run" / "execution.json").exists()
