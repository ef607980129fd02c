"""Output files that are never half written, and output folders replaced as a whole.

Every command writes its files through ``OutputDir``. The files go to a hidden
staging folder beside the destination; only when the whole command succeeded
is the destination swapped for it (old folder renamed away, new one renamed
in, old one deleted). So a failed run leaves the destination as it was, and a
run never leaves another run's files beside its own.

Deleting a folder needs care, so lbw only replaces a folder it wrote itself:
each output folder holds a marker file (``MARKER``). A non-empty folder without
it is refused before any work is done (exit 2), as is ``--out`` naming a file.

A command may read its input from the folder it writes (``lbw analyze
out/actions.json`` writes out/plan.json): such inputs, and the files of the
earlier phases it continues (``keep``), are carried into the new folder.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import uuid
from collections.abc import Iterable
from pathlib import Path
from types import TracebackType
from typing import Any

from lbw_engine.errors import InputError

MARKER = ".lbw-output"
MARKER_TEXT = ("This folder was written by lbw. The next lbw command writing into it replaces "
               "it as a whole;\nlbw refuses to replace a non-empty folder without this file.\n")


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


def replaceable(dest: Path, flag: str = "--out") -> None:
    """Exit 2 unless ``dest`` is missing, an empty folder or a folder lbw wrote."""
    if dest.is_symlink():
        raise InputError("is a symbolic link; give the folder itself", file=dest, where=flag)
    if dest.exists() and not dest.is_dir():
        raise InputError("names a file; give a folder (lbw writes its files into it)",
                         file=dest, where=flag)
    if Path.cwd().resolve().is_relative_to(dest.resolve()):
        raise InputError("is the current folder or holds it; lbw replaces its output folder "
                         "as a whole, so give a folder below the current one", file=dest,
                         where=flag)
    if dest.is_dir() and not (dest / MARKER).is_file() and any(dest.iterdir()):
        raise InputError(f"is a folder that lbw did not write (it has no {MARKER}); lbw "
                         "replaces its output folder as a whole, so give a new or empty one",
                         file=dest, where=flag)


class OutputDir:
    """Stage a command's output files; on success the destination becomes exactly them.

    ``inputs``: files the command read; those directly inside ``dest`` are carried
    over (one deeper is refused: the folder is replaced). ``keep``: names of files of
    ``dest`` the command continues from (earlier phases), carried over if present.
    """

    def __init__(self, dest: str | Path, inputs: Iterable[str | Path] = (),
                 keep: Iterable[str] = (), flag: str = "--out") -> None:
        self.dest = Path(dest)
        self.flag = flag
        self._staging: Path | None = None
        self._carry = self._carried(inputs, keep)

    def _carried(self, inputs: Iterable[str | Path], keep: Iterable[str]) -> list[Path]:
        """Existing files of ``dest`` to carry into the new folder."""
        home = self.dest.resolve()
        carry = [home / name for name in keep]
        for item in map(Path, inputs):
            where = item.resolve()
            if where.parent == home and where.is_file():
                carry.append(where)
            elif where.is_relative_to(home):
                raise InputError(f"the input {item} lies inside this output folder, which is "
                                 "replaced as a whole; give another folder", file=self.dest,
                                 where=self.flag)
        return [p for p in carry if p.is_file()]

    def __enter__(self) -> OutputDir:
        replaceable(self.dest, self.flag)
        parent = self.dest.absolute().parent
        staging = parent / f".{self.dest.name}.lbw-staging-{uuid.uuid4().hex[:12]}"
        try:
            parent.mkdir(parents=True, exist_ok=True)
            staging.mkdir()  # not mkdtemp: the published folder gets the usual permissions
            self._staging = staging
        except OSError as exc:
            raise InputError(f"cannot create the output folder here ({exc.strerror})",
                             file=self.dest, where=self.flag) from None
        (self._staging / MARKER).write_text(MARKER_TEXT, encoding="utf-8")
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
                replaceable(self.dest, self.flag)  # again: it may have changed meanwhile
                for src in self._carry:
                    if not (staging / src.name).exists():
                        _link_or_copy(src, staging / src.name)
                _swap(staging, self.dest)
        finally:
            shutil.rmtree(staging, ignore_errors=True)


def _link_or_copy(src: Path, dst: Path) -> None:
    """A hard link where the file system allows one (no bytes copied), else a copy."""
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _swap(staging: Path, dest: Path) -> None:
    """Put ``staging`` in the place of ``dest``: rename old away, rename new in, delete old."""
    old = None
    if dest.exists():
        old = dest.with_name(f".{dest.name}.lbw-old-{uuid.uuid4().hex[:12]}")
        os.rename(dest, old)
    try:
        os.rename(staging, dest)
    except OSError:
        if old is not None:
            os.rename(old, dest)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
