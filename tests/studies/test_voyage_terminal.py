"""The voyage's terminal tables as a piped (80-column) terminal shows them: units in brackets are printed,
not taken for rich markup, and long cells fold instead of being cut with "…"."""

from __future__ import annotations

import io

from rich.console import Console

import floebreak.cli.study as studies_cli


def _fit(scale: float) -> dict:
    return {
        "k": 2.136,
        "k_ci95": [2.078, 2.194],
        "rule_k": 0.75,
        "scale": scale,
        "n_per_hour": 4290.0,
        "x_max_per_hour": 924.0,
        "x_max_per_hour_ci95": [900.0, 951.0],
        "n_lifetime": 1.0725e8,
        "x_max_lifetime": 1340.0,
        "x_max_lifetime_ci95": [1293.0, 1391.0],
    }


def test_rule_form_table_keeps_units_and_whole_numbers_at_80_columns(monkeypatch):
    screen = io.StringIO()
    monkeypatch.setattr(studies_cli, "console", Console(file=screen, width=80, color_system=None))
    studies_cli._print_rule_form({"force_kn": _fit(341.9), "torque_knm": _fit(527.5)})
    text = screen.getvalue()
    assert "…" not in text
    assert "[kN]" in text and "[kN·m]" in text


def _voyage(load_model: str) -> dict:
    case = {"loads_per_hour": 4290.0, "loads_per_km": 397.2, "max_force_kn": 341.9, "max_torque_knm": 527.5}
    return {
        "hours_in_ice": 3.0,
        "distance_km": 32.4,
        "load_model": {"load_model": load_model},
        "cases": {"operated": {**case, "beyond_table_fraction": 0.0}},
    }


def test_the_cases_table_shows_the_fem_share_only_with_fem_tables(monkeypatch):
    for model, shown in (("milling", False), ("fem", True)):
        screen = io.StringIO()
        monkeypatch.setattr(studies_cli, "console", Console(file=screen, width=100, color_system=None))
        monkeypatch.setattr(studies_cli, "voyage_model_line", lambda summary: "")
        monkeypatch.setattr(studies_cli, "_print_rule_form", lambda fits: None)
        summary = _voyage(model) | {"n_periods_simulated": 1, "n_periods": 1, "rule_form": {}}
        summary |= {"generators": {}, "notes": [], "failures": []}
        studies_cli._print_voyage(summary, studies_cli.Path("v"))
        text = screen.getvalue()
        assert ("beyond FEM table" in text) is shown
        assert "…" not in text and max(len(line) for line in text.splitlines()) <= 100
