"""The line-aware safe YAML loader shared by rule files and scenarios."""

import pytest

from lbw_engine.errors import InputError
from lbw_engine.yamlio import line_of, load_file, loads

BOOLEAN_CASES = [
    # (yaml text, expected value of key "v") - YAML 1.1 words stay strings
    ("v: on", "on"),
    ("v: off", "off"),
    ("v: yes", "yes"),
    ("v: no", "no"),
    ("v: true", True),
    ("v: False", False),
    ("v: 3", 3),
    ("v: 2.5", 2.5),
]


@pytest.mark.parametrize("text,expected", BOOLEAN_CASES, ids=[c[0] for c in BOOLEAN_CASES])
def test_booleans_are_only_true_and_false(text, expected):
    assert loads(text)["v"] == expected


def test_bare_on_key_is_a_string():
    data = loads("- place: brick1\n  on: table\n")
    assert data[0]["on"] == "table"


def test_lines_are_remembered():
    data = loads("a: 1\nb:\n  - x\n  - y: 2\n")
    assert line_of(data, "a") == 1
    assert line_of(data, "b") == 2
    assert line_of(data["b"], 1) == 4
    assert line_of(data["b"][1], "y") == 4


ERROR_CASES = [
    # (yaml text, expected line, fragment of the message)
    ("a: 1\na: 2\n", 2, "duplicate key"),
    ("a: [1, 2\n", 1, "invalid YAML"),
    ("a: !!python/object:os.system x\n", 1, "invalid YAML"),
    # an unclosed bracket or quote names the line it opened on, not the end of the file
    ("a: 1\nb: {c: [1, 2]\n\n\n", 2, "the flow mapping begun here is not closed"),
    ("a: 1\nb: 'abc\n\nc: 3\n", 2, "the quoted scalar begun here is not closed"),
    # a value refused while loading names its key path
    ("a:\n  b: [1, .nan]\n", 2, "a.b[1]: .nan is not a finite number"),
    ("a:\n  - {c: !!binary abc}\n", 2, "a[0].c: the tag !!binary is not allowed"),
]


@pytest.mark.parametrize(
    "text,line,fragment", ERROR_CASES, ids=["duplicate", "syntax", "unsafe-tag",
                                            "unclosed-bracket", "unclosed-quote",
                                            "nan-key-path", "tag-key-path"]
)
def test_errors_name_file_and_line(text, line, fragment):
    with pytest.raises(InputError) as info:
        loads(text, file="x.yaml")
    assert info.value.file == "x.yaml"
    assert info.value.line == line
    assert fragment in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        load_file(tmp_path / "nope.yaml")
