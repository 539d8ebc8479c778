"""Every key a result file holds is in docs/results.md, in that file's section (a reliability engineer reading the
JSON with scripts found a fifth of the keys documented nowhere)."""

from __future__ import annotations

import json
import re
from pathlib import Path

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
    """The key names of the JSON file at ``path`` that its section of docs/results.md does not give as `name`; a key
    the section gives as `key.<...>` (a dict keyed by the study's names, such as its joints) is not looked into."""
    text = doc_section(path.name)
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
