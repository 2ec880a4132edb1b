"""The design-load table in the terminal, summary.json and report.html, the rule's N_ice in
the exceedance figure, and the report's collapsed provenance at the end."""

from __future__ import annotations

import io
import json

import pytest
from rich.console import Console

from floebreak.app.propeller import design_load_summary, propeller_figures
from floebreak.cli.tables import design_basis_lines as _design_basis_lines
from floebreak.cli.tables import design_load_tables as _design_load_tables
from floebreak.output.propeller_files import write_propeller_files
from floebreak.output.report import propeller_section, render_report

from .test_design_loads import N_ICE, _analysed, _table


def _printed(tables, width=80) -> str:
    buffer = io.StringIO()
    console = Console(file=buffer, width=width, force_terminal=False)
    for table in tables:
        console.print(table)
    return buffer.getvalue()


def test_terminal_table_fits_80_columns_with_units_and_ratios():
    summary = json.loads(json.dumps({"design_loads": [_table().as_dict()]}))
    text = _printed(_design_load_tables(summary))
    assert max(len(line) for line in text.splitlines()) <= 80
    assert "design loads, port, against IACS UR I3 PC5" in text
    assert "pitch 95.9 %" in text and "pitch 0 %" in text
    full = summary["design_loads"][0]["rows"][1]
    assert f"{full['torque_ratio']:.2f}" in text and "kN·m" in text and "…" not in text
    assert "x_max over profile" in text and "largest of 511" in text  # where each design value comes from
    lines = _design_basis_lines(summary)
    assert any(line.startswith("rule Q_max: IACS UR I3") for line in lines)
    assert any("not extrapolated" in line for line in lines)


def test_summary_report_and_figure_of_an_analysis(tmp_path):
    result = _analysed("hull")
    design = design_load_summary(result)
    run = tmp_path / "run"
    run.mkdir()
    figures = propeller_figures(result)
    write_propeller_files(result, run / "propeller", figures, extra_summary={"design_loads": design})
    written = json.loads((run / "propeller" / "summary.json").read_text(encoding="utf-8"))
    assert [t["propeller"] for t in written["design_loads"]] == ["propeller 1", "propeller 2"]
    row = written["design_loads"][0]["rows"][0]
    assert row["rule_n_ice"] == pytest.approx(N_ICE)
    assert row["torque_ratio"] == pytest.approx(row["design_torque_kn_m"] / row["rule_max_torque_kn_m"])
    # the exceedance figure's rule curve at the rule's N_ice, not at the sample size
    legend = figures["ice_class_exceedance.png"].legends[0]
    assert f"N_ice = {N_ICE:.3g}" in " ".join(t.get_text() for t in legend.get_texts())

    (run / "summary.json").write_text(
        json.dumps({"scenario_hash": "ab" * 32, "model_hash": "cd" * 32, "n_cusps": 3, "provenance": {}}),
        encoding="utf-8",
    )
    page = render_report(run)
    assert "<h3>Design loads, propeller 1, against IACS UR I3 PC5</h3>" in page
    assert "<summary>Basis of each number</summary>" in page and "rule-form x_max" in page
    # hashes and provenance collapsed at the end, not in the summary table at the top
    end = page.index("<h2>Provenance</h2>")
    assert page.index("cd" * 32) > end and page.index("Provenance of the propeller files") > end
    assert page[end:].count("<details>") == 2 and "<details open" not in page


def test_report_without_a_polar_class_says_how_to_get_the_table(tmp_path):
    result = _analysed("all")
    run = tmp_path / "run"
    run.mkdir()
    write_propeller_files(result, run / "propeller", {}, extra_summary={"design_loads": None})
    (run / "summary.json").write_text(json.dumps({"n_cusps": 1}), encoding="utf-8")
    assert "<code>--polar-class</code>" in render_report(run)


def test_the_three_design_torques_of_a_pitch_say_which_is_which(tmp_path, monkeypatch):
    """With cusps assigned to two propellers, the rule-form table's q_max (all cusps, the mean propeller's
    rate) and each propeller's design Q (its own cusps and rate) differ; each is labelled with its basis,
    in the terminal and in the report."""
    import floebreak.cli.tables as tables

    result = _analysed("hull")
    write_propeller_files(
        result, tmp_path / "p", {}, extra_summary={"design_loads": design_load_summary(result)}
    )
    summary = json.loads((tmp_path / "p" / "summary.json").read_text(encoding="utf-8"))
    fit = summary["rule_form"]["p0"]["torque_knm"]["x_max_lifetime"]
    per_propeller = [t["rows"][0]["design_torque_kn_m"] for t in summary["design_loads"]]
    assert len({round(fit), *(round(q) for q in per_propeller)}) == 3  # three numbers for one pitch

    buffer = io.StringIO()
    monkeypatch.setattr(tables, "console", Console(file=buffer, width=100, force_terminal=False))
    tables.print_propeller_summary(summary, tmp_path / "p", quiet=False)
    text = " ".join(buffer.getvalue().split())
    assert "mean propeller" in text and "all cusps" in text  # the rule-form table's title and column
    assert text.count("x_max over profile, this") >= 2  # both design tables (folded before "propeller")
    assert "q_max profile (rule-form table): the fit to all cusps at the mean propeller's rate" in text

    page = "\n".join(propeller_section(tmp_path / "p"))
    assert "|Q| max over the profile, all cusps, mean propeller [kN·m]" in page
    assert "design ice torque Q, this propeller" in page and "Which design torque is which" in page
