"""Plan analysis (Sec. VI): from a recognized action sequence to a hierarchical plan.

Public API::

    analyze_file(actions_path, rules_dir=None) -> Analysis     # load + analyse
    load_rules(rules_dir=None) -> AnalysisRules                # rules/analysis.yaml, checked
    load_templates(rules) -> Templates                         # rules/templates.lark, checked
    load_actions(path, RelationTable(rules.tolerance)) -> ActionSequence
    analyze(sequence, rules) -> Analysis                       # .plan is the plan.json dict
    write_plan_text(plan) -> str / read_plan_text(text, file=) -> plan   # plan.txt

See docs/analysis.md for the conventions and the decisions taken where the
paper is silent.
"""

from lbw_engine.rules.analysis import AnalysisRules, load_rules
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
from lbw_engine.understand.templates import Templates, load_templates

__all__ = [
    "ActionSequence", "Analysis", "AnalysisRules", "Operation", "Operator", "Rel",
    "RelationTable", "Templates", "analyze", "analyze_file", "focused_objects",
    "gather_changes", "leaf_changes", "load_actions", "load_rules", "load_templates",
    "parse_actions", "protected", "read_plan_text", "write_plan_text",
]
