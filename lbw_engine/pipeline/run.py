"""The whole task, phase after phase: watch → analyze → execute (Sec. III-VII).

``run`` goes through the phases on a loaded scenario and never raises for a
failed task: a ``RunResult`` records what each phase produced and the *first*
phase that went wrong (design.md: recognition, analysis, instantiation,
execution, verification). An internal mismatch — the analysis refusing the
recognizer's own output, a plan the executor cannot instantiate — is a failed
task, never bad input. ``publish`` stages the run's files; ``lbw run``, ``lbw
demo``, ``lbw bench`` and the report all use these.

After watching, the recognized sequence is checked against rules/domain.yaml
and repaired where exactly one single change fits (Sec. IX-C2,
lbw_engine.understand.repair); analysis reads the repaired sequence, and
``actions.json`` records every change in ``repairs``.

The ground truth is consulted only *after* recognition, to check the
recognized sequence, raw and repaired, against what a perfect eye would have
recognized under the same rules (evaluation, perception.world.groundtruth).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.do import plan as planmod
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.names import RESERVED
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.pipeline.watch import repair, watch
from lbw_engine.rules import RuleSet, load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.understand import RelationTable, analyze, parse_actions, write_plan_text

PHASES = ("recognition", "analysis", "instantiation", "execution", "verification")

@dataclass
class RunResult:
    """Everything one end-to-end run produced, phase by phase."""

    scenario: Any
    actions: dict[str, Any]
    recognition: dict[str, Any]
    plan: dict[str, Any] | None = None
    plan_text: str | None = None
    execution: Any = None  # lbw_engine.pipeline.execute.ExecutionResult
    failure: str | None = None  # first phase that failed, with why
    seconds: dict[str, float] = field(default_factory=dict)
    rules: Any = None  # the RuleSet the run used
    raw: dict[str, Any] | None = None  # actions.json as recognized, before repair
    phases: dict[str, str] = field(default_factory=dict)  # every phase that failed: why

    @property
    def success(self) -> bool:
        """No phase failed: recognized as demonstrated (design.md: a recognition that does
        not verify fails the task), a plan learned, and any execution verified."""
        if self.failure or self.plan is None:
            return False
        return self.execution is None or bool(self.execution.success)

    def report(self) -> dict[str, Any]:
        """execution.json: the verdict of the whole run (design.md "Execution report")."""
        out: dict[str, Any] = {"success": self.success}
        if self.execution is not None:
            out.update({k: v for k, v in self.execution.report.items() if k != "success"})
        out["failure"] = self.failure if not self.success else None
        # design.md's keys, also when nothing was executed: nothing built, nothing watched
        out.setdefault("verification", {"cameras": False, "ground_truth": False})
        out.setdefault("monitor", {"detections": [], "repairs": []})
        out["recognition"] = self.recognition
        out["seconds"] = {k: round(v, 3) for k, v in self.seconds.items()}
        return out


def compare_with_truth(scenario: Any, actions: dict[str, Any], rules: RuleSet
                       ) -> dict[str, Any]:
    """The recognized top-level sequence against the ground truth (evaluation only): what
    the same rules make of perfect detectors (perception.world.groundtruth)."""
    from lbw_engine.report.metrics import compare_sequence
    from perception.world.demonstrator import Demonstration
    from perception.world.groundtruth import ground_truth

    demo = Demonstration(scenario)  # one schedule for every reading of the truth below
    truth = ground_truth(scenario, rules, demo)
    expected = [op.operation for op in truth]
    recognized = [op["operation"] for op in actions["operations"]]
    # The bench's definition (lbw_engine/report/metrics.py): a repeated closing
    # operation counts once (the hand leaving may be split, Fig. 12).
    same = compare_sequence([{"operation": op} for op in expected], actions["operations"])
    fine = _fine(truth, rules)
    out = {"expected": expected, "expected_fine": fine, "recognized": recognized,
           "exact": same["exact"], "difference": same["difference"]}
    # An align whose slide is within align-slide-doubt of align-slide may be read either
    # way (rules/constants.yaml): the fine motions a stricter and a more lenient eye expect.
    from perception.world.layout import slide_reading

    least = float(rules.constants["align-slide"])
    doubt = float(rules.constants["align-slide-doubt"])
    if any(must != may for must, may in (slide_reading(s, least, doubt)
                                         for s in scenario.demonstration)):
        out["fine_at_least"] = _fine(ground_truth(scenario, rules, demo, least + doubt), rules)
        out["fine_at_most"] = _fine(ground_truth(scenario, rules, demo, max(0.0, least - doubt)),
                                    rules)
    return with_fine(out, actions["operations"], rules)


def _fine(truth: list[Any], rules: RuleSet) -> list[list[str]]:
    """Per true operation, its fine motions that change the environment model (an ALIGN's
    relation)."""
    return [sorted({f.operation for f in op.fine if f.operation in rules.effects})
            for op in truth]


def with_fine(result: dict[str, Any], ops: list[dict[str, Any]], rules: RuleSet
              ) -> dict[str, Any]:
    """``result`` not exact if some operation's fine motions that change the environment
    model differ from the demonstrated ones: a lost ALIGN leaves every top-level operation
    right, and the plan without its relation. Where the truth has ``fine_at_least`` and
    ``fine_at_most`` (a slide in doubt), any set between the two is right."""
    if not result["exact"]:
        return result
    least = result.get("fine_at_least", result["expected_fine"])
    most = result.get("fine_at_most", result["expected_fine"])
    for i, (want, low, high, op) in enumerate(zip(result["expected_fine"], least, most, ops,
                                                   strict=False)):
        got = sorted({f["operation"] for f in op.get("fine", ()) if f["operation"]
                      in rules.effects and f.get("t_end") is not None})  # as the truth
        if not set(low) <= set(got) <= set(high):
            return {**result, "exact": False,
                    "difference": f"at #{i}: expected fine motion(s) {'/'.join(want) or 'none'}"
                                  f" in {op['operation']}, got {'/'.join(got) or 'none'}"}
    return result


def foreign_objects(scenario: Any, actions: dict[str, Any]) -> str | None:
    """The first object the operations act on, or their states relate, that the teach
    workspace does not hold with that name and shape (evaluation only: the recognizer
    names what it finds after the teach objects, perception.vision.envnodes.objects);
    None when all are there. A block the finder split in two moves with its rider in
    the states only, and the plan then names the piece (a user's loaded plank)."""
    teach = {n: o.shape for n, o in scenario.teach.objects.items()}
    found = actions.get("objects", {})
    for op in actions["operations"]:
        for name in _named(op):
            if name in RESERVED or teach.get(name) == found.get(name, {}).get("shape"):
                continue
            shape = found.get(name, {}).get("shape", "?")
            return (f"{op.get('name', op['operation'])}: the object '{name}' ({shape}) that "
                    "it acts on or relates is not in the teach workspace (the object-finder "
                    "misread it)")
    return None


def _named(op: dict[str, Any]) -> list[str]:
    """Every object name an operation acts on (target, special) or its states relate."""
    names = [*op.get("target", ()), *op.get("special", ())]
    for state in ("initial_state", "final_state"):
        for rel in (op.get(state) or {}).get("relations", ()):
            for arg in rel[1:3]:
                names += arg if isinstance(arg, list) else [arg]
    return [n for n in names if isinstance(n, str)]


def with_repair(recognition: dict[str, Any], repaired: Any, rules: RuleSet
                ) -> dict[str, Any]:
    """``recognition`` (the raw comparison) with ``repair``: the repaired sequence against
    the same expected one (docs/repair.md). Without repairs it is the raw sequence."""
    from lbw_engine.report.metrics import compare_sequence

    after = {"repairs": len(repaired.repairs), "checked": repaired.checked,
             "inconsistent": repaired.left}
    if repaired.repairs:
        same = compare_sequence([{"operation": op} for op in recognition["expected"]],
                                repaired.actions["operations"])
        same = with_fine({**recognition, "exact": same["exact"],
                          "difference": same["difference"]},
                         repaired.actions["operations"], rules)
        after.update(recognized=repaired.operations, exact=same["exact"],
                     difference=same["difference"])
    else:
        after.update(recognized=recognition["recognized"], exact=recognition["exact"],
                     difference=recognition["difference"])
    return {**recognition, "repair": after}


def repair_lines(actions: dict[str, Any]) -> list[str]:
    """One line per recognition repair of an actions.json document (never repair silently)."""
    def names(ops: list[dict[str, Any]]) -> str:
        return " ".join(f"{op.get('name', '?')}:{op['operation']}" for op in ops) or "nothing"

    return [f"repaired at #{r['at']}: {names(r['was'])} -> {names(r['now'])} ({r['why']})"
            for r in actions.get("repairs", [])]


def verdict_words(recognition: dict[str, Any]) -> str:
    """The recognition verdict in words, raw and after repair."""
    after = recognition["repair"]
    if recognition["exact"]:
        return "exactly as demonstrated"
    if after["exact"]:
        return f"as demonstrated after {after['repairs']} repair(s)"
    return "NOT as demonstrated"


def run(scenario: Any, rules_dir: Any = None, fps: float = 30.0,
        watcher: Callable[..., Any] | None = None,
        on_step: Callable[[Any], None] | None = None,
        rules: RuleSet | None = None) -> RunResult:
    """Run watch → analyze → execute on a loaded scenario; never raises for a failed task.

    ``watcher(scenario, rules, fps)`` replaces the plain watch (it must return
    the recognizer), e.g. to draw the monitor display; ``on_step(world)`` is
    called after every step of the robot's world (to record the execution).
    Every phase that can run does (its files are written); ``failure`` names the
    first that went wrong. ``rules``: the RuleSet already loaded from ``rules_dir``.
    """
    rules = rules if rules is not None else load_rules(rules_dir)
    clock = time.perf_counter()
    if watcher is None:
        recognizer, _ = watch(scenario, rules, fps=fps)
    else:
        recognizer = watcher(scenario, rules, fps)
    raw = to_actions(recognizer)
    # Sec. IX-C2: the sequence checked against domain.yaml, repaired where exactly
    # one change fits; analysis reads the repaired one, the report keeps both.
    repaired = repair(raw, rules)
    actions = repaired.actions
    result = RunResult(scenario, actions,
                       with_repair(compare_with_truth(scenario, raw, rules), repaired, rules),
                       rules=rules, raw=raw)
    result.seconds["watch"] = time.perf_counter() - clock
    failures = result.phases
    after = result.recognition["repair"]
    if not after["exact"]:
        # what was learned is not what was shown: the task failed (design.md exit codes)
        failures["recognition"] = after["difference"] + (
            f" (after {after['repairs']} repair(s))" if after["repairs"] else "")
    elif (wrong := foreign_objects(scenario, actions)):
        failures["recognition"] = wrong  # the right operations on objects not shown
    clock = time.perf_counter()
    try:  # the recognizer's own output: a template mismatch is a failed task, not bad input
        analysis = analyze_actions(actions, rules)
    except InputError as exc:
        failures["analysis"] = str(exc)
    else:
        result.plan = analysis.plan
        result.plan_text = write_plan_text(analysis.plan)
        result.seconds["analyze"] = time.perf_counter() - clock
        if scenario.execute is not None:
            clock = time.perf_counter()
            _execute(result, scenario, rules, on_step, failures)
            result.seconds["execute"] = time.perf_counter() - clock
    result.failure = next((f"{phase}: {failures[phase]}" for phase in PHASES
                           if phase in failures), None)
    return result


def analyze_actions(actions: dict[str, Any], rules: RuleSet) -> Any:
    """The analysis of a (repaired) recognized sequence; InputError when its templates
    do not fit (the caller decides whose fault that is)."""
    seq = parse_actions(actions, RelationTable(rules.analysis.tolerance), file="actions.json")
    return analyze(seq, rules.analysis)


def _execute(result: RunResult, scenario: Any, rules: RuleSet,
             on_step: Callable[[Any], None] | None, failures: dict[str, str]) -> None:
    """Instantiate, execute and verify the learned plan; note the phase that failed."""
    try:  # a plan the analysis wrote that execution cannot take is an internal mismatch
        plan = planmod.parse(result.plan, file="plan.json")
        result.execution = execute_plan(plan, scenario, rules, on_step=on_step)
    except (InputError, TaskFailed) as exc:
        failures["instantiation"] = str(exc)
        return
    if not result.execution.success:
        failures[result.execution.phase or "execution"] = result.execution.message


def publish(result: RunResult, out: OutputDir) -> None:
    """Stage the run's files (design.md: actions, plan, plan text, commands, verdict)."""
    out.write_json("actions.json", result.actions)
    if result.plan is not None:
        out.write_json("plan.json", result.plan)
        out.write_text("plan.txt", result.plan_text or "")
    if result.execution is not None:
        out.write_text("commands.txt", result.execution.commands_text)
    out.write_json("execution.json", result.report())
