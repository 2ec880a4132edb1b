"""A run with ship.propulsion writes surge.csv and a "surge" summary; a run without it writes neither. The
force series is checked against the contact model's own force vectors, collected by a callback."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import floebreak
from floebreak.engine.loop import ContactEvaluated
from floebreak.output.surge_file import SURGE_FILE, surge_of

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "single_floe.toml"
PROPULSION = [
    "ship.propulsion.model=bollard_pull",
    "ship.propulsion.displacement_kg=1.3687e7",
    "ship.propulsion.bollard_pull_n=1.12e6",
    "ship.propulsion.open_water_speed_m_s=8.23",
]


@pytest.fixture(scope="module")
def propelled():
    events: list[ContactEvaluated] = []
    result = floebreak.run(EXAMPLE, overrides=PROPULSION, callbacks=[events.append])
    return result, [e for e in events if isinstance(e, ContactEvaluated)]


def test_force_after_the_breaks_is_the_contact_models_force_on_the_pieces_that_stay(propelled):
    result, events = propelled
    surge = surge_of(result)
    expected = np.zeros(result.simulation.n_steps)
    for event in events:
        if not event.outcome.failed:
            expected[event.step] += event.contact.force_on_ice_xyz_n[0]
    reached = len(surge.ice_force_x_after_breaks_n)
    assert expected.max() > 0.0
    assert surge.ice_force_x_after_breaks_n == pytest.approx(expected[:reached], rel=1e-9, abs=1e-6)


def test_run_directory_has_the_surge_series_and_summary(propelled, tmp_path):
    result, _ = propelled
    out = result.write(tmp_path / "run", report=False, figures=False)
    summary = json.loads((out / "summary.json").read_text())["surge"]
    with (out / SURGE_FILE).open() as file:
        rows = list(csv.DictReader(line for line in file if not line.startswith("#")))
    assert list(rows[0]) == ["bow_x_m", "time_s", "speed_m_s", "ice_force_x_n", "ice_force_x_after_breaks_n"]
    x = np.array([float(r["bow_x_m"]) for r in rows])
    t = np.array([float(r["time_s"]) for r in rows])
    v = np.array([float(r["speed_m_s"]) for r in rows])
    assert v[0] == result.scenario.ship.speed_m_s and np.all(np.diff(t) > 0) and np.all(np.diff(x) > 0)
    assert summary["distance_m"] == pytest.approx(x[-1] - x[0])
    assert summary["transit_time_s"] == pytest.approx(t[-1])
    assert summary["stuck"] is False and summary["mean_ice_resistance_n"] > 0.0
    assert "surge.csv" in json.loads((out / "summary.json").read_text())["files"]


def test_without_propulsion_nothing_changes(tmp_path):
    result = floebreak.run(EXAMPLE)
    assert "surge" not in result.summary and surge_of(result) is None
    out = result.write(tmp_path / "run", report=False, figures=False)
    assert not (out / SURGE_FILE).exists()
