"""Fuzzing every input kind through ``lbw_engine.cli.main`` (issue #15), a seeded sample.

Hypothesis draws the mutators' choices (``st.randoms``), so a failing case
shrinks to a simple one; ``derandomize`` makes the sample the same on every
run. The full campaign is ``python -m bench fuzz --count 10000``
(docs/benchmarks.md). Each case checks: exit 0, 1 or 2 (never 3), no traceback,
a rejection in exactly one line, nothing left behind (bench/fuzzcases.py).
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench.fuzzcases import KINDS, run_case

# Cases per kind: about 200 in all, ~35 s on one core (rule folders cost most:
# every case compiles a fresh copy of the template grammar). A sample, kept small for
# the 10-minute suite; the campaign runs the thousands.
EXAMPLES = {"rules": 30, "scenario": 50, "actions": 50, "plan": 40, "trace": 30}


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.heavy
def test_fuzz_sample(kind):
    @settings(max_examples=EXAMPLES[kind], derandomize=True, deadline=None, database=None,
              suppress_health_check=list(HealthCheck))
    @given(rng=st.randoms(use_true_random=False))
    def case(rng):
        outcome = run_case(kind, rng)
        assert outcome.ok, outcome.summary()

    case()
