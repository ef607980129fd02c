"""Write the replay traces of tests/data/traces/ and the bundled demo trace.

Run: .venv/bin/python tests/data/traces/make_traces.py
The traces are what detectors would report while a person performs the tasks
of Fig. 12 (an inverted arch on a pillar) and Fig. 20 (Build Table); positions
of Fig. 20 are those of Fig. 21. Committed output; this script documents how
it was made.
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEMO = HERE.parents[2] / "lbw_engine" / "data" / "build-table.trace.jsonl"
HEADER = {"format": "lbw-event-trace", "version": 1}


class Trace:
    """A trace under construction: one record per detector answer."""

    def __init__(self, objects: dict[str, dict]) -> None:
        self.t = 0.0
        self.lines: list[dict] = [HEADER]
        self.pos = {n: list(o["position"]) for n, o in objects.items()}
        self.size = {n: o["size"] for n, o in objects.items()}
        self.rec(event="loc-exist", found=list(objects), objects=objects)

    def rec(self, **data) -> None:
        """Append a record at the current time."""
        self.lines.append({"t": round(self.t, 2), **data})

    def tick(self, dt: float = 0.5) -> None:
        """Advance the clock."""
        self.t += dt

    def hand_at(self, xy, z) -> list[float]:
        """A hand position above ``xy``."""
        return [round(xy[0], 1), round(xy[1], 1), z]

    def enter(self) -> None:
        """The hand comes into view (Task :Found-moving)."""
        self.tick(1.0)
        self.rec(event="found-moving", found=["hand"], positions={"hand": [250.0, 350.0, 200.0]})

    def descend(self, xy, value: str | None = None) -> None:
        """A slow downward motion above ``xy`` (Transfer :Small-motion)."""
        self.tick()
        extra = {"value": value} if value else {"velocity": [2.0, -3.0, -30.0]}
        self.rec(event="small-motion", positions={"hand": self.hand_at(xy, 120.0)}, **extra)

    def local(self, found, diff: str, at, end: str = "far") -> None:
        """Near the target, touch, let go, move off; the change-detector's result."""
        self.tick()
        self.rec(event="near", found=list(found))
        self.tick()
        self.rec(event="join")
        self.tick()
        self.rec(event="split")
        self.tick()
        if end == "far":
            self.rec(event="far", positions={"hand": self.hand_at(at, 150.0)})
        else:
            hand = [167.5, 153.2, 125.2]  # Fig. 21's final hand position
            self.rec(event="found-moving", found=["hand"], positions={"hand": hand})
        self.rec(detector="change-detector", value=diff, at=[round(c, 1) for c in at])

    def pick(self, name: str) -> None:
        """Reach down to ``name`` and take it."""
        self.descend(self.pos[name][:2])
        self.local([name], "decreased", self.pos[name])

    def place(self, name: str, supports, xy, end: str = "far") -> None:
        """Put the held ``name`` on ``supports`` at ``xy``; the change is measured 4 mm low."""
        self.descend(xy)
        top = max(self.pos[s][2] + self.size[s][2] / 2 if s != "table" else 0.0 for s in supports)
        measured = [xy[0], xy[1], top + self.size[name][2] / 2 - 4.0]  # measured a little low
        self.pos[name] = [xy[0], xy[1], top + self.size[name][2] / 2]
        self.local(supports, "increased", measured, end)

    def touch(self, name: str) -> None:
        """Come down to ``name``, stay, and leave it where it is (NO-OP)."""
        self.descend(self.pos[name][:2], value="staying")
        self.local([name], "no-change", self.pos[name])

    def leave(self) -> None:
        """The hand leaves the view."""
        self.tick()
        self.rec(event="disappeared")

    def write(self, path: Path) -> None:
        """Write the trace as JSON Lines."""
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("".join(json.dumps(line) + "\n" for line in self.lines))


def obj(shape: str, size, xy) -> dict:
    """An object standing on the table at ``xy``."""
    return {"shape": shape, "size": list(size), "position": [xy[0], xy[1], size[2] / 2]}


def build_table() -> Trace:
    """Fig. 20: four bricks as legs, then the plate on them (positions of Fig. 21)."""
    brick = (30.0, 30.0, 50.0)
    legs = {
        "brick190": ((-200.0, 300.0), (-24.9, 178.9)),
        "brick186": ((-120.0, 320.0), (12.5, 126.9)),
        "brick187": ((-200.0, 60.0), (-73.1, 137.3)),
        "brick188": ((-120.0, 40.0), (-42.9, 85.7)),
    }
    objects = {n: obj("brick", brick, start) for n, (start, _) in legs.items()}
    objects["plate189"] = obj("plate", (130.0, 130.0, 19.6), (180.0, 250.0))
    tr = Trace(objects)
    tr.enter()
    for name, (_, goal) in legs.items():
        tr.pick(name)
        tr.place(name, ["table"], goal)
    tr.pick("plate189")
    tr.place("plate189", list(legs), (-25.1, 151.0), end="found-moving")
    tr.leave()
    return tr


def inverted_arch() -> Trace:
    """Fig. 12: a pillar, a plank carrying two bricks put on it (Fig. 14)."""
    objects = {
        "short-brick1": obj("short-brick", (30.0, 30.0, 50.0), (-150.0, 300.0)),
        "planar-brick2": obj("planar-brick", (140.0, 60.0, 10.0), (100.0, 100.0)),
        "medium-brick3": obj("medium-brick", (30.0, 30.0, 70.0), (-200.0, 100.0)),
        "medium-brick4": obj("medium-brick", (30.0, 30.0, 70.0), (200.0, 320.0)),
    }
    tr = Trace(objects)
    tr.enter()
    tr.pick("short-brick1")
    tr.place("short-brick1", ["table"], (-20.7, 126.6))
    tr.pick("medium-brick3")
    tr.place("medium-brick3", ["planar-brick2"], (83.5, 115.3))
    tr.touch("short-brick1")
    tr.pick("medium-brick4")
    tr.place("medium-brick4", ["planar-brick2"], (134.3, 57.6))
    tr.pick("planar-brick2")
    tr.place("planar-brick2", ["short-brick1"], (-36.7, 128.4))
    tr.tick()
    tr.rec(event="found-moving", found=["hand"], positions={"hand": [200.0, 300.0, 200.0]})
    tr.leave()
    return tr


def pick_from_block() -> Trace:
    """A brick standing on another is picked and put on the table (Sec. IX-B3)."""
    objects = {
        "brick1": obj("brick", (30.0, 30.0, 50.0), (0.0, 200.0)),
        "brick2": obj("brick", (30.0, 30.0, 50.0), (0.0, 200.0)),
    }
    objects["brick2"]["position"][2] = 75.0  # brick2 stands on brick1
    tr = Trace(objects)
    tr.enter()
    tr.pick("brick2")
    tr.place("brick2", ["table"], (120.0, 200.0))
    tr.leave()
    return tr


if __name__ == "__main__":
    pick_from_block().write(HERE / "pick-from-block.jsonl")
    build_table().write(HERE / "fig20-build-table.jsonl")
    build_table().write(DEMO)
    inverted_arch().write(HERE / "fig12-inverted-arch.jsonl")
