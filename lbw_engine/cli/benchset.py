"""The scenario set of ``lbw bench``: which generator seed, noise level and family
each scenario of ``--count N --seed S [--families ...]`` gets. A pure function of
the arguments, so any runner (one process, ``--jobs``, a cluster) and ``--resume``
see the same set."""

from __future__ import annotations

from collections.abc import Sequence

from lbw_engine.errors import InputError

LEVELS = ("nominal", "2x", "4x")


def tasks(count: int, seed: int, families: Sequence[str] | None = None
          ) -> list[tuple[int, str, str]]:
    """(generator seed, noise level, family) of each scenario of the set."""
    from perception.world.generator import FAMILIES, family_of

    fams = tuple(families or FAMILIES)
    return [(seed * 1000 + i, LEVELS[i % len(LEVELS)], family_of(i, fams)) for i in range(count)]


def parse_families(text: str | None) -> tuple[str, ...] | None:
    """``--families a,b``: known family names, in the order given (InputError if not)."""
    if text is None:
        return None
    from perception.world.generator import FAMILIES

    names = tuple(n.strip() for n in text.split(",") if n.strip())
    unknown = [n for n in names if n not in FAMILIES]
    if unknown or not names:
        raise InputError(f"unknown family {', '.join(unknown) or '(none given)'} "
                         f"(families: {', '.join(FAMILIES)})", where="--families")
    return names
