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
