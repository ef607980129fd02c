"""OutputDir publishes all files or none."""

import pytest

from lbw_engine.errors import InputError
from lbw_engine.outputs import OutputDir, atomic_write_text


def test_files_published_on_success(tmp_path):
    with OutputDir(tmp_path / "out") as out:
        out.write_json("a.json", {"x": 1})
        out.write_text("b.txt", "hello\n")
        assert not (tmp_path / "out" / "a.json").exists()  # still staged
    assert (tmp_path / "out" / "a.json").read_text() == '{\n "x": 1\n}\n'
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["a.json", "b.txt"]


def test_nothing_published_on_error(tmp_path):
    dest = tmp_path / "out"
    dest.mkdir()
    (dest / "a.json").write_text("old")
    with pytest.raises(InputError):
        with OutputDir(dest) as out:
            out.write_json("a.json", {"x": 1})
            raise InputError("bad")
    assert (dest / "a.json").read_text() == "old"
    assert [p.name for p in dest.iterdir()] == ["a.json"]


def test_atomic_write_replaces(tmp_path):
    target = tmp_path / "f.txt"
    atomic_write_text(target, "one")
    atomic_write_text(target, "two")
    assert target.read_text() == "two"
    assert [p.name for p in tmp_path.iterdir()] == ["f.txt"]
