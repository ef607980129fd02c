"""Mutators for fuzzing lbw's input files (bench/fuzzcases.py, tests/fuzz).

Every mutator takes a ``random.Random``-like ``rng`` (a seeded Random in the
bench, Hypothesis' ``st.randoms()`` in the tests, so failures shrink) and
returns the mutated input and a short label of what was done. Two layers:

- tree mutations work on the parsed document (YAML or JSON): delete, duplicate,
  rename or retype a key or item, swap values, empty a container, negate or
  blow up a number, put a weird string, NaN or infinity, nest deeply, or plant
  an alias bomb. Documents are written back with the format's own dumper;
  what a dumper cannot write (a 5,000-digit integer, 3,000 levels of nesting,
  an alias bomb) goes in as a marker string replaced in the text afterwards;
- text mutations work on the bytes: truncation, random bytes, bytes that are
  not UTF-8, control characters, a byte-order mark, lines deleted, doubled or
  swapped, an empty file; Lark grammars also get broken regex terminals.
"""

from __future__ import annotations

import copy
import json
from typing import Any

import yaml

from lbw_engine.yamlio import plain

# Replaced in the dumped text (the dumpers cannot write these values themselves).
DEEP, BOMB, HUGE = "zzDEEPzz", "zzBOMBzz", "zzHUGEzz"

WEIRD_STRINGS = (
    "", " ", "table", "hand", "on", "true", "null", "~", "-", "0", "ñandú 漢字", "\u202eabc",
    "a" * 5000, "x\ty", "new\nline", "$var", "*", "../../etc/passwd", "NaN", "'quoted'",
    "[1, 2]", "{a: 1}", "#comment", "@at", "REACH", "pick01",
)
NUMBERS = (0, -0.0, -1, 1, 0.5, -273.15, 1e-300, 1e300, -1e300, 2**63, -(2**63), 10**17,
           123456789012345678, 3.0e38)
NONFINITE = (float("nan"), float("inf"), float("-inf"))


def _paths(doc: Any) -> list[tuple[Any, Any]]:
    """Every (container, key) inside ``doc``, without recursion."""
    out: list[tuple[Any, Any]] = []
    stack = [doc]
    while stack:
        node = stack.pop()
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for key, child in list(items):
            out.append((node, key))
            if isinstance(child, (dict, list)):
                stack.append(child)
    return out


def _random_value(rng: Any) -> Any:
    """A value of some type, often not the expected one."""
    pick = rng.randrange(8)
    if pick == 0:
        return rng.choice(WEIRD_STRINGS)
    if pick == 1:
        return rng.choice(NUMBERS)
    if pick == 2:
        return rng.choice(NONFINITE)
    if pick == 3:
        return rng.choice([None, True, False])
    if pick == 4:
        return [rng.choice(NUMBERS) for _ in range(rng.randrange(5))]
    if pick == 5:
        return {rng.choice(WEIRD_STRINGS[:12]) or "k": rng.choice(NUMBERS)}
    if pick == 6:
        return rng.choice([[], {}, [[]], [{}]])
    return rng.choice([DEEP, HUGE, BOMB])


def _nest(depth: int, rng: Any) -> Any:
    """A value nested ``depth`` lists or mappings deep (dumpers manage a few hundred)."""
    value: Any = rng.choice([1, "x", None])
    for _ in range(depth):
        value = [value] if rng.random() < 0.5 else {"k": value}
    return value


def mutate_tree(doc: Any, rng: Any) -> tuple[Any, str]:
    """One structural mutation of a parsed document; returns (document, label)."""
    doc = plain(doc)
    paths = _paths(doc) if isinstance(doc, (dict, list)) else []
    if not paths:
        return _random_value(rng), "replace-document"
    node, key = rng.choice(paths)
    value = node[key]
    op = rng.choice(("delete", "duplicate", "rename", "retype", "retype", "swap", "empty",
                     "negate", "huge", "nonfinite", "string", "deep", "bomb"))
    if op == "delete":
        del node[key]
    elif op == "duplicate":
        if isinstance(node, list):
            node.insert(key, value)
        else:
            node[f"{key}2" if isinstance(key, str) else "dup"] = value
    elif op == "rename" and isinstance(node, dict):
        node[rng.choice(WEIRD_STRINGS[:14]) + rng.choice(("", "x", "_"))] = node.pop(key)
    elif op == "swap":  # copies: one value may contain the other
        other_node, other_key = rng.choice(paths)
        mine, theirs = copy.deepcopy(value), copy.deepcopy(other_node[other_key])
        node[key], other_node[other_key] = theirs, mine
    elif op == "empty":
        node[key] = type(value)() if isinstance(value, (dict, list, str)) else None
    elif op == "negate":
        node[key] = -value if isinstance(value, (int, float)) and not isinstance(
            value, bool) else rng.choice(NUMBERS)
    elif op == "huge":
        node[key] = rng.choice((HUGE, 10**400, -(10**400), 1e308, 10**30))
    elif op == "nonfinite":
        node[key] = rng.choice(NONFINITE)
    elif op == "string":
        node[key] = rng.choice(WEIRD_STRINGS)
    elif op == "deep":
        node[key] = DEEP if rng.random() < 0.5 else _nest(rng.choice((60, 101, 300)), rng)
    elif op == "bomb":
        node[key] = BOMB
    else:  # retype (and rename of a list item)
        node[key] = _random_value(rng)
    return doc, op


# -- writing documents back -------------------------------------------------


def alias_bomb(levels: int) -> str:
    """A YAML alias bomb: ``levels`` anchors, each nine copies of the previous one."""
    text = "&a0 [1, 1, 1, 1, 1, 1, 1, 1, 1]"
    for i in range(1, levels + 1):
        text = f"&a{i} [{text}, " + ", ".join([f"*a{i - 1}"] * 8) + "]"
    return text


def _expand(text: str, fmt: str, rng: Any) -> str:
    """Replace the markers by what the dumper could not write."""
    quote = '"' if fmt == "json" else ""
    while f"{quote}{DEEP}{quote}" in text:
        n = rng.choice((150, 1000, 5000))
        text = text.replace(f"{quote}{DEEP}{quote}", "[" * n + "]" * n, 1)
    while f"{quote}{HUGE}{quote}" in text:
        huge = rng.choice(("9" * 400, "-" + "9" * 5000, "1e999", "-1e400", "1" + "0" * 40))
        if fmt == "yaml" and "e" in huge:
            huge = huge.replace("e", ".0e+").replace("+-", "-")
        text = text.replace(f"{quote}{HUGE}{quote}", huge, 1)
    bomb = alias_bomb(rng.choice((3, 5, 7, 9))) if fmt == "yaml" else "[" + "0," * 50000 + "0]"
    return text.replace(f"{quote}{BOMB}{quote}", bomb)


def dump(doc: Any, fmt: str, rng: Any) -> bytes:
    """Write a (mutated) document as YAML or JSON text."""
    if fmt == "json":
        text = json.dumps(doc, indent=1, ensure_ascii=False)
    else:
        text = yaml.safe_dump(doc, sort_keys=False, allow_unicode=True, width=1000)
    return _expand(text, fmt, rng).encode("utf-8", "surrogatepass")


# -- text mutations ---------------------------------------------------------

BAD_UTF8 = (b"\xff", b"\xc3\x28", b"\xed\xa0\x80", b"\xf0\x28\x8c\x28", b"\x80", b"\xc0\xaf")
CONTROL = tuple(bytes([c]) for c in (*range(0, 9), 11, 12, *range(14, 32), 127))
LARK_LINES = (
    'BAD: /[/', 'BAD: /(?P<x>/', 'BAD: /a{99999999999}/', 'BAD: /(a+)+$/', 'BAD: ""',
    'bad: BAD | "X"', "start: start", "%import common.NOPE", "%ignore /[/", "bad: /[/",
    "_x: _x _x", "NAME: /./", "task: task*", "%declare X", ": :",
)


def _lines(data: bytes) -> list[bytes]:
    return data.split(b"\n")


def mutate_text(data: bytes, rng: Any, fmt: str) -> tuple[bytes, str]:
    """One byte-level mutation; ``fmt`` is yaml, json or lark. Returns (bytes, label)."""
    ops = ["truncate", "random-bytes", "bad-utf8", "control", "bom", "delete-line",
           "duplicate-line", "swap-lines", "empty", "flip-byte"]
    if fmt == "lark":
        ops += ["lark-line", "lark-line", "lark-regex"]
    op = rng.choice(ops)
    at = rng.randrange(len(data) + 1)
    lines = _lines(data)
    row = rng.randrange(len(lines))
    if op == "truncate":
        return data[:at], op
    if op == "random-bytes":
        return data[:at] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40))) + \
            data[at:], op
    if op == "bad-utf8":
        return data[:at] + rng.choice(BAD_UTF8) + data[at:], op
    if op == "control":
        return data[:at] + rng.choice(CONTROL) + data[at:], op
    if op == "bom":
        return b"\xef\xbb\xbf" + data, op
    if op == "empty":
        return b"", op
    if op == "flip-byte" and data:
        at = min(at, len(data) - 1)
        return data[:at] + bytes([data[at] ^ (1 << rng.randrange(8))]) + data[at + 1:], op
    if op == "delete-line":
        del lines[row]
    elif op == "duplicate-line":
        lines.insert(row, lines[row])
    elif op == "swap-lines":
        other = rng.randrange(len(lines))
        lines[row], lines[other] = lines[other], lines[row]
    elif op == "lark-line":
        lines.insert(row, rng.choice(LARK_LINES).encode())
    elif op == "lark-regex":  # a quoted terminal of a rule becomes a broken regex
        lines[row] = lines[row].replace(b'"', b"/[", 1)
    return b"\n".join(lines), op
