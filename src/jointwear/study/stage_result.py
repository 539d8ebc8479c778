"""The shared base of the typed stage results: JSON save and load, with unknown keys kept in ``extra``."""

from __future__ import annotations

from dataclasses import MISSING, fields
from pathlib import Path
from typing import ClassVar

from jointwear.study.io import provenance, read_json, write_json

__all__ = ["StageResult", "save_figure"]


class StageResult:
    """Shared save/load of the stage results: the JSON holds every field not marked ``json=False``."""

    FILE: ClassVar[str] = ""

    def to_json(self) -> dict:
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.metadata.get("json", True)}
        for key, value in getattr(self, "extra", {}).items():
            out.setdefault(key, value)
        return out

    @classmethod
    def from_json(cls, data: dict):
        """The result from its JSON; keys this version does not know are kept in ``extra`` (and written back)."""
        kwargs, known = {}, set()
        for f in fields(cls):
            known.add(f.name)
            if not f.metadata.get("json", True):
                continue
            if f.name in data:
                kwargs[f.name] = data[f.name]
            elif f.default is MISSING and f.default_factory is MISSING:
                raise ValueError(f"{cls.FILE}: missing key '{f.name}'")
        if "extra" in known:
            kwargs["extra"] = {k: v for k, v in data.items() if k not in known}
        return cls(**kwargs)

    @classmethod
    def load(cls, folder: Path | str):
        """Read the result back from ``folder / FILE``."""
        return cls.from_json(read_json(Path(folder) / cls.FILE))

    def write(self, folder: Path | str) -> Path:
        payload = self.to_json()
        payload.setdefault("provenance", provenance())
        return write_json(Path(folder) / self.FILE, payload)


def save_figure(fig, path: Path) -> None:
    """Write a figure with the project's style (PNG)."""
    from jointwear.report.style import savefig

    savefig(fig, path)
