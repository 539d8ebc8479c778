"""Every key a result file holds is in docs/results.md, in that file's section (a reliability engineer reading the
JSON with scripts found a fifth of the keys documented nowhere; a dynamics audit found the series file and the joints'
table documented nowhere)."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np

RESULTS_DOC = Path(__file__).resolve().parents[1] / "docs" / "results.md"
#: subtrees documented as a whole: the versions (the page's introduction), the config itself (docs/config.md)
OPAQUE = {"provenance", "study_config", "reference"}
#: ... and, in one file, a section of the config (wear.json's `settings`: docs/config.md's [wear]) or a setting's
#: value (config.json's `settings[].value`, a table keyed by joints or points where the setting is one)
OPAQUE_IN = {"wear.json": {"settings"}, "config.json": {"value"}}
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def doc_section(file_name: str) -> str:
    """The text of docs/results.md's section whose heading names ``file_name``."""
    sections = re.split(r"^## ", RESULTS_DOC.read_text(encoding="utf-8"), flags=re.M)
    found = [s for s in sections if file_name in s.splitlines()[0]]
    assert found, f"docs/results.md has no section of {file_name}"
    return found[0]


def undocumented_keys(path: Path) -> list[str]:
    """The key names of the result file at ``path`` that its section of docs/results.md does not give as `name`: a
    JSON file's keys (a key the section gives as `key.<...>`, a dict keyed by the study's names such as its joints,
    is not looked into), an ``.npz`` file's arrays (:func:`undocumented_series`) or a CSV table's columns."""
    if path.suffix == ".npz":
        return undocumented_series(path)
    text = doc_section(path.name)
    if path.suffix == ".csv":
        with path.open(encoding="utf-8", newline="") as f:
            header = next(csv.reader(f))
        words = {word for span in re.findall(r"`([^`\n]+)`", text) for word in _NAME.findall(span)}
        return sorted(set(header) - words)
    spans = re.findall(r"`([^`\n]+)`", text)  # the section's code spans, in order (each pair of backticks once)
    words = {word for span in spans for word in _NAME.findall(span)}
    opaque = OPAQUE | OPAQUE_IN.get(path.name, set())
    missing: set[str] = set()

    def walk(value) -> None:
        if isinstance(value, dict):
            for key, inner in value.items():
                if not _NAME.fullmatch(key) or key in opaque:
                    continue
                if key not in words:
                    missing.add(key)
                if not any(f"{key}.<" in span for span in spans):
                    walk(inner)
        elif isinstance(value, list):
            for item in value:
                walk(item)

    walk(json.loads(path.read_text(encoding="utf-8")))
    return sorted(missing)


def undocumented_series(path: Path) -> list[str]:
    """The arrays of the series file at ``path`` (``simulate.npz``) that its section of docs/results.md does not give
    as a code span of its own: `name`, or `<joint>_name` for a clearance joint's (the joints named in the
    ``simulate.json`` beside it)."""
    spans = set(re.findall(r"`([^`\n]+)`", doc_section(path.name)))
    joints = [j["name"] for j in json.loads((path.parent / "simulate.json").read_text(encoding="utf-8"))["joints"]]
    with np.load(path) as data:
        keys = list(data.files)
    missing = []
    for key in keys:
        generic = [f"<joint>_{key[len(name) + 1:]}" for name in joints if key.startswith(f"{name}_")]
        if key not in spans and not any(g in spans for g in generic):
            missing.append(key)
    return sorted(missing)
