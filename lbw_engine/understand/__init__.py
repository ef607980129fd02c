"""Plan analysis (Sec. VI): from a recognized action sequence to a hierarchical plan.

Public API::

    analyze_file(actions_path, rules_dir=None) -> Analysis     # load + analyse
    lbw_engine.rules.load_rules(dir).analysis -> AnalysisRules # rules/analysis.yaml, checked
    rules.templates() -> Templates                             # rules/templates.lark, compiled
    load_actions(path, RelationTable(rules.tolerance)) -> ActionSequence
    analyze(sequence, rules) -> Analysis                       # .plan is the plan.json dict
    write_plan_text(plan) -> str / read_plan_text(text, file=) -> plan   # plan.txt

See docs/analysis.md for the conventions and the decisions taken where the
paper is silent.
"""

from lbw_engine.rules.analysis import AnalysisRules
from lbw_engine.rules.grammars import Templates
from lbw_engine.understand.actions import ActionSequence, Operation, load_actions, parse_actions
from lbw_engine.understand.plan import Analysis, analyze, analyze_file
from lbw_engine.understand.plottext import read_plan_text, write_plan_text
from lbw_engine.understand.relations import Rel, RelationTable
from lbw_engine.understand.state import (
    Operator,
    focused_objects,
    gather_changes,
    leaf_changes,
    protected,
)

__all__ = [
    "ActionSequence", "Analysis", "AnalysisRules", "Operation", "Operator", "Rel",
    "RelationTable", "Templates", "analyze", "analyze_file", "focused_objects",
    "gather_changes", "leaf_changes", "load_actions",
    "parse_actions", "protected", "read_plan_text", "write_plan_text",
]
