"""The recognized action sequence as ``actions.json`` (design.md)."""

from __future__ import annotations

from collections import Counter
from typing import Any

from lbw_engine.see.actmodel import ActNode
from lbw_engine.see.recognizer import Recognizer


def _fine(rec: Recognizer, node: ActNode) -> list[dict[str, Any]]:
    """Sub-motions of ``node`` whose class rules/motions.yaml marks ``fine``."""
    return [
        {
            "operation": sub.operation,
            "t_start": round(sub.t_start, 3),
            "t_end": round(sub.t_end, 3) if sub.t_end is not None else None,
        }
        for sub in node.history
        if rec.rules.motions[sub.motion].fine
    ]


def operation_names(labels: list[str]) -> list[str]:
    """Fig. 12 style names: the operation's label and a per-label count."""
    counts: Counter[str] = Counter()
    out = []
    for key in labels:
        counts[key] += 1
        out.append(f"{key}{counts[key]:02d}")
    return out


def to_actions(rec: Recognizer) -> dict[str, Any]:
    """The actions.json document of a finished recognizer."""
    history = rec.root.history if rec.root is not None else []
    names = operation_names([rec.rules.label(n.motion, n.operation) for n in history])
    ops = []
    for name, node in zip(names, history, strict=True):
        ops.append(
            {
                "name": name,
                "operation": node.operation,
                "motion": node.motion,
                "t_start": round(node.t_start, 3),
                "t_end": round(node.t_end, 3) if node.t_end is not None else None,
                "initial_event": node.initial_event,
                "final_event": node.final_event,
                "base": list(node.base),
                "target": list(node.target),
                "special": list(node.special),
                "fine": _fine(rec, node),
                "initial_state": node.initial_state.to_json() if node.initial_state else {},
                "final_state": node.final_state.to_json() if node.final_state else {},
            }
        )
    objects = {
        name: {"shape": o["shape"], "position": [round(c, 1) for c in o["position"]]}
        for name, o in rec.initial_objects.items()
    }
    return {"objects": objects, "operations": ops}


def sequence(rec: Recognizer) -> list[str]:
    """The recognized operations, in order (Fig. 12 / Fig. 20)."""
    return [n.operation for n in rec.root.history] if rec.root is not None else []
