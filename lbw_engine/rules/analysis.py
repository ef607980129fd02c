"""rules/analysis.yaml: the data plan analysis runs on, checked when loaded.

The file names the template grammar (Fig. 15) and the table from its rule names
to operator classes, the position tolerance of relation equality and the order
of the dependency closure searches (Sec. VI-C2). The agent (the hand) and the
fixed object (the table) are design.md's reserved names (lbw_engine.names).
See docs/analysis.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from lbw_engine.errors import InputError
from lbw_engine.names import HAND, TABLE
from lbw_engine.rules.grammars import Templates, compile_plot, compile_templates
from lbw_engine.rules.reader import Reader
from lbw_engine.yamlio import line_of

# The operator classes of plan.json (design.md); Sec. VI-A3 gives them a priori.
PLAN_CLASSES = ("BUILD", "PACHIEVE", "ACHIEVE", "FETCH", "PUT", "FAKE")
# The dependency relations of Sec. VI-C2 (the closed registry of pass names).
RELATION_KINDS = ("C-T", "B-T", "B-S", "B-B")


@dataclass(frozen=True)
class AnalysisRules:
    """Everything plan analysis reads from the rules directory."""

    rules_dir: Path
    file: Path
    grammar_file: Path
    start: str
    operators: dict[str, str]  # grammar rule -> operator class
    removed: frozenset[str]  # grammar rules whose match is dropped
    trailing: frozenset[str]  # operations dropped where they end the demonstration
    plot_grammar_file: Path
    tolerance: float
    passes: tuple[str, ...]
    closure_class: str
    protected_class: str
    same_spot: float = 0.0  # mm per axis: S-S orders a place after the move off its spot
    # design.md's reserved names: the hand is an agent (never focused, never protected),
    # the table is fixed (never a base; Fig. 22 has it as a target).
    agents: frozenset[str] = frozenset({HAND})
    fixed: frozenset[str] = frozenset({TABLE})

    def templates(self) -> Templates:
        """The compiled template grammar (checked against this table when loaded)."""
        return compile_templates(self.grammar_file, self.start)


def parse(rules_dir: Path) -> AnalysisRules:
    """Read and check ``analysis.yaml`` and the two grammars it names."""
    file = rules_dir / "analysis.yaml"
    rd, data = Reader.load(file, ("templates", "plot-grammar", "position-tolerance",
                                  "dependencies"))
    tpl = rd.mapping(data["templates"], "templates", data, "templates")
    rd.keys(tpl, "templates", ("grammar", "start", "operators"), ("removed", "trailing"),
            where="templates")
    ops = rd.mapping(tpl["operators"], "templates.operators", tpl, "operators")
    for rule, cls in ops.items():
        rd.one_of(cls, PLAN_CLASSES, "operator class", ops, rule)
    removed = rd.names(tpl, "removed", "templates.removed") if "removed" in tpl else ()
    for rule in removed:
        if rule in ops:
            rd.fail(f"rule {rule!r} is both an operator and removed", tpl, "removed",
                    "templates")
    dep = rd.mapping(data["dependencies"], "dependencies", data, "dependencies")
    rd.keys(dep, "dependencies", ("passes", "closure-class", "protected-class"),
            ("same-spot",), where="dependencies")
    passes = rd.names(dep, "passes", "dependencies.passes", RELATION_KINDS,
                      "dependencies.passes")
    rules = AnalysisRules(
        rules_dir=rules_dir,
        file=file,
        grammar_file=rules_dir / rd.name(tpl, "grammar", "templates"),
        start=rd.name(tpl, "start", "templates"),
        operators=dict(ops),
        removed=frozenset(removed),
        trailing=frozenset(rd.names(tpl, "trailing", "templates.trailing")
                           if "trailing" in tpl else ()),
        plot_grammar_file=rules_dir / rd.name(data, "plot-grammar", "analysis"),
        tolerance=rd.number(data, "position-tolerance", "position-tolerance", 0.0, 100.0),
        passes=passes,
        closure_class=rd.one_of(dep["closure-class"], PLAN_CLASSES, "class", dep,
                                "closure-class"),
        protected_class=rd.one_of(dep["protected-class"], PLAN_CLASSES, "class", dep,
                                  "protected-class"),
        same_spot=rd.number(dep, "same-spot", "dependencies.same-spot", 0.0, 100.0)
        if "same-spot" in dep else 0.0,
    )
    templates = rules.templates()
    for rule in [*rules.operators, *rules.removed, rules.start]:
        if rule not in templates.rules():
            raise InputError(f"analysis.yaml names the rule {rule!r}, which "
                             f"{rules.grammar_file.name} does not define", file=file,
                             line=line_of(ops, rule) if rule in ops else line_of(tpl, "start"),
                             where="templates")
    compile_plot(rules.plot_grammar_file)
    return rules
