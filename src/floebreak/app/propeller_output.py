"""The output directory of ``floebreak propeller``: the propeller analysis and, with a shaft line, the shaft
analysis in ``shaft/``, written into one temporary directory that becomes the output at once — a full disk
or an interruption leaves either the complete directory or nothing (never the propeller files without
``shaft/``). Its ``report.html`` (propeller, design loads, shaft) is written into the same temporary
directory; when the output lies inside a run directory, that run's ``report.html`` is rendered with it and
replaced (atomically) once the output is in place."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any, NamedTuple

from floebreak.app.propeller import write_propeller
from floebreak.io.atomic import atomic_directory
from floebreak.io.output_lock import output_lock
from floebreak.io.storage import StorageError
from floebreak.output.report import (
    analysis_folders,
    render_analysis_report,
    render_report,
    write_text_report,
)

# below this much free space the HDF5 library (the shaft's netCDF files) may crash instead of reporting
# ENOSPC; a propeller directory with its shaft analysis is a few MB
MIN_FREE_BYTES = 32 * 1024 * 1024

Stage = Callable[[str], AbstractContextManager[Any]]


def require_free_space(directory: Path, target: Path, needed: int | None = None) -> None:
    """StorageError (exit 3) naming `target` when `directory`'s file system has less than `needed` bytes
    (default `MIN_FREE_BYTES`) free."""
    needed = MIN_FREE_BYTES if needed is None else needed
    free = shutil.disk_usage(directory).free
    if free < needed:
        raise StorageError(
            target, f"No space left on device ({free / 1e6:.3g} MB free, {needed / 1e6:.3g} MB needed)"
        )


class WrittenPropeller(NamedTuple):
    """Where `write_propeller_directory` wrote: the output directory, its report and the report of the run
    directory it lies in (None outside a run directory)."""

    folder: Path
    report: Path
    run_report: Path | None


def enclosing_run(out: Path) -> Path | None:
    """The run directory (summary.json and scenario.resolved.toml) that `out` lies in, None if none."""
    for parent in Path(out).resolve().parents:
        if (parent / "summary.json").is_file() and (parent / "scenario.resolved.toml").is_file():
            return parent
    return None


def write_propeller_directory(
    result, record: dict, shaft, out: Path, *, overwrite: bool, stage: Stage, workers=(None, None)
) -> WrittenPropeller:
    """Write the propeller `result` (provenance `record`) and the prepared `shaft` analysis (or None) to
    `out` as one atomic directory with its report.html, and update the report of the run directory `out`
    lies in; `stage(label)` gives a progress context for each part; of the two figure `workers` the first
    draws the propeller's figures, the second the shaft's."""
    out = Path(out)
    parent = out.parent if str(out.parent) else Path(".")
    if parent.is_dir():
        require_free_space(parent, out)
    mine, theirs = workers
    run_dir = enclosing_run(out)
    with output_lock(out), atomic_directory(out, overwrite=overwrite, field="out") as temp:
        with stage("writing") as progress:
            # replaces the empty temporary directory (so that the propeller files are complete in it)
            write_propeller(
                result, temp, overwrite=True, record=record, progress=progress, figure_worker=mine
            )
        if shaft is not None:
            with stage("writing the shaft analysis") as progress:
                shaft.write(temp / "shaft", progress=progress, figure_worker=theirs)
        (temp / "report.html").write_text(render_analysis_report(temp, out.name), encoding="utf-8")
        run_text = None if run_dir is None else _run_report_text(run_dir, out, temp)
    run_report = None if run_text is None else write_text_report(run_text, run_dir / "report.html")
    return WrittenPropeller(out, out / "report.html", run_report)


def _run_report_text(run_dir: Path, out: Path, temp: Path) -> str:
    """The report of `run_dir` with the analysis being written (`temp`, to become `out`) in place of what
    `out` holds now."""
    name = out.resolve().relative_to(run_dir).as_posix()
    analyses = {**analysis_folders(run_dir), name: temp}
    ordered = dict(sorted(analyses.items(), key=lambda item: (item[0] != "propeller", item[0])))
    return render_report(run_dir, analyses=ordered)
