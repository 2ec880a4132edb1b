"""A small fixed sample of the fuzz campaign (`floebreak.fuzz`; the full campaign: `make fuzz N=5000`)."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest

from floebreak import fuzz
from floebreak.scenario import Scenario


def test_drawn_scenarios_are_valid_and_reproducible():
    first, again = fuzz.draw_scenarios(20, 7), fuzz.draw_scenarios(20, 7)
    assert first == again and len(first) == 20
    for data in first:
        Scenario.from_dict(data)  # every drawn scenario passes validation (the campaign tests the engine)
        if "observation" not in data["field"]:  # only an observation brings its thickness (thesis Table 1)
            assert {"thickness_m", "thickness_range_m"} & set(data["ice"])


def test_fixed_sample_has_no_crash_or_violation(tmp_path):
    summary = fuzz.run_campaign(4, 3, 1, tmp_path, max_rss_mb=1024.0)
    assert summary["runs"] == 4
    assert summary["crash"] == 0 and summary["violations"] == 0 and summary["over_memory"] == 0, list(
        tmp_path.glob("case-*.toml")
    )
    assert json.loads((tmp_path / "summary.json").read_text())["runs"] == 4


def _fake_check(data):
    """A stand-in for `fuzz.check_one`: the scenario's seed as its time, no simulation."""
    return {
        "scenario": data,
        "status": "ok",
        "problems": [],
        "seconds": float(data["seed"]),
        "peak_rss_mb": 1.0,
    }


def _indices(path):
    return [json.loads(line)["index"] for line in path.read_text().splitlines()]


def test_records_are_appended_and_resume_runs_only_the_missing(tmp_path):
    fuzz.run_campaign(5, 3, 0, tmp_path, 1024.0, check=_fake_check)
    log = tmp_path / "records.jsonl"
    assert sorted(_indices(log)) == [0, 1, 2, 3, 4]
    lines = log.read_text().splitlines(keepends=True)
    log.write_text("".join(lines[:2]) + lines[2][:17])  # a campaign stopped while writing its third record
    with pytest.raises(SystemExit, match="--resume"):
        fuzz.run_campaign(5, 3, 0, tmp_path, 1024.0, check=_fake_check)
    with pytest.raises(SystemExit, match="seed=3"):
        fuzz.run_campaign(5, 4, 0, tmp_path, 1024.0, resume=True, check=_fake_check)
    ran = []
    summary = fuzz.run_campaign(
        5, 3, 0, tmp_path, 1024.0, resume=True, check=lambda d: ran.append(d) or _fake_check(d)
    )
    assert len(ran) == 3 and summary["runs"] == 5
    assert sorted(_indices(log)) == [0, 1, 2, 3, 4]
    assert ran == [s for i, s in enumerate(fuzz.draw_scenarios(5, 3)) if i not in _indices(log)[:2]]


def test_summary_is_rebuilt_from_the_records():
    records = [
        {
            "index": i,
            "scenario": {},
            "status": "ok",
            "problems": [],
            "seconds": float(s),
            "peak_rss_mb": 100.0,
        }
        for i, s in enumerate([7, 3, 10, 1, 9, 2, 8, 4, 6, 5, 0.5])
    ]
    records[0].update(status="crash")
    records[1].update(problems=["area balance 1e-6"], area_balance_rel_error=1e-6)
    records[2].update(status="refused", peak_rss_mb=2000.0)
    summary = fuzz.summarize(records, 11, 1, max_rss_mb=1024.0)
    seconds = [r["seconds"] for r in records]
    assert (summary["runs"], summary["ok"], summary["refused"], summary["crash"]) == (11, 9, 1, 1)
    assert (summary["violations"], summary["over_memory"]) == (1, 1)
    assert summary["worst"] == {"area_balance_rel_error": 1e-6, "peak_rss_mb": 2000.0}
    assert summary["seconds"]["p50"] == np.percentile(seconds, 50, method="inverted_cdf") == 5.0
    assert summary["seconds"]["p90"] == np.percentile(seconds, 90, method="inverted_cdf") == 9.0
    assert summary["seconds"]["max"] == 10.0 and summary["seconds"]["total"] == sum(seconds)
    assert summary["cpu_seconds"]["max"] == 0.0  # not recorded in these records
    assert [s["index"] for s in summary["slowest"]] == [2, 4, 6, 0, 8, 9, 7, 1, 5, 3]


def _wait_for_the_others(data):
    """Scenario 0 finishes only after every other scenario has: a worker must not wait for it."""
    folder = Path(data["folder"])
    if data["seed"] == 0:
        for _ in range(600):
            if len(list(folder.glob("done-*"))) == data["n"] - 1:
                break
            time.sleep(0.1)
        else:
            return {**_fake_check(data), "status": "crash"}
    (folder / f"done-{data['seed']}").touch()
    return _fake_check(data)


def test_a_slow_scenario_holds_only_its_own_worker(tmp_path, monkeypatch):
    monkeypatch.setattr(fuzz, "WORKER_SCENARIOS", 2)  # fresh workers during the slow scenario too
    todo = [(i, {"seed": i, "n": 5, "folder": str(tmp_path)}) for i in range(5)]
    records = list(fuzz._records(todo, 2, _wait_for_the_others))
    assert [r["index"] for r in records][-1] == 0 and records[-1]["status"] == "ok"
    assert sorted(r["index"] for r in records) == [0, 1, 2, 3, 4]
