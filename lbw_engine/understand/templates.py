"""Step 1 of plan analysis (Sec. VI-C1): the fixed-order templates of Fig. 15.

rules/templates.lark is the reference (compiled when the rules load,
``lbw_engine.rules.grammars``). The action sequence is fed to Lark one word per
operation; a word no terminal accepts is an error. The parse tree is read through the
analysis.yaml table (grammar rule → operator class; removed rules): an operator
is made for every rule in the table, rules outside it are transparent, removed
rules are dropped with everything they matched. No operation name appears here.
"""

from __future__ import annotations

from lark import Token, Tree
from lark.exceptions import UnexpectedEOF, UnexpectedInput

from lbw_engine.errors import InputError
from lbw_engine.guard import shorten
from lbw_engine.rules.analysis import AnalysisRules
from lbw_engine.rules.grammars import Templates, UnknownWord
from lbw_engine.understand.actions import ActionSequence, Operation
from lbw_engine.understand.state import Member, Operator, make_operator

CONTEXT = 2  # operations shown on each side of an error position


def _around(ops: tuple[Operation, ...], index: int) -> str:
    """The operations around ``index``, the offending one in brackets."""
    lo, hi = max(0, index - CONTEXT), min(len(ops), index + CONTEXT + 1)
    words = [f"[{op.name}]" if op.index == index else op.name for op in ops[lo:hi]]
    if index >= len(ops):
        words.append("[end]")
    return ("... " if lo > 0 else "") + " ".join(words) + (" ..." if hi < len(ops) else "")


def parse_sequence(tpl: Templates, seq: ActionSequence) -> Tree:
    """Parse the operation names; a sequence no template covers is an InputError."""
    ops = seq.operations
    words = [op.operation for op in ops]
    try:
        return tpl.parser.parse(words)
    except UnknownWord as exc:
        raise InputError(
            f"operation {exc.word} is not in the templates of {tpl.file.name}; "
            f"around it: {_around(ops, exc.index)}",
            file=seq.file, where=f"operations[{exc.index}]") from None
    except UnexpectedInput as exc:
        token = getattr(exc, "token", None)
        if isinstance(exc, UnexpectedEOF) or (token is not None and token.type == "$END"):
            _ended_inside(exc, tpl, seq)
        index = token.start_pos if token is not None else exc.pos_in_stream
        accepts = getattr(exc, "accepts", None) or getattr(exc, "expected", set())
        expected = ", ".join(sorted({tpl.shown.get(e, e) for e in accepts if e != "$END"}))
        allowed = f"expected {expected}" if expected else "expected the end of the sequence"
        raise InputError(
            f"no template covers {ops[index].operation} here ({allowed}); "
            f"around it: {_around(ops, index)}",
            file=seq.file, where=f"operations[{index}]") from None


def _ended_inside(exc: UnexpectedInput, tpl: Templates, seq: ActionSequence) -> None:
    """The sequence stopped in the middle of a template (e.g. still holding an object)."""
    ops = seq.operations
    accepts = getattr(exc, "accepts", None) or getattr(exc, "expected", set())
    expected = ", ".join(sorted({tpl.shown.get(e, e) for e in accepts if e != "$END"}))
    raise InputError(
        f"the sequence ends inside a template (expected {expected}); "
        f"around it: {_around(ops, len(ops))}",
        file=seq.file, where=f"operations[{len(ops)}]") from None


def build_step1(
    tree: Tree, seq: ActionSequence, rules: AnalysisRules
) -> tuple[list[Operator], list[Operation]]:
    """Turn the parse tree into operators; return the top-level ones and the removed leaves."""
    removed: list[Operation] = []

    def members(node: Tree) -> list[Member]:
        """The plot members under ``node`` (transparent rules are flattened)."""
        out: list[Member] = []
        for child in node.children:
            if isinstance(child, Token):
                out.append(seq.operations[child.start_pos])
            elif child.data in rules.removed:
                removed.extend(seq.operations[t.start_pos] for t in child.scan_values(
                    lambda v: isinstance(v, Token)))
            elif child.data in rules.operators:
                out.append(make(child))
            else:
                out.extend(members(child))
        return out

    def make(node: Tree) -> Operator:
        """One operator for a rule of the table; its plot is its members in order."""
        parts = members(node)
        if not parts:
            raise InputError(f"template rule {shorten(node.data)} matched no operation",
                             file=rules.grammar_file)
        plot = parts[0] if len(parts) == 1 else ("$sequence", *parts)
        return make_operator(rules.operators[node.data], plot, parts, rules.agents, rules.fixed)

    top = members(tree)
    # Operations directly under the start rule belong to no operator: redundant too.
    kept = [m for m in top if isinstance(m, Operator)]
    removed.extend(m for m in top if isinstance(m, Operation))
    removed.sort(key=lambda op: op.index)
    return kept, removed
