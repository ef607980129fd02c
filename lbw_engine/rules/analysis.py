"""rules/analysis.yaml: the data plan analysis runs on, checked when loaded.

The file names the template grammar (Fig. 15) and the table from its rule names
to operator classes, the object roles the focused-object formulas need (agents,
fixed objects), the position tolerance of relation equality and the order of the
dependency closure searches (Sec. VI-C2). See docs/analysis.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lbw_engine import yamlio
from lbw_engine.errors import InputError
from lbw_engine.guard import Place, number, shorten
from lbw_engine.paths import default_rules_dir

# The operator classes of plan.json (design.md); Sec. VI-A3 gives them a priori.
PLAN_CLASSES = ("BUILD", "PACHIEVE", "ACHIEVE", "FETCH", "PUT", "FAKE")
# The dependency relations of Sec. VI-C2 (the closed registry of pass names).
RELATION_KINDS = ("C-T", "B-T", "B-S")


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
    agents: frozenset[str]
    fixed: frozenset[str]
    tolerance: float
    passes: tuple[str, ...]
    closure_class: str
    protected_class: str


class _Checker:
    """Small typed getters that fail with the file and line of the offending key."""

    def __init__(self, file: Path) -> None:
        self.file = file

    def fail(self, message: str, container: Any, key: Any = None, where: str = "") -> None:
        """Raise an InputError at ``container[key]``."""
        raise InputError(
            message, file=self.file, line=yamlio.line_of(container, key), where=where or None
        )

    def mapping(self, data: Any, key: str, where: str) -> dict:
        """``data[key]`` is a mapping."""
        if not isinstance(data, dict) or key not in data:
            self.fail(f"missing the mapping {key!r}", data, where=where)
        value = data[key]
        if not isinstance(value, dict):
            self.fail("must be a mapping", data, key, f"{where}.{key}".lstrip("."))
        return value

    def name(self, data: dict, key: str, where: str) -> str:
        """``data[key]`` is a non-empty string."""
        value = data.get(key)
        if not isinstance(value, str) or not value:
            self.fail(f"must be a name, got {shorten(value)}", data, key,
                      f"{where}.{key}".lstrip("."))
        return value

    def names(self, data: dict, key: str, where: str) -> list[str]:
        """``data[key]`` is a list of names."""
        value = data.get(key)
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            self.fail("must be a list of names", data, key, f"{where}.{key}".lstrip("."))
        return list(value)

    def known_keys(self, data: dict, allowed: tuple[str, ...], where: str) -> None:
        """No key outside ``allowed`` (typos are errors, not silently ignored)."""
        for key in data:
            if key not in allowed:
                self.fail(
                    f"unknown key {key!r} (allowed: {', '.join(allowed)})",
                    data,
                    key,
                    f"{where}.{key}".lstrip("."),
                )

    def choice(self, data: dict, key: str, allowed: tuple[str, ...], where: str) -> str:
        """``data[key]`` is one of ``allowed``."""
        value = self.name(data, key, where)
        if value not in allowed:
            self.fail(f"{shorten(value)} is not one of {', '.join(allowed)}", data, key,
                      f"{where}.{key}")
        return value


def load_rules(rules_dir: str | Path | None = None) -> AnalysisRules:
    """Read and check ``analysis.yaml`` from ``rules_dir`` (default: the bundled rules)."""
    rules_dir = Path(rules_dir) if rules_dir is not None else default_rules_dir()
    file = rules_dir / "analysis.yaml"
    data = yamlio.load_file(file)
    c = _Checker(file)
    if not isinstance(data, dict):
        c.fail("must be a mapping", data)
    c.known_keys(
        data, ("templates", "plot_grammar", "objects", "position_tolerance", "dependencies"), ""
    )
    tpl = c.mapping(data, "templates", "")
    c.known_keys(tpl, ("grammar", "start", "operators", "removed", "trailing"), "templates")
    ops = c.mapping(tpl, "operators", "templates")
    for rule, cls in ops.items():
        if cls not in PLAN_CLASSES:
            c.fail(
                f"class {shorten(cls)} is not one of {', '.join(PLAN_CLASSES)}",
                ops,
                rule,
                f"templates.operators.{rule}",
            )
    removed = c.names(tpl, "removed", "templates") if "removed" in tpl else []
    for rule in removed:
        if rule in ops:
            c.fail(f"rule {rule!r} is both an operator and removed", tpl, "removed", "templates")
    objs = c.mapping(data, "objects", "")
    c.known_keys(objs, ("agents", "fixed"), "objects")
    tol = data.get("position_tolerance")
    tol = number(tol, Place(file, yamlio.line_of(data, "position_tolerance"),
                            "position_tolerance"), 0, unit="mm")
    dep = c.mapping(data, "dependencies", "")
    c.known_keys(dep, ("passes", "closure_class", "protected_class"), "dependencies")
    passes = c.names(dep, "passes", "dependencies")
    for i, kind in enumerate(passes):
        if kind not in RELATION_KINDS:
            c.fail(
                f"pass {shorten(kind)} is not one of {', '.join(RELATION_KINDS)}",
                dep["passes"],
                i,
                f"dependencies.passes[{i}]",
            )
    return AnalysisRules(
        rules_dir=rules_dir,
        file=file,
        grammar_file=rules_dir / c.name(tpl, "grammar", "templates"),
        start=c.name(tpl, "start", "templates"),
        operators=dict(ops),
        removed=frozenset(removed),
        trailing=frozenset(c.names(tpl, "trailing", "templates") if "trailing" in tpl else ()),
        plot_grammar_file=rules_dir / c.name(data, "plot_grammar", ""),
        agents=frozenset(c.names(objs, "agents", "objects")),
        fixed=frozenset(c.names(objs, "fixed", "objects")),
        tolerance=float(tol),
        passes=tuple(passes),
        closure_class=c.choice(dep, "closure_class", PLAN_CLASSES, "dependencies"),
        protected_class=c.choice(dep, "protected_class", PLAN_CLASSES, "dependencies"),
    )
