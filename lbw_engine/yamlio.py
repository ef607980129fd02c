"""Safe YAML loading that remembers where every value came from.

Rule files and scenarios are validated at load time with messages naming the
file and line, so the loader keeps line numbers: mappings load as ``LocDict``
and sequences as ``LocList``; both carry ``.line`` (their own) and
``.lines`` (per key or per index). Only ``yaml.SafeLoader`` is used.

YAML 1.1 reads a bare ``on`` / ``off`` / ``yes`` / ``no`` as booleans. The
scenario format uses ``on:`` as a key, so this loader only accepts ``true`` /
``false`` as booleans and reads the rest as strings; dates stay strings too.

The loader is part of lbw's guarded boundary (``lbw_engine.guard``): text must
be printable, nesting is limited to ``MAX_DEPTH`` levels and a document to
``MAX_NODES`` values with its aliases expanded (an alias bomb is refused before
anything walks it), integers to ``MAX_DIGITS`` digits and floats to finite
values, and only plain tags (strings, numbers, booleans, null, lists, mappings)
are read. Each refusal names the line.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import yaml

from lbw_engine.errors import InputError
from lbw_engine.guard import MAX_DEPTH, MAX_DIGITS, MAX_NODES, check_size, first_line, read_text


class LocDict(dict):
    """A dict that remembers the 1-based line of itself and of each key."""

    line: int = 0
    lines: dict[Any, int]


class LocList(list):
    """A list that remembers the 1-based line of itself and of each item."""

    line: int = 0
    lines: list[int]


class _Refused(yaml.MarkedYAMLError):
    """A document outside lbw's limits (not a syntax error); ``where`` is the key path of
    the value refused, when it is known."""

    where: str | None = None


def _refused(loader: Any, problem: str, mark: Any) -> _Refused:
    """A refusal at ``mark`` naming the key path being read (``teach.objects.a.at[0]``)."""
    err = _Refused(None, None, problem, mark)
    err.where = "".join(f"[{p}]" if isinstance(p, int) else f".{p}"
                        for p in getattr(loader, "_path", ())).lstrip(".") or None
    return err


class _Loader(yaml.SafeLoader):
    """SafeLoader with YAML-1.2-like booleans, line-annotated containers and limits."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0
        self._weight: dict[int, int] = {}  # id(node) -> values under it, aliases expanded
        self._path: list[Any] = []  # keys and indices down to the value being constructed

    def compose_node(self, parent: Any, index: Any) -> yaml.Node:
        """Compose with a depth limit, and weigh each node as if aliases were copies."""
        if self.check_event(yaml.AliasEvent):
            node = super().compose_node(parent, index)
            if id(node) not in self._weight:  # an alias inside its own anchor
                raise _Refused(None, None, "an alias refers to a value that contains it",
                               node.start_mark)
            return node
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Refused(None, None, f"nested more than {MAX_DEPTH} levels deep",
                               self.peek_event().start_mark)
            node = super().compose_node(parent, index)
        finally:
            self._depth -= 1
        self._weigh(node)
        return node

    def _weigh(self, node: yaml.Node) -> None:
        """Refuse a document whose expansion (through aliases) exceeds MAX_NODES."""
        w = self._weight
        if isinstance(node, yaml.SequenceNode):
            weight = 1 + sum(w[id(c)] for c in node.value)
        elif isinstance(node, yaml.MappingNode):
            weight = 1 + sum(w[id(k)] + w[id(v)] for k, v in node.value)
        else:
            weight = 1
        if weight > MAX_NODES:
            raise _Refused(None, None, f"expands to more than {MAX_NODES:,} values through its "
                           "aliases (an alias bomb?)", node.start_mark)
        w[id(node)] = weight

    def construct_object(self, node: yaml.Node, deep: bool = False) -> Any:
        """Construct; a value its tag cannot read (``!!int abc``) names its line."""
        try:
            return super().construct_object(node, deep=deep)
        except (ValueError, TypeError, OverflowError) as exc:
            raise _refused(self, f"cannot read this value ({first_line(exc, 80)})",
                           node.start_mark) from None


# Drop the YAML 1.1 bool resolver (yes/no/on/off) and install true/false only;
# drop the timestamp resolver too (2001-13-45 would fail; lbw has no dates).
_Loader.yaml_implicit_resolvers = {
    key: [(tag, rx) for tag, rx in resolvers
          if tag not in ("tag:yaml.org,2002:bool", "tag:yaml.org,2002:timestamp")]
    for key, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool",
    re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
    list("tTfF"),
)


def plain(value: Any) -> Any:
    """A loaded document with its located containers (LocDict, LocList) as plain dicts
    and lists, so that it can be dumped again."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain(v) for v in value]
    return value


def _construct_mapping(loader: _Loader, node: yaml.MappingNode) -> LocDict:
    loader.flatten_mapping(node)
    out = LocDict()
    out.line = node.start_mark.line + 1
    out.lines = {}
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            raise yaml.constructor.ConstructorError(
                None, None, "found an unhashable key", key_node.start_mark
            ) from None
        if key in out:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key {key!r}", key_node.start_mark
            )
        loader._path.append(key)
        try:
            out[key] = loader.construct_object(value_node, deep=True)
        finally:
            loader._path.pop()
        out.lines[key] = key_node.start_mark.line + 1
    return out


def _construct_sequence(loader: _Loader, node: yaml.SequenceNode) -> LocList:
    out = LocList()
    for i, child in enumerate(node.value):
        loader._path.append(i)
        try:
            out.append(loader.construct_object(child, deep=True))
        finally:
            loader._path.pop()
    out.line = node.start_mark.line + 1
    out.lines = [child.start_mark.line + 1 for child in node.value]
    return out


def _construct_int(loader: _Loader, node: yaml.ScalarNode) -> int:
    digits = sum(ch.isalnum() for ch in str(node.value))
    if digits > MAX_DIGITS:
        raise _refused(loader, f"an integer of {digits} digits; expected a number of at "
                       f"most {MAX_DIGITS} digits", node.start_mark)
    return yaml.SafeLoader.construct_yaml_int(loader, node)


def _construct_float(loader: _Loader, node: yaml.ScalarNode) -> float:
    value = yaml.SafeLoader.construct_yaml_float(loader, node)
    if not math.isfinite(value):
        raise _refused(loader, f"{str(node.value)[:40]} is not a finite number",
                       node.start_mark)
    return value


def _not_allowed(loader: _Loader, node: yaml.Node) -> Any:
    tag = str(node.tag).replace("tag:yaml.org,2002:", "!!")
    raise _refused(loader, f"the tag {tag} is not allowed; use plain values, lists "
                   "and mappings", node.start_mark)


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)
_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_SEQUENCE_TAG, _construct_sequence)
_Loader.add_constructor("tag:yaml.org,2002:int", _construct_int)
_Loader.add_constructor("tag:yaml.org,2002:float", _construct_float)
for _tag in ("binary", "timestamp", "omap", "pairs", "set"):
    _Loader.add_constructor(f"tag:yaml.org,2002:{_tag}", _not_allowed)


def _printable(text: str, file: str | Path) -> None:
    """YAML allows no control characters but tab and line breaks; name the first one."""
    bad = yaml.reader.Reader.NON_PRINTABLE.search(text)
    if bad:
        at = bad.start()
        line = text.count("\n", 0, at) + 1
        column = at - (text.rfind("\n", 0, at) + 1) + 1
        raise InputError(f"control character U+{ord(bad.group()):04X} at column {column}; "
                         "expected printable text (tabs and line breaks are fine)",
                         file=file, line=line)


def loads(text: str, file: str | Path = "<string>") -> Any:
    """Parse YAML text safely; syntax errors become InputError with file:line."""
    check_size(text, file)
    _printable(text, file)
    try:
        loader = _Loader(text)  # a SafeLoader subclass: no arbitrary objects
        try:
            return loader.get_single_data()
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else None
        problem = exc.problem or exc.context or "invalid YAML"
        opened = exc.context_mark
        if exc.context and opened is not None and line is not None and opened.line + 1 < line:
            # an unclosed bracket or quote: the line it opened on is the one to fix
            what = exc.context.replace("while parsing a ", "").replace("while scanning a ", "")
            problem = f"the {what} begun here is not closed ({problem} on line {line})"
            line = opened.line + 1
        prefix = "" if isinstance(exc, _Refused) else "invalid YAML: "
        raise InputError(prefix + problem, file=file, line=line,
                         where=getattr(exc, "where", None)) from None
    except yaml.YAMLError as exc:
        raise InputError(f"invalid YAML: {first_line(exc)}", file=file) from None


def load_file(path: str | Path) -> Any:
    """Read and parse a YAML file; a missing or unreadable file is an InputError."""
    path = Path(path)
    return loads(read_text(path, expected="a YAML file"), file=path)


def line_of(container: Any, key: Any = None) -> int | None:
    """Best-known line of ``container[key]`` (or of the container itself)."""
    if key is None:
        return getattr(container, "line", None) or None
    lines = getattr(container, "lines", None)
    if isinstance(lines, dict):
        return lines.get(key) or getattr(container, "line", None)
    if isinstance(lines, list) and isinstance(key, int) and 0 <= key < len(lines):
        return lines[key]
    return getattr(container, "line", None) or None
