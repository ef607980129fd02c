"""Tall free-standing towers stand in the simulated world (stop 32, round 15's AG).

With 4 substeps and 10 solver iterations a tower of six aligned 30 mm cubes rocked with
growing amplitude and fell with nothing touching it; in the teach world a 6-high tower
of 20 x 20 x 45 blocks collapsed after the demonstration in 15 of 25 runs. Each row
is a tower that balances (each block's load centred within its support's top) and must
stand for 20 s; the last falls (its upper blocks' centre of mass lies past the edge).
"""

import types

import pytest

from perception.world.physics import World


def _tower(n: int, width: float, height: float, offset: float) -> World:
    """``n`` blocks stacked, each set ``offset`` mm along x from the one under it."""
    return World([types.SimpleNamespace(
        name=f"b{i}", size=(width, width, height), center=(offset * i, 200.0, height * (i + .5)),
        on=["table"] if i == 0 else [f"b{i - 1}"]) for i in range(n)])


def _fell(world: World, seconds: float = 20.0) -> bool:
    for _ in range(int(30 * seconds)):
        world.step(1 / 30)
    return any(abs(a) > 0.3 for a in world.angles().values())


@pytest.mark.parametrize("n,width,height,offset", [
    (6, 30, 30, 0), (6, 30, 30, 1), (6, 30, 30, 4),  # 180 mm of 30 mm cubes
    (6, 20, 45, 0), (6, 20, 45, 1),  # 270 mm of 20 x 20 x 45 blocks
    (5, 30, 59, 0), (5, 30, 59, 1), (5, 30, 59, 4),  # 295 mm (round 15, 64)
    (6, 40, 40, 1), (6, 40, 40, 4),
], ids=lambda v: str(v))
def test_a_balanced_tall_tower_stands(n, width, height, offset):
    assert not _fell(_tower(n, width, height, offset))


def test_a_tower_whose_top_overhangs_falls():
    """Blocks 1-3 of 20 mm set off 6 mm each: their centre of mass is 12 mm past the
    lowest block's centre, 2 mm past its edge."""
    assert _fell(_tower(4, 20, 45, 6))
