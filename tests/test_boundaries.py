"""Import boundaries of docs/architecture.md.

The interpreter never imports perception; the seeing side of perception never
imports the simulator, the demonstrator, the robot or the ground truth. This is
what makes "detectors read only images" checkable: they cannot even name the
world's state.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

WORLD_SIDE = {"world", "pictures"}


def _imports(path: Path) -> set[str]:
    """Absolute names of every module ``path`` imports (relative ones resolved)."""
    package = path.relative_to(ROOT).with_suffix("").parts[:-1]
    tree = ast.parse(path.read_text(), filename=str(path))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = package[: len(package) - node.level + 1]
                base = ".".join([*anchor, node.module] if node.module else anchor)
            else:
                base = node.module or ""
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return names


def _modules(package: str):
    for path in sorted((ROOT / package).rglob("*.py")):
        yield path.relative_to(ROOT).as_posix(), path


ENGINE = [(rel, p) for rel, p in _modules("lbw_engine") if not rel.startswith("lbw_engine/cli/")]
SEEING = list(_modules("perception/vision"))


@pytest.mark.parametrize("rel,path", ENGINE, ids=[r for r, _ in ENGINE])
def test_engine_does_not_import_perception(rel, path):
    bad = {n for n in _imports(path) if n == "perception" or n.startswith("perception.")}
    assert not bad, f"{rel} imports {sorted(bad)}"


def test_the_seeing_side_exists():
    assert len(SEEING) >= 8, "the seeing-side prefixes no longer match perception's detectors"


@pytest.mark.parametrize("rel,path", SEEING, ids=[r for r, _ in SEEING])
def test_seeing_side_does_not_import_the_world(rel, path):
    bad = set()
    for name in _imports(path):
        if name == "pymunk" or name.startswith("pymunk."):
            bad.add(name)
        parts = name.split(".")
        if parts[0] == "perception" and len(parts) > 1 and parts[1] in WORLD_SIDE:
            bad.add(name)
    assert not bad, f"{rel} reaches the simulator through {sorted(bad)}"
