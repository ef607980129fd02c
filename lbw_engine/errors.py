"""Errors users see: one sentence naming the file, the place and what is wrong."""

from __future__ import annotations

from pathlib import Path


class LbwError(Exception):
    """Base class of errors reported to the user without a traceback."""

    exit_code = 2


class InputError(LbwError):
    """Bad input (a file, a rule, a scenario, a trace): exit code 2.

    ``where`` is a key path such as ``teach.demonstration[3].on`` or a row id;
    ``line`` is 1-based when known.
    """

    exit_code = 2

    def __init__(
        self,
        message: str,
        file: str | Path | None = None,
        line: int | None = None,
        where: str | None = None,
    ) -> None:
        self.message = message
        self.file = str(file) if file is not None else None
        self.line = line
        self.where = where
        super().__init__(str(self))

    def __str__(self) -> str:
        place = ""
        if self.file:
            place = self.file + (f":{self.line}" if self.line else "")
        if self.where:
            place = f"{place}: {self.where}" if place else self.where
        return f"{place}: {self.message}" if place else self.message


class TaskFailed(LbwError):
    """The task failed (recognition or execution did not verify): exit code 1."""

    exit_code = 1


def read_input(path: str | Path, noun: str = "file", expected: str = "a file") -> str:
    """The text of an input file; any failure to read it is one InputError naming it."""
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{noun} not found", file=path) from None
    except IsADirectoryError:
        raise InputError(f"is a directory, expected {expected}", file=path) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {noun} ({exc.__class__.__name__})", file=path) from None
