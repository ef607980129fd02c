"""The architecture holds (issue #11): import-linter's contracts, and module size.

The import ladder is written once, as contracts in pyproject.toml
([tool.importlinter]): command line → pipeline → perception's pictures → world
→ vision → the interpreter (see | understand | do) → environment model → rules →
utilities; perception's vision never reaches the simulator; the interpreter
never imports perception; no two modules import each other in a circle. This
test runs the linter; a contract broken on purpose in a copy shows the linter
would notice.
"""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LINT = Path(sys.executable).parent / "lint-imports"
MAX_LINES = 400  # style.md: modules under ~400 lines


def _lint(config: Path, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT), "--config", str(config), "--no-cache"], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def test_import_contracts_are_kept():
    out = _lint(ROOT / "pyproject.toml", ROOT)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]
    assert "4 kept, 0 broken" in out.stdout


def test_a_detector_that_reads_the_world_breaks_a_contract(tmp_path):
    """The contracts can fail: a copy whose hand state imports the simulator is caught."""
    for package in ("lbw_engine", "perception"):
        shutil.copytree(ROOT / package, tmp_path / package,
                        ignore=shutil.ignore_patterns("__pycache__"))
    hand = tmp_path / "perception" / "vision" / "envnodes" / "hand.py"
    hand.write_text(hand.read_text() + "\nfrom perception.world import physics  # noqa\n")
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    out = subprocess.run([str(LINT), "--config", "pyproject.toml", "--no-cache"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300,
                         env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert out.returncode != 0
    assert "never reaches the simulator BROKEN" in out.stdout


@pytest.mark.parametrize("path", sorted((ROOT / "lbw_engine").rglob("*.py"))
                         + sorted((ROOT / "perception").rglob("*.py")),
                         ids=lambda p: p.relative_to(ROOT).as_posix())
def test_modules_stay_small(path):
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_LINES, f"{path.name} has {lines} lines"
