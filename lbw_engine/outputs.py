"""Output files that are never half written.

Every command writes its files through ``OutputDir``: files go to a hidden
staging folder inside the destination and are renamed into place only when the
whole command succeeded. On an error the staging folder is removed, so a
failed run leaves the destination as it was.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from types import TracebackType
from typing import Any


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` via a temporary file and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def to_json(data: Any) -> str:
    """The project's JSON style: indented, UTF-8, newline at the end."""
    return json.dumps(data, indent=1, ensure_ascii=False) + "\n"


class OutputDir:
    """Stage a command's output files; publish them all only on success."""

    def __init__(self, dest: str | Path) -> None:
        self.dest = Path(dest)
        self._staging: Path | None = None

    def __enter__(self) -> OutputDir:
        try:
            self.dest.mkdir(parents=True, exist_ok=True)
            self._staging = Path(tempfile.mkdtemp(prefix=".lbw-staging-", dir=self.dest))
        except OSError as exc:  # --out names a file, or a folder lbw may not write to
            from lbw_engine.errors import InputError

            what = "is a file" if self.dest.is_file() else \
                f"cannot be made ({(exc.strerror or exc.__class__.__name__).lower()})"
            raise InputError(f"the output folder {what}; expected a folder lbw can write to",
                             file=self.dest) from None
        return self

    def path(self, name: str) -> Path:
        """Where to write ``name`` while staging (e.g. for cv2.VideoWriter)."""
        assert self._staging is not None, "OutputDir used outside its with-block"
        return self._staging / name

    def write_text(self, name: str, text: str) -> Path:
        """Stage a text file."""
        target = self.path(name)
        target.write_text(text, encoding="utf-8")
        return self.dest / name

    def write_json(self, name: str, data: Any) -> Path:
        """Stage a JSON file in the project's style."""
        return self.write_text(name, to_json(data))

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        staging, self._staging = self._staging, None
        if staging is None:
            return
        try:
            if exc_type is None:
                for item in sorted(staging.iterdir()):
                    os.replace(item, self.dest / item.name)
        finally:
            shutil.rmtree(staging, ignore_errors=True)
