"""Static balance of the expected structure: does every stack stay standing?

The plan's ``$parallel`` branches carry no order (Fig. 17), yet the order in
which parts are added can matter physically: a brick put first on the
overhanging end of a plank that already lies on a pillar tips the plank over,
while the other brick first keeps it up (the inverted arch, Fig. 14). An
object resting on other objects stands while the centre of mass of it and
everything riding on it (mass taken proportional to volume, all blocks being
of one material) lies over the region where it meets its supports, shrunk by
``balance_margin`` (commands.yaml) for measurement error.
"""

from __future__ import annotations

from .geometry import TABLE
from .model import ExecModel


def unbalanced(model: ExecModel, margin: float) -> str | None:
    """The first object (by name) that would tip over its supports, if any."""
    for name in sorted(model.bodies):
        rel = model.support_of(name)
        if rel is None or model.held == name:
            continue
        under = [s for s in rel[2] if s != TABLE and s in model.bodies]
        if not under or len(under) < len(rel[2]):
            continue  # on the table (alone or in part): the table holds it
        if not _over(name, under, model, margin):
            return name
    return None


def _over(name: str, under: list[str], model: ExecModel, margin: float) -> bool:
    """Is the load's centre of mass over where ``name`` meets ``under``?"""
    load = [name, *model.riders(name)]
    mass = [_volume(model, n) for n in load]
    total = sum(mass)
    b = model.bodies[name]
    for k in range(2):
        com = sum(m * model.bodies[n].position[k] for m, n in zip(mass, load, strict=True)) / total
        lo = max(b.position[k] - b.size[k] / 2,
                 min(model.bodies[s].position[k] - model.bodies[s].size[k] / 2 for s in under))
        hi = min(b.position[k] + b.size[k] / 2,
                 max(model.bodies[s].position[k] + model.bodies[s].size[k] / 2 for s in under))
        if not lo + margin <= com <= hi - margin:
            return False
    return True


def _volume(model: ExecModel, name: str) -> float:
    """An object's volume (mm³), its mass up to the common density."""
    s = model.bodies[name].size
    return s[0] * s[1] * s[2]
