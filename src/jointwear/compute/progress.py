"""A small progress display for long work: model calls done / total, free-text fields (current Pf,
COV, ...), elapsed time and time left. Built on ``rich.progress``; silent when the output is neither a
terminal nor a Jupyter notebook, when disabled, or when ``JOINTWEAR_PROGRESS=0``.

    with Progress(total=None, description="AK-MCS") as progress:
        evaluator = Evaluator(model, executor, store, progress=progress)
        ...
        progress.update(pf=f"{pf:.3e}", cov=f"{cov:.3f}")
"""

from __future__ import annotations

import os
import sys
from typing import Any

__all__ = ["Progress"]


def _format_fields(fields: dict[str, Any]) -> str:
    parts = []
    for k, v in fields.items():
        if v is None:
            continue
        if isinstance(v, float):
            v = f"{v:.4g}"
        parts.append(f"{k}={v}")
    return "  ".join(parts)


def _in_notebook() -> bool:
    """Whether this process is a Jupyter kernel (rich's own detection), where stderr is no terminal."""
    from rich.console import Console

    return bool(Console(stderr=True).is_jupyter)


class Progress:
    """Progress of model calls.

    ``total=None`` means *grow as work arrives*: every :meth:`expect` (the evaluator calls it with each
    batch's size) adds to the total. A study that knows its budget passes ``total`` (or sets it later
    with :meth:`update`), and :meth:`expect` then leaves it alone.

    ``enabled=None`` shows the display only on a terminal (``sys.stderr.isatty()``) or in a Jupyter notebook
    (rich draws it there as a live cell output), unless the
    environment variable ``JOINTWEAR_PROGRESS`` is ``0`` (never) or ``1`` (always). The counters
    (:attr:`completed`, :attr:`total`, :attr:`fields`) are kept even when nothing is shown.
    """

    def __init__(
        self,
        total: int | None = None,
        description: str = "model calls",
        *,
        enabled: bool | None = None,
        console=None,
        transient: bool = False,
    ) -> None:
        self.description = description
        self.completed = 0
        self._auto_total = total is None
        self.total: int | None = None if total is None else int(total)
        self.fields: dict[str, Any] = {}
        if enabled is None:
            env = os.environ.get("JOINTWEAR_PROGRESS", "").strip()
            if env in ("0", "1"):
                enabled = env == "1"
            else:
                enabled = console.is_terminal if console is not None else (sys.stderr.isatty() or _in_notebook())
        self.enabled = bool(enabled)
        self._rich = None
        self._task = None
        self._console = console
        self._transient = transient

    # -- context manager ----------------------------------------------------------------------------
    def start(self) -> "Progress":
        if self.enabled and self._rich is None:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )
            from rich.progress import (
                Progress as RichProgress,
            )

            console = self._console or Console(stderr=True)
            self._rich = RichProgress(
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[info]}"),
                TimeElapsedColumn(),
                TextColumn("left"),
                TimeRemainingColumn(),
                console=console,
                transient=self._transient,
                refresh_per_second=4,
            )
            self._rich.start()
            self._task = self._rich.add_task(
                self.description, total=self.total, completed=self.completed, info=_format_fields(self.fields)
            )
        return self

    def stop(self) -> None:
        if self._rich is not None:
            self._refresh()
            self._rich.stop()
            self._rich = None
            self._task = None

    def __enter__(self) -> "Progress":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # -- updates ------------------------------------------------------------------------------------
    def _refresh(self) -> None:
        if self._rich is not None:
            self._rich.update(
                self._task,
                total=self.total,
                completed=self.completed,
                description=self.description,
                info=_format_fields(self.fields),
            )

    def expect(self, n: int) -> None:
        """``n`` more calls are on their way (adds to the total in grow-as-you-go mode)."""
        if self._auto_total:
            self.total = (self.total or 0) + int(n)
            self._refresh()

    def advance(self, n: int = 1) -> None:
        """``n`` more calls are done."""
        self.completed += int(n)
        self._refresh()

    def update(
        self,
        *,
        completed: int | None = None,
        total: int | None = None,
        description: str | None = None,
        **fields: Any,
    ) -> None:
        """Set counters and free-text fields (``progress.update(pf="1.2e-3", cov=0.04)``; a field set
        to None is removed)."""
        if completed is not None:
            self.completed = int(completed)
        if total is not None:
            self.total = int(total)
            self._auto_total = False
        if description is not None:
            self.description = description
        for k, v in fields.items():
            if v is None:
                self.fields.pop(k, None)
            else:
                self.fields[k] = v
        self._refresh()
