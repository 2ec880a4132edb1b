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
