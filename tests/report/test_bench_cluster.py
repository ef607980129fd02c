"""`lbw bench --cluster`: a Dask cluster gives the same records, seed for seed, as --jobs."""

import json
import sys

import pytest

from lbw_engine.cli import cluster, main
from lbw_engine.cli.bench import TIMINGS, reproducible

# Seed 12's two scenarios (a pyramid with two touches; a tower) are among the cheapest
# of the generator's first 40 sets: the whole watch → analyze → execute runs on each.
SEED, COUNT = 12, 2
# Summary figures that are wall-clock speeds, not results.
SPEEDS = ("realtime_factor_watch", "realtime_factor_pipeline")


def run_bench(tmp_path, name, *where):
    out = tmp_path / f"{name}.json"
    argv = ["bench", "--count", str(COUNT), "--seed", str(SEED), "--out", str(out), *where]
    assert main(argv) == 0
    records = [json.loads(line) for line in (tmp_path / f"{name}.jsonl").read_text().splitlines()]
    return json.loads(out.read_text()), records


def results(summary):
    return {level: {k: v for k, v in figures.items() if k not in SPEEDS}
            for level, figures in summary.items()}


@pytest.mark.heavy
def test_local_cluster_of_two_workers_gives_the_records_of_the_process_pool(tmp_path):
    pool_doc, pool = run_bench(tmp_path, "pool", "--jobs", "2")
    dask_doc, dask = run_bench(tmp_path, "dask", "--cluster", "local:2")
    assert dask_doc["runner"] == "Dask cluster local:2 (2 workers, 2 threads)"
    assert [r["seed"] for r in dask] == [SEED * 1000, SEED * 1000 + 1]
    assert all("error" not in r and "exact" in r for r in dask)  # real, scored records
    assert all(set(TIMINGS) - {"analyze_seconds", "execute_seconds"} <= set(r) for r in dask)
    assert [reproducible(r) for r in dask] == [reproducible(r) for r in pool]
    assert results(dask_doc["summary"]) == results(pool_doc["summary"])
    assert dask_doc["failures"] == pool_doc["failures"]
    assert dask_doc["command"].endswith("--cluster local:2")


def test_without_dask_the_sentence_says_how_to_install_it(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    code = main(["bench", "--count", "1", "--cluster", "local:2", "--out",
                 str(tmp_path / "b.json")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "--cluster: running on a Dask cluster needs Dask's distributed package: " \
           "pip install 'lbw[cluster]'" in err
    assert not (tmp_path / "b.json").exists()


BAD = [
    (["--cluster", "local:0"], "--cluster: 'local:0' is not local:N"),
    (["--cluster", "local:two"], "--cluster: 'local:two' is not local:N"),
    (["--cluster", "tcp://127.0.0.1:9"], "--cluster: cannot reach a Dask scheduler at "
                                          "'tcp://127.0.0.1:9'"),
]


@pytest.mark.parametrize("argv,message", BAD, ids=["zero-workers", "not-a-number",
                                                   "no-scheduler"])
def test_a_cluster_that_cannot_be_used_is_bad_input(monkeypatch, tmp_path, capsys, argv,
                                                    message):
    monkeypatch.setattr(cluster, "CONNECT_S", 1)  # nothing listens on port 9 (discard)
    code = main(["bench", "--count", "1", "--out", str(tmp_path / "b.json"), *argv])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_a_lost_worker_is_a_crashed_record_not_the_end(monkeypatch, tmp_path):
    """What an executor raises for a task (a Dask KilledWorker, a broken process pool)
    becomes that scenario's record; the others finish, and the partial file holds all."""
    import concurrent.futures as cf

    from lbw_engine.cli import bench as benchmod

    def fake(task):
        seed, level = task[:2]
        if seed == 2:
            raise RuntimeError("worker tcp://10.0.0.1:1 died")
        return {"seed": seed, "level": level, "structures": ["tower"], "touches": 0,
                "exact": True, "plan_correct": True, "execution_success": True}

    monkeypatch.setattr(benchmod, "run_one", fake)
    partial = tmp_path / "r.jsonl.partial"
    with cf.ThreadPoolExecutor(2) as pool:
        records = benchmod.run_all([(s, "nominal", "classic", None) for s in (3, 2, 1)], pool,
                                   partial)
    assert [r["seed"] for r in records] == [1, 2, 3]
    assert records[1]["error"] == "worker lost: RuntimeError: worker tcp://10.0.0.1:1 died"
    crashed = f"crashed: {records[1]['error']}"
    assert benchmod.failures(records) == [{"seed": 2, "level": "nominal", "family": "classic",
                                           "structures": [], "touches": 0, "what": [crashed]}]
    assert sorted(json.loads(line)["seed"] for line in partial.read_text().splitlines()) == \
        [1, 2, 3]


def test_resume_keeps_a_stopped_runs_records_and_runs_the_rest(monkeypatch, tmp_path):
    from lbw_engine.cli import bench as benchmod

    ran = []

    figures = {"accuracy": 1.0, "timing_errors": [0.1], "demo_seconds": 100.0,
               "watch_seconds": 1.0, "total_seconds": 2.0, "pixels_per_frame": 5000.0}

    def fake(task):
        ran.append(task[0])
        return {"seed": task[0], "level": task[1], "structures": ["arch"], "touches": 0,
                "exact": True, "plan_correct": True, "execution_success": True, **figures}

    monkeypatch.setattr(benchmod, "run_one", fake)
    partial = tmp_path / "r.jsonl.partial"
    kept = {"seed": 1000, "level": "nominal", "structures": ["table"], "touches": 1,
            "exact": False, "difference": "at #3: expected PICK, got NO-OP",
            "plan_correct": True, "execution_success": True, **figures}
    other_set = dict(kept, seed=7000)
    partial.write_text(benchmod.records_text([kept, other_set]) + '{"seed": 1001, "lev')
    doc = benchmod.bench(3, 1, 1, partial=partial, resume=True)
    assert ran == [1001, 1002]  # the torn line's scenario runs again; 7000 is not in the set
    assert [r["seed"] for r in doc["scenarios"]] == [1000, 1001, 1002]
    assert doc["scenarios"][0] == kept
    assert doc["summary"]["nominal"]["exact_sequence_rate"] == 0.0  # the kept record counts
    assert [json.loads(line)["seed"] for line in partial.read_text().splitlines()] == \
        [1000, 1001, 1002]
