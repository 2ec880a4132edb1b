"""`floebreak propeller RUN --out P`: P/report.html with the propeller, design-load and shaft sections, and
RUN/report.html updated when P lies inside RUN; the command says where both are."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from floebreak.app.propeller_output import enclosing_run

from .test_cli_shaft import make_run


def _floebreak(*args: str) -> subprocess.CompletedProcess:
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", *args], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="module")
def analysed(tmp_path_factory):
    """A run directory (cusps, scenario, summary) and its propeller analysis with the shaft line, written to
    RUN/analyses/p (not the demo's RUN/propeller) at PC5 over an operating profile."""
    base = tmp_path_factory.mktemp("propeller_report")
    run = make_run(base / "run", speed_m_s=3.0, profile="default")
    (run / "summary.json").write_text(json.dumps({"scenario_hash": "ab" * 8}), encoding="utf-8")
    (run / "report.html").write_text("<html>before</html>", encoding="utf-8")
    (run / "analyses").mkdir()
    out = run / "analyses" / "p"
    done = _floebreak(
        "propeller", str(run), "--out", str(out), "--shaft-line", "agulhas_ii", "--polar-class", "PC5",
        "--hours-in-ice-per-year", "1000", "--years", "25", "--excitation-cases", "1,2", "--quiet",
    )  # fmt: skip
    return run, out, done.stdout


def test_the_analysis_has_its_own_report_with_every_section(analysed):
    _, out, stdout = analysed
    page = (out / "report.html").read_text(encoding="utf-8")
    for heading in ("<h2>Propeller loads</h2>", "<h2>Shaft line</h2>", "<h2>Provenance</h2>"):
        assert heading in page
    assert "<h3>Design loads, " in page and "against IACS UR I3 PC5" in page
    for figure in ("rule_form.png", "torque_spectrum_log.png", "campbell.png", "rainflow_histogram.png"):
        assert f"alt='{figure}'" in page, figure
    assert "<code>p</code>" in page  # the final name, not the temporary directory's
    assert f"report: {out / 'report.html'}" in stdout


def test_the_run_report_is_updated_with_the_analysis(analysed):
    run, _, stdout = analysed
    page = (run / "report.html").read_text(encoding="utf-8")
    assert "before" not in page
    assert "<h2>Propeller loads (analyses/p/)</h2>" in page and "<h2>Shaft line (analyses/p/)</h2>" in page
    assert "alt='campbell.png'" in page
    assert f"updated the run's report: {run / 'report.html'}" in stdout
    assert not [p for p in (run / "analyses").iterdir() if p.name.startswith(".")]  # no temporaries left


def test_an_analysis_outside_a_run_updates_no_run_report(analysed, tmp_path):
    run, _, _ = analysed
    out = tmp_path / "elsewhere"
    done = _floebreak("propeller", str(run), "--out", str(out), "--quiet")
    assert (out / "report.html").is_file() and "<h2>Propeller loads</h2>" in (out / "report.html").read_text()
    assert "updated the run's report" not in done.stdout
    assert enclosing_run(out) is None and enclosing_run(run / "x" / "y") == run
