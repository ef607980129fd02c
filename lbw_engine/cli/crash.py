"""The last resort: an unexpected exception is an internal error (exit 3), not bad input.

design.md: exit 3 prints one line saying where the details were written and
never a traceback on the terminal. The details (command line, versions,
traceback) go to a crash file beside the output folder (--out's parent, when it
exists) or else in the temporary folder. Output files are already safe: every
command writes through ``OutputDir``, which removes its staging folder when an
exception passes through it.
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
import time
import traceback
from collections.abc import Sequence
from pathlib import Path

EXIT_INTERNAL = 3


def _folders(out: str | None) -> list[Path]:
    """Where a crash file may go, in order of preference."""
    places = []
    if out:
        parent = Path(out).absolute().parent
        if parent.is_dir():
            places.append(parent)
    places.append(Path(tempfile.gettempdir()))
    return places


def _details(command: str, argv: Sequence[str], exc: BaseException) -> str:
    """The crash file's text: what ran, on what, and the traceback."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        lbw_version = version("lbw")
    except PackageNotFoundError:
        lbw_version = "unknown"
    lines = [
        f"lbw {command}: internal error",
        f"command line: lbw {' '.join(argv)}",
        f"lbw {lbw_version}, Python {platform.python_version()} on {platform.platform()}",
        f"time: {time.strftime('%Y-%m-%d %H:%M:%S')}",
        "",
        *traceback.format_exception(type(exc), exc, exc.__traceback__),
    ]
    return "\n".join(line.rstrip("\n") for line in lines) + "\n"


def write_crash_file(command: str, argv: Sequence[str], out: str | None,
                     exc: BaseException) -> Path | None:
    """Write the details to a new crash file; None if no folder would take it."""
    text = _details(command, argv, exc)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for folder in _folders(out):
        try:
            fd, name = tempfile.mkstemp(prefix=f"lbw-crash-{command}-{stamp}-", suffix=".txt",
                                        dir=folder)
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text)
            return Path(name)
        except OSError:
            continue
    return None


def report(command: str, argv: Sequence[str], out: str | None, exc: BaseException) -> int:
    """Write the crash file, print the one line, and return exit code 3."""
    path = write_crash_file(command, argv, out, exc)
    where = f"details in {path}" if path else "the details could not be written"
    print(f"lbw {command}: internal error ({exc.__class__.__name__}), a bug in lbw, not in "
          f"your input; {where}", file=sys.stderr)
    return EXIT_INTERNAL
