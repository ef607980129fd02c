"""One recorded ``lbw run --report --video`` shared by the report tests, and Chromium.

The run (watch with the monitor and the motion recorder, analyze, execute with
the robot recorded) is the expensive part, so it is made once per test session
and shared between pytest-xdist's workers: the first worker to take the lock
makes it in a folder all workers see, the others wait and read the files.
"""

from __future__ import annotations

import fcntl
import json
import os
from dataclasses import dataclass
from pathlib import Path

import pytest

from .browser import EXE, Chromium, Page

ROOT = Path(__file__).resolve().parents[2]
SEED = 5  # a generated tower: 3 blocks, a touch, recognized exactly (tests/generator)


@dataclass(frozen=True)
class RecordedRun:
    """The published output folder of one run, and the scenario file it ran."""

    out: Path
    scenario: Path

    def json(self, name: str) -> dict:
        """One of the run's JSON files."""
        return json.loads((self.out / name).read_text())


def _make_run(folder: Path) -> None:
    """Run the tower into ``folder/out`` (published atomically by OutputDir)."""
    from lbw_engine.cli.pictures import run_with_pictures
    from lbw_engine.outputs import OutputDir
    from lbw_engine.pipeline.run import publish
    from perception.world.generator import generate
    from perception.world.scenario import load

    folder.mkdir(parents=True, exist_ok=True)
    scenario = folder / "tower.yaml"  # a file, so the report shows the scenario's text
    scenario.write_text(generate(SEED, structures=["tower"]).text)
    with OutputDir(folder / "out") as out:
        # scale 1 (256-px views): the pictures are the same, the encoding four times cheaper
        publish(run_with_pictures(load(scenario), None, out, video=True, report=True, scale=1),
                out)


@pytest.fixture(scope="session")
def recorded_run(tmp_path_factory: pytest.TempPathFactory) -> RecordedRun:
    """The shared run; made by whichever worker gets here first."""
    base = tmp_path_factory.getbasetemp()
    shared = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    folder = shared / "report-run"
    with open(shared / "report-run.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / "out" / "execution.json").is_file():
            _make_run(folder)
    return RecordedRun(folder / "out", folder / "tower.yaml")


def need_chromium() -> None:
    """Skip without Chromium, except in CI (CI=true), where its absence is a failure."""
    if EXE is None:
        if os.environ.get("CI") == "true":
            pytest.fail("chromium is not installed in CI (.ci/run installs it)")
        pytest.skip("chromium is not installed (apt-get install -y chromium)")


@pytest.fixture(scope="module")
def browser(tmp_path_factory: pytest.TempPathFactory):
    """One headless Chromium per test module."""
    need_chromium()
    with Chromium(tmp_path_factory.mktemp("chromium-profile")) as chromium:
        yield chromium


@pytest.fixture(scope="module")
def report_page(browser: Chromium, recorded_run: RecordedRun) -> Page:
    """The shared run's report.html, loaded once per module at 1280 x 900 CSS px."""
    return browser.open(recorded_run.out / "report.html", width=1280, height=900)
