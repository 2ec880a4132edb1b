"""A resumed study trusts a run only as far as its checksums reach, its summary.json included: a
hand-edited summary is not aggregated but run again."""

from __future__ import annotations

import json

import pyarrow.parquet as pq

from floebreak.studies.aggregate import aggregate
from floebreak.studies.design import expand, study_from_dict
from floebreak.studies.runner import run_study

STUDY = {
    "name": "s",
    "n_fields": 1,
    "base": {"seed": 1, "field": {"observation": "2019-12-18T20:20", "length_m": 50.0, "width_m": 30.0}},
}


def test_a_hand_edited_summary_is_run_again_not_aggregated(tmp_path):
    spec = study_from_dict(STUDY)
    runs, members = expand(spec)
    run_study(spec, runs, members, tmp_path)
    summary_file = tmp_path / "runs" / "run-00000" / "summary.json"
    original = json.loads(summary_file.read_text(encoding="utf-8"))
    assert original["n_cusps"] != 123456
    # the campaign's edit: one value changed, every listed file (and its checksum) left as it was
    summary_file.write_text(json.dumps({**original, "n_cusps": 123456}, indent=2) + "\n", encoding="utf-8")

    state = run_study(spec, runs, members, tmp_path)
    assert state.skipped == 0 and state.done == 1 and state.failed == 0  # not trusted: run again
    assert json.loads(summary_file.read_text(encoding="utf-8"))["n_cusps"] == original["n_cusps"]
    aggregate(tmp_path)
    rows = pq.read_table(tmp_path / "study_runs.parquet").to_pylist()
    assert [row["n_cusps"] for row in rows] == [original["n_cusps"]]


def test_an_untouched_summary_is_trusted(tmp_path):
    spec = study_from_dict(STUDY)
    runs, members = expand(spec)
    run_study(spec, runs, members, tmp_path)
    summary_file = tmp_path / "runs" / "run-00000" / "summary.json"
    doc = json.loads(summary_file.read_text(encoding="utf-8"))
    summary_file.write_text(json.dumps(doc) + "\n", encoding="utf-8")  # other layout, same content
    state = run_study(spec, runs, members, tmp_path)
    assert state.skipped == 1 and state.done == 1


def test_a_study_resumed_under_another_event_location_runs_again(tmp_path, monkeypatch):
    """The profile's event location is not in the scenario hash (the scenario does not state it): a run made
    under one default is not reused under another."""
    from floebreak.config import profiles

    spec = study_from_dict(STUDY)
    runs, members = expand(spec)
    run_study(spec, runs, members, tmp_path)
    summary_file = tmp_path / "runs" / "run-00000" / "summary.json"
    first = json.loads(summary_file.read_text(encoding="utf-8"))
    assert first["event_location"] == profiles.DEFAULT_EVENT_LOCATION
    other = "root" if profiles.DEFAULT_EVENT_LOCATION == "step_end" else "step_end"
    monkeypatch.setattr(profiles, "DEFAULT_EVENT_LOCATION", other)

    state = run_study(spec, runs, members, tmp_path)
    assert state.skipped == 0 and state.done == 1 and state.failed == 0
    again = json.loads(summary_file.read_text(encoding="utf-8"))
    assert again["event_location"] == other and again["scenario_hash"] == first["scenario_hash"]
    assert run_study(spec, runs, members, tmp_path).skipped == 1  # and now it is trusted again
