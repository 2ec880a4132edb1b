"""A small fixed sample of the fuzz campaign (`fuzz`; the full campaign: `make fuzz N=5000`)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import fuzz
from floebreak.config.scenario import Scenario


def _scenario(data):
    """A drawn record's scenario (without the files it names)."""
    return {key: value for key, value in data.items() if key != fuzz.FILES}


def test_drawn_scenarios_are_valid_and_reproducible():
    first, again = fuzz.draw_scenarios(20, 7), fuzz.draw_scenarios(20, 7)
    assert first == again and len(first) == 20
    json.dumps(first)  # records are JSON (records.jsonl), files included
    for data in first:
        Scenario.from_dict(
            _scenario(data)
        )  # every drawn scenario passes validation (the campaign tests the engine)
        if not {"observation", "file"} & set(data["field"]):  # an observation brings its thickness (Table 1)
            assert {"thickness_m", "thickness_range_m"} & set(data["ice"])
        for key, name in (("field", "file"), ("ship", "file")):
            if name in data[key]:  # a named file is carried by the record
                assert data[key][name] in data[fuzz.FILES]


# each option the harness draws beyond the flat sections, as a test on a drawn record
OPTIONS = {
    "policy list": lambda d: any(isinstance(v, list) for v in d["failure"].get("policy", {}).values()),
    "policy per region": lambda d: any(
        isinstance(v, dict) and v for v in d["failure"].get("policy", {}).values()
    ),
    "hull parameters": lambda d: bool(d["ship"].get("hull_parameters")),
    "bow file (a)": lambda d: "line" in d.get(fuzz.FILES, {}).get("bow.csv", {}).get("text", ""),
    "bow file (b)": lambda d: "frame_angle_deg" in d.get(fuzz.FILES, {}).get("bow.csv", {}).get("text", ""),
    "field file": lambda d: (
        d.get(fuzz.FILES, {}).get("field.parquet", {}).get("field", {}).get("domain_metadata")
    ),
    "field file, no domain": lambda d: (
        "file" in d["field"] and not d[fuzz.FILES]["field.parquet"]["field"]["domain_metadata"]
    ),
    "sqp": lambda d: d["field"].get("generator") == "sqp",
    "propeller": lambda d: bool(d.get("propeller")),
}


def test_the_sample_draws_every_option_and_each_runs_or_is_refused_cleanly():
    # Hypothesis mixes the package's literal constants into its draws (`fuzz._import_every_module`), so one
    # seed's sample moves with every source change: draw from successive seeds until every option is drawn.
    drawn = []
    for campaign_seed in range(4, 16):
        drawn += fuzz.draw_scenarios(80, campaign_seed)
        if all(any(has(d) for d in drawn) for has in OPTIONS.values()):
            break
    for option, has in OPTIONS.items():
        data = next((d for d in drawn if has(d)), None)
        assert data is not None, f"no {option} in the sample"
        data = json.loads(json.dumps(data))
        data["ship"]["x_end_m"] = data["ship"].get("x_start_m", 0.0) + 8 * data["ship"]["step_m"]  # cheap
        record = fuzz.check_one(data)
        assert record["status"] in ("ok", "refused") and not record["problems"], (option, record)
        if record["status"] == "refused":  # an input error names a key or a file
            assert record["message"].split(":")[0].strip(), (option, record)


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


WORKER_SCRIPT = """
import os, sys, time
from pathlib import Path
import fuzz

def stuck(data):
    Path(sys.argv[1], f"worker-{os.getpid()}").touch()
    time.sleep(3600)

if __name__ == "__main__":
    with fuzz.exit_on_sigterm():
        fuzz.run_campaign(4, 1, 2, Path(sys.argv[1]), 1024.0, check=stuck)
"""


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_stopped_campaign_leaves_no_worker_running(tmp_path, signum):
    """SIGTERM or Ctrl-C to the campaign's process while both workers run a scenario: the campaign exits
    and terminates its workers (before the fix they ran on as orphans)."""
    script = tmp_path / "campaign.py"
    script.write_text(WORKER_SCRIPT)
    out = tmp_path / "out"
    out.mkdir()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    campaign = subprocess.Popen([sys.executable, str(script), str(out)], env=env, stderr=subprocess.PIPE)
    try:
        for _ in range(1200):  # until both workers are inside a scenario (or the campaign died)
            workers = [int(path.name.split("-")[1]) for path in out.glob("worker-*")]
            if len(workers) == 2 or campaign.poll() is not None:
                break
            time.sleep(0.1)
        assert len(workers) == 2, campaign.communicate()[1]
        campaign.send_signal(signum)
        _, stderr = campaign.communicate(timeout=120)
    finally:
        if campaign.poll() is None:
            campaign.kill()
    left = [pid for pid in workers if _alive(pid)]
    for pid in left:  # the test's own processes: not left behind if it fails
        os.kill(pid, signal.SIGKILL)
    assert campaign.returncode == (143 if signum == signal.SIGTERM else -signal.SIGINT), stderr
    assert not left  # terminated and joined by the campaign, not orphaned


def test_resume_runs_the_kept_scenarios_and_retry_reruns_the_flagged(tmp_path):
    drawn = fuzz.draw_scenarios(4, 3)
    first = fuzz.run_campaign(4, 3, 0, tmp_path, 1024.0, check=_fake_check)
    assert first["crash"] == 0
    kept = tmp_path / "scenarios.jsonl"
    lines = kept.read_text().splitlines()
    assert [json.loads(line) for line in lines[1:]] == drawn
    log = tmp_path / "records.jsonl"
    records = [json.loads(line) for line in log.read_text().splitlines()]
    records[0].update(status="crash")  # as if scenario 0 had crashed
    log.write_text("".join(json.dumps(r) + "\n" for r in records))
    (tmp_path / f"case-{records[0]['index']:05d}.toml").write_text("# stale\n")
    changed = {**json.loads(lines[1 + records[0]["index"]]), "seed": 12345}  # the kept scenario is what runs
    lines[1 + records[0]["index"]] = json.dumps(changed)
    kept.write_text("\n".join(lines) + "\n")
    ran = []
    summary = fuzz.run_campaign(
        4, 3, 0, tmp_path, 1024.0, resume=True, retry=True, check=lambda d: ran.append(d) or _fake_check(d)
    )
    assert ran == [changed] and summary["crash"] == 0 and summary["runs"] == 4
    assert not list(tmp_path.glob("case-*"))  # the stale case of the retried scenario is gone
    assert sorted(_indices(log)) == [0, 1, 2, 3]
