"""Issue #12 class 5 (doing): workspaces that start with blocks stacked, executed and verified.

The execution workspace is measured from the world's ground truth here: whether
the object-finder tells two blocks in contact apart is the seeing half of the
class (tests/vision); these rows check that execution does the rest. Plans are
the oracle's (see test_side_contact.py).
"""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.do.matching import Measured
from lbw_engine.pipeline import execute
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parent / "data"
RULES = load_rules()


def _measured_truly(world, sc, images, needs=None):
    """The execution workspace as it is (evaluation's ground truth), names dropped."""
    shape = {n: o.shape for n, o in sc.execute.objects.items()}
    pos = world.positions()
    return [Measured(shape[n], pos[n], world.sizes[n]) for n in world.names], "ground-truth"


ROWS = [
    # name, blocks set aside before a pick, final supports
    # the post is taken off the cube it stands on, then the cube goes on the post
    ("unstack", [], {"top": ("on", ("table",)), "base": ("on", ("top",))}),
    # the brick stands on the cube that is to go onto the brick: it is set aside first
    ("reverse-stack", ["b"], {"a": ("on", ("b",)), "b": ("on", ("table",))}),
]


@pytest.mark.parametrize("name,aside,supports", ROWS, ids=[r[0] for r in ROWS])
def test_stacked_start_executes_and_verifies(monkeypatch, name, aside, supports):
    monkeypatch.setattr(execute, "measure_initial_state", _measured_truly)
    plan = planmod.load(DATA / f"{name}.plan.json")
    result = execute.execute_plan(plan, load(DATA / f"{name}.yaml"), RULES)
    assert result.success, result.message
    set_aside = [note.split("'")[1] for op in result.trace.ops for note, *_ in op.aside]
    assert set_aside == aside
    assert result.trace.model.final_supports(list(supports)) == supports
    # the robot watching itself expects the blocks it sets aside: nothing went wrong
    assert result.report["monitor"]["detections"] == []
