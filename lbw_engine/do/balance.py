"""Static balance of the expected structure: does every stack stay standing?

The plan's ``$parallel`` branches carry no order (Fig. 17), yet the order in
which parts are added can matter physically: a brick put first on the
overhanging end of a plank that already lies on a pillar tips the plank over,
while the other brick first keeps it up (the inverted arch, Fig. 14). An
object resting on other objects stands while the centre of mass of it and
everything riding on it (mass taken proportional to volume, all blocks being
of one material) lies over the region where it meets its supports, shrunk by
``balance_margin`` (commands.yaml) for measurement error.

The same test guards each placement (``steadied``): a taught placement whose
load could not stand where it is put (its offset on the support was measured
wrong while watching: the demonstrated structure stood) is moved the least
distance that puts the load's centre of mass ``steady_margin`` inside where it
meets its supports.
"""

from __future__ import annotations

from collections.abc import Sequence

from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import TABLE


def unbalanced(model: EnvModel, margin: float) -> str | None:
    """The first object (by name) that would tip over its supports, if any."""
    for name in sorted(model.bodies):
        rel = model.support_of(name)
        if rel is None or model.holding() == name:
            continue
        under = _raised(model, rel.objects)
        if under and not _over(name, under, model, margin):
            return name
    return None


def steadied(model: EnvModel, name: str, xy: tuple[float, float], supports: list[str],
             margin: float, steady: float, coming: Sequence[tuple[float, float, float]] = ()
             ) -> tuple[tuple[float, float], float]:
    """Where ``name`` (held, its riders with it, and what the plan will still put on it:
    ``coming``, x-y offsets from it and volumes) can be put on ``supports`` near ``xy``.

    Per axis: when the load's centre of mass at ``xy`` is within ``margin`` of
    the edge of where the object would meet its supports (or beyond it), the
    object moves along that axis until the centre of mass is ``steady`` mm
    inside (at most to the middle of the supports). The load is the object with
    its riders, which must stand until the rest comes, and with ``coming`` too:
    the spot must suit both, or else the first. Returns the x-y and how far it
    moved (mm). Placements on the table, or partly on it, are not moved.
    """
    under = _raised(model, supports)
    if not under:
        return xy, 0.0
    b = model.bodies[name]
    com, mass = _load(model, name)
    total = mass + sum(v for _, _, v in coming)
    out = list(xy)
    for k in range(2):
        # centres of mass relative to the object's centre (they move with it): the load
        # now, and with what is to come
        now = com[k] - b.position[k]
        loads = [now] + ([(mass * now + sum(v * d[k] for *d, v in coming)) / total]
                         if coming else [])
        half = b.size[k] / 2
        # off the object's own footprint: moving the object cannot help that load
        loads = [c for c in loads if -half + margin <= c <= half - margin]
        if not loads:
            continue
        lo, hi = _span(model, under, k)
        if all(lo + margin <= xy[k] + c <= hi - margin for c in loads):
            continue  # it stands where it was taught
        inset = min(steady, (hi - lo) / 2)
        # the object's centres that keep each load's centre of mass ``inset`` inside
        spans = [(lo + inset - c, hi - inset - c) for c in loads]
        low, high = max(a for a, _ in spans), min(z for _, z in spans)
        if low > high:  # no spot suits both: the load there now must stand
            low, high = spans[0]
        out[k] = min(max(xy[k], low), high)
    moved = ((out[0] - xy[0]) ** 2 + (out[1] - xy[1]) ** 2) ** 0.5
    return (out[0], out[1]), moved


def _raised(model: EnvModel, supports: Sequence[str]) -> list[str]:
    """The supports, when all of them are objects; [] when the table holds any part."""
    under = [s for s in supports if s != TABLE and s in model.bodies]
    return under if under and len(under) == len(supports) else []


def _load(model: EnvModel, name: str) -> tuple[tuple[float, float], float]:
    """x-y centre of mass of ``name`` and everything riding on it, and their mass."""
    load = [name, *model.supported_by(name)]
    mass = [volume(model.bodies[n].size) for n in load]
    total = sum(mass)
    return tuple(sum(m * model.bodies[n].position[k] for m, n in zip(mass, load, strict=True))
                 / total for k in range(2)), total


def _span(model: EnvModel, names: Sequence[str], k: int) -> tuple[float, float]:
    """Joint extent of the objects ``names`` along axis ``k``."""
    return (min(model.bodies[s].position[k] - model.bodies[s].size[k] / 2 for s in names),
            max(model.bodies[s].position[k] + model.bodies[s].size[k] / 2 for s in names))


def _over(name: str, under: list[str], model: EnvModel, margin: float) -> bool:
    """Is the load's centre of mass over where ``name`` meets ``under``?"""
    b = model.bodies[name]
    com, _ = _load(model, name)
    for k in range(2):
        lo, hi = _span(model, under, k)
        lo, hi = max(b.position[k] - b.size[k] / 2, lo), min(b.position[k] + b.size[k] / 2, hi)
        if not lo + margin <= com[k] <= hi - margin:
            return False
    return True


def volume(size: Sequence[float]) -> float:
    """A block's volume (mm³), its mass up to the common density."""
    return size[0] * size[1] * size[2]
