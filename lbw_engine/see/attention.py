"""ATTN-nodes and the attention stack (Sec. IV-B3, Table VIII).

The stack has one level per depth of motion (rules/motions.yaml). Each level
holds ATTN-nodes: an expected event, the ENV-nodes it concerns, the ACT-node
that will interpret it, and the detection recorded by the last detect pass.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lbw_engine.see.detectors import Detection

if TYPE_CHECKING:  # pragma: no cover
    from lbw_engine.see.actmodel import ActNode


@dataclass(eq=False)
class AttnNode:
    """An expected event with its base/target ENV-nodes and owning ACT-node."""

    event: str
    base: tuple[str, ...]
    target: tuple[str, ...]
    owner: ActNode
    detection: Detection | None = None
    asked: bool = False  # queried during the current frame

    def describe(self) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
        """(event, base, target), for tests and traces of the stack."""
        return (self.event, self.base, self.target)


class AttentionStack:
    """Levels of ATTN-nodes, bottom (coarse motions) to top (fine motions)."""

    def __init__(self) -> None:
        self.levels: list[list[AttnNode]] = []

    def _level(self, level: int) -> list[AttnNode]:
        while len(self.levels) <= level:
            self.levels.append([])
        return self.levels[level]

    def add(self, level: int, node: AttnNode) -> None:
        """:add - put ``node`` on ``level``, replacing a node waiting for the same event."""
        nodes = self._level(level)
        for index, other in enumerate(nodes):
            if other.event == node.event:
                nodes[index] = node
                return
        nodes.append(node)

    def reset(self, level: int, node: AttnNode | None = None) -> None:
        """:reset - pop ``level`` and every level above it, then place ``node`` there."""
        del self.levels[level:]
        if node is not None:
            self._level(level).append(node)

    def delete(self, level: int, node: AttnNode | None = None, event: str | None = None) -> None:
        """:delete - remove ``node`` (or the node waiting for ``event``) from ``level``."""
        if level < len(self.levels):
            self.levels[level] = [
                n
                for n in self.levels[level]
                if n is not node and (event is None or n.event != event)
            ]

    def scan(self) -> Iterator[AttnNode]:
        """All nodes from the bottom level to the top (Sec. V-A detect order)."""
        for nodes in list(self.levels):
            yield from list(nodes)

    def contains(self, node: AttnNode) -> bool:
        """Whether ``node`` is still on the stack."""
        return any(n is node for n in self.scan())

    def describe(self) -> list[list[tuple[str, tuple[str, ...], tuple[str, ...]]]]:
        """Per level, the (event, base, target) of each node; empty top levels dropped."""
        out = [[n.describe() for n in nodes] for nodes in self.levels]
        while out and not out[-1]:
            out.pop()
        return out
