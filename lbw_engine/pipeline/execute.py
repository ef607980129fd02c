"""Doing (Sec. VII): instantiate a plan in the execution workspace, run it, verify.

The wiring between the pure execution logic (``lbw_engine.do``) and the
simulated workspace (``perception``): build the scenario's execution
workspace, measure its initial state through the cameras, match it to the
plan's objects, trace the plan into Table IX commands, run them with the robot,
let the world settle for 2 s and verify the final structure. ``lbw execute``
and ``lbw run`` use ``execute_plan``; a result that did not succeed names the
phase: instantiation, execution or verification.
"""

from __future__ import annotations

import copy
import math
import re
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.do.listing import format_commands
from lbw_engine.do.matching import (
    Measured,
    anchors,
    match_initial_state,
    plan_objects,
    raised,
    resting,
    taught_shapes,
)
from lbw_engine.do.monitor import pair_by_shape
from lbw_engine.do.placement import anchor_table_places
from lbw_engine.do.plan import Plan
from lbw_engine.do.tracing import Trace, trace
from lbw_engine.do.verification import TOPPLE_RAD, ObjectState, verify
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.model.geometry import tilt
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.monitor import (
    Eyes,
    Monitored,
    camera_verdict,
    run_monitored,
    step_aside,
)
from lbw_engine.pipeline.robotwatch import RobotWatch
from lbw_engine.rules import RuleSet

SETTLE_S = 2.0  # seconds the world runs after the last command before measuring
VIA = ("trace", "bt")  # how the robot is driven: the traced command list, or a behaviour tree


@dataclass
class ExecutionResult:
    """What an execution produced: the two output files' contents and the verdict."""

    success: bool
    message: str
    commands_text: str
    report: dict[str, Any]
    trace: Trace | None = None
    views: dict[str, Any] = field(default_factory=dict)  # name -> {"top": img, "side": img}
    phase: str | None = None  # the phase that failed: instantiation, execution, verification


def execute_plan(plan: Plan, sc: Any, ruleset: RuleSet,
                 on_step: Callable[[Any], None] | None = None,
                 via: str = VIA[0]) -> ExecutionResult:
    """Instantiate ``plan`` in ``sc.execute``, run it with the robot and verify it.

    ``sc`` is a loaded ``perception.world.scenario.Scenario``; ``on_step(world)`` is
    called after every world step of the robot (e.g. to render frames); ``via="bt"``
    ticks the plan's behaviour tree instead of running the traced commands. Raises
    InputError when the plan and the scenario do not fit together; a task that
    cannot be done or does not verify gives ``success=False`` with a message.
    """
    from perception.vision.camera import back_camera, default_cameras
    from perception.world.faults import FaultInjector
    from perception.world.physics import World
    from perception.world.render import Renderer
    from perception.world.robot import FINGERTIP, Robot

    rules = ruleset.commands
    if rules.tip != FINGERTIP:
        raise InputError(f"gripper.tip must be the simulated gripper's {FINGERTIP:g} mm",
                         file=rules.file, where="gripper.tip")
    if sc.execute is None:
        raise InputError("the scenario has no 'execute' workspace", file=sc.file, where="execute")
    taught = _taught(plan, sc)
    world = World(sc.execute.objects.values())
    world.settle(0.5)
    renderer = Renderer(default_cameras(), pixel_noise=sc.noise.pixel, seed=sc.seed)
    views = {"execution-initial": renderer.render(world.scene())}
    measured, source = measure_initial_state(world, sc, views["execution-initial"],
                                             Counter(t["shape"] for t in taught.values()))
    start = world.positions()
    errors = [min(math.dist(m.position, p) for p in start.values()) for m in measured]
    report: dict[str, Any] = {
        "success": False,
        "initial_state": {"source": source, "objects_in_world": len(start),
                          "max_error_mm": round(max(errors, default=0.0), 1),
                          "measured": [{"shape": m.shape, "position": _r(m.position),
                                        "size": list(m.size)} for m in measured]},
    }
    try:
        fixed = anchors(plan, rules.support_relations)
        matching = match_initial_state(taught, plan_objects(plan), measured, fixed,
                                       resting(plan, rules.support_relations),
                                       raised(plan, rules.support_relations))
        report["initial_state"]["matching"] = {n: _r(p) for n, p in matching.positions.items()}
        plan = anchor_table_places(plan, rules.support_relations, fixed)
        model = _model(taught, sc.shapes, matching, measured, ruleset)
        fresh = copy.deepcopy(model) if via == "bt" else None
        planned = trace(plan, rules, copy.deepcopy(model))  # one that cannot be traced fails
    except TaskFailed as exc:
        # nothing was executed: the plan's structure is not there (design.md: booleans)
        report.update(stage="instantiation", failure=f"instantiation: {exc}", mismatches=[],
                      verification={"cameras": False, "ground_truth": False},
                      faults_not_injected=FaultInjector(None, sc.faults, {}).missed())
        return ExecutionResult(False, str(exc), f";;; no commands: {exc}\n", report, None, views,
                               "instantiation")
    shape_of = {n: taught[n]["shape"] for n in matching.assigned}
    # blocks per shape: the first look's count, or the plan's where it names more
    most = Counter(m.shape for m in measured) | Counter(shape_of.values())
    back = Renderer({"back": back_camera()}, pixel_noise=sc.noise.pixel, seed=sc.seed + 2)
    eyes = Eyes(world, renderer, sc.shapes, shape_of, most, back)
    eyes.others = [(b.shape, b.position, b.size) for b in model.bodies.values()
                   if not b.relevant]
    injector = FaultInjector(world, sc.faults, {n: n for n in world.names})
    watch = RobotWatch(Renderer(default_cameras(), pixel_noise=sc.noise.pixel, seed=sc.seed + 1),
                       sc.shapes, ruleset) if via != "bt" else None
    robot = Robot(world, rules.arm_frame, rules.home, on_step=_steps(injector, watch, on_step),
                  finger=rules.finger, max_opening=rules.max_opening)
    report["via"] = via
    if watch is not None:  # the carry watched through the side and back views
        watch.robot, watch.back = robot, back
    mon = Monitored(watch=watch)
    report["monitor"] = {"detections": mon.detections, "repairs": mon.repairs,
                         "units": mon.spans, "operations": mon.operations}
    if hasattr(on_step, "follow"):  # a recorder that shows the monitor (pictures)
        on_step.follow(mon, robot, eyes)
    try:
        if fresh is None:
            run_monitored(plan, ruleset, model, robot, eyes, injector, mon, watch)
            tr, model, log = Trace(mon.ops, mon.model), mon.model, robot.log
        else:
            from lbw_engine.do.behaviour import run_tree
            tr, report["ticks"] = run_tree(plan, rules, fresh, robot.execute)
            log, model = robot.log, tr.model
    except TaskFailed as exc:
        stopped = _stopped_verdict(planned, robot, eyes, world, sc, shape_of, rules)
        exc = TaskFailed(authors_names(str(exc), matching, measured, sc, shape_of))
        report.update(stage="execution", failure=f"execution: {exc}", mismatches=[],
                      faults=injector.injected, faults_not_injected=injector.missed(),
                      ground_truth_toppled=_toppled(world), verification=stopped)
        # the commands the robot ran before it stopped stay on record (helper round 9)
        ran = format_commands(Trace(mon.ops, mon.model), f"plan {plan.root} in {sc.name}") \
            if mon.ops else ""
        return ExecutionResult(False, str(exc), f"{ran};;; stopped: {exc}\n", report, None,
                               views, "execution")
    names = list(matching.assigned)
    expected = model.settled(names)
    expected_sup = model.final_supports(names)
    verdict, seen, truth = _verdicts(robot, eyes, world, sc, shape_of, rules, expected,
                                     expected_sup, tr.alignments)
    views["execution-final"] = eyes.last_images  # the views the verdict was read from
    report.update(verdict.to_json())
    report.update(
        stage="verification",
        verification={"cameras": verdict.success, "ground_truth": truth.success},
        commands=len(tr.commands),
        expected={"relations": [[t, n, list(o) if len(o) > 1 else o[0]]
                                for n, (t, o) in sorted(expected_sup.items())],
                  "positions": {n: _r(p) for n, p in sorted(expected.items())},
                  "aligned": [{"object": a.subject, "with": a.partner, "face": a.face}
                              for a in tr.alignments]},
        final_state_source="object-finder",
        inferred_hidden=seen.inferred,
        ground_truth_mismatches=truth.mismatches,
        faults=injector.injected,
        faults_not_injected=injector.missed(),
        ground_truth_toppled=_toppled(world),
        robot={"grasps": log.grasps, "sim_time": round(log.time, 2)},
    )
    msg = "the executed structure matches the plan" if verdict.success else \
        "the executed structure does not match the plan: " + \
        "; ".join(m["message"] for m in verdict.mismatches)
    report["failure"] = None if verdict.success else f"verification: {msg}"
    title = f"plan {plan.root} in {sc.name}"
    return ExecutionResult(verdict.success, msg, format_commands(tr, title), report, tr, views,
                           None if verdict.success else "verification")


AUTHOR_MM = 15.0  # a measured block this near an execute object's given centre is it


def authors_names(text: str, matching: Any, measured: Sequence[Any], sc: Any,
                  shape_of: Mapping[str, str]) -> str:
    """``text`` with each quoted plan object followed by the name the scenario's author gave
    it in execute.objects, where the block the cameras matched it to first stood at that
    object's given centre, with its shape (helper round 7: "remove q2" was reported as
    "'p1' is gone"). The system matches by shape; the names only help the author read."""
    def author(name: str) -> str | None:
        if name not in matching.assigned:
            return None
        at = measured[matching.assigned[name]].position
        near = [(math.dist(at, o.center), o.name) for o in sc.execute.objects.values()
                if o.shape == shape_of.get(name)]
        d, own = min(near, default=(math.inf, None))
        return own if d <= AUTHOR_MM and own != name else None

    def named(m: re.Match) -> str:
        own = author(m.group(1))
        return m.group(0) if own is None else f"{m.group(0)} (execute.objects '{own}')"

    return re.sub(r"'([a-z][a-z0-9_:-]*)'", named, text)


def fault_notes(report: dict[str, Any]) -> list[str]:
    """One line per scenario fault that never fired (execution.json faults_not_injected)."""
    out = []
    for f in report.get("faults_not_injected", ()):
        when = f"during ACHIEVE {f['during']}" if "during" in f else f"after ACHIEVE {f['after']}"
        what = f" of '{f['object']}'" if "object" in f else ""
        where = f" (line {f['line']})" if "line" in f else ""
        out.append(f"note: the {f['kind']}{what} {when}{where} never happened: the robot "
                   "did not get that far, or the object was already gone")
    return out


def _verdicts(robot: Any, eyes: Eyes, world: Any, sc: Any, shape_of: dict[str, str],
              rules: Any, expected: dict[str, Any], supports: dict[str, tuple],
              alignments: list) -> tuple[Any, Any, Any]:
    """The arm steps out of view, the world settles, and the cameras (the verdict, what
    they saw) and the simulator (evaluation only) compare what stands with ``expected``."""
    step_aside(robot, rules)  # the cameras must see the structure, not the gripper
    robot.settle(SETTLE_S)
    fine = {"alignments": alignments, "coplanar_tolerance": rules.fine.coplanar_tolerance}
    verdict, seen = camera_verdict(eyes, expected, supports, rules.support_relations, fine)
    truth = verify(expected, supports, _final_state(world, sc, expected, shape_of),
                   rules.support_relations, **fine)
    return verdict, seen, truth


def _stopped_verdict(planned: Trace, robot: Any, eyes: Eyes, world: Any, sc: Any,
                     shape_of: dict[str, str], rules: Any) -> dict[str, bool]:
    """Both verdicts on a run that stopped: what stands against the plan's traced final
    state (the structure is unfinished, so they normally both say no). A block still in
    the jaws is not where the plan puts it, and stepping aside would carry it through
    the structure: both say no without looking."""
    if robot.gripper.holding:
        return {"cameras": False, "ground_truth": False}
    names = list(shape_of)
    verdict, _, truth = _verdicts(robot, eyes, world, sc, shape_of, rules,
                                  planned.model.settled(names),
                                  planned.model.final_supports(names), planned.alignments)
    return {"cameras": verdict.success, "ground_truth": truth.success}


def _toppled(world: Any) -> list[str]:
    """World blocks lying tilted (ground truth, evaluation only: the bench's scoring)."""
    return sorted(n for n, a in world.angles().items() if tilt(a, world.sizes[n]) > TOPPLE_RAD)


def _steps(injector: Any, watch: Any, on_step: Callable[[Any], None] | None
           ) -> Callable[[Any], None]:
    """The robot's per-step hook: the world's faults first, then the monitor's eyes on the
    robot (frames rendered once, reused by the caller's video), then the caller's."""
    def step(world: Any) -> None:
        injector.on_step(world)
        if watch is not None:
            watch(world)
        if on_step is not None:
            on_step(world)
    return step


def _taught(plan: Plan, sc: Any) -> dict[str, dict]:
    """Taught objects {name: {shape, position}}; every plan object must be among them."""
    teach = {n: {"shape": o.shape, "position": list(o.center)} for n, o in sc.teach.objects.items()}
    taught = taught_shapes(plan, teach)
    for name in plan_objects(plan):
        if name not in taught:
            raise InputError(f"the plan uses object '{name}', which the scenario's teach "
                             "workspace does not have", file=plan.file, where="root")
        if taught[name]["shape"] not in sc.shapes:
            raise InputError(f"object '{name}' has shape '{taught[name]['shape']}', which the "
                             "scenario's shapes do not define", file=plan.file, where="objects")
    return taught


def measure_initial_state(world: Any, sc: Any, images: dict, needs: Counter | None = None
                          ) -> tuple[list[Measured], str]:
    """The execution workspace's objects as the object-finder sees them (Sec. VII-A 3).

    The finder reads only the two camera images; the world is passed for the
    report's ground-truth comparison, never to the finder. ``needs`` (shape -> count,
    the plan's objects): a block of a shape seen more often than needed may be read as
    a stack of needed shapes the finder missed, where the images allow it.
    """
    from perception.vision.camera import default_cameras
    from perception.vision.frames import Frame
    from perception.vision.vfd.objects import ObjectFinder
    from perception.vision.vfd.resources import VisionResources

    finder = ObjectFinder(default_cameras(), VisionResources())
    frame = Frame(0, world.time, images["top"], images["side"])
    # Best-fitting first: matching is first come first served, so the surest
    # measurement of a shape is used first and doubtful extra ones are left over.
    found = finder.find(frame, sc.shapes)
    if needs:
        found = finder.restack(frame, found, needs, sc.shapes)
    found = sorted(found, key=lambda f: f.mismatch)
    return [Measured(f.shape, tuple(f.position), tuple(f.size)) for f in found], "object-finder"


def _model(taught: dict, shapes: dict, matching: Any, measured: list[Measured],
           rules: RuleSet) -> EnvModel:
    """The execution environment model: plan objects at measured places, the rest obstacles."""
    bodies = {}
    for name, i in matching.assigned.items():
        shape = taught[name]["shape"]
        bodies[name] = Body(shape, tuple(shapes[shape]), tuple(measured[i].position))
    for k, i in enumerate(matching.unmatched, 1):
        m = measured[i]
        bodies[f"unused-{m.shape}-{k}"] = Body(m.shape, tuple(m.size), tuple(m.position), False)
    return EnvModel.measured(rules, bodies, rules.commands.home)


def _final_state(world: Any, sc: Any, expected: dict[str, tuple],
                 shape_of: dict[str, str]) -> dict[str, ObjectState]:
    """Final ground-truth states, named by plan object (evaluation only).

    Blocks of one shape are interchangeable: each plan object is the world body
    of its shape nearest to where it is expected (the robot may have used a
    spare for a removed one).
    """
    pos, ang = world.positions(), world.angles()
    bodies = list(world.names)
    truth = [Measured(sc.execute.objects[b].shape, pos[b], world.sizes[b]) for b in bodies]
    named = pair_by_shape(expected, shape_of, truth)
    out = {n: ObjectState(pos[bodies[i]], world.sizes[bodies[i]], ang[bodies[i]])
           for n, i in named.items()}
    for i, b in enumerate(bodies):
        if i not in named.values():
            out[f"unused:{b}"] = ObjectState(pos[b], world.sizes[b], ang[b])
    return out


def write_views(out: OutputDir, views: dict[str, Any]) -> None:
    """Stage each view pair as one PNG: top and side camera images side by side."""
    import cv2
    import numpy as np

    for name, imgs in views.items():
        cv2.imwrite(str(out.path(f"{name}.png")), np.hstack([imgs["top"], imgs["side"]]))


def _r(v: Any) -> list[float]:
    """Round a vector for the report."""
    return [round(float(c), 1) for c in v]

