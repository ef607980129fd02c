"""Ground truth of a demonstration, for evaluating the recognizer only.

The true operations are what the rules make of perfect detectors: the
recognizer is run on the oracle registry (perception.world.oracle), which
answers every query from the demonstrator's schedule. Their names therefore
come from the rules under test, never from Python; their times are the
schedule's; their targets and the true relations before and after come from
the scenario's symbolic layouts. The recognizer, its detectors and lbw_engine
never import this module (import-linter contracts).

Segmentation convention (Sec. V-B): a Transfer runs from the end of the
previous Depart to the hand's arrival above the next target; the LocalMotion
then runs until the hand has risen again (end of its Depart). The final
Transfer, the hand leaving the workspace, is one operation (the recognizer may
split it: Fig. 12 shows two closing withdraws, and the comparison in
lbw_engine.report.metrics treats trailing repeats as one).
"""

from __future__ import annotations

from dataclasses import dataclass

from lbw_engine.rules import RuleSet
from perception.world.demonstrator import Demonstration
from perception.world.layout import Layout
from perception.world.oracle import oracle_recognizer


@dataclass(frozen=True)
class TrueFine:
    """A fine operation inside a LocalMotion (e.g. ALIGN, Sec. V-B5)."""

    operation: str
    t_start: float
    t_end: float


@dataclass(frozen=True)
class TrueOperation:
    """One top-level operation as it really happened."""

    operation: str
    motion: str
    t_start: float
    t_end: float
    step: int  # demonstration step index, -1 for the hand entering or leaving
    target: tuple[str, ...]
    special: tuple[str, ...]
    initial_relations: list
    final_relations: list
    fine: tuple[TrueFine, ...] = ()


def ground_truth(scenario, rules: RuleSet, demonstration: Demonstration | None = None,
                 slide: float | None = None) -> list[TrueOperation]:
    """True operations with times (the demonstrator's schedule) and relations (layouts);
    ``slide``: the least slide that is an align (default: rules ``align-slide``)."""
    demo = demonstration or Demonstration(scenario)
    rec = oracle_recognizer(scenario, rules, demo, slide=slide)
    arrived = [next(s.t1 for s in demo.segments if s.step == i and s.phase == "transfer")
               for i in range(len(scenario.demonstration))]
    layouts: list[Layout] = [scenario.teach.layout(), *scenario.states]
    out = []
    for node in rec.root.history if rec.root is not None else []:
        # The oracle dates every segmentation at the schedule's own times: an operation
        # ending at step i's arrival is its Transfer, one starting there its local motion.
        step, before, after = -1, layouts[-1], layouts[-1]
        for i, t in enumerate(arrived):
            if abs(node.t_end - t) < 1e-6:
                step, before, after = i, layouts[i], layouts[i]
            elif abs(node.t_start - t) < 1e-6:
                step, before, after = i, layouts[i], layouts[i + 1]
        fine = tuple(TrueFine(sub.operation, sub.t_start, sub.t_end) for sub in node.history
                     if rules.motions[sub.motion].fine and sub.t_end is not None)
        out.append(TrueOperation(node.operation, node.motion, node.t_start, node.t_end, step,
                                 node.target, node.special, before.relations(rules.roles),
                                 after.relations(rules.roles), fine))
    return out


def expected_operations(scenario, rules: RuleSet) -> list[str]:
    """The top-level operations a perfect eye would report under ``rules``, in order."""
    return [op.operation for op in ground_truth(scenario, rules)]
