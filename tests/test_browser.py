"""report.html in a real headless browser: a demo run with its propeller analysis (PC5, operating
profile) and shaft line renders every section, every figure decodes, and the screenshots are kept.

Marked `browser` (not in the default run): `make test-browser` installs Debian's Chromium where it is missing
and runs it. Screenshots go to $FLOEBREAK_SCREENSHOTS (default build/screenshots): the whole page, and one
image per section (cut at its heading)."""

from __future__ import annotations

import itertools
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
BROWSER = next((path for name in BROWSERS if (path := shutil.which(name))), None)
WIDTH_PX = 1280
SECTIONS = ("Summary", "Figures", "Propeller loads", "Shaft line", "Scenario (resolved)", "Provenance")

# appended to a copy of the page: writes what the browser laid out into the DOM that --dump-dom prints
PROBE = """<script>
window.addEventListener("load", () => {
  const images = [...document.images];
  const heads = [...document.querySelectorAll("h2, h3")].map(h => [h.tagName, h.textContent,
      Math.round(h.getBoundingClientRect().top + window.scrollY)]);
  const out = {height: document.documentElement.scrollHeight,
               width: document.documentElement.scrollWidth,
               images: images.length,
               broken: images.filter(i => !i.complete || i.naturalWidth === 0).map(i => i.alt),
               heads: heads};
  const pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>"""


def _browser(*args: str) -> subprocess.CompletedProcess:
    command = [BROWSER, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *args]
    done = subprocess.run(command, capture_output=True, text=True, timeout=180)
    assert done.returncode == 0, done.stderr
    return done


def _floebreak(*args: str, cwd: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", *args], capture_output=True, text=True, timeout=900, cwd=cwd
    )
    assert done.returncode == 0, done.stderr


@pytest.fixture(scope="module")
def demo_report(tmp_path_factory) -> Path:
    """The demo run, its propeller analysis at PC5 over an operating profile with the shaft line, and
    its report.html (as the README's commands)."""
    base = tmp_path_factory.mktemp("browser")
    torque_csv = Path(__file__).parents[1] / "src" / "floebreak" / "data" / "synthetic_shaft_torque.csv"
    _floebreak("demo", "--out", "demo-output", "--quiet", cwd=base)
    _floebreak(
        "propeller", "demo-output", "--out", "demo-output/propeller", "--overwrite", "--polar-class", "PC5",
        "--hours-in-ice-per-year", "1000", "--years", "25", "--shaft-line", "agulhas_ii", "--speed-m-s", "3",
        "--torque-csv", str(torque_csv), "--sn-curve", "torque,5,1000,1e7", "--quiet",
        cwd=base,
    )  # fmt: skip
    _floebreak("report", "demo-output", cwd=base)
    return base / "demo-output" / "report.html"


def _layout(report: Path, tmp_path: Path) -> dict:
    probed = tmp_path / "probed.html"
    probed.write_text(report.read_text(encoding="utf-8").replace("</body>", PROBE + "</body>"), "utf-8")
    size = f"--window-size={WIDTH_PX},1000"  # the screenshots' width: the same layout
    dom = _browser(size, "--virtual-time-budget=10000", "--dump-dom", probed.as_uri()).stdout
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)
    assert found, "the probe script did not run"
    return json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))


NO_BROWSER = "no Chromium or Chrome on PATH (make test-browser installs Debian's: apt-get install chromium)"


@pytest.mark.skipif(BROWSER is None, reason=NO_BROWSER)
def test_report_renders_every_section_in_a_headless_browser(demo_report, tmp_path):
    from PIL import Image

    layout = _layout(demo_report, tmp_path)
    assert layout["broken"] == [], f"figures the browser could not decode: {layout['broken']}"
    assert layout["images"] >= 10
    assert layout["width"] <= WIDTH_PX, "the page scrolls sideways"
    heads = [text for tag, text, _ in layout["heads"] if tag == "H2"]
    for section in SECTIONS:
        assert section in heads, f"section {section!r} missing: {heads}"
    assert any(text.startswith("Design loads, propeller") for tag, text, _ in layout["heads"] if tag == "H3")

    out = Path(os.environ.get("FLOEBREAK_SCREENSHOTS", "build/screenshots"))
    out.mkdir(parents=True, exist_ok=True)
    page = out / "report_full.png"
    _browser(f"--window-size={WIDTH_PX},{layout['height']}", f"--screenshot={page.resolve()}",
             demo_report.as_uri())  # fmt: skip
    with Image.open(page) as image:
        assert image.size[0] == WIDTH_PX and image.size[1] >= layout["height"] - 1
        assert len(image.convert("L").getcolors(1 << 16) or ()) > 16  # drawn, not a blank page
        tops = [(text, top) for _, text, top in layout["heads"]] + [("end", layout["height"])]
        for k, ((text, top), (_, bottom)) in enumerate(itertools.pairwise(tops)):
            name = re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")
            image.crop((0, max(0, top - 20), WIDTH_PX, bottom)).save(out / f"section_{k:02d}_{name}.png")


@pytest.mark.skipif(BROWSER is None, reason=NO_BROWSER)
def test_the_propeller_analysis_has_its_own_report(demo_report, tmp_path):
    """`floebreak propeller RUN --out P` writes P/report.html: the propeller loads, the design loads against
    the rule, the shaft torque with its Campbell and rainflow figures, each figure decoded."""
    from PIL import Image

    report = demo_report.parent / "propeller" / "report.html"
    layout = _layout(report, tmp_path)
    assert layout["broken"] == [], f"figures the browser could not decode: {layout['broken']}"
    assert layout["width"] <= WIDTH_PX, "the page scrolls sideways"
    heads = " | ".join(text for _, text, _ in layout["heads"])
    for part in ("Propeller loads", "Design loads", "Shaft"):
        assert part in heads, f"{part!r} missing: {heads}"
    html = report.read_text(encoding="utf-8")
    assert "campbell" in html.lower() and "rainflow" in html.lower()
    out = Path(os.environ.get("FLOEBREAK_SCREENSHOTS", "build/screenshots"))
    out.mkdir(parents=True, exist_ok=True)
    page = out / "propeller_report_full.png"
    _browser(
        f"--window-size={WIDTH_PX},{layout['height']}", f"--screenshot={page.resolve()}", report.as_uri()
    )
    with Image.open(page) as image:
        assert len(image.convert("L").getcolors(1 << 16) or ()) > 16  # drawn, not a blank page
