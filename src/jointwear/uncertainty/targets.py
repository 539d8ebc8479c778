"""Dotted paths from a random variable to the config field it sets.

A path walks the SI config as plain data: ``mechanism.rod.length``, ``clearance_joints.0.journal_radius``.
List items are addressed by index or, when they are tables with a ``name``, by name; the two coordinates of a
point by 0/1 or x/y. So a point of a ``general`` mechanism is ``mechanism.bodies.coupler.points.B.x`` (or
``mechanism.bodies.1.points.B.0``) and a ground pivot ``mechanism.ground_points.C.y``.
The suffix ``.clearance`` on a clearance joint is a derived target: the bearing radius becomes the
(sampled) journal radius plus the clearance.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from typing import Any

CLEARANCE_SUFFIX = ".clearance"


_COORD = {"x": 0, "y": 1}


def _is_point(node: Any) -> bool:
    """Whether ``node`` is a coordinate pair (its items addressed as x/y too)."""
    return isinstance(node, (list, tuple)) and len(node) == 2 and all(isinstance(v, (int, float)) for v in node)


def _index(node: list | tuple, key: str) -> int:
    """Position of `key` in a list/tuple: an integer, x/y for a coordinate pair, or the `name` of a table."""
    if key in _COORD and _is_point(node):
        return _COORD[key]
    try:
        return int(key)
    except ValueError:
        for i, item in enumerate(node):
            if isinstance(item, dict) and item.get("name") == key:
                return i
        raise KeyError(key) from None


def _step(node: Any, key: str) -> Any:
    """The item ``key`` of a table, list or point."""
    return node[_index(node, key)] if isinstance(node, (list, tuple)) else node[key]


def _walk(data: Any, keys: list[str]) -> Any:
    node = data
    for key in keys:
        node = _step(node, key)
    return node


def _missing_step(data: Any, keys: list[str]) -> str:
    """Where a path leaves the config, with the keys it could take there (a typo's likely fix first):
    ": 'hardnes' is not in clearance_joints.A.bearing_material (did you mean 'hardness'?)"."""
    node, walked = data, []
    for key in keys:
        try:
            node = _step(node, key)
        except (KeyError, IndexError, ValueError, TypeError):
            if isinstance(node, dict):
                options = [str(k) for k in node]
            elif _is_point(node):
                options = [*_COORD, "0", "1"]
            elif isinstance(node, (list, tuple)):
                options = [str(item["name"]) for item in node if isinstance(item, dict) and "name" in item]
                options = options or [str(i) for i in range(len(node))]
            else:
                return f": {'.'.join(walked)} is a number, with no '{key}' in it"
            where = ".".join(walked) or "the config"
            close = difflib.get_close_matches(key, options, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else f" (it has: {', '.join(options)})"
            return f": '{key}' is not in {where}{hint}"
        walked.append(key)
    return ""


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
        return f"'{path}' is not a field of the config{_missing_step(data, path.split('.'))}"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"'{path}' is not a numeric field of the config"
    return None


def target_value(data: dict, path: str) -> float:
    """The config's own value at a target (for ``<joint>.clearance``: bearing radius - journal radius)."""
    if path.endswith(CLEARANCE_SUFFIX):
        node = _walk(data, path[: -len(CLEARANCE_SUFFIX)].split("."))
        return float(node["bearing_radius"]) - float(node["journal_radius"])
    return float(_walk(data, path.split(".")))


def point_shift(data: dict, path: str, value: float) -> float:
    """How far setting ``path`` to ``value`` moves a drawn point of a general mechanism (a coordinate of
    ``mechanism.bodies.<b>.points.<p>`` or ``mechanism.ground_points.<p>``; 0 for any other target)."""
    keys = path.split(".")
    if not (keys[:2] == ["mechanism", "ground_points"] or (keys[:2] == ["mechanism", "bodies"] and len(keys) == 6
                                                          and keys[3] == "points")):
        return 0.0
    parent = _walk(data, keys[:-1])
    return abs(float(value) - float(parent[_index(parent, keys[-1])]))


def set_target(data: dict, path: str, value: float) -> None:
    """Set a plain (non-derived) target in place (a coordinate of a point tuple: the tuple is replaced)."""
    keys = path.split(".")
    parent = _walk(data, keys[:-1])
    if isinstance(parent, tuple):
        items = list(parent)
        items[_index(parent, keys[-1])] = value
        grand = _walk(data, keys[:-2])
        if isinstance(grand, list):
            grand[_index(grand, keys[-2])] = tuple(items)
        else:
            grand[keys[-2]] = tuple(items)
    elif isinstance(parent, list):
        parent[_index(parent, keys[-1])] = value
    else:
        parent[keys[-1]] = value


def set_clearance(data: dict, path: str, clearance: float) -> None:
    """Derived target: bearing radius = journal radius + clearance."""
    node = _walk(data, path[: -len(CLEARANCE_SUFFIX)].split("."))
    node["bearing_radius"] = node["journal_radius"] + clearance


def apply_targets(data: dict, assignments: Iterable[tuple[str, float]]) -> None:
    """Set target values (SI) on the raw config ``data`` in place; the paths are taken as valid (target_error).

    The plain targets are set in the order given, then the derived clearances (R_i = R_j + c), so that a journal
    radius set with a clearance combines with it in either order. A general linkage's closure tolerance is then
    widened once by the total move of its drawn points over its drawn link size (mechanism.assembly.drawn_link_size,
    of the points before the move): the moved points are assembled with their joint partners where they are drawn,
    so a crank's pin moved out makes the crank longer with the rod as drawn.
    """
    assignments = [(path, float(value)) for path, value in assignments]
    plain = [(path, value) for path, value in assignments if not path.endswith(CLEARANCE_SUFFIX)]
    mech = data.get("mechanism") or {}
    size = None
    if plain and mech.get("type") == "general":
        from jointwear.mechanism.assembly import drawn_link_size  # the mechanism's modules load the kernels

        size = drawn_link_size([b["points"].values() for b in mech["bodies"]])
    moved = 0.0
    for path, value in plain:
        moved += point_shift(data, path, value)
        set_target(data, path, value)
    for path, value in assignments:
        if path.endswith(CLEARANCE_SUFFIX):
            set_clearance(data, path, value)
    if moved > 0.0 and size is not None:
        mech["closure_tolerance"] = float(mech["closure_tolerance"]) + moved / size
