"""The HTML report of a run directory: summary rows with units, embedded figures, scenario, provenance."""

from __future__ import annotations

import base64
import json

import pytest

from floebreak.errors import InputError
from floebreak.output.report import render_report, write_report

PNG = base64.b64decode(  # a 1 × 1 white PNG
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP4//8/AAX+Av4N70a4AAAAAElFTkSuQmCC"
)


@pytest.fixture
def run_dir(tmp_path):
    folder = tmp_path / "run"
    (folder / "figures").mkdir(parents=True)
    (folder / "figures" / "field.png").write_bytes(PNG)
    summary = {
        "scenario_hash": "0123456789abcdef",
        "profile": "<thesis>",
        "seed": 3,
        "floebreak_version": "9.9",
        "n_cusps": 12,
        "cusp_area_m2": 12.5,
        "crushing_force_max_n": 1234567.0,
        "area_balance_rel_error": 0.001,
        "mean_cusp_area_m2": None,
        "breaks_by_mode": {"bending": 1, "cracking": 2},
        "provenance": {"libraries": {"numpy": "2.0"}},
    }
    (folder / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
    (folder / "scenario.resolved.toml").write_text('profile = "thesis"\n', encoding="utf-8")
    return folder


def test_summary_rows_are_labelled_with_units_and_formatted(run_dir):
    text = render_report(run_dir)
    assert "<title>floebreak run 0123456789ab</title>" in text  # the hash's first 12 characters
    assert "<td>A_cusp^tot (total cusp area)</td><td class='num'>12.5</td><td>m²</td>" in text
    assert "<td class='num'>12</td>" in text  # integers as they are
    assert "<td class='num'>1.235e+06</td><td>N</td>" in text  # ≥ 1e6: scientific notation
    assert "<td class='num'>1.000e-03</td>" in text  # < 1e-2: scientific notation
    assert "<td class='num'>–</td>" in text  # None (NaN in the run) as a dash
    assert "bending: 1, cracking: 2" in text  # keys without a label: their own row
    assert "&lt;thesis&gt;" in text and "<thesis>" not in text  # everything from the files is escaped


def test_figures_scenario_and_provenance_are_embedded(run_dir):
    text = render_report(run_dir, directory_name="final-name")
    assert f"src='data:image/png;base64,{base64.b64encode(PNG).decode()}'" in text
    assert "Initial floe field" in text  # the figure's caption
    assert "profile = &quot;thesis&quot;" in text
    assert "&quot;numpy&quot;: &quot;2.0&quot;" in text
    assert "<code>final-name</code>" in text  # the name given, not the directory's current one


def test_a_run_without_figures_says_so(run_dir):
    for png in (run_dir / "figures").iterdir():
        png.unlink()
    assert "<p>(no figures)</p>" in render_report(run_dir)


def test_write_report_writes_report_html_in_the_run_directory(run_dir):
    path = write_report(run_dir)
    assert path == run_dir / "report.html"
    assert path.read_text(encoding="utf-8") == render_report(run_dir)


def test_a_directory_that_is_not_a_run_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"summary\.json") as info:
        render_report(tmp_path)
    assert info.value.field == "run_dir"
    (tmp_path / "summary.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(InputError, match="not readable JSON"):
        render_report(tmp_path)


def test_a_design_table_written_by_an_earlier_version_shows_a_dash_for_what_it_lacks():
    """A run directory keeps the propeller analyses written by earlier versions; re-rendering its report
    with a newer one must not fail on the quantities the old summary.json does not have."""
    from floebreak.output.report import design_load_parts

    old_row = {
        "pitch_percent": 95.86,
        "design_torque_kn_m": 812.0,
        "rule_max_torque_kn_m": 864.0,
        "basis": {},
    }
    html = "".join(design_load_parts([{"propeller": "propeller 1", "polar_class": "PC5", "rows": [old_row]}]))
    assert "<td class='num'>812</td>" in html and "<td class='num'>864</td>" in html
    lacking = html.split("simulated impacts per hour on one blade</td>", 1)[1].split("</tr>", 1)[0]
    assert "<td class='num'>–</td>" in lacking
