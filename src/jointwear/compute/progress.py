"""A small progress display for long work: model calls done / total, free-text fields (current Pf,
COV, ...), elapsed time and time left. Built on ``rich.progress`` on a terminal or in a Jupyter notebook;
elsewhere (nohup, CI, a log file) a plain line at most every ``PLAIN_INTERVAL`` seconds; silent when disabled
or when ``JOINTWEAR_PROGRESS=0``.

    with Progress(total=None, description="AK-MCS") as progress:
        evaluator = Evaluator(model, executor, store, progress=progress)
        ...
        progress.update(pf=f"{pf:.3e}", cov=f"{cov:.3f}")
"""

from __future__ import annotations

import os
import sys
import time
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


def _clock(seconds: float) -> str:
    """'1:02:03' for 3,723 s."""
    s = int(seconds)
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class Progress:
    """Progress of model calls.

    ``total=None`` means *grow as work arrives*: every :meth:`expect` (the evaluator calls it with each
    batch's size) adds to the total. A study that knows its budget passes ``total`` (or sets it later
    with :meth:`update`), and :meth:`expect` then leaves it alone.

    ``enabled=None`` shows the display on a terminal (``sys.stderr.isatty()``) or in a Jupyter notebook
    (rich draws it there as a live cell output); elsewhere (:attr:`plain`) it writes a plain line to stderr at
    most every ``plain_interval`` seconds (default :attr:`PLAIN_INTERVAL`; nothing for work shorter than that), and
    one more at the end when it wrote any. The environment variable ``JOINTWEAR_PROGRESS`` set to ``0`` (never) or
    ``1`` (the rich display always) overrides this; ``enabled=False`` is silent. The counters
    (:attr:`completed`, :attr:`total`, :attr:`fields`) are kept even when nothing is shown.
    """

    #: seconds between two plain progress lines off a terminal (a log file of a day-long study stays short)
    PLAIN_INTERVAL = 30.0

    def __init__(
        self,
        total: int | None = None,
        description: str = "model calls",
        *,
        enabled: bool | None = None,
        console=None,
        transient: bool = False,
        plain_interval: float | None = None,
    ) -> None:
        self.description = description
        self.completed = 0
        self._auto_total = total is None
        self.total: int | None = None if total is None else int(total)
        self.fields: dict[str, Any] = {}
        self.plain = False
        if enabled is None:
            env = os.environ.get("JOINTWEAR_PROGRESS", "").strip()
            if env in ("0", "1"):
                enabled = env == "1"
            else:
                enabled = console.is_terminal if console is not None else (sys.stderr.isatty() or _in_notebook())
                self.plain = not enabled
        self.enabled = bool(enabled)
        self.plain_interval = self.PLAIN_INTERVAL if plain_interval is None else float(plain_interval)
        self._started = self._last_line = time.monotonic()
        self._lines = 0
        self._rich = None
        self._task = None
        self._console = console
        self._transient = transient

    # -- context manager ----------------------------------------------------------------------------
    def start(self) -> "Progress":
        self._started = self._last_line = time.monotonic()
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
            from rich.table import Column

            class FieldsColumn(TextColumn):
                """The fields, cut with an ellipsis where the line is too narrow (they give way first: the
                count and the times stay; at 80 columns rich dropped the count instead)."""

                def render(self, task):
                    text = super().render(task)
                    text.no_wrap, text.overflow = True, "ellipsis"
                    return text

            def kept() -> Column:
                return Column(no_wrap=True)  # rich narrows only the columns that may wrap

            console = self._console or Console(stderr=True)
            self._rich = RichProgress(
                TextColumn("[bold]{task.description}", table_column=kept()),
                BarColumn(bar_width=20, table_column=kept()),
                MofNCompleteColumn(table_column=kept()),
                FieldsColumn("{task.fields[info]}", table_column=Column(no_wrap=False)),
                TimeElapsedColumn(table_column=kept()),
                TextColumn("left", table_column=kept()),
                TimeRemainingColumn(table_column=kept()),
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
        if self.plain and self._lines:  # the log ends with where the work ended
            self._plain_line()

    def __enter__(self) -> "Progress":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # -- updates ------------------------------------------------------------------------------------
    def _plain_line(self) -> None:
        """'model calls 12/60  Pf(300k)=0.0123  elapsed 0:01:02  left 0:04:08' on stderr (or the console's file): the
        phase's elapsed time, and the time left at its rate so far when it has a total."""
        self._last_line = time.monotonic()
        self._lines += 1
        elapsed = self._last_line - self._started
        done = f"{self.completed}/{self.total}" if self.total else str(self.completed)
        left = ""
        if self.total and 0 < self.completed < self.total:
            left = f"left {_clock(elapsed * (self.total - self.completed) / self.completed)}"
        info = _format_fields(self.fields)
        line = "  ".join(p for p in (f"{self.description} {done}", info, f"elapsed {_clock(elapsed)}", left) if p)
        out = self._console.file if self._console is not None else sys.stderr
        print(line, file=out, flush=True)

    def _refresh(self) -> None:
        if self.plain and time.monotonic() - self._last_line >= self.plain_interval:
            self._plain_line()
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
        if description is not None and description != self.description and completed == 0:
            self._started = time.monotonic()  # another phase (validation samples after the learning): its own clock
            if self._rich is not None:
                self._rich.reset(self._task)
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
