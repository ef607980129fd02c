"""The ``lbw`` command line.

Each subcommand is a module in this package with ``HELP`` (one line),
``EXIT_CODES`` (what each exit code means for it; shown under its --help),
``add_arguments(parser)`` and ``run(args) -> int``. Help texts name values in
capitals by their kind: SCENARIO, PLAN.json, ACTIONS.json, TRACE, DIR, FILE, N,
ADDRESS. ``SUBCOMMANDS`` is the
closed registry; modules are imported only when their command runs, so
``lbw check`` never loads the simulator.

Exit codes (design.md): 0 success, 1 the task failed, 2 bad input, 3 an
internal error. Errors derived from ``LbwError`` print one sentence and no
traceback; any other exception is a bug, reported in one line naming the crash
file that holds its traceback (``crash.py``). A command that
fails its task returns 1 *after* its output files are published; bad input
raises ``InputError`` inside ``OutputDir`` so nothing half-written is left.

This package is the only part of lbw_engine allowed to import ``perception``.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.metadata
import sys
from collections.abc import Sequence

from lbw_engine.errors import LbwError

# name -> module (relative to this package). Keep sorted by pipeline order.
SUBCOMMANDS: dict[str, str] = {
    "check": "check",
    "recognize": "recognize",
    "render": "render",
    "watch": "watch",
    "analyze": "analyze",
    "execute": "execute",
    "export": "export",
    "run": "run",
    "demo": "demo",
    "bench": "bench",
}

EXIT_CODES = ("exit codes: 0 success; 1 the task failed (recognition or execution did not "
              "verify); 2 bad input (one line naming the file and the place); 3 an internal "
              "error (one line naming the crash file with the details)")


def _available() -> dict[str, object]:
    """Import the registered subcommand modules that exist in this checkout."""
    found: dict[str, object] = {}
    for name, module in SUBCOMMANDS.items():
        try:
            found[name] = importlib.import_module(f"{__name__}.{module}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{module}":
                raise
    return found


def version() -> str:
    """The installed distribution's version (pyproject.toml)."""
    try:
        return importlib.metadata.version("lbw")
    except importlib.metadata.PackageNotFoundError:  # run from a source tree, not installed
        return "unknown (not installed)"


def build_parser() -> argparse.ArgumentParser:
    """The argparse tree of all available subcommands."""
    parser = argparse.ArgumentParser(
        prog="lbw", description="Learning by watching: see, understand and do a block assembly.",
        epilog=EXIT_CODES,
    )
    parser.add_argument("--version", action="version", version=f"lbw {version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, module in _available().items():
        # A command's own EXIT_CODES say what each code means for it (its --help).
        codes = getattr(module, "EXIT_CODES", None)
        p = sub.add_parser(name, help=module.HELP, description=module.HELP,
                           epilog=f"exit codes: {codes}" if codes else EXIT_CODES)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``lbw`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code = args._run(args)
    except LbwError as exc:
        print(f"lbw {args.command}: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # the last resort (design.md exit 3): never a traceback
        from lbw_engine.cli import crash

        given = list(argv) if argv is not None else sys.argv[1:]
        return crash.report(args.command, given, getattr(args, "out", None), exc)
    return int(code or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
