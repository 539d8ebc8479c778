"""The progress display beside the stages' own lines."""

from jointwear.compute.progress import Progress


def test_a_stage_line_is_printed_above_the_live_progress_line():
    """The reliability summary was written onto the end of the live bar ('... left 0:00:00reliability: 80 model
    calls'): click.echo reached the terminal past rich's own stream."""
    import io
    import re

    from rich.console import Console

    from jointwear.cli import say

    buf = io.StringIO()
    progress = Progress(total=10, enabled=True, console=Console(file=buf, force_terminal=True, width=100))
    progress.start()
    say("reliability: 80 model calls")
    progress.stop()
    text = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", buf.getvalue())
    assert "\rreliability: 80 model calls\n" in text  # on a line of its own, the bar redrawn below it


def test_a_plain_line_times_its_own_phase_and_says_what_is_left(monkeypatch, capsys):
    """Off a terminal, 'validation samples 65/600 elapsed 0:00:30' counted from the start of the process (the
    learning's time included) and gave no time left."""
    from jointwear.compute import progress as module

    now = [1000.0]
    monkeypatch.setattr(module.time, "monotonic", lambda: now[0])
    progress = Progress(total=80, enabled=False, plain_interval=0.0)
    progress.plain = True
    progress.start()
    now[0] += 600.0  # the learning
    progress.update(completed=80)
    progress.update(description="validation samples", completed=0, total=600)
    now[0] += 30.0
    progress.update(completed=60)  # 60 in 30 s: 540 more take 270 s
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line == "validation samples 60/600  elapsed 0:00:30  left 0:04:30"


def test_a_narrow_terminal_cuts_the_fields_not_the_count():
    """At 80 columns the live line read 'model calls ... Pf(400k)=0.284 COV=0.0036 min U=0.00 budget=12 calls ...
    left ...': rich had dropped the call count and the times to keep the fields (a reliability engineer's audit)."""
    import io
    import re

    from rich.console import Console

    buf = io.StringIO()
    progress = Progress(total=23, enabled=True, console=Console(file=buf, force_terminal=True, width=80))
    progress.start()
    progress.update(completed=12, **{"Pf(400k)": "0.284", "COV": "0.0036", "min U": "0.00", "budget": "80 calls"})
    progress.stop()
    last = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", buf.getvalue()).strip().splitlines()[-1]
    assert "12/23" in last and " left " in last and "Pf" in last, last
    assert len(last.rstrip()) <= 80
