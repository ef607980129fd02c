"""The guarded boundary: what every input file passes before any reader sees it.

Scenarios, rule files, actions.json, plan.json, traces and Lark grammars come
from users and other tools. Whatever they hold, lbw answers with one line
naming the file, the place, what is wrong and what was expected (exit 2) —
never a traceback. This module holds the checks every format shares:

- ``read_text``: a file, not a folder; at most ``MAX_BYTES``; UTF-8 text;
- ``json_document``: JSON with finite numbers of at most ``MAX_DIGITS`` digits,
  no duplicate keys, at most ``MAX_DEPTH`` levels of nesting;
- ``number``: a finite number inside the range where it is used;
- ``lark_grammar``: a grammar file Lark can compile, regex terminals included;
- ``shorten``: an offending value as at most about 80 characters.

The YAML limits (depth, aliases, numbers, control characters) are enforced by
the loader in ``yamlio``, which uses the same constants. Format readers (rule
files, scenarios, plans) call these; none of them knows a rule's name.
"""

from __future__ import annotations

import json
import math
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError

MAX_BYTES = 64 * 1024 * 1024  # an input file; actions.json of 10,000 ACHIEVEs: 15 MB
MAX_DEPTH = 100  # nesting of lists and mappings; real files nest under 12 deep
MAX_NODES = 100_000  # YAML values once aliases are expanded (alias bombs); a rule file: <300
MAX_DIGITS = 18  # digits of an integer: no size, count or seed of lbw has more
SHOWN = 80  # characters of an offending value shown in a message
MAX_FPS = 1000.0  # --fps: nan or inf passed "> 0" and never ended


def _int_text(x: int) -> str:
    """An integer, or its size when it is too long to print (str() may refuse it)."""
    if x.bit_length() <= 64:
        return str(x)
    return f"<an integer of about {int(x.bit_length() * math.log10(2)) + 1} digits>"


def _pieces(value: Any, limit: int, depth: int = 0) -> Iterator[str]:
    """The repr of ``value`` piece by piece, so a huge or aliased value is never
    printed whole (an alias bomb of a few kB expands to millions of items)."""
    if depth > 20:
        yield "..."
    elif isinstance(value, dict):
        yield "{"
        for i, (key, item) in enumerate(value.items()):
            yield ", " if i else ""
            yield from _pieces(key, limit, depth + 1)
            yield ": "
            yield from _pieces(item, limit, depth + 1)
        yield "}"
    elif isinstance(value, (list, tuple)):
        yield "["
        for i, item in enumerate(value):
            yield ", " if i else ""
            yield from _pieces(item, limit, depth + 1)
        yield "]"
    elif isinstance(value, int) and not isinstance(value, bool):
        yield _int_text(value)
    elif isinstance(value, str):
        yield repr(value[: limit + 1])
    else:
        yield repr(value)[: limit + 1]


def shorten(value: Any, limit: int = SHOWN) -> str:
    """``value`` as a one-line repr of at most ``limit`` characters (cut with "…")."""
    text = ""
    for piece in _pieces(value, limit):
        text += piece
        if len(text) > limit:
            return text[: limit - 1] + "…"
    return text


def clip(text: str, limit: int = SHOWN) -> str:
    """Plain text (a key path, a name) cut to ``limit`` characters."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def first_line(text: str, limit: int = 160) -> str:
    """The first non-empty line of an exception text, cut to ``limit`` characters."""
    line = next((s.strip() for s in str(text).splitlines() if s.strip()), "")
    return line if len(line) <= limit else line[: limit - 1] + "…"


@dataclass(frozen=True)
class Place:
    """Where a value came from, for the one-line error about it."""

    file: str | Path | None = None
    line: int | None = None
    where: str | None = None

    def error(self, message: str) -> InputError:
        """An InputError at this place."""
        return InputError(message, file=self.file, line=self.line, where=self.where)


# -- files ------------------------------------------------------------------


def read_text(path: str | Path, noun: str = "file", expected: str = "a file") -> str:
    """The UTF-8 text of an input file; any problem is one InputError naming it."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise InputError(f"{noun} not found", file=path) from None
    except IsADirectoryError:
        raise InputError(f"is a directory, expected {expected}", file=path) from None
    except PermissionError:
        raise InputError(f"cannot read the {noun}: permission denied", file=path) from None
    except OSError as exc:
        reason = exc.strerror or exc.__class__.__name__
        raise InputError(f"cannot read the {noun}: {reason}", file=path) from None
    if len(data) > MAX_BYTES:
        raise InputError(f"the {noun} is larger than {MAX_BYTES >> 20} MB, the most lbw reads",
                         file=path)
    return utf8(data, path)


def utf8(data: bytes, file: str | Path | None = None) -> str:
    """Decode UTF-8 (a leading byte-order mark is dropped); else name the line."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        bad = data[exc.start:exc.start + 1].hex()
        raise InputError(f"not UTF-8 text: byte 0x{bad} at column {column}; save the file "
                         "as UTF-8", file=file, line=line) from None
    return text.removeprefix("\ufeff")


def known_keys(raw: dict, allowed: tuple[str, ...], where: str,
               fail: Any) -> None:
    """No key outside ``allowed`` (a typo must not be silently ignored); ``fail(message,
    key path)`` makes the caller's InputError."""
    for key in raw:
        if key not in allowed:
            path = f"{where}.{key}" if where else str(key)
            expected = ", ".join(allowed)  # outside the f-string: Python 3.11 tokenizes it whole
            raise fail(f"unknown key {shorten(key)} (expected one of: {expected})",
                       clip(path, 120))


def check_size(text: str, file: str | Path | None = None) -> None:
    """Text already in memory (tests, tools) obeys the same size limit as files."""
    if len(text) > MAX_BYTES:
        raise InputError(f"the text is larger than {MAX_BYTES >> 20} MB, the most lbw reads",
                         file=file)


# -- numbers ----------------------------------------------------------------


def number(value: Any, place: Place, low: float | None = None, high: float | None = None,
           *, unit: str = "", above: bool = False, integer: bool = False) -> float:
    """``value`` as a float: a finite number in [low, high] (``above``: > low).

    A boolean is not a number; ``integer`` asks for a whole number.
    """
    kind = "a whole number" if integer else "a number"
    if isinstance(value, bool) or not isinstance(value, (int, float)) or (
            integer and not isinstance(value, int)):
        raise place.error(f"expected {kind}{_range(low, high, unit, above)}, got "
                          f"{shorten(value)}")
    if isinstance(value, int) and abs(value) >= 10 ** MAX_DIGITS:
        raise place.error(f"expected {kind}{_range(low, high, unit, above)}, got "
                          f"{shorten(value)}")
    if not math.isfinite(value):
        raise place.error(f"expected a finite number, got {value}")
    out = float(value)
    if (low is not None and (out < low or (above and out <= low))) or (
            high is not None and out > high):
        raise place.error(f"expected {kind}{_range(low, high, unit, above)}, got {value:g}")
    return out


def _range(low: float | None, high: float | None, unit: str, above: bool) -> str:
    """' in [10, 200] mm', ' > 0 mm', ' <= 5 s' or ''."""
    u = f" {unit}" if unit else ""
    if low is not None and high is not None and not above:
        return f" in [{low:g}, {high:g}]{u}"
    lower = f" {'>' if above else '>='} {low:g}" if low is not None else ""
    upper = f" <= {high:g}" if high is not None else ""
    both = " and" if lower and upper else ""
    return f"{lower}{both}{upper}{u}" if lower or upper else ""


# -- JSON -------------------------------------------------------------------


class _JsonNumber(ValueError):
    """A JSON number lbw does not accept (raised from the parser's hooks)."""

    def __init__(self, message: str, token: str) -> None:
        super().__init__(message)
        self.token = token


def _json_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise _JsonNumber(f"an integer of {len(text.lstrip('-'))} digits; expected at most "
                          f"{MAX_DIGITS}", text[:40])
    return int(text)


def _json_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _JsonNumber(f"the number {text[:40]} is too large; expected a finite number",
                          text[:40])
    return value


def _json_constant(name: str) -> Any:
    raise _JsonNumber(f"{name} is not a number; expected a finite number", name)


def _json_object(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _JsonNumber(f"duplicate key {shorten(key)} in one object", json.dumps(key))
        out[key] = value
    return out


def json_document(text: str, file: str | Path | None = None) -> Any:
    """Parse JSON text with lbw's limits; every failure is one InputError."""
    check_size(text, file)
    try:
        doc = json.loads(text, parse_int=_json_int, parse_float=_json_float,
                         parse_constant=_json_constant, object_pairs_hook=_json_object)
    except json.JSONDecodeError as exc:
        raise InputError(f"invalid JSON: {exc.msg} at column {exc.colno}", file=file,
                         line=exc.lineno) from None
    except _JsonNumber as exc:
        raise InputError(str(exc), file=file, line=_line_of(text, exc.token)) from None
    except RecursionError:
        raise InputError(f"nested more than {MAX_DEPTH} levels deep", file=file) from None
    check_depth(doc, file)
    return doc


def _line_of(text: str, token: str) -> int | None:
    """The line where ``token`` first appears (JSON's parser hooks do not say)."""
    at = text.find(token)
    return text.count("\n", 0, at) + 1 if at >= 0 else None


def check_depth(doc: Any, file: str | Path | None = None, limit: int = MAX_DEPTH) -> None:
    """No list or mapping nests more than ``limit`` deep (checked without recursion)."""
    stack: list[tuple[Any, int, str]] = [(doc, 1, "")]
    while stack:
        value, depth, where = stack.pop()
        if not isinstance(value, (list, dict)):
            continue
        if depth > limit:
            place = where if len(where) <= SHOWN else "…" + where[-SHOWN:]
            raise InputError(f"nested more than {limit} levels deep", file=file,
                             where=place or None)
        items = value.items() if isinstance(value, dict) else enumerate(value)
        for key, child in items:
            sub = f"{where}.{key}".lstrip(".") if isinstance(value, dict) else f"{where}[{key}]"
            stack.append((child, depth + 1, sub))


# -- Lark grammars ----------------------------------------------------------


def lark_grammar(text: str, file: str | Path, what: str, **options: Any) -> Any:
    """A Lark parser made from a rule file's grammar; a bad grammar is an InputError.

    A grammar is user data: besides Lark's own errors, a regex terminal Python
    cannot compile (``/[/``) raises ``re.error`` while the lexer is built.
    """
    from lark import Lark
    from lark.exceptions import LarkError, UnexpectedInput

    try:
        with warnings.catch_warnings():  # re's FutureWarnings on odd sets are no errors
            warnings.simplefilter("ignore", FutureWarning)
            return Lark(text, **options)
    except UnexpectedInput as exc:
        raise InputError(f"bad {what}: {_lark_text(exc)}", file=file,
                         line=getattr(exc, "line", None) or None) from None
    except re.error as exc:
        pattern = exc.pattern if isinstance(exc.pattern, str) else ""
        raise InputError(f"bad {what}: the regular expression /{clip(pattern, 40)}/ does "
                         f"not compile ({exc.msg})", file=file,
                         line=_line_of(text, pattern) if pattern else None) from None
    except (LarkError, RecursionError) as exc:
        found = re.search(r"\bat line (\d+)", str(exc))
        raise InputError(f"bad {what}: {_lark_text(exc)}", file=file,
                         line=int(found.group(1)) if found else None) from None


def _lark_text(exc: BaseException) -> str:
    """Lark's first line of an error, without its trailing 'in <string>:'."""
    text = first_line(str(exc)).removesuffix(":").removesuffix(" in <string>")
    return text or exc.__class__.__name__
