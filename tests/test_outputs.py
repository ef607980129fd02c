"""OutputDir publishes all files or none, and replaces an output folder as a whole."""

import os

import pytest

from lbw_engine.cli import main
from lbw_engine.errors import InputError
from lbw_engine.outputs import MARKER, OutputDir, atomic_write_text


def names(folder):
    return sorted(p.name for p in folder.iterdir())


def write(folder, files):
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (folder / name).write_text(text)


def test_files_published_on_success(tmp_path):
    with OutputDir(tmp_path / "out") as out:
        out.write_json("a.json", {"x": 1})
        out.write_text("b.txt", "hello\n")
        assert not (tmp_path / "out").exists()  # still staged beside it
    assert (tmp_path / "out" / "a.json").read_text() == '{\n "x": 1\n}\n'
    assert names(tmp_path / "out") == [MARKER, "a.json", "b.txt"]
    assert names(tmp_path) == ["out"]  # no staging or old folder left behind
    assert oct((tmp_path / "out").stat().st_mode & 0o777) == oct(0o777 & ~_umask())


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


# (what is at --out before, files there) -> files after a run writing new.json
REPLACE = [
    ("missing", None, [MARKER, "new.json"]),
    ("empty folder", {}, [MARKER, "new.json"]),
    ("an earlier run's folder", {MARKER: "", "old.json": "", "report.html": ""},
     [MARKER, "new.json"]),
]


@pytest.mark.parametrize("before,files,after", REPLACE, ids=[r[0] for r in REPLACE])
def test_a_run_replaces_the_folder_as_a_whole(tmp_path, before, files, after):
    dest = tmp_path / "out"
    if files is not None:
        write(dest, files)
    with OutputDir(dest) as out:
        out.write_json("new.json", {})
    assert names(dest) == after
    assert names(tmp_path) == ["out"]


# (what is at --out) -> the one-line error; nothing is changed
REFUSE = [
    ("a file", lambda p: p.write_text("keep me"), "names a file; give a folder"),
    ("a folder lbw did not write", lambda p: write(p, {"thesis.tex": "keep me"}),
     f"is a folder that lbw did not write (it has no {MARKER})"),
    ("a symbolic link", lambda p: p.symlink_to(p.parent), "is a symbolic link"),
]


@pytest.mark.parametrize("what,make,message", REFUSE, ids=[r[0] for r in REFUSE])
def test_refused_before_any_work(tmp_path, what, make, message):
    dest = tmp_path / "out"
    make(dest)
    before = sorted(str(p) for p in tmp_path.rglob("*"))
    with pytest.raises(InputError, match="--out: " + message.replace("(", r"\(")
                       .replace(")", r"\)")):
        OutputDir(dest).__enter__()
    assert sorted(str(p) for p in tmp_path.rglob("*")) == before


def test_refuses_the_current_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(InputError, match="is the current folder or holds it"):
        OutputDir(".").__enter__()
    with pytest.raises(InputError, match="is the current folder or holds it"):
        OutputDir(tmp_path.parent).__enter__()


def test_nothing_published_on_error(tmp_path):
    dest = tmp_path / "out"
    write(dest, {MARKER: "", "a.json": "old"})
    with pytest.raises(InputError):
        with OutputDir(dest) as out:
            out.write_json("a.json", {"x": 1})
            raise InputError("bad")
    assert (dest / "a.json").read_text() == "old"
    assert names(dest) == [MARKER, "a.json"] and names(tmp_path) == ["out"]


def test_inputs_and_earlier_phases_inside_the_folder_are_carried(tmp_path):
    dest = tmp_path / "out"
    write(dest, {MARKER: "", "actions.json": "A", "plan.json": "P", "plan.txt": "T",
                 "execution.json": "stale", "report.html": "stale"})
    with OutputDir(dest, inputs=[dest / "plan.json", tmp_path / "elsewhere.yaml"],
                   keep=["actions.json", "plan.txt", "absent.json"]) as out:
        out.write_json("execution.json", {"new": True})
    assert names(dest) == [MARKER, "actions.json", "execution.json", "plan.json", "plan.txt"]
    assert (dest / "plan.json").read_text() == "P"
    assert (dest / "execution.json").read_text() == '{\n "new": true\n}\n'


def test_an_input_deeper_inside_the_folder_is_refused(tmp_path):
    dest = tmp_path / "out"
    write(dest / "sub", {"scenario.yaml": ""})
    (dest / MARKER).write_text("")
    with pytest.raises(InputError, match="lies inside this output folder"):
        OutputDir(dest, inputs=[dest / "sub" / "scenario.yaml"])


CLI_REFUSALS = [
    (["analyze", "ACTIONS", "--out", "FILE"], "FILE: --out: names a file; give a folder"),
    (["recognize", "TRACE", "--out", "FILE"], "FILE: --out: names a file; give a folder"),
    (["analyze", "ACTIONS", "--out", "FOREIGN"], "FOREIGN: --out: is a folder that lbw did not"),
]


@pytest.mark.parametrize("argv,message", CLI_REFUSALS, ids=["analyze-file", "recognize-file",
                                                             "analyze-foreign-folder"])
def test_cli_out_refusals_are_exit_2_with_one_line(tmp_path, capsys, argv, message):
    data = os.path.join(os.path.dirname(__file__), "data")
    (tmp_path / "FILE").write_text("mine")
    write(tmp_path / "FOREIGN", {"notes.txt": "mine"})
    subst = {"ACTIONS": os.path.join(data, "fig20-build-table.actions.json"),
             "TRACE": os.path.join(data, "traces", "fig20-build-table.jsonl"),
             "FILE": str(tmp_path / "FILE"), "FOREIGN": str(tmp_path / "FOREIGN")}
    assert main([subst.get(a, a) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert message.replace("FILE", str(tmp_path / "FILE")).replace(
        "FOREIGN", str(tmp_path / "FOREIGN")) in err
    assert (tmp_path / "FILE").read_text() == "mine"
    assert names(tmp_path / "FOREIGN") == ["notes.txt"]


def test_atomic_write_replaces(tmp_path):
    target = tmp_path / "f.txt"
    atomic_write_text(target, "one")
    atomic_write_text(target, "two")
    assert target.read_text() == "two"
    assert [p.name for p in tmp_path.iterdir()] == ["f.txt"]
