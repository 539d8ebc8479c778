"""The report in a real browser: headless Chromium loads the page without errors and every figure displays.

How: the report is built from the synthetic study fixtures; a probe copy of the page gets two tiny scripts
(the report itself has none): one in <head> records every error event (script errors and resources that fail to
load), one on the window's load event writes a JSON marker into the DOM with the number of <img> elements,
how many have loaded (complete, naturalWidth > 0) and are laid out at a visible size, the errors and the
network resources fetched. ``chromium --headless --dump-dom`` prints the DOM after load and the test reads the
marker. A screenshot of the real page (no probe) must not be blank.

Chromium comes from the Debian packages ``chromium`` and ``chromium-driver`` (``.ci/install-chromium.sh``).
Without it the test skips locally and fails in CI (environment variable CI set).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest

from jointwear.report import build_report

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--mute-audio",
]

PROBE_HEAD = (
    "<script>window.__jwErrors=[];window.addEventListener('error',function(ev){var t=ev.target;"
    "window.__jwErrors.push(t&&t.tagName?('resource '+t.tagName+' failed to load'):String(ev.message));},true);"
    "</script>"
)
PROBE_TAIL = (
    "<script>window.addEventListener('load',function(){var imgs=Array.prototype.slice.call(document.images);"
    "var bad=[];imgs.forEach(function(i,k){var b=i.getBoundingClientRect();"
    "if(!(i.complete&&i.naturalWidth>0&&i.naturalHeight>0&&b.width>=100&&b.height>=60))"
    "bad.push(k+': '+(i.alt||'').slice(0,60)+' '+i.naturalWidth+'x'+i.naturalHeight+' shown '"
    "+Math.round(b.width)+'x'+Math.round(b.height));});"
    "var r={n:imgs.length,bad:bad,errors:window.__jwErrors,"
    "resources:performance.getEntriesByType('resource').map(function(x){return x.name;}),"
    "title:document.title,sections:document.querySelectorAll('section').length};"
    "var p=document.createElement('pre');p.id='jw-probe';p.textContent=JSON.stringify(r);"
    "document.body.appendChild(p);});</script>"
)


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def chromium() -> str:
    path = _chromium()
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is not installed in CI: .ci/install-chromium.sh must run before the tests")
        pytest.skip("chromium is not installed (run .ci/install-chromium.sh, or apt-get install chromium "
                    "chromium-driver); the browser test runs in CI")
    return path


def _run(chromium: str, *args: str, timeout: float = 120.0) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory(prefix="jw-chromium-") as profile:
        return subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile}", *args], capture_output=True,
                              text=True, timeout=timeout, check=False)


def _probe(chromium: str, page: Path, tmp_path: Path) -> dict:
    html = page.read_text(encoding="utf-8")
    assert "<head>" in html and "</body>" in html
    probe = tmp_path / "probe.html"
    probe.write_text(html.replace("<head>", "<head>" + PROBE_HEAD, 1).replace("</body>", PROBE_TAIL + "</body>", 1),
                     encoding="utf-8")
    proc = _run(chromium, "--window-size=1280,1000", "--virtual-time-budget=15000", "--dump-dom", probe.as_uri())
    m = re.search(r'<pre id="jw-probe">(.*?)</pre>', proc.stdout, re.S)
    assert m, f"no probe marker in the DOM (exit {proc.returncode}); stderr tail:\n{proc.stderr[-2000:]}"
    return json.loads(m.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">")
                      .replace("&amp;", "&"))


def test_report_loads_and_every_figure_displays(chromium, full_report: Path, tmp_path: Path):
    html = full_report.read_text(encoding="utf-8")
    n_img = len(re.findall(r"<img\s", html))
    assert n_img >= 13
    result = _probe(chromium, full_report, tmp_path)
    assert result["title"] == "jointwear study report"
    assert result["n"] == n_img
    assert result["bad"] == [], result["bad"]
    assert result["errors"] == [], result["errors"]
    assert result["resources"] == [], f"the page fetched external resources: {result['resources']}"
    assert result["sections"] >= 8

    shot = tmp_path / "report.png"
    proc = _run(chromium, "--window-size=1280,2400", f"--screenshot={shot}", full_report.as_uri())
    assert shot.is_file() and shot.stat().st_size > 10_000, proc.stderr[-2000:]
    from matplotlib.image import imread

    img = imread(shot)
    assert img.shape[0] >= 2000 and img.shape[1] >= 1200
    assert float(np.std(img[..., :3])) > 0.05  # not a blank page


def test_probe_detects_a_broken_figure(chromium, tmp_path: Path):
    """The probe itself works: a page with an undecodable image is reported."""
    page = tmp_path / "broken.html"
    page.write_text("<!DOCTYPE html><html><head><title>t</title></head><body>"
                    '<img alt="broken" width="300" height="200" src="data:image/png;base64,iVBORw0KGgoAAAA=">'
                    "</body></html>", encoding="utf-8")
    result = _probe(chromium, page, tmp_path)
    assert result["n"] == 1
    assert len(result["bad"]) == 1
    assert result["errors"], "the failed image load should be recorded as an error"


def test_report_of_a_partial_study_loads(chromium, tmp_path: Path, nominal: Path):
    """A folder with only the wear stage: the page still loads cleanly and its figures display."""
    from report_fixtures import make_fixture_dir

    d = make_fixture_dir(tmp_path / "study", nominal, which=("wear",))
    page = build_report(d)
    result = _probe(chromium, page, tmp_path)
    assert result["n"] == 3 and result["bad"] == [] and result["errors"] == []
