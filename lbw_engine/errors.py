"""Errors users see: one sentence naming the file, the place and what is wrong."""

from __future__ import annotations

import re
from pathlib import Path

MAX_MESSAGE = 400  # characters of an error message, place not included
_LINE_BREAKS = re.compile("[\n\r\v\f\x1c-\x1e\x85\u2028\u2029]+")  # str.splitlines' set


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
        # The last guard on length: values are shortened where they are printed
        # (guard.shorten); a message built from many long names is cut here.
        if len(message) > MAX_MESSAGE:
            message = message[: MAX_MESSAGE - 41] + "…" + message[-40:]
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
        text = f"{place}: {self.message}" if place else self.message
        # One line on the terminal, whatever a message or a file name holds.
        return _LINE_BREAKS.sub(" ", text)


class TaskFailed(LbwError):
    """The task failed (recognition or execution did not verify): exit code 1."""

    exit_code = 1
