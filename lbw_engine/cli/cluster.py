"""Where ``lbw bench`` runs its scenarios: this process, a process pool or a Dask cluster.

``executor(jobs, cluster)`` is a context manager giving a ``concurrent.futures``
executor (None: run here, one scenario after the other) and a phrase saying
what it is. Every kind runs the same picklable task function on the same task
tuples, so the records do not depend on where they were made (the bench sorts
them by seed).

| ``--cluster``       | what runs the scenarios                                        |
|---------------------|----------------------------------------------------------------|
| (none), --jobs 1    | this process                                                   |
| (none), --jobs N    | ``concurrent.futures.ProcessPoolExecutor`` of N processes      |
| ``local:N``         | a Dask ``LocalCluster`` of N single-threaded worker processes  |
| ``tcp://HOST:PORT`` | the workers of a running Dask scheduler (``dask scheduler``)   |

Dask is the optional extra ``lbw[cluster]``; it is imported only here, and only
when ``--cluster`` is given.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import sys
from collections.abc import Iterator
from typing import Any

from lbw_engine.errors import InputError

INSTALL = "pip install 'lbw[cluster]' (in a checkout: .venv/bin/pip install -e '.[cluster]')"
CONNECT_S = 10  # seconds to reach a scheduler before saying it cannot be reached
WORKERS_S = 30  # seconds to wait for a scheduler's first worker


@contextlib.contextmanager
def executor(jobs: int, cluster: str | None) -> Iterator[tuple[cf.Executor | None, str]]:
    """(executor or None, description) for ``--jobs`` / ``--cluster``; closed on exit."""
    if cluster is None:
        if jobs <= 1:
            yield None, "1 process"
            return
        with cf.ProcessPoolExecutor(max_workers=jobs) as pool:
            yield pool, f"{jobs} processes"
        return
    distributed = _import_distributed()
    with _client(distributed, cluster) as client:
        threads = client.nthreads()  # worker address -> threads
        if any(n > 1 for n in threads.values()):
            # The pipeline is CPU-bound Python: threads of one worker share one core's
            # worth of interpreter, so they add waiting, not speed.
            print("lbw bench: note: some workers run several threads; start them with "
                  "`dask worker ADDRESS --nthreads 1 --nworkers N` for one scenario per core",
                  file=sys.stderr)
        # pure=False: every scenario is run, never taken from an earlier result by key.
        yield (client.get_executor(pure=False),
               f"Dask cluster {cluster} ({len(threads)} workers, {sum(threads.values())} "
               "threads)")


def _import_distributed() -> Any:
    """The ``distributed`` package, or exit 2 saying how to install it."""
    try:
        import distributed
    except ImportError:
        raise InputError(f"running on a Dask cluster needs Dask's distributed package: "
                         f"{INSTALL}", where="--cluster") from None
    return distributed


def local_workers(cluster: str) -> int | None:
    """N of ``local:N`` (None for a scheduler address); exit 2 when N is not a count."""
    if not cluster.startswith("local:"):
        return None
    text = cluster.removeprefix("local:")
    if not text.isdigit() or int(text) < 1:
        raise InputError(f"'{cluster}' is not local:N with N a number of workers of at least "
                         "1", where="--cluster")
    return int(text)


@contextlib.contextmanager
def _client(distributed: Any, cluster: str) -> Iterator[Any]:
    """A Dask client of a new local cluster or of the scheduler at ``cluster``."""
    n = local_workers(cluster)
    if n is not None:
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      dashboard_address=":0", silence_logs=logging.ERROR) as lc, \
                distributed.Client(lc) as client:
            yield client
        return
    try:
        client = distributed.Client(cluster, timeout=f"{CONNECT_S}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot reach a Dask scheduler at '{cluster}' ({exc}); start one "
                         "with `dask scheduler` and give its tcp://HOST:PORT",
                         where="--cluster") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=WORKERS_S)
        except TimeoutError:
            raise InputError(f"the Dask scheduler at '{cluster}' has no workers after "
                             f"{WORKERS_S} s; start some with `dask worker {cluster}`",
                             where="--cluster") from None
        yield client
