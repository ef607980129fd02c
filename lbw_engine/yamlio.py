"""Safe YAML loading that remembers where every value came from.

Rule files and scenarios are validated at load time with messages naming the
file and line, so the loader keeps line numbers: mappings load as ``LocDict``
and sequences as ``LocList``; both carry ``.line`` (their own) and
``.lines`` (per key or per index). Only ``yaml.SafeLoader`` is used.

YAML 1.1 reads a bare ``on`` / ``off`` / ``yes`` / ``no`` as booleans. The
scenario format uses ``on:`` as a key, so this loader only accepts ``true`` /
``false`` as booleans and reads the rest as strings.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import yaml

from lbw_engine.errors import InputError, read_input


class LocDict(dict):
    """A dict that remembers the 1-based line of itself and of each key."""

    line: int = 0
    lines: dict[Any, int]


class LocList(list):
    """A list that remembers the 1-based line of itself and of each item."""

    line: int = 0
    lines: list[int]


class _Loader(yaml.SafeLoader):
    """SafeLoader with YAML-1.2-like booleans and line-annotated containers."""


# Drop the YAML 1.1 bool resolver (yes/no/on/off) and install true/false only.
_Loader.yaml_implicit_resolvers = {
    key: [(tag, rx) for tag, rx in resolvers if tag != "tag:yaml.org,2002:bool"]
    for key, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool",
    re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
    list("tTfF"),
)


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
        out[key] = loader.construct_object(value_node, deep=True)
        out.lines[key] = key_node.start_mark.line + 1
    return out


def _construct_sequence(loader: _Loader, node: yaml.SequenceNode) -> LocList:
    out = LocList(loader.construct_object(child, deep=True) for child in node.value)
    out.line = node.start_mark.line + 1
    out.lines = [child.start_mark.line + 1 for child in node.value]
    return out


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)
_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_SEQUENCE_TAG, _construct_sequence)


def loads(text: str, file: str | Path = "<string>") -> Any:
    """Parse YAML text safely; syntax errors become InputError with file:line."""
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
        raise InputError(f"invalid YAML: {problem}", file=file, line=line) from None
    except yaml.YAMLError as exc:
        raise InputError(f"invalid YAML: {exc}", file=file) from None


def load_file(path: str | Path) -> Any:
    """Read and parse a YAML file; a missing or unreadable file is an InputError."""
    path = Path(path)
    return loads(read_input(path, expected="a YAML file"), file=path)


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
