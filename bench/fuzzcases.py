"""Fuzz cases: a mutated input, the real ``lbw`` entry point run in-process, the verdict.

One case per call of ``run_case(kind, rng)``. Kinds and what runs:

| kind | input mutated | command |
|---|---|---|
| rules | a rule file in a copy of rules/ | ``lbw check``, ``analyze`` (``simulate``: ``run``) |
| scenario | a bundled scenario | ``lbw watch``, stopped after the loader unless ``simulate`` |
| actions | a recorded actions.json | ``lbw analyze`` |
| plan | a learned plan.json (with its scenario) | ``lbw execute``, same |
| trace | a recorded event trace (JSON lines) | ``lbw recognize`` |

``lbw analyze`` (and with ``simulate``, ``lbw run``) runs on the mutated rules when
``lbw check`` accepted them;
``lbw watch`` and ``lbw execute`` simulate only when ``simulate`` is asked for.
Now and then the command line itself is broken instead (input path missing or a
folder, ``--out`` naming a file). Each run must end with exit 0, 1 or 2 (never
3, an internal error), print no traceback, print exactly one line on stderr
when it rejects its input (2), and leave nothing behind: no new file after a
rejection, no staging folder or temporary file ever.
"""

from __future__ import annotations

import contextlib
import io
import shutil
import signal
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from unittest import mock

from bench import mutators

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "rules"
DATA = ROOT / "tests" / "data"
SCENARIOS = tuple(sorted((ROOT / "scenarios").glob("*.yaml")))
ACTIONS = (DATA / "fig20-build-table.actions.json", DATA / "fig12-inverted-arch.actions.json")
PLANS = ((DATA / "build-table.plan.json", ROOT / "scenarios" / "build-table.yaml"),
         (DATA / "inverted-arch.plan.json", ROOT / "scenarios" / "inverted-arch.yaml"))
TRACES = (ROOT / "lbw_engine" / "data" / "build-table.trace.jsonl",)
RUN_SCENARIO = ROOT / "scenarios" / "unstack.yaml"  # the fewest operations: a short lbw run
KINDS = ("rules", "scenario", "actions", "plan", "trace")
RULE_FILES = tuple(sorted(p.name for p in RULES.iterdir() if p.suffix in (".yaml", ".lark")))
CASE_SECONDS = 120  # a case still running after this is counted as hung


class _Hung(BaseException):
    """A case ran past CASE_SECONDS (BaseException: the CLI's last resort lets it pass)."""


@dataclass
class Run:
    """One ``lbw`` command of a case and what it did."""

    argv: list[str]
    code: int
    stderr: str
    seconds: float
    escaped: str = ""  # an exception that escaped main() (never expected)

    @property
    def traceback(self) -> bool:
        return bool(self.escaped) or "Traceback (most recent call last)" in self.stderr

    @property
    def internal(self) -> bool:
        return self.code == 3 or bool(self.escaped)

    @property
    def multiline(self) -> bool:
        """A rejection (exit 2) must be one line."""
        return self.code == 2 and len(self.stderr.splitlines()) != 1


@dataclass
class Outcome:
    """A case: what was mutated, the runs, and the invariants' verdict."""

    kind: str
    mutation: str
    runs: list[Run] = field(default_factory=list)
    leftovers: list[str] = field(default_factory=list)
    hung: bool = False

    @property
    def code(self) -> int:
        """The exit code that decides the case (the last run's)."""
        return self.runs[-1].code if self.runs else -1

    @property
    def ok(self) -> bool:
        bad = any(r.traceback or r.internal or r.multiline or r.code not in (0, 1, 2)
                  for r in self.runs)
        return not (bad or self.leftovers or self.hung)

    def summary(self) -> str:
        """What went wrong, for a test failure."""
        lines = [f"{self.kind} case ({self.mutation}): leftovers={self.leftovers} "
                 f"hung={self.hung}"]
        for r in self.runs:
            lines.append(f"  lbw {' '.join(r.argv)} -> {r.code} {r.escaped}\n"
                         f"  stderr: {r.stderr[:2000]}")
        return "\n".join(lines)


@contextlib.contextmanager
def _stubs(simulate: bool):
    """Stop ``lbw watch`` after the scenario loader, ``lbw execute`` before the world
    (unless ``simulate``: then both run in full)."""
    from lbw_engine.errors import TaskFailed

    def stop_watch(*args: Any, **kwargs: Any) -> Any:
        raise TaskFailed("fuzz: stopped after the scenario loader")

    class NoWorld:
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            raise TaskFailed("fuzz: stopped before the simulation")

    with contextlib.ExitStack() as stack:
        if not simulate:
            stack.enter_context(mock.patch("lbw_engine.cli.watch.watch", stop_watch))
            stack.enter_context(mock.patch("perception.world.physics.World", NoWorld))
        yield


def _on_alarm(signum: int, frame: Any) -> None:
    raise _Hung()


def run_lbw(argv: list[str], simulate: bool = False) -> Run:
    """``lbw_engine.cli.main(argv)`` in this process, stdout and stderr captured."""
    from lbw_engine.cli import main

    err, out = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    escaped = ""
    code = -1
    with _stubs(simulate), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main(argv)
        except _Hung:
            raise
        except SystemExit as exc:  # argparse
            code = exc.code if isinstance(exc.code, int) else 2
        except BaseException as exc:  # noqa: BLE001 - anything escaping main is a finding
            escaped = f"{exc.__class__.__name__}: {str(exc)[:200]}"
    return Run(list(argv), code, err.getvalue(), time.perf_counter() - start, escaped)


def _tree(folder: Path) -> set[str]:
    """Every path under ``folder``, relative."""
    return {p.relative_to(folder).as_posix() + ("/" if p.is_dir() else "")
            for p in folder.rglob("*")}


def _leftovers(folder: Path, before: set[str], runs: list[Run]) -> list[str]:
    """New files after a rejection; staging folders and temporary files at any time."""
    new = sorted(_tree(folder) - before)
    rejected = any(r.code not in (0, 1) for r in runs)
    return [p for p in new if ".lbw-staging-" in p or p.endswith(".tmp") or "lbw-crash-" in p
            or (rejected and not p.endswith("/"))]


# -- the inputs of each kind --------------------------------------------------


def _mutated(data: bytes, fmt: str, rng: Any) -> tuple[bytes, str]:
    """Tree mutations (1-3) on a parsed document, or one text mutation."""
    if fmt != "lark" and rng.random() < 0.6:
        doc = _parse(data, fmt)
        labels = []
        for _ in range(rng.choice((1, 1, 2, 3))):
            doc, label = mutators.mutate_tree(doc, rng)
            labels.append(label)
        return mutators.dump(doc, fmt, rng), "+".join(labels)
    out, label = mutators.mutate_text(data, rng, fmt)
    return out, label


def _parse(data: bytes, fmt: str) -> Any:
    """A base document, as the format's reader sees it."""
    import json

    from lbw_engine.yamlio import loads

    text = data.decode("utf-8")
    return json.loads(text) if fmt == "json" else loads(text)


def _setup(kind: str, rng: Any, case: Path,
           simulate: bool = False) -> tuple[list[list[str]], str]:
    """Write the case's mutated input under ``case``; return the commands and a label."""
    out = str(case / "out")
    if kind == "rules":
        rules = case / "rules"
        shutil.copytree(RULES, rules, ignore=shutil.ignore_patterns("__pycache__"))
        name = rng.choice(RULE_FILES)
        fmt = "lark" if name.endswith(".lark") else "yaml"
        target = rules / name
        if rng.random() < 0.05:
            target.unlink()
            if rng.random() < 0.5:
                target.mkdir()
            label = "removed"
        else:
            data, label = _mutated(target.read_bytes(), fmt, rng)
            target.write_bytes(data)
        analyze = ["analyze", str(ACTIONS[0]), "--rules", str(rules), "--out", out]
        # A rules folder that lbw check accepts must never crash lbw run (#15): with
        # --simulate the whole pipeline runs on the smallest bundled scenario too.
        run = ["run", str(RUN_SCENARIO), "--rules", str(rules), "--out", str(case / "run")]
        return [["check", str(rules)], analyze, *([run] if simulate else [])], f"{name}:{label}"
    if kind == "scenario":
        base = rng.choice(SCENARIOS)
        path = case / base.name
        data, label = _mutated(base.read_bytes(), "yaml", rng)
        path.write_bytes(data)
        return [["watch", str(path), "--out", out]], f"{base.stem}:{label}"
    if kind == "actions":
        base = rng.choice(ACTIONS)
        path = case / "actions.json"
        data, label = _mutated(base.read_bytes(), "json", rng)
        path.write_bytes(data)
        return [["analyze", str(path), "--out", out]], f"{base.stem}:{label}"
    if kind == "plan":
        base, scenario = rng.choice(PLANS)
        path = case / "plan.json"
        data, label = _mutated(base.read_bytes(), "json", rng)
        path.write_bytes(data)
        return [["execute", str(path), str(scenario), "--out", out]], f"{base.stem}:{label}"
    if kind == "trace":
        base = rng.choice(TRACES)
        lines = base.read_bytes().split(b"\n")
        row = rng.randrange(len(lines))
        if lines[row].strip().startswith(b"{") and rng.random() < 0.7:
            lines[row], label = _mutated(lines[row], "json", rng)
            lines[row] = lines[row].replace(b"\n", b" ")
        else:
            joined, label = mutators.mutate_text(b"\n".join(lines), rng, "json")
            lines = joined.split(b"\n")
        path = case / "trace.jsonl"
        path.write_bytes(b"\n".join(lines))
        return [["recognize", str(path), "--out", out]], f"{base.stem}:{label}"
    raise ValueError(f"unknown fuzz kind {kind!r} (kinds: {', '.join(KINDS)})")


def _break_paths(commands: list[list[str]], rng: Any, case: Path) -> str:
    """Break the first command's paths instead: a missing input, a folder, --out a file."""
    argv = commands[0]
    how = rng.choice(("missing", "folder", "out-file"))
    if how == "out-file" and "--out" in argv:
        blocker = case / "blocker"
        blocker.write_text("not a folder\n")
        argv[argv.index("--out") + 1] = str(blocker / "sub" if rng.random() < 0.5 else blocker)
    elif how == "folder":
        argv[1] = str(case)
    else:
        argv[1] = str(case / "missing.file")
    del commands[1:]
    return f"path:{how}"


def run_case(kind: str, rng: Any, simulate: bool = False) -> Outcome:
    """One fuzz case of ``kind`` in a fresh temporary folder."""
    with tempfile.TemporaryDirectory(prefix=f"lbw-fuzz-{kind}-") as tmp:
        case = Path(tmp)
        commands, label = _setup(kind, rng, case, simulate)
        if rng.random() < 0.04:
            label = _break_paths(commands, rng, case)
        outcome = Outcome(kind, label)
        before = _tree(case)
        old = signal.signal(signal.SIGALRM, _on_alarm)
        signal.alarm(CASE_SECONDS * (5 if simulate else 1))
        try:
            for argv in commands:
                run = run_lbw(argv, simulate)
                outcome.runs.append(run)
                if run.code != 0 and argv is commands[0]:
                    break  # the input was refused; later commands would read it too
        except _Hung:
            outcome.hung = True
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, old)
        outcome.leftovers = _leftovers(case, before, outcome.runs)
        return outcome
