"""The command line's help: one metavar style, exit codes under every command, --version."""

import argparse
import importlib.metadata
import re

import pytest

from lbw_engine.cli import SUBCOMMANDS, _available, build_parser, main

# Values are named in capitals by their kind (SCENARIO, PLAN.json, DIR, FILE, N, ADDRESS).
METAVAR = re.compile(r"^[A-Z][A-Z_]*(\.json)?$")


def subparsers():
    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return sub.choices


COMMANDS = sorted(_available())


def test_every_registered_command_is_there():
    assert set(COMMANDS) == set(SUBCOMMANDS)


@pytest.mark.parametrize("command", COMMANDS)
def test_metavars_are_one_style(command):
    for action in subparsers()[command]._actions:
        if action.nargs == 0 or isinstance(action, argparse._HelpAction):
            continue  # flags take no value
        shown = action.metavar or (action.dest if not action.option_strings else None)
        assert shown is not None and METAVAR.match(shown), \
            f"lbw {command} {'/'.join(action.option_strings) or action.dest}: metavar {shown!r}"


@pytest.mark.parametrize("command", COMMANDS)
def test_help_states_the_exit_codes(command, capsys):
    module = _available()[command]
    assert isinstance(getattr(module, "EXIT_CODES", None), str), f"{command} has no EXIT_CODES"
    with pytest.raises(SystemExit) as done:
        main([command, "--help"])
    assert done.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert re.search(r"exit codes: 0 [^;]+; (1 [^;]+; )?2 [^;]+; 3 internal error$", text), text


def test_version(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out == f"lbw {importlib.metadata.version('lbw')}\n"
