"""The README's commands, run as written.

Every fenced ``sh`` block of README.md runs line by line in bash, in a fresh folder
holding the repository's ``scenarios/``, and every line must exit 0. A test cannot
make a venv or reach other machines, so these lines have stand-ins (STAND_INS):

| README line                                  | here                                        |
|----------------------------------------------|---------------------------------------------|
| ``make demo``, ``make test``, a venv + pip   | skipped: this venv is installed and tested  |
| ``. .venv/bin/activate``                     | this interpreter's bin folder first on PATH |
| ``dask scheduler``                           | in the background, on a free port (for 8786)|
| ``dask worker ...``                          | in the background; stopped at the end       |
| ``HOST``, ``8786``                           | 127.0.0.1 and that free port                |
| ``--count 1000``                             | ``--count 1`` (one scenario: seconds)       |

Then what the README says the commands leave behind is checked.
"""

import os
import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
SKIP, BACKGROUND = "skip", "background"
STAND_INS = [  # (pattern of a README line, what to do with it)
    (re.compile(r"^make (demo|test)$"), SKIP),
    (re.compile(r"-m venv .venv && .*pip install"), SKIP),
    (re.compile(r"^\. \.venv/bin/activate$"), SKIP),  # PATH below does it
    (re.compile(r"^dask (scheduler|worker)\b"), BACKGROUND),
]


def commands(text: str) -> list[str]:
    """The command lines of the README's ```sh blocks, comments removed, in order."""
    lines = []
    for block in re.findall(r"^```sh\n(.*?)^```", text, re.S | re.M):
        for line in block.splitlines():
            line = re.sub(r"\s+#.*$", "", line).strip()
            if line and not line.startswith("#"):
                lines.append(line)
    return lines


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def localize(line: str, port: int) -> str:
    """The stand-ins for one machine: HOST, the scheduler's port, a short bench."""
    line = line.replace("HOST", "127.0.0.1").replace("8786", str(port))
    line = line.replace("--count 1000", "--count 1")
    if line == "dask scheduler":
        line += f" --port {port} --dashboard-address :0"
    return line


def test_readme_sh_blocks_have_the_commands_this_test_expects():
    lines = commands(README.read_text())
    assert "make demo" in lines and ". .venv/bin/activate" in lines
    assert any(line.startswith("lbw run ") for line in lines)
    assert any(line.startswith("dask scheduler") for line in lines)


@pytest.mark.heavy
def test_readme_commands_run_as_written(tmp_path):
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    env = dict(os.environ, PATH=str(Path(sys.executable).parent) + os.pathsep +
               os.environ.get("PATH", ""))
    port = free_port()
    servers: list[subprocess.Popen] = []
    try:
        for line in commands(README.read_text()):
            what = next((act for pat, act in STAND_INS if pat.search(line)), None)
            if what == SKIP:
                continue
            line = localize(line, port)
            if what == BACKGROUND:
                servers.append(subprocess.Popen(
                    ["bash", "-c", f"exec {line}"], cwd=tmp_path, env=env,
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                    start_new_session=True))
                continue
            done = subprocess.run(["bash", "-c", line], cwd=tmp_path, env=env,
                                  capture_output=True, text=True, timeout=600)
            assert done.returncode == 0, f"{line}\n{done.stdout}\n{done.stderr}"
            assert "Traceback" not in done.stderr, line
    finally:
        for server in reversed(servers):  # the worker first, then its scheduler
            _stop(server)
    out = tmp_path / "out"
    # What the README says these commands leave: a run's files; the phases continued
    # in one folder keep the earlier phases' files.
    run_files = {"actions.json", "plan.json", "plan.txt", "commands.txt", "execution.json"}
    assert run_files <= {p.name for p in (out / "build-table").iterdir()}
    assert run_files <= {p.name for p in (out / "arch").iterdir()}
    assert (tmp_path / "bench-1000.jsonl").read_text().count("\n") == 1


def _stop(server: subprocess.Popen) -> None:
    """Stop a background server and the processes it started (its own session)."""
    if server.poll() is None:
        os.killpg(server.pid, signal.SIGTERM)
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(server.pid, signal.SIGKILL)
            server.wait()


@pytest.mark.parametrize("line,expected", [
    ("dask scheduler", "dask scheduler --port 5 --dashboard-address :0"),
    ("dask worker tcp://HOST:8786 --nthreads 1", "dask worker tcp://127.0.0.1:5 --nthreads 1"),
    ("lbw bench --cluster tcp://HOST:8786 --count 1000", "lbw bench --cluster "
                                                         "tcp://127.0.0.1:5 --count 1"),
    ("lbw run scenarios/x.yaml --out out/x", "lbw run scenarios/x.yaml --out out/x"),
], ids=["scheduler", "worker", "bench", "unchanged"])
def test_stand_ins(line, expected):
    assert localize(line, 5) == expected
