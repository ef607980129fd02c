"""The Lark grammars of rules/: the plan templates (Fig. 15) and the plot notation (Fig. 17, 22).

Both are compiled when the rules are loaded, so a grammar that does not
compile, is ambiguous (LALR(1), strict), is not UTF-8, or lacks a rule the
readers need is refused with the file before anything runs. Compiled parsers
are cached by file and modification time.

The template grammar is fed one word per operation (``WordLexer``): a word
becomes the terminal whose quoted text equals it, else the first /regex/
terminal matching it in full.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from lark import Lark, Token
from lark.lexer import Lexer

from lbw_engine.errors import InputError
from lbw_engine.guard import lark_grammar, read_text
from lbw_engine.rules.reader import listing

# The rules and aliases the plot reader (lbw_engine.understand.plottext) transforms.
PLOT_NAMES = frozenset({
    "start", "operator", "class_slot", "base", "target", "special", "next", "plot_slot",
    "sc_plus", "sc_minus", "si", "sp", "sequence", "parallel", "action", "nil", "name_list",
    "relation_list", "relation", "single_object", "object_list", "at", "wrt",
})


class UnknownWord(Exception):
    """A word that no terminal of the template grammar accepts."""

    def __init__(self, index: int, word: str) -> None:
        """The ``index``-th word, ``word``, has no terminal."""
        super().__init__(word)
        self.index = index
        self.word = word


class WordLexer(Lexer):
    """Tokenizes a list of operation names, one token per name, matched in full."""

    def __init__(self, lexer_conf) -> None:
        """Index the grammar's terminals: literal text → name, then regex terminals."""
        self.literals: dict[str, str] = {}
        self.patterns = []
        for term in sorted(lexer_conf.terminals, key=lambda t: -t.priority):
            if term.pattern.type == "str":
                self.literals.setdefault(term.pattern.value, term.name)
            else:
                self.patterns.append((term.name, lexer_conf.re_module.compile(
                    term.pattern.to_regexp(), lexer_conf.g_regex_flags)))

    def lex(self, words):  # type: ignore[override]
        """Yield one Token per word; its position is the operation's index."""
        for i, word in enumerate(words):
            kind = self.literals.get(word)
            if kind is None:
                kind = next((n for n, rx in self.patterns if rx.fullmatch(word)), None)
            if kind is None:
                raise UnknownWord(i, word)
            yield Token(kind, word, start_pos=i, line=1, column=i + 1, end_pos=i + 1)


@dataclass(frozen=True)
class Templates:
    """A compiled template grammar with the readable form of each terminal."""

    parser: Lark
    shown: dict[str, str]  # terminal name -> how it reads in messages
    file: Path

    def words(self) -> set[str]:
        """The operation names the grammar quotes."""
        return {t.pattern.value for t in self.parser.terminals if t.pattern.type == "str"}

    def rules(self) -> set[str]:
        """The names of the grammar's rules."""
        return {r.origin.name for r in self.parser.rules}


def _text(path: Path, what: str) -> str:
    """A grammar file's text (UTF-8), with the file named on any failure."""
    if not path.is_file():
        raise InputError(f"the {what} is missing", file=path)
    return read_text(path, noun=what, expected=f"the {what}")


@lru_cache(maxsize=8)
def _compile_templates(path: Path, mtime: float, start: str) -> Templates:
    del mtime  # part of the cache key only: an edited file is recompiled
    text = _text(path, "template grammar")
    parser = lark_grammar(text, path, "template grammar", parser="lalr", lexer=WordLexer,
                          start=start, strict=True, keep_all_tokens=True)
    for term in parser.terminals:  # a /regex/ the lexer could not compile fails at use
        if term.pattern.type != "str":
            try:
                re.compile(term.pattern.to_regexp())
            except re.error as exc:
                raise InputError(f"bad template grammar: terminal {term.name} is not a valid "
                                 f"regular expression ({exc})", file=path) from None
    shown = {t.name: (t.pattern.value if t.pattern.type == "str" else f"/{t.pattern.value}/")
             for t in parser.terminals}
    return Templates(parser, shown, path)


def compile_templates(path: Path, start: str) -> Templates:
    """The template grammar at ``path`` compiled from rule ``start`` (cached)."""
    mtime = path.stat().st_mtime if path.is_file() else 0.0
    return _compile_templates(path, mtime, start)


@lru_cache(maxsize=8)
def _compile_plot(path: Path, mtime: float) -> Lark:
    del mtime
    text = _text(path, "plot grammar")
    parser = lark_grammar(text, path, "plot grammar", parser="lalr", propagate_positions=False)
    defined = {r.origin.name for r in parser.rules} | {r.alias for r in parser.rules if r.alias}
    missing = sorted(PLOT_NAMES - defined)
    if missing:
        raise InputError(f"the plot grammar lacks the rules the plan.txt reader needs: "
                         f"{listing(missing)}", file=path)
    return parser


def compile_plot(path: Path) -> Lark:
    """The plot-notation parser of ``path`` (cached)."""
    mtime = path.stat().st_mtime if path.is_file() else 0.0
    return _compile_plot(path, mtime)
