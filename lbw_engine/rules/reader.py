"""The one checker every rule file is read with: typed getters, file:line messages.

Rule files are plain YAML read by ``yamlio`` (which keeps line numbers); a
``Reader`` turns a shape mismatch into an ``InputError`` naming the file, the
line and, where given, the key path (``gripper.finger[1]``). Every rule file
(recognition, analysis, commands) is parsed through this class, so a kind of
mistake reads the same wherever it is made.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, NoReturn

from lbw_engine.errors import InputError
from lbw_engine.guard import Place, number, shorten
from lbw_engine.yamlio import line_of, load_file


def listing(items: Any, sep: str = ", ") -> str:
    """Names separated by ``sep`` (for messages)."""
    return sep.join(str(item) for item in items)


def _path(where: str | None, key: Any) -> str | None:
    """``where`` extended by ``key`` (``a.b`` or ``a[3]``), None when both are unknown."""
    if key is None:
        return where or None
    if isinstance(key, int):
        return f"{where or ''}[{key}]"
    return f"{where}.{key}" if where else str(key)


class Reader:
    """Checks values of one rule file and reports errors with its name and lines."""

    def __init__(self, file: str | Path) -> None:
        """A reader for ``file`` (the name used in messages)."""
        self.file = str(file)

    @classmethod
    def load(cls, path: Path, required: tuple[str, ...] = (),
             optional: tuple[str, ...] = ()) -> tuple[Reader, dict]:
        """Read a YAML rule file whose top level is a mapping with these keys."""
        reader = cls(path)
        data = reader.mapping(load_file(path), "the file")
        reader.keys(data, "the file", required, optional)
        return reader, data

    # -- failing ---------------------------------------------------------------------
    def error(self, message: str, container: Any = None, key: Any = None,
              where: str | None = None) -> InputError:
        """An InputError at the line of ``container[key]``."""
        return InputError(message, file=self.file, line=line_of(container, key), where=where)

    def fail(self, message: str, container: Any = None, key: Any = None,
             where: str | None = None) -> NoReturn:
        """Raise an InputError at the line of ``container[key]``."""
        raise self.error(message, container, key, where)

    # -- shapes -------------------------------------------------------------------------
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

    def keys(self, data: dict, what: str, required: tuple[str, ...] = (),
             optional: tuple[str, ...] = (), where: str | None = None) -> None:
        """``data`` has all ``required`` keys and no key outside required + optional."""
        allowed = set(required) | set(optional)
        for key in data:
            if key not in allowed:
                names = listing(sorted(allowed)) or "none"
                self.fail(f"unknown key {shorten(key)} in {what} (allowed: {names})", data, key,
                          _path(where, key) if where else None)
        for key in required:
            if key not in data:
                self.fail(f"{what} lacks the required key {key!r}", data, None, where)

    # -- values -------------------------------------------------------------------------
    def name(self, data: dict | list, key: str | int, what: str) -> str:
        """``data[key]`` (a mapping's key or a list's index) must be a non-empty string."""
        value = _get(data, key)
        if value is True:
            self.fail(f"{what} {key!r} reads as a boolean; quote the name", data, key)
        if not isinstance(value, str) or not value:
            self.fail(f"{what} {key!r} must be a name, got {shorten(value)}", data, key)
        return value

    def names(self, data: Any, key: Any, what: str, allowed: Any = None,
              where: str | None = None) -> tuple[str, ...]:
        """``data[key]`` must be a list of names, optionally from a closed set."""
        value = data[key]
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            self.fail(f"{what} must be a list of names", data, key, where)
        for i, item in enumerate(value):
            if allowed is not None and item not in allowed:
                self.fail(f"unknown name {shorten(item)} (allowed: {listing(allowed)})", value, i,
                          _path(where, i) if where else None)
        return tuple(value)

    def number(self, data: Any, key: Any, what: str, low: float | None = None,
               high: float | None = None, where: str | None = None, *, above: bool = False,
               unit: str = "") -> float:
        """``data[key]`` must be a finite number, within [low, high] where given."""
        place = Place(self.file, line_of(data, key), where or what)
        return number(_get(data, key), place, low, high, above=above, unit=unit)

    def vector(self, data: Any, key: Any, n: int, what: str, low: float | None = None,
               high: float | None = None, where: str | None = None) -> tuple[float, ...]:
        """``data[key]`` must be a list of ``n`` numbers (each within [low, high])."""
        value = data[key]
        if not isinstance(value, list) or len(value) != n:
            self.fail(f"{what} must be a list of {n} numbers", data, key, where)
        return tuple(self.number(value, i, f"{what}[{i}]", low, high, _path(where or what, i))
                     for i in range(n))

    def boolean(self, data: dict, key: str, what: str, default: bool) -> bool:
        """``data[key]`` must be true or false (``default`` when absent)."""
        value = data.get(key, default)
        if not isinstance(value, bool):
            self.fail(f"{what} must be true or false", data, key)
        return value

    def one_of(self, value: Any, allowed: Any, what: str, container: Any, key: Any) -> Any:
        """``value`` must be in ``allowed`` (a collection of names)."""
        if isinstance(value, list | dict) or value not in allowed:
            names = listing(sorted(str(a) for a in allowed))
            self.fail(f"{what} {shorten(value)} does not exist (known: {names})", container, key)
        return value


def _get(data: Any, key: Any) -> Any:
    """``data[key]`` of a mapping or a list; None when absent."""
    if isinstance(data, list):
        return data[key] if isinstance(key, int) and 0 <= key < len(data) else None
    return data.get(key) if isinstance(data, dict) else None
