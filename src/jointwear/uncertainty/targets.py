"""Dotted paths from a random variable to the config field it sets.

A path walks the SI config as plain data: ``mechanism.rod.length``, ``clearance_joints.0.journal_radius``.
The suffix ``.clearance`` on a clearance joint is a derived target: the bearing radius becomes the
(sampled) journal radius plus the clearance.
"""

from __future__ import annotations

from typing import Any

CLEARANCE_SUFFIX = ".clearance"


def _walk(data: Any, keys: list[str]) -> Any:
    node = data
    for key in keys:
        node = node[int(key)] if isinstance(node, list) else node[key]
    return node


def target_error(data: dict, path: str) -> str | None:
    """None if ``path`` names a numeric field of ``data`` (or a clearance joint + '.clearance'), else why not."""
    if path.endswith(CLEARANCE_SUFFIX):
        try:
            node = _walk(data, path[: -len(CLEARANCE_SUFFIX)].split("."))
        except (KeyError, IndexError, ValueError, TypeError):
            return f"'{path}' does not name a clearance joint of the config"
        if not isinstance(node, dict) or "journal_radius" not in node or "bearing_radius" not in node:
            return f"'{path}' does not name a clearance joint of the config"
        return None
    try:
        value = _walk(data, path.split("."))
    except (KeyError, IndexError, ValueError, TypeError):
        return f"'{path}' is not a field of the config"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"'{path}' is not a numeric field of the config"
    return None


def set_target(data: dict, path: str, value: float) -> None:
    """Set a plain (non-derived) target in place."""
    keys = path.split(".")
    parent = _walk(data, keys[:-1])
    if isinstance(parent, list):
        parent[int(keys[-1])] = value
    else:
        parent[keys[-1]] = value


def set_clearance(data: dict, path: str, clearance: float) -> None:
    """Derived target: bearing radius = journal radius + clearance."""
    node = _walk(data, path[: -len(CLEARANCE_SUFFIX)].split("."))
    node["bearing_radius"] = node["journal_radius"] + clearance
