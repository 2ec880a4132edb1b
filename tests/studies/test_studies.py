"""Studies: design expansion, seeds, validation before running, resume, failures, executors."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from floebreak.errors import InputError
from floebreak.studies.aggregate import aggregate
from floebreak.studies.design import StudySpec, Sweep, expand, run_seed, study_from_dict, thesis_study
from floebreak.studies.executors import DaskExecutor, ProcessPoolExecutor, SerialExecutor
from floebreak.studies.runner import execute_run, run_study

SMALL_FIELD = {"length_m": 50.0, "width_m": 30.0}


def small_base() -> dict:
    return {
        "seed": 1,
        "field": {"observation": "2019-12-18T20:20", **SMALL_FIELD},
        "ice": {"thickness_m": 1.0},
        "ship": {"hull": "agulhas_ii", "step_m": 0.5},
    }


def small_study(**kwargs) -> StudySpec:
    values = {
        "name": "toughness",
        "root_seed": 7,
        "n_fields": 2,
        "base": small_base(),
        "sweeps": [Sweep(name="K", parameters={"ice.fracture_toughness_pa_sqrt_m": [120e3, 230e3]})],
    }
    return StudySpec(**{**values, **kwargs})


def test_thesis_study_design():
    runs, members = expand(thesis_study(n_fields=2))
    # groups: 3 K_Ic + 4 criteria + 3 h + 1 random h + 3 laws = 14 points × 2 fields; the reference point
    # (145.7 kPa√m, tensile, h = 1 m, BZ) is shared by four groups and runs once: 11 unique points
    assert len(members) == 14 * 2
    assert len(runs) == 11 * 2
    assert {m.group for m in members} == {
        "fracture toughness",
        "crack criterion",
        "ice thickness",
        "random thickness",
        "size-effect law",
    }


def test_seeds_follow_the_root_seed_sequence():
    runs, _ = expand(small_study(common_fields=False))
    for run in runs:
        expected = np.random.SeedSequence(7, spawn_key=(run.index,)).generate_state(1, dtype=np.uint32)[0]
        assert run.seed == int(expected) == run.scenario["seed"]
    common, _ = expand(small_study(common_fields=True))
    assert [r.seed for r in common] == [run_seed(7, 0), run_seed(7, 1)] * 2


@pytest.mark.parametrize(
    ("data", "field"),
    [
        ({"sweeps": [{"parameters": {}}]}, "sweeps.parameters"),
        ({"sweeps": [{"parameters": {"ice.thickness_m": []}}]}, "sweeps.parameters.ice.thickness_m"),
        ({"sweeps": [{"parameters": {"ice.colour": ["blue"]}}]}, "ice.colour"),
        ({"sweeps": [{"parameters": {"ice.thickness_m": [1.0, -0.5]}}]}, "ice.thickness_m"),
        ({"n_fields": 0}, "n_fields"),
    ],
)
def test_bad_studies_are_refused_before_running(data, field):
    with pytest.raises(InputError) as info:
        expand(study_from_dict({"base": small_base(), **data}))
    assert field in str(info.value)


def test_run_resume_failure_and_aggregate(tmp_path):
    spec = small_study()
    runs, members = expand(spec)
    state = run_study(spec, runs, members, tmp_path)
    assert state.done == 4 and state.failed == 0
    summary = aggregate(tmp_path)
    assert summary["complete"] == 4
    table = pq.read_table(tmp_path / "study_runs.parquet").to_pylist()
    assert len(table) == 4 and all(row["area_balance_rel_error"] <= 1e-9 for row in table)
    assert (tmp_path / "tables" / "k.csv").exists() and (tmp_path / "figures" / "spider.png").exists()

    # resume: a run killed mid-write leaves a temporary directory and no run directory
    shutil.rmtree(tmp_path / "runs" / "run-00002")
    (tmp_path / "runs" / ".run-00002.tmp-killed").mkdir()
    state = run_study(spec, runs, members, tmp_path)
    assert state.skipped == 3 and state.done == 4
    assert not (tmp_path / "runs" / ".run-00002.tmp-killed").exists()

    # a run made with other model settings (a profile value changed by an upgrade) is run again: the
    # scenario is the same, the fingerprint in its summary is not
    summary_file = tmp_path / "runs" / "run-00001" / "summary.json"
    doc = json.loads(summary_file.read_text(encoding="utf-8"))
    summary_file.write_text(json.dumps({**doc, "model_hash": "0" * 64}), encoding="utf-8")
    state = run_study(spec, runs, members, tmp_path)
    assert state.skipped == 3 and state.done == 4
    assert json.loads(summary_file.read_text(encoding="utf-8"))["model_hash"] == doc["model_hash"]

    # a single run recomputed alone equals the study's run
    alone = tmp_path / "alone"
    execute_run({"scenario": runs[1].scenario, "run_dir": str(alone)})
    a = pq.read_table(alone / "cusps.parquet").drop_columns(["geometry"])
    b = pq.read_table(tmp_path / "runs" / "run-00001" / "cusps.parquet").drop_columns(["geometry"])
    assert a.to_pylist() == b.to_pylist()


@pytest.mark.parametrize("common_fields", [True, False])
def test_common_fields_are_generated_once_by_the_study(tmp_path, monkeypatch, common_fields):
    # two design points × two fields: with common fields, two fields are generated, in the study's process,
    # saved in the study directory, and every run of a field reads that one — whichever worker runs it (a
    # worker on another CPU would generate another field from the same seed, docs/model.md §4)
    from floebreak.ice import generation

    seeds = []
    original = generation.generate_field

    def counting(*args, **kwargs):
        seeds.append(kwargs["seed"])
        return original(*args, **kwargs)

    monkeypatch.setattr(generation, "generate_field", counting)
    spec = small_study(common_fields=common_fields)
    runs, members = expand(spec)
    state = run_study(spec, runs, members, tmp_path)
    assert state.failed == 0 and state.fields == (2 if common_fields else 0)
    fields = sorted((tmp_path / "fields").glob("field-*.parquet"))
    if not common_fields:  # independent fields: each run generates its own, nothing is shared
        assert len(seeds) == 4 and fields == []
        return
    assert len(seeds) == 2 and len(fields) == 2

    def geometry(run):
        return (
            pq.read_table(tmp_path / "runs" / run.run_name / "field.parquet").column("geometry").to_pylist()
        )

    by_field = {}
    for run in runs:
        by_field.setdefault(run.field_index, []).append(geometry(run))
    assert len(by_field) == 2
    for index, geometries in by_field.items():
        assert len(geometries) == 2 and geometries[0] == geometries[1], index  # same field at both points


def test_failing_run_is_recorded_and_the_study_goes_on(tmp_path):
    base = small_base()
    spec = StudySpec(
        name="dense",
        n_fields=1,
        base=base,
        sweeps=[
            Sweep(
                name="obs",
                parameters={
                    "field.observation": ["2019-12-18T20:20", "2019-12-18T22:30"],
                    # 89 % in 400 m × 200 m: its 22 floes of 60 m do not fit (18 at most in a lattice)
                    "field.width_m": [30.0, 200.0],
                    "field.length_m": [50.0, 400.0],
                },
                mode="zip",
            )
        ],
    )
    runs, members = expand(spec)
    state = run_study(spec, runs, members, tmp_path)
    assert state.failed == 1 and state.done == 2
    record = json.loads((tmp_path / "failed" / "run-00001.json").read_text())
    assert record["status"] == "failed" and "concentration" in record["error"]
    assert record["scenario"]["field"]["observation"] == "2019-12-18T22:30"


def _summaries(executor, tmp_path, name):
    spec = small_study(n_fields=1)
    runs, members = expand(spec)
    try:
        run_study(spec, runs, members, tmp_path / name, executor)
    finally:
        executor.close()
    return [
        json.loads((tmp_path / name / "runs" / r.run_name / "summary.json").read_text())["cusp_area_m2"]
        for r in runs
    ]


def test_process_pool_and_dask_give_the_serial_results(tmp_path):
    serial = _summaries(SerialExecutor(), tmp_path, "serial")
    assert _summaries(ProcessPoolExecutor(2), tmp_path, "pool") == serial
    assert _summaries(DaskExecutor("local", 2), tmp_path, "dask") == serial


def _worker_state(_: int) -> tuple[int, bool, str | None]:
    import os

    return os.getpid(), "floebreak.app.run" in sys.modules, os.environ.get("OMP_NUM_THREADS")


def test_pool_workers_start_prepared_with_one_thread(monkeypatch):
    """Both workers are started at the pool's creation, each with what a run imports and one BLAS thread,
    before any task of the study reaches them."""
    import multiprocessing

    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    before = {child.pid for child in multiprocessing.active_children()}
    pool = ProcessPoolExecutor(2)
    try:
        started = {child.pid for child in multiprocessing.active_children()} - before
        states = [result for _, result, _ in pool.run(_worker_state, range(4))]
    finally:
        pool.close()
    assert len(started) == 2
    assert {pid for pid, _, _ in states} <= started
    assert all(prepared and threads == "1" for _, prepared, threads in states)


def test_unreachable_scheduler_is_a_clear_error():
    with pytest.raises(InputError, match=r"within 0\.2 s") as info:
        DaskExecutor("tcp://127.0.0.1:9", timeout_s=0.2)
    assert info.value.field == "scheduler"


def test_a_scheduler_without_dask_installed_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed: importing it fails
    with pytest.raises(InputError, match=r"floebreak\[cluster\]") as info:
        DaskExecutor("tcp://127.0.0.1:8786")
    assert info.value.field == "scheduler"


def test_study_cli_runs_and_resumes(tmp_path):
    import subprocess
    import sys

    study_file = tmp_path / "study.toml"
    study_file.write_text(
        'name = "cli"\nn_fields = 1\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
        "length_m = 50.0\nwidth_m = 30.0\n[base.ship]\nstep_m = 0.5\n"
        '[[sweeps]]\nname = "K"\nparameters = { "ice.fracture_toughness_pa_sqrt_m" = [120e3, 230e3] }\n',
        encoding="utf-8",
    )
    command = [
        sys.executable,
        "-c",
        "from floebreak.cli import main; main()",
        "study",
        str(study_file),
        "--out",
        str(tmp_path / "out"),
        "--workers",
        "1",
    ]
    first = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    assert (tmp_path / "out" / "tables" / "k.csv").exists()
    second = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert second.returncode == 0 and "complete 2, failed 0" in second.stdout.replace("\n", " ")
    bad = subprocess.run(
        [*command[:4], str(tmp_path / "missing.toml"), "--out", str(tmp_path / "x")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert bad.returncode == 2 and "study" in bad.stderr and not (tmp_path / "x").exists()


# --- damaged runs, relative paths, failed runs, temporary folders ----------------------------


class RecordingExecutor(SerialExecutor):
    """Serial, and remembers the tasks it was given (what a remote worker would receive)."""

    def __init__(self):
        self.tasks = []

    def run(self, fn, items):
        items = list(items)
        self.tasks.extend(items)
        yield from super().run(fn, items)


def test_a_damaged_run_is_run_again(tmp_path):
    spec = small_study(n_fields=1, sweeps=[])
    runs, members = expand(spec)
    run_study(spec, runs, members, tmp_path)
    cusps = tmp_path / "runs" / "run-00000" / "cusps.parquet"
    intact = cusps.read_bytes()
    cusps.write_bytes(intact[: len(intact) // 2])  # truncated next to an intact summary.json
    again = run_study(spec, runs, members, tmp_path)
    assert again.skipped == 0 and again.failed == 0
    assert cusps.read_bytes() == intact  # the same run, written again
    assert aggregate(tmp_path)["complete"] == 1
    assert run_study(spec, runs, members, tmp_path).skipped == 1  # and now trusted


def test_paths_reach_workers_absolute(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    spec = small_study(n_fields=1, sweeps=[])
    runs, members = expand(spec)
    executor = RecordingExecutor()
    state = run_study(spec, runs, members, Path("relative"), executor)
    assert state.failed == 0 and executor.tasks
    for task in executor.tasks:
        assert task["run_dir"].startswith(str(tmp_path)) and task["field_file"].startswith(str(tmp_path))


def test_temporary_run_folders_are_removed_when_the_study_ends(tmp_path):
    spec = small_study(n_fields=1, sweeps=[])
    runs, members = expand(spec)

    class KilledWorker(SerialExecutor):  # a worker killed mid-write leaves its temporary folder
        def run(self, fn, items):
            (tmp_path / "runs" / ".run-00000.tmp-killed").mkdir(parents=True)
            yield from super().run(fn, items)

    run_study(spec, runs, members, tmp_path, KilledWorker())
    assert [p.name for p in (tmp_path / "runs").iterdir()] == ["run-00000"]


def test_a_study_with_failed_runs_exits_4_and_says_how_many(tmp_path, monkeypatch, cli):
    from floebreak.studies import runner

    def broken(task):
        raise RuntimeError("worker lost")

    monkeypatch.setattr(runner, "execute_run", broken)
    study_file = tmp_path / "study.toml"
    study_file.write_text(
        'name = "f"\nn_fields = 2\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
        "length_m = 50.0\nwidth_m = 30.0\n",
        encoding="utf-8",
    )
    code, out, _ = cli("study", study_file, "--out", tmp_path / "out", "--workers", "1")
    assert code == 4 and "2 of 2 runs failed" in out.replace("\n", " ")
