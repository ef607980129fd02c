"""Where the bundled data lives, for an installed or an editable ``lbw``."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def default_rules_dir() -> Path:
    """The rules/ folder shipped with the package."""
    return Path(str(resources.files("rules")))


def repo_root() -> Path | None:
    """The source checkout, when running from one (bundled scenarios live there)."""
    here = Path(__file__).resolve().parent.parent
    return here if (here / "pyproject.toml").exists() else None


def bundled_scenario(name: str) -> Path:
    """Path of a scenario shipped in scenarios/ (e.g. ``build-table``)."""
    return Path(str(resources.files("scenarios"))) / f"{name}.yaml"
