"""Verification of an executed assembly against the plan's expected final state.

The executed structure is equivalent to the taught one (Sec. VIII, Fig. 18)
when, among the plan's objects, the same support relations hold (which rests
on what), every object is within a tolerance of its expected position — the
taught world positions, since the placements ground out on the table — and
nothing has toppled; and the faces the demonstration aligned (ALIGN, Sec.
V-B5) are coplanar within the fine motion's ``coplanar-tolerance``. Pure
logic: the caller measures the final state.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from lbw_engine.do.fine import Alignment, coplanar_errors
from lbw_engine.model.geometry import Vec, support_relations, tilt, tilted

POSITION_TOLERANCE_MM = 5.0
TOPPLE_RAD = 0.2  # ~11°: a block tilted more than this has fallen over
# The final state is the world's ground truth, exact to the physics' contact slop, so
# a support bears a block whose footprint it meets by any more than this; the
# recognizer's 3 mm (geometry.SUPPORT_OVERLAP_MM) allows for measurement error and
# would miss a support of a small block (a 12 mm cube across a 4-8 mm gap rests on
# 2-4 mm of each cube, issue #12).
CONTACT_OVERLAP_MM = 0.5


@dataclass(frozen=True)
class ObjectState:
    """A measured object: centre, size (mm) and tilt in the x-z plane (rad)."""

    position: Vec
    size: Vec
    angle: float = 0.0


@dataclass
class Verdict:
    """Success, the measured final relations and positions, and every mismatch."""

    success: bool
    relations: list[list] = field(default_factory=list)
    positions: dict[str, list[float]] = field(default_factory=dict)
    mismatches: list[dict] = field(default_factory=list)

    def to_json(self) -> dict:
        """The verification part of execution.json."""
        return {"success": self.success, "relations": self.relations,
                "positions": self.positions, "mismatches": self.mismatches}


def verify(
    expected_positions: Mapping[str, Vec],
    expected_supports: Mapping[str, tuple[str, tuple[str, ...]]],
    measured: Mapping[str, ObjectState],
    support_types: tuple[str, ...],
    tolerance: float = POSITION_TOLERANCE_MM,
    topple_rad: float = TOPPLE_RAD,
    alignments: Sequence[Alignment] = (),
    coplanar_tolerance: float = 2.0,
    support_overlap: float = CONTACT_OVERLAP_MM,
) -> Verdict:
    """Compare the measured final state of the plan's objects with the expected one.

    ``measured`` may hold objects the plan does not use: they count as
    possible supports, so a block resting on a stray object is a mismatch.
    """
    names = sorted(expected_positions)
    boxes = {n: tilted(s.position, s.size, s.angle) for n, s in measured.items()}
    supports = support_relations(boxes, support_types[0], support_types[-1], support_overlap)
    mismatches: list[dict] = []
    relations: list[list] = []
    positions: dict[str, list[float]] = {}
    for name in names:
        state = measured.get(name)
        if state is None:
            mismatches.append(_mm("missing", name, "present", None,
                                  f"'{name}' was not found in the final state"))
            continue
        positions[name] = [round(c, 1) for c in state.position]
        turned = tilt(state.angle, state.size)
        if turned > topple_rad:
            mismatches.append(_mm("toppled", name, 0.0, round(state.angle, 3),
                                  f"'{name}' is tilted by {turned:.2f} rad"))
        got = supports.get(name)
        if got is not None:
            relations.append([got[0], name, list(got[1]) if len(got[1]) > 1 else got[1][0]])
        want = expected_supports.get(name)
        if want is not None and (got is None or set(got[1]) != set(want[1])):
            mismatches.append(_mm(
                "relation", name, [want[0], list(want[1])],
                None if got is None else [got[0], list(got[1])],
                f"'{name}' should rest on {', '.join(want[1])} but rests on "
                f"{'nothing' if got is None else ', '.join(got[1])}",
            ))
        exp = expected_positions[name]
        err = max(abs(state.position[k] - exp[k]) for k in range(3))
        if err > tolerance:
            mismatches.append(_mm(
                "position", name, [round(c, 1) for c in exp], positions[name],
                f"'{name}' is {err:.1f} mm from its goal (tolerance {tolerance:.0f} mm)",
            ))
    mismatches += _alignments(alignments, measured, coplanar_tolerance)
    return Verdict(not mismatches, relations, positions, mismatches)


def _alignments(alignments: Sequence[Alignment], measured: Mapping[str, ObjectState],
                tolerance: float) -> list[dict]:
    """A mismatch for each aligned pair whose faces are not coplanar."""
    out = []
    for a in alignments:
        if a.subject not in measured or a.partner not in measured:
            continue  # reported as missing
        pos = {n: measured[n].position for n in (a.subject, a.partner)}
        size = {n: measured[n].size for n in (a.subject, a.partner)}
        # The distance across the contact is held by the position check; the faces
        # must be flush more closely than positions are checked.
        face, gap = coplanar_errors(a, pos, size)
        if face > tolerance:
            out.append(_mm(
                "aligned", a.subject,
                {"with": a.partner, "face": a.face, "face_mm": 0.0, "gap_mm": round(a.gap, 1)},
                {"with": a.partner, "face": a.face, "face_mm": round(face, 1),
                 "gap_mm": round(gap, 1)},
                f"the {a.face} faces of '{a.subject}' and '{a.partner}' should be coplanar: "
                f"they are {face:.1f} mm apart (tolerance {tolerance:g} mm)"))
    return out


def _mm(kind: str, name: str, expected: object, measured: object, message: str) -> dict:
    """One mismatch record."""
    return {"kind": kind, "object": name, "expected": expected, "measured": measured,
            "message": message}
