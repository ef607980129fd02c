"""``lbw export``: the learned plan for other tools (design.md "Command line").

``FORMATS`` maps each ``--to`` value to the files it writes. The PDDL and HDDL
files come from rules/domain.yaml and the plan's root SC⁻ / SC⁺ (problem.py,
pddl.py, hddl.py); ``solve`` runs a planner on the PDDL files and ``replan``
turns its plan back into an executable plan.json document (replan.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from lbw_engine.do.plan import Plan
from lbw_engine.export import dot, hddl, leaves, pddl, problem, replan
from lbw_engine.outputs import OutputDir
from lbw_engine.rules import load_rules
from lbw_engine.rules.commands import CommandRules
from lbw_engine.rules.domain import Domain

FORMATS = {
    "pddl": ("domain.pddl", "problem.pddl"),
    "hddl": ("domain.hddl", "problem.hddl"),
    "bt": ("tree.yaml",),
    "dot": ("plan.dot",),
}
PLANNER = "pyperplan"  # the unified-planning engine the round trip uses (up-pyperplan)


@dataclass
class Rules:
    """What the export reads from rules/."""

    domain: Domain
    commands: CommandRules
    agents: frozenset[str]
    fixed: frozenset[str]
    closure_class: str  # analysis.yaml: the class of a group of operators (BUILD)


def load(rules_dir: str | Path) -> Rules:
    """The domain, the command rules and the object roles of ``rules_dir``."""
    rules = load_rules(rules_dir)
    analysis = rules.analysis
    return Rules(rules.domain, rules.commands, analysis.agents, analysis.fixed,
                 analysis.closure_class)


def symbolic(plan: Plan, rules: Rules) -> problem.SymbolicProblem:
    """The plan's symbolic problem."""
    return problem.build(plan, rules.domain, rules.agents, rules.fixed)


def write(plan: Plan, fmt: str, out: OutputDir, rules: Rules) -> list[Path]:
    """Stage the files of one format in ``out``; return their final paths."""
    files = [out.path(n) for n in FORMATS[fmt]]
    name = plan.root
    if fmt == "pddl":
        pddl.write(pddl.build_model(symbolic(plan, rules), name), *files)
    elif fmt == "hddl":
        sp = symbolic(plan, rules)
        steps = leaves.bind_leaves(plan, sp, rules.commands)
        model = pddl.build_model(sp, name, hierarchical=True)
        hddl.add_hierarchy(model, plan, steps)
        pddl.write(model, *files)
    elif fmt == "bt":
        from lbw_engine.do.behaviour import tree_data
        files[0].write_text(TREE_HEADER + yaml.safe_dump(tree_data(plan), sort_keys=False),
                            encoding="utf-8")
    else:
        files[0].write_text(dot.plan_dot(plan), encoding="utf-8")
    return [out.dest / n for n in FORMATS[fmt]]


TREE_HEADER = """\
# A py_trees behaviour tree of a learned plan, as data (lbw_engine/do/behaviour.py).
# kind: sequence | parallel (children run in order / unordered), action (a
# recognized operation: its Table IX commands), update (an operator's SC- / SC+
# applied to the execution model). `lbw execute PLAN.json SCENARIO --via bt` ticks it.
"""


def solve(domain_file: Path, problem_file: Path) -> list[tuple[str, list[str]]] | None:
    """Read PDDL files back with unified-planning and solve them; (action, arguments) or None."""
    import unified_planning.shortcuts as up
    from unified_planning.io import PDDLReader

    parsed = PDDLReader().parse_problem(str(domain_file), str(problem_file))
    with up.OneshotPlanner(name=PLANNER) as planner:
        result = planner.solve(parsed)
    if result.plan is None:
        return None
    return [(a.action.name, [str(p) for p in a.actual_parameters]) for a in result.plan.actions]


def replan_doc(plan: Plan, rules: Rules, actions: list[tuple[str, list[str]]],
               step_class: str) -> dict[str, Any]:
    """A planner's actions (on this plan's PDDL export) as an executable plan.json document."""
    sp = symbolic(plan, rules)
    model = pddl.build_model(sp, plan.root)
    steps = []
    for name, args in actions:
        variant = model.variants[name]
        steps.append((variant.operation,
                      variant.bindings(args, rules.domain.operations[variant.operation])))
    return replan.executable_plan(sp, steps, rules.closure_class, step_class)
