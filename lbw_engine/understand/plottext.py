"""plan.txt: the plan in the plot notation of Fig. 17 / Fig. 22 (rules/plot.lark).

``write_plan_text(plan)`` renders a plan.json document; ``read_plan_text(text)``
parses it back with the grammar into the same document. Every operator is
written in the long form of Fig. 22 (($action NAME :base ... :plot ...)) with
:class and the state changes of Fig. 14 added, level by level from the root.
Reading also accepts the paper's own text: a missing slot is empty, a missing
:class is read from the name (build5197 → BUILD).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from lark import Transformer, v_args
from lark.exceptions import UnexpectedInput, VisitError

from lbw_engine.errors import InputError
from lbw_engine.guard import shorten
from lbw_engine.paths import default_rules_dir
from lbw_engine.rules.analysis import PLAN_CLASSES
from lbw_engine.rules.grammars import compile_plot

RELATION_SLOTS = (("sc_plus", ":sc-plus"), ("sc_minus", ":sc-minus"), ("si", ":si"), ("sp", ":sp"))
NAME_SLOTS = (("base", ":base"), ("target", ":target"), ("special", ":special"),
              ("next", ":next-action"))
CLASS_FROM_NAME = re.compile(r"([a-z]+)\d+\Z")


def _num(x: float | int) -> str:
    """A number as JSON would read it back exactly (repr is the shortest round trip)."""
    return repr(x)


def _names(names: list[str]) -> str:
    """``nil`` or ``(a b c)``."""
    return f"({' '.join(names)})" if names else "nil"


def _plot(plot: list) -> str:
    """($sequence ...) / ($parallel ...) / ($action name)."""
    if plot[0] == "$action":
        return f"($action {plot[1]})"
    return f"({plot[0]} {' '.join(_plot(p) for p in plot[1:])})"


def relation_text(rel: list) -> str:
    """(subject type object :at #f(x y z) :wrt frame), as in Fig. 14."""
    obj = _names(rel[2]) if isinstance(rel[2], list) else rel[2]
    parts = [rel[1], rel[0], obj]
    meta = rel[3] if len(rel) > 3 else {}
    if "at" in meta:
        parts.append(f":at #f({' '.join(_num(c) for c in meta['at'])})")
    if "wrt" in meta:
        parts.append(f":wrt {meta['wrt']}")
    return f"({' '.join(parts)})"


def _levels(plan: dict) -> list[list[str]]:
    """Operator names level by level from the root (Fig. 22's expansion levels)."""
    ops = plan["operators"]
    seen, levels, frontier = set(), [], [plan["root"]]
    while frontier:
        levels.append(frontier)
        seen.update(frontier)
        nxt = []
        for name in frontier:
            for child in _plot_names(ops[name]["plot"]):
                if child in ops and child not in seen and child not in nxt:
                    nxt.append(child)
        frontier = nxt
    rest = [n for n in ops if n not in seen]
    if rest:
        levels.append(rest)
    return levels


def _plot_names(plot: list) -> list[str]:
    """$action names in a plot, in order."""
    if plot[0] == "$action":
        return [plot[1]]
    return [n for sub in plot[1:] for n in _plot_names(sub)]


def write_plan_text(plan: dict) -> str:
    """Render a plan.json document as plan.txt."""
    ops = plan["operators"]
    lines = [";;; Task plan in the plot notation of Fig. 17 / Fig. 22 (rules/plot.lark).",
             f";;; The first operator is the root: {plan['root']}."]
    for depth, names in enumerate(_levels(plan)):
        lines.append(f";;; Expansion level {depth}")
        for name in names:
            op = ops[name]
            lines.append(f"($action {name}")
            lines.append(f"  :class {op['class']}")
            for key, word in NAME_SLOTS:
                lines.append(f"  {word} {_names(op[key])}")
            lines.append(f"  :plot {_plot(op['plot'])}")
            for key, word in RELATION_SLOTS:
                rels = op[key]
                if not rels:
                    lines.append(f"  {word} nil")
                    continue
                pad = " " * (len(word) + 4)
                body = f"\n{pad}".join(relation_text(r) for r in rels)
                lines.append(f"  {word} ({body})")
            lines[-1] += ")"
    return "\n".join(lines) + "\n"


class _ToPlan(Transformer):
    """Parse tree of rules/plot.lark → plan.json pieces."""

    def NAME(self, tok):  # noqa: N802 - Lark terminal callback
        return str(tok)

    def NUMBER(self, tok):  # noqa: N802
        text = str(tok)
        return float(text) if any(c in text for c in ".eE") else int(text)

    def start(self, ops):
        return ops

    @v_args(inline=True)
    def nil(self):
        return []

    def name_list(self, names):
        return list(names)

    def relation_list(self, rels):
        return list(rels)

    @v_args(inline=True)
    def single_object(self, name):
        return name

    def object_list(self, names):
        return list(names)

    def at(self, nums):
        return ("at", list(nums))

    @v_args(inline=True)
    def wrt(self, name):
        return ("wrt", name)

    def relation(self, items):
        subject, rtype, obj, *options = items
        rel: list[Any] = [rtype, subject, obj]
        if options:
            rel.append(dict(options))
        return rel

    def sequence(self, plots):
        return ["$sequence", *plots]

    def parallel(self, plots):
        return ["$parallel", *plots]

    @v_args(inline=True)
    def action(self, name):
        return ["$action", name]

    @v_args(inline=True)
    def class_slot(self, name):
        return ("class", name)

    @v_args(inline=True)
    def plot_slot(self, plot):
        return ("plot", plot)

    def __default__(self, data, children, meta):
        # base / target / special / next / sc_plus / sc_minus / si / sp
        return (str(data), children[0])

    def operator(self, items):
        name, *slots = items
        return (name, slots)


def read_plan_text(text: str, file: str = "<plan.txt>",
                   grammar_file: str | Path | None = None) -> dict:
    """Parse plan.txt into a plan.json document; errors name the file and line."""
    grammar_file = Path(grammar_file) if grammar_file else default_rules_dir() / "plot.lark"
    try:
        tree = compile_plot(grammar_file).parse(text)
        ops = _ToPlan().transform(tree)
    except UnexpectedInput as exc:
        raise InputError(f"not in the plot notation at column {exc.column}: "
                         f"{shorten(exc.get_context(text).splitlines()[0].strip())}",
                         file=file, line=exc.line) from None
    except VisitError as exc:
        raise InputError(f"cannot read the plot notation ({shorten(str(exc.orig_exc))})",
                         file=file) from None
    if not ops:
        raise InputError("contains no operator", file=file)
    operators: dict[str, dict] = {}
    for name, slots in ops:
        if name in operators:
            raise InputError(f"operator {name} is written twice", file=file, where=name)
        entry: dict[str, Any] = {}
        for key, value in slots:
            if key in entry:
                raise InputError(f"slot {key} is given twice", file=file, where=name)
            entry[key] = value
        if "plot" not in entry:
            raise InputError("the operator has no :plot", file=file, where=name)
        if "class" not in entry:
            m = CLASS_FROM_NAME.match(name)
            if not m or m.group(1).upper() not in PLAN_CLASSES:
                raise InputError("no :class, and the name does not tell it", file=file,
                                 where=name)
            entry["class"] = m.group(1).upper()
        operators[name] = {
            "class": entry["class"],
            **{key: entry.get(key, []) for key, _ in NAME_SLOTS[:3]},
            **{key: entry.get(key, []) for key, _ in RELATION_SLOTS},
            "plot": entry["plot"],
            "next": entry.get("next", []),
        }
    return {"root": ops[0][0], "operators": operators}


def check_grammar(grammar_file: Path, relation: str) -> None:
    """``lbw check``: the plot grammar builds and reads back what ``write_plan_text``
    writes (a two-level sample plan with every slot, :at coordinates and a
    multiple-object relation of type ``relation``), unchanged."""
    build, achieve = PLAN_CLASSES[0], PLAN_CLASSES[2]
    at = {"at": [1.5, -2.0, 30.0], "wrt": "t1"}
    top = {"class": build, "base": ["b1", "b2"], "target": ["t1"], "special": [],
           "sc_plus": [[relation, "b1", ["b2", "t1"], at]], "sc_minus": [[relation, "b2", "t1"]],
           "si": [], "sp": [], "next": [],
           "plot": ["$sequence", ["$action", f"{achieve.lower()}01"],
                    ["$parallel", ["$action", "x01"], ["$action", "x02"]]]}
    leaf = {**top, "class": achieve, "base": ["b2"], "sc_plus": [], "sc_minus": [],
            "plot": ["$action", "x03"]}
    sample = {"root": f"{build.lower()}01",
              "operators": {f"{build.lower()}01": top, f"{achieve.lower()}01": leaf}}
    try:
        back: Any = read_plan_text(write_plan_text(sample), "<sample plan.txt>", grammar_file)
    except InputError as exc:
        if exc.file == str(grammar_file):
            raise
        back = exc.message
    except (TypeError, ValueError, KeyError, IndexError, AttributeError):
        back = None  # the grammar's tree is not the plot notation's
    if back != sample:
        why = f" ({back})" if isinstance(back, str) else ""
        raise InputError("does not read back the plot notation lbw writes to plan.txt "
                         f"(Fig. 17, 22){why}", file=grammar_file)
