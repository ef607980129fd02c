"""The common shape of an image-backed ENV-node: a method table and the Detector protocol.

An ENV-node answers an ATTN-node's query (lbw_engine.see.detectors.Query) by
the method the rules' event-table names (Table II): ``methods`` maps each
method word of the node's closed vocabulary to the Python function that
answers it. ``answers`` lists what its snapshot comparisons can return. Every
node is fed each frame through ``begin_frame``; the shared ``HandState``
updates once per frame whichever node is first.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.model.env import EnvModel
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import ActView, Detection, Query
from perception.vision.envnodes.hand import HandState


class EnvNodeBase:
    """One detector of rules/events.yaml, answering from images (the Detector protocol)."""

    name = ""
    calls: dict[str, str] = {}  # method word (the node's vocabulary) -> Python method name
    answers: tuple[Any, ...] = ()  # what ``compare`` may return as its value

    def __init__(self, hand: HandState, rules: RuleSet) -> None:
        """A node on the shared hand state."""
        self.hand, self.rules = hand, rules
        self.sight = hand.sight
        self.methods = frozenset(self.calls)

    def begin_frame(self, t: float, frame: Any) -> None:
        """A new frame: the always-on detectors run once (HandState.update)."""
        self.hand.update(t, frame)

    def query(self, query: Query, env: EnvModel) -> Detection | None:
        """Answer the query by the method the event-table names."""
        method = self.calls.get(query.method)
        if method is None:
            raise InputError(f"detector {self.name!r} cannot answer {query.method!r} "
                             f"(asked for the event {query.event!r})")
        self.hand.observe(env)
        return getattr(self, method)(query, env)

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """No snapshot for this node."""
        return None

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """Nothing to compare."""
        return None
