"""Small helpers for checking rule data at load time with file:line messages.

Rule files are plain YAML read by ``yamlio`` (which keeps line numbers); these
helpers turn a shape mismatch into an ``InputError`` naming file, line and key.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.guard import Place, number, shorten
from lbw_engine.yamlio import line_of


class Reader:
    """Checks values of one rule file and reports errors with its name and lines."""

    def __init__(self, file: str | Path) -> None:
        self.file = str(file)

    def fail(self, message: str, container: Any = None, key: Any = None, where: str | None = None):
        """Raise an InputError at the line of ``container[key]``."""
        raise InputError(message, file=self.file, line=line_of(container, key), where=where)

    def mapping(self, value: Any, what: str, container: Any = None, key: Any = None) -> dict:
        """``value`` must be a mapping."""
        if not isinstance(value, dict):
            self.fail(f"{what} must be a mapping", container, key)
        return value

    def sequence(self, value: Any, what: str, container: Any = None, key: Any = None) -> list:
        """``value`` must be a list."""
        if not isinstance(value, list):
            self.fail(f"{what} must be a list", container, key)
        return value

    def keys(
        self, data: dict, what: str, required: tuple[str, ...] = (), optional: tuple[str, ...] = ()
    ) -> None:
        """``data`` has all ``required`` keys and no key outside required + optional."""
        allowed = set(required) | set(optional)
        for key in data:
            if key not in allowed:
                names = listing(sorted(allowed)) or "none"
                self.fail(f"unknown key {shorten(key)} in {what} (allowed: {names})", data, key)
        for key in required:
            if key not in data:
                self.fail(f"{what} lacks the required key {key!r}", data)

    def name(self, data: dict | list, key: str | int, what: str) -> str:
        """``data[key]`` (a mapping's key or a list's index) must be a non-empty string."""
        value = _get(data, key)
        if value is True:
            self.fail(f"{what} {key!r} reads as a boolean; quote the name", data, key)
        if not isinstance(value, str) or not value:
            self.fail(f"{what} {key!r} must be a name, got {shorten(value)}", data, key)
        return value

    def number(self, data: dict | list, key: str | int, what: str, low: float | None = None,
               high: float | None = None, *, above: bool = False, unit: str = "") -> float:
        """``data[key]`` must be a finite number, within [low, high] when given."""
        place = Place(self.file, line_of(data, key), f"{what} {key!r}")
        return number(_get(data, key), place, low, high, above=above, unit=unit)

    def one_of(self, value: Any, allowed: Any, what: str, container: Any, key: Any) -> Any:
        """``value`` must be in ``allowed`` (a collection of names)."""
        if isinstance(value, (dict, list)) or value not in allowed:  # lists are unhashable
            names = listing(sorted(str(a) for a in allowed))
            self.fail(f"{what} {shorten(value)} does not exist (known: {names})", container, key)
        return value


def _get(data: dict | list, key: Any) -> Any:
    """``data[key]`` of a mapping or a list; None when absent."""
    if isinstance(data, list):
        return data[key] if isinstance(key, int) and 0 <= key < len(data) else None
    return data.get(key)


def listing(items: Any, sep: str = ", ") -> str:
    """Names separated by ``sep`` (for messages)."""
    out = ""
    for index, item in enumerate(items):
        out += (sep if index else "") + str(item)
    return out
