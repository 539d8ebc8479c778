"""The config reference of the user guide, generated from the config schema (``jointwear.config.StudyConfig``).

    python -m jointwear.report.config_reference docs/user-guide.md          # rewrite the generated part
    python -m jointwear.report.config_reference --check docs/user-guide.md  # exit 1 if it is out of date

The generated Markdown sits between the markers ``<!-- config-reference:start -->`` and
``<!-- config-reference:end -->``; nothing else in the file is touched.
"""

from __future__ import annotations

import sys
import types
import typing
from pathlib import Path
from typing import Any

START = "<!-- config-reference:start -->"
END = "<!-- config-reference:end -->"

#: The suffix a user would typically write for a field stored in this SI unit.
_TYPICAL_SUFFIX = {"m": "_mm", "Pa": "_GPa (hardness: _HB)", "rad/s": "_rpm", "rad": "_deg", "m/s": "_m_s",
                   "m/s^2": "_m_s2", "N m": "_N_m", "N": "_N", "kg": "_kg", "kg m^2": "_kg_m2", "s": "_s"}


def _models_in(annotation: Any) -> list[type]:
    """The pydantic model classes inside a field's annotation (through Annotated, Union, list, Optional)."""
    from pydantic import BaseModel

    out: list[type] = []
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _models_in(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType, list, tuple, set, frozenset) or origin is not None:
        for arg in typing.get_args(annotation):
            for m in _models_in(arg):
                if m not in out:
                    out.append(m)
    return out


def _is_list(annotation: Any) -> bool:
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _is_list(typing.get_args(annotation)[0])
    return origin is list


def _default(info) -> str:
    from pydantic_core import PydanticUndefined

    if info.default_factory is not None:
        if _models_in(info.annotation):
            return "(section)"
        try:
            value = info.default_factory()
        except Exception:  # noqa: BLE001 - a factory that needs context: say so, do not fail the docs
            return "(computed)"
        return f"`{value!r}`"
    if info.default is PydanticUndefined:
        return "**required**"
    return f"`{info.default!r}`"


def _esc(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _type_name(annotation: Any) -> str:
    text = getattr(annotation, "__name__", None) if isinstance(annotation, type) else None
    if text is None:
        text = str(annotation).replace("typing.", "")
    return text


def config_reference_markdown(root: type | None = None) -> str:
    """Markdown tables of every config section and field: key, SI unit and the suffix to write, default,
    description (the field's docstring, which says where the default comes from)."""
    if root is None:
        from jointwear.config import StudyConfig as root  # noqa: N813
    lines: list[str] = [
        "_Generated from the config schema by `python -m jointwear.report.config_reference docs/user-guide.md`; "
        "do not edit by hand._",
        "",
        "Values are stored in SI units. A key may carry a unit suffix, converted once at loading: "
        "`length_mm = 6`, `crank_speed_rpm = 480`, `youngs_modulus_GPa = 120`, `hardness_HB = 350`, "
        "`angle_deg = 30`. Unknown keys, NaN and infinities are refused with a message that names the field.",
        "",
    ]
    seen: set[tuple[str, type]] = set()
    queue: list[tuple[str, type, bool]] = [("", root, False)]
    while queue:
        path, model, is_list = queue.pop(0)
        if (path, model) in seen:
            continue
        seen.add((path, model))
        title = (f"`[[{path}]]`" if is_list else f"`[{path}]`") if path else "top level"
        doc = (model.__doc__ or "").strip().splitlines()[0] if model.__doc__ else ""
        variant = ""
        tfield = model.model_fields.get("type")
        if tfield is not None and typing.get_origin(tfield.annotation) is typing.Literal:
            variant = f" with `type = \"{typing.get_args(tfield.annotation)[0]}\"`"
        lines += [f"#### {title}{variant} ({model.__name__})", ""]
        if doc:
            lines += [_esc(doc), ""]
        lines += ["| key | unit (suffix to write) | default | description |", "|---|---|---|---|"]
        for name, info in model.model_fields.items():
            subs = _models_in(info.annotation)
            extra = info.json_schema_extra if isinstance(info.json_schema_extra, dict) else {}
            unit = extra.get("unit")
            unit_txt = f"{unit} (`{name}{_TYPICAL_SUFFIX[unit]}`)" if unit in _TYPICAL_SUFFIX else (unit or "")
            if subs:
                sub_path = f"{path}.{name}" if path else name
                shown = f"[[{sub_path}]]" if _is_list(info.annotation) else f"[{sub_path}]"
                desc = _esc(info.description or "") + f" See `{shown}`."
                lines.append(f"| `{name}` | | {_default(info)} | {desc} |")
                for sub in subs:
                    queue.append((sub_path, sub, _is_list(info.annotation)))
            else:
                desc = _esc(info.description or "")
                typ = typing.get_origin(info.annotation)
                if typ is typing.Literal:
                    desc += " One of: " + ", ".join(f"`{a!r}`" for a in typing.get_args(info.annotation)) + "."
                lines.append(f"| `{name}` | {_esc(unit_txt)} | {_esc(_default(info))} | {desc} |")
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def update(path: Path | str, *, check: bool = False) -> bool:
    """Rewrite (or, with ``check``, compare) the generated part of ``path``; True when it was up to date."""
    path = Path(path)
    text = path.read_text(encoding="utf-8")
    if START not in text or END not in text:
        raise SystemExit(f"{path}: markers {START} / {END} not found")
    head, rest = text.split(START, 1)
    _old, tail = rest.split(END, 1)
    new = f"{head}{START}\n{config_reference_markdown()}{END}{tail}"
    if new == text:
        return True
    if not check:
        path.write_text(new, encoding="utf-8")
    return False


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    check = "--check" in args
    files = [a for a in args if a != "--check"] or ["docs/user-guide.md"]
    stale = [f for f in files if not update(f, check=check)]
    if check and stale:
        print(f"config reference out of date in {', '.join(stale)}: run "
              f"python -m jointwear.report.config_reference {' '.join(stale)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
