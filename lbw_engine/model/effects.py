"""What a recognized operation changes in the environment model (Sec. V-B4, Fig. 21).

``apply_effect`` runs one rule of rules/effects.yaml on an EnvModel: remove the
relation templates, move the object (it follows the hand; or it is put at the
measured point, its height from the tops of its supports, Sec. IX-A2), then add
the relation templates. Where the placed object comes to rest is read with the
one support test of ``geometry.resting_on``.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.model.env import EnvModel, EnvNode, Relation, Vec3, _add, _sub
from lbw_engine.model.geometry import resting_on
from lbw_engine.names import TABLE
from lbw_engine.rules import EffectRule, Template


def apply_effect(
    env: EnvModel, rule: EffectRule, binds: dict[str, tuple[str, ...]], measured: dict[str, Any]
) -> None:
    """Apply one operation's effect: remove, move, then add relations."""
    for tpl in rule.remove:
        env.relations = [r for r in env.relations if not _matches(env, r, tpl, binds)]
    if "follow" in rule.move:
        env.follow(binds[rule.move["object"][1:]])
    if "place" in rule.move:
        point = measured.get(rule.move["measured"])
        on = rule.move["on"][1:]
        binds = {**binds, on: _place(env, binds[rule.move["place"][1:]], binds[on], point)}
    for tpl in rule.add:
        if tpl.when is not None:
            count = len(binds[tpl.when[1][1:]])
            if (tpl.when[0] == "single") != (count == 1):
                continue
        env.relations.extend(_instances(env, tpl, binds))

def _names(env: EnvModel, text: str, binds: dict[str, tuple[str, ...]]) -> tuple[str, ...] | None:
    """Names a template term stands for; None for the wildcard."""
    if text == "*":
        return None
    return binds[text[1:].rstrip("*")]

def _matches(env: EnvModel, r: Relation, tpl: Template, binds) -> bool:
    if r.type != tpl.type:
        return False
    subj = _names(env, tpl.subject, binds)
    if subj is not None and r.subject not in subj:
        return False
    obj = _names(env, tpl.object, binds)
    if obj is None:
        return True
    return (r.obj in obj) if isinstance(r.obj, str) else set(r.obj) == set(obj)

def _instances(env: EnvModel, tpl: Template, binds) -> list[Relation]:
    subjects = _names(env, tpl.subject, binds) or ()
    if not tpl.subject.endswith("*"):
        subjects = subjects[:1]
    objs = _names(env, tpl.object, binds) or ()
    if not objs:
        return []
    obj: str | tuple[str, ...] = objs[0] if len(objs) == 1 else tuple(objs)
    out = []
    for subject in subjects:
        at = wrt = None
        if tpl.wrt is not None:
            ref = _names(env, tpl.wrt, binds) or ()
            if len(ref) == 1:
                wrt = ref[0]
                p, q = env.nodes[subject].position, env.nodes[wrt].position
                at = _sub(p, q) if p is not None and q is not None else None
        out.append(Relation(tpl.type, subject, obj, at, wrt if at is not None else None))
    return out

def _clear_of_neighbours(env: EnvModel, node: EnvNode, at: Vec3, ignore: set[str]) -> Vec3:
    """``at`` moved out of any block it overlaps sideways by a measurement error."""
    if node.size is None:
        return at
    clearance = float(env.rules.constants["place-clearance"])
    limit = float(env.rules.constants["place-overlap-limit"])
    pos = list(at)
    for other in env.nodes.values():
        if other.name in ignore or other.name == node.name or other.kind != node.kind:
            continue
        if other.position is None or other.size is None or other.name in env.followers:
            continue
        pen = [(node.size[i] + other.size[i]) / 2 - abs(pos[i] - other.position[i])
               for i in range(3)]
        if min(pen) <= 0:
            continue  # apart along some axis
        axis = 0 if pen[0] <= pen[1] else 1
        if pen[axis] > limit:
            continue  # not a measurement error: leave it for the physics to show
        away = 1.0 if pos[axis] >= other.position[axis] else -1.0
        pos[axis] += away * (pen[axis] + clearance)
    return (pos[0], pos[1], pos[2])

def _place(env: EnvModel, objects, supports, point: Vec3 | None) -> tuple[str, ...]:
    """Put the object at the measured point, its height from the supports' tops.

    Returns the supports it rests on there: the objects whose top face carries its
    bottom face under its footprint where it was let go (Sec. V-B4). The ones found
    on the way down (the hand still beside the spot) may be fewer or others.
    """
    tops = [env.nodes[s].top() for s in supports if s in env.nodes]
    for name in objects:
        node = env.nodes[name]
        riders = [r for r in env.followers if r != name]
        for moving in (name, *riders):
            env.followers.pop(moving, None)
        old = node.position or (0.0, 0.0, 0.0)
        x, y = (point[0], point[1]) if point is not None else (old[0], old[1])
        height = node.size[2] if node.size else 0.0
        z = (max(tops) if tops else 0.0) + height / 2.0
        node.position = _clear_of_neighbours(env, node, (float(x), float(y), float(z)),
                                                  set(supports) | set(riders))
        delta = _sub(node.position, old)
        for rider in riders:
            p = env.nodes[rider].position
            if p is not None:
                env.nodes[rider].position = _add(p, delta)
        if tops and all(env.nodes[s].kind == node.kind for s in supports if s in env.nodes):
            below = _carrying(env, node, set(riders))
            if below:
                supports = tuple(below)
    return tuple(supports)

def _carrying(env: EnvModel, node: EnvNode, riders: set[str]) -> list[str]:
    """The objects ``node`` rests on where it is now (geometry.resting_on), riders aside."""
    boxes = env.boxes()
    if node.name not in boxes:
        return []
    return [n for n in resting_on(node.name, boxes, frozenset(riders)) if n != TABLE]
