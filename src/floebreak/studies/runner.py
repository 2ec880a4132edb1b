"""Running a study: one run directory per run, resume, failures recorded, progress.

Layout of a study directory::

    study.json                 the study spec and the list of runs (index, group, point, field, seed)
    fields/field-<key>.parquet the common fields (``common_fields``), each generated once, here
    runs/run-00000/ …          one complete run directory per run (written atomically by the run pipeline)
    failed/run-00007.json      status, error and scenario of a failed run (removed when it later succeeds)
    study_runs.parquet         one row per run: parameters + summary (see `aggregate`)
    tables/, figures/          aggregated tables and figures

Common fields are generated once, in the process that runs the study, each just before the first run that
reads it is handed out (the workers start on the first field's runs meanwhile), and every run of that field
reads them: the design points then see the same fields even when the runs go to workers whose
CPUs make OpenBLAS pick other kernels, with which the packing would generate other fields from the same
seed (docs/model.md §4, Reproducibility), and a run's result does not depend on where it ran.

Resume: a run is complete when ``runs/<name>/summary.json`` exists with the scenario hash of the run, the
fingerprint of its model's settings and its event location (a profile's value can change between versions
while the scenario stays the same), and every file it lists (``files``: SHA-256 per file,
`floebreak.api.file_checksums`) is there with that checksum: a damaged run (a truncated Parquet file) is run
again. So is a run whose ``summary.json`` does not match the checksum of its own content (``summary_sha256``,
`floebreak.io.checksums`: an edited value, or a summary written before summaries carried one), since the
aggregate reads its values. Since run directories appear only by an atomic rename, a study killed at any
moment (even SIGKILL) resumes with no run lost or duplicated.
Left-over temporary directories of killed runs (or of killed workers) are removed at the start and at the
end. Paths are made absolute before they reach workers, whose working directory may be another.
"""

from __future__ import annotations

import json
import shutil
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from floebreak.io.atomic import write_text_atomic
from floebreak.studies.design import Membership, RunSpec, StudySpec
from floebreak.studies.executors import Executor, SerialExecutor


@dataclass
class StudyProgress:
    """Counters handed to the progress callback after every finished run."""

    total: int
    fields: int = 0  # common fields ready (generated now or by an earlier, resumed start)
    done: int = 0
    skipped: int = 0
    failed: int = 0
    failures: list[dict[str, Any]] = field(default_factory=list)


def run_identity(scenario: dict[str, Any]) -> tuple[str, str, str]:
    """(scenario hash, model fingerprint, event location) of a run: what its summary must record for it to
    be reused. The event location is the resolved one: a profile's default is not in the scenario hash."""
    from floebreak.app.build import event_location
    from floebreak.app.run import build_model_for
    from floebreak.config.scenario import Scenario

    resolved = Scenario.from_dict(scenario).resolved()
    return resolved.hash(), build_model_for(resolved).fingerprint(), event_location(resolved)


def is_complete(run_dir: Path, identity: tuple[str, str, str]) -> bool:
    """Whether `run_dir` holds the finished run of `identity` (`run_identity`: the same scenario run with the
    same model settings and event location) with every file intact (checksums), its summary included (the
    checksum of its own content, `floebreak.io.checksums`)."""
    from floebreak.app.run import file_checksums
    from floebreak.io.checksums import checksum_matches

    summary = run_dir / "summary.json"
    if not summary.exists():
        return False
    try:
        doc = json.loads(summary.read_text(encoding="utf-8"))
        if not isinstance(doc, dict) or not checksum_matches(doc):
            return False
        recorded = (doc.get("scenario_hash"), doc.get("model_hash"), doc.get("event_location"))
        if recorded != identity or not isinstance(doc.get("files"), dict):
            return False
        return file_checksums(run_dir, doc["files"]) == doc["files"]
    except (OSError, json.JSONDecodeError):
        return False


def remove_temporary_runs(runs_dir: Path) -> None:
    """Remove temporary run directories left by killed runs or workers (nothing reads them)."""
    for pattern in (".run-*.tmp-*", ".run-*.old-*", ".run-*.spool-*"):
        for stale in runs_dir.glob(pattern):
            shutil.rmtree(stale, ignore_errors=True)


def execute_run(task: dict[str, Any]) -> dict[str, Any]:
    """Run one scenario into its run directory; return its small summary (runs in a worker process)."""
    from floebreak.app.run import run, write_run_directory
    from floebreak.io.atomic import scratch_directory
    from floebreak.output.field_files import load_field

    field_file = task.get("field_file")
    floe_field = load_field(field_file) if field_file else None
    with scratch_directory(task["run_dir"]) as spool:  # the contact records stream there (bounded memory)
        result = run(task["scenario"], floe_field=floe_field, spool=spool)
        write_run_directory(
            result, task["run_dir"], overwrite=True, report=False, figures=task.get("figures", True)
        )
    return {key: value for key, value in result.summary.items() if not isinstance(value, dict | list)}


def generate_common_field(scenario: dict[str, Any], fields_dir: Path) -> str | None:
    """The saved common field of a run's scenario, generated here on first request (errors raised); None
    when its field is not generated (file, inline floes)."""
    import numpy as np

    from floebreak.app.run import build_field, field_key
    from floebreak.config.scenario import Scenario
    from floebreak.output.field_files import save_field

    resolved = Scenario.from_dict(scenario).resolved()
    key = field_key(resolved)
    if key is None:
        return None
    path = fields_dir / f"field-{key[:20]}.parquet"
    if not path.exists():
        floe_field = build_field(resolved, np.random.default_rng(resolved.seed))
        fields_dir.mkdir(exist_ok=True)
        save_field(floe_field, path)  # atomic: a study killed here leaves no half file
    return str(path.resolve())  # absolute: a worker's working directory may be another


def common_field_file(scenario: dict[str, Any], fields_dir: Path) -> str | None:
    """`generate_common_field`, or None when the field cannot be generated (the run then fails in its
    worker and is recorded)."""
    try:
        return generate_common_field(scenario, fields_dir)
    except Exception:  # the run meets the same error in its worker, which records it as the run's
        return None


def _study_document(spec: StudySpec, runs: list[RunSpec], members: list[Membership]) -> dict[str, Any]:
    """The content of study.json: the spec, every run and every group membership."""
    return {
        "spec": spec.model_dump(mode="json"),
        "runs": [
            {
                "index": r.index,
                "name": r.run_name,
                "group": r.group,
                "point": r.point,
                "field_index": r.field_index,
                "seed": r.seed,
            }
            for r in runs
        ],
        "members": [
            {"group": m.group, "point": m.point, "field_index": m.field_index, "run": m.run_name}
            for m in members
        ],
    }


def _record_failure(
    state: StudyProgress, failure_file: Path, name: str, scenario: dict[str, Any], error: BaseException
) -> None:
    """Count a failed run and write its error, traceback and scenario to `failure_file`."""
    state.failed += 1
    record = {
        "run": name,
        "status": "failed",
        "error": f"{type(error).__name__}: {error}",
        "traceback": "".join(traceback.format_exception(error)),
        "scenario": scenario,
    }
    state.failures.append(record)
    write_text_atomic(failure_file, json.dumps(record, indent=2, default=str) + "\n")


def _pending_tasks(
    spec: StudySpec,
    runs: list[RunSpec],
    out_dir: Path,
    state: StudyProgress,
    progress: Callable[[StudyProgress], None] | None,
    run_figures: bool,
) -> Iterator[dict[str, Any]]:
    """The tasks of the runs not complete yet, in order; a run's common field is generated when its task is
    due, so the workers start on the first field's runs while the next fields are generated."""
    fields_ready: set[str] = set()
    for spec_run in runs:
        run_dir = out_dir / "runs" / spec_run.run_name
        if is_complete(run_dir, run_identity(spec_run.scenario)):
            state.skipped += 1
            state.done += 1
            continue
        task = {
            "index": spec_run.index,
            "scenario": spec_run.scenario,
            "run_dir": str(run_dir),
            "figures": run_figures,
        }
        if spec.common_fields:
            task["field_file"] = common_field_file(spec_run.scenario, out_dir / "fields")
            if task["field_file"] and task["field_file"] not in fields_ready:
                fields_ready.add(task["field_file"])
                state.fields = len(fields_ready)
                if progress:  # generating a field may take a while
                    progress(state)
        yield task


def run_study(
    spec: StudySpec,
    runs: list[RunSpec],
    members: list[Membership],
    out_dir: Path,
    executor: Executor | None = None,
    progress: Callable[[StudyProgress], None] | None = None,
    run_figures: bool = True,
) -> StudyProgress:
    """Run every incomplete run of the study; failures are recorded and the study goes on.

    `run_figures=False`: the run directories get no figures/ (a voyage reads only their tables)."""
    executor = executor or SerialExecutor()
    out_dir = Path(out_dir).absolute()  # workers (Dask) may have another working directory
    runs_dir, failed_dir = out_dir / "runs", out_dir / "failed"
    runs_dir.mkdir(parents=True, exist_ok=True)
    failed_dir.mkdir(exist_ok=True)
    remove_temporary_runs(runs_dir)
    study_doc = _study_document(spec, runs, members)
    write_text_atomic(out_dir / "study.json", json.dumps(study_doc, indent=2) + "\n")
    state = StudyProgress(total=len(runs))
    if progress:
        progress(state)
    tasks = _pending_tasks(spec, runs, out_dir, state, progress, run_figures)
    for task, _summary, error in executor.run(execute_run, tasks):
        name = Path(task["run_dir"]).name
        failure_file = failed_dir / f"{name}.json"
        state.done += 1
        if error is None:
            failure_file.unlink(missing_ok=True)
        else:
            _record_failure(state, failure_file, name, task["scenario"], error)
        if progress:
            progress(state)
    remove_temporary_runs(runs_dir)  # e.g. of a worker killed mid-write whose run was redone elsewhere
    return state
