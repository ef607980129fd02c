"""ENV-nodes backed by images: each answers the events its detector's methods name (Table III)."""

from __future__ import annotations


def vocabulary() -> dict[str, dict[str, frozenset]]:
    """Detector name -> the methods it answers and the answers its comparisons give."""
    from perception.vision.envnodes.registry import VOCABULARY

    return VOCABULARY
