"""A `Result` → its run directory, written atomically (temporary sibling, renamed when complete; a failed
run leaves no half directory):

- ``summary.json``: thesis Tables 5–8 columns (n_cusp, A_cusp^tot, n_flip, A_flip^tot, V̄_cusp, Ā_cusp), the
  area balance, contact/break counters, the maximum crushing force, wall time, provenance;
- ``cusps.parquet``, ``flipped.parquet``, ``remaining.parquet``, ``field.parquet`` (the initial field as
  simulated, i.e. after any shift for no initial contact): GeoParquet, ``"crs": null``, one row per piece;
- ``contacts.parquet``: one row per floe–panel contact evaluation
(`floebreak.engine.records.CONTACT_COLUMNS`);
- ``pieces.parquet``: every piece that existed in the run (initial floes, broken pieces, cusps, flipped and
  remaining pieces; GeoParquet, field frame; the geometry is empty for a piece created and broken at one bow
  position, which is never in the field between two steps) with ``piece_id``, ``parent_piece_id`` (−1 for
  initial floes), ``parent_floe_id``, ``fate`` (``broken``/``cusp``/``flipped``/``remaining``),
  ``created_step`` (−1 for initial floes), ``ended_step`` (the step it broke or left the field; −1 if it
  remains), ``thickness_m``, ``area_m2``, ``ended_by`` (the failure mode that broke the piece or took it out
  whole, "" if none; `floebreak.engine.records.failure_chain` rebuilds a piece's chain); the metadata adds
  ``x_start_m``, ``step_m``, ``n_steps`` (bow x at step s = x_start_m + s·step_m). Enough to replay the
  transit (``floebreak animate``);
- ``poses.parquet`` (a `dynamic` run with ``simulation.pose_interval_steps``): the poses of the pieces the
  ice motion moved, every that many steps (`floebreak.output.pose_file`, `floebreak.io.poses`), for the
  animation;
- ``scenario.resolved.toml`` (every default filled in), ``figures/*.png``, ``report.html``.

Every file carries provenance (floebreak and library versions, the resolved scenario, its hash, the seed).

The figures take most of the writing (importing matplotlib, drawing, encoding the PNGs). Where
`floebreak.output.figure_process.fork_for_figures` allows, a forked figure worker draws them from plain data
(`Result.figure_call`) while this process writes the tables (that module says how). The command line forks
the worker before the run, so that it imports matplotlib while the engine runs, and sends it the field's
figure as soon as the field is generated (`floebreak.app.run.run`); a `Result.write` without a worker forks
one at the write. The files are the same as drawn serially (benchmarks/README.md).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager, nullcontext
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from floebreak.engine.loop import SimulationResult
from floebreak.engine.records import ContactRecords, oriented_box_dimensions_m, piece_table
from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.io.atomic import atomic_directory
from floebreak.io.checksums import with_checksum
from floebreak.io.contacts import write_contacts
from floebreak.io.geoparquet import row_groups, write_geoparquet, write_geoparquet_groups
from floebreak.io.jsonable import jsonable
from floebreak.io.provenance import floebreak_version
from floebreak.io.storage import as_storage_error, probe_directory
from floebreak.io.writers import write_json
from floebreak.output import figure_process
from floebreak.output.record import RunRecord
from floebreak.output.registry import run_writers

PIECE_FILES = {"cusp": "cusps.parquet", "flipped": "flipped.parquet", "remaining": "remaining.parquet"}
PIECES_FILE = "pieces.parquet"  # every piece with its life span (replay / `floebreak animate`)
CONTACTS_FILE = "contacts.parquet"
FIGURES = {
    "breaking_pattern": "breaking_pattern.png",
    "cusp_volume_spectrum": "cusp_volume_spectrum.png",
    "crushing_force_spectrum": "crushing_force_spectrum.png",
    "field": "field.png",
}
# the run directory's figures of a longer field or transit show its first this many metres: its whole length


def field_table(floe_field: FloeField) -> dict[str, Any]:
    """Columns of the initial field in the layout of the piece tables (step −1, no failure mode)."""
    polygons = floe_field.polygons
    area = floe_field.area_m2
    length, width = oriented_box_dimensions_m(polygons)
    centroids = shapely.get_coordinates(shapely.centroid(polygons)) if polygons.size else np.zeros((0, 2))
    n = floe_field.n_floes
    return {
        "geometry": polygons,
        "floe_id": floe_field.floe_id,
        "area_m2": area,
        "thickness_m": floe_field.thickness_m,
        "volume_m3": area * floe_field.thickness_m,
        "diameter_class_m": floe_field.diameter_class_m,
        "centroid_x_m": centroids[:, 0],
        "centroid_y_m": centroids[:, 1],
        "bbox_length_m": length,
        "bbox_width_m": width,
        "step": np.full(n, -1, dtype=np.int64),
        "bow_x_m": np.full(n, np.nan),
        "parent_floe_id": floe_field.floe_id,
        "parent_piece_id": np.full(n, -1, dtype=np.int64),
        "failure_mode": np.array([""] * n, dtype=object),
    }


def pieces_table(
    simulation: SimulationResult,
    contacts: Mapping[str, np.ndarray] | ContactRecords,
    geometry: bool = True,
) -> dict[str, Any]:
    """Columns of every piece of the run (fates "broken", "cusp", "flipped", "remaining"), geometry included.

    ``created_step``: −1 for initial floes, else the step at which the parent broke (the engine adds the
    children in the same step, `floebreak.engine.loop.simulate`). ``ended_step``: the step a cusp or flipped
    piece left the field (`SimulationResult.step`), the step a broken piece broke, −1 for remaining pieces.
    `SimulationResult.step` of a broken piece is its creation step, and a child that rotated away later
    carries its leaving step, so the break step is taken from the recorded contact evaluations: a piece
    fails at most once, in its one evaluation with an outcome other than "no_failure". (Fallback without a
    record: the earliest step among its children, which is exact whenever one child stayed in the field or
    broke again.) `contacts`: the records' columns, or what `ContactRecorder.records` keeps of them.
    `geometry=False`: no ``geometry`` column (for a writer that takes the polygons a row group at a time).
    """
    if isinstance(contacts, ContactRecords):
        failed_piece, failed_step = contacts.failed_piece_id, contacts.failed_step
    else:
        failed = np.asarray(contacts["outcome"]) != "no_failure"
        failed_piece = np.asarray(contacts["piece_id"])[failed]
        failed_step = np.asarray(contacts["step"])[failed]
    fate = simulation.fate
    n = len(fate)
    ended = np.full(n, -1, dtype=np.int64)
    gone = (fate == "cusp") | (fate == "flipped")
    ended[gone] = simulation.step[gone]
    parents = simulation.parent_piece_id
    broken = np.flatnonzero(fate == "broken")
    if broken.size:
        never = np.iinfo(np.int64).max
        break_step = np.full(n, never, dtype=np.int64)
        np.minimum.at(break_step, failed_piece, failed_step)
        children_step = np.full(n, never, dtype=np.int64)
        child = parents >= 0
        np.minimum.at(children_step, parents[child], simulation.step[child])
        ended[broken] = np.where(break_step[broken] != never, break_step[broken], children_step[broken])
    created = np.where(parents >= 0, ended[np.maximum(parents, 0)], -1).astype(np.int64)
    columns = {
        "piece_id": simulation.piece_id,
        "parent_piece_id": parents,
        "parent_floe_id": simulation.parent_floe_id,
        "fate": np.asarray(fate, dtype=object),
        "created_step": created,
        "ended_step": ended,
        "thickness_m": simulation.thickness_m,
        "area_m2": simulation.piece_area_m2,
        "ended_by": simulation.ended_by,
    }
    return {"geometry": simulation.polygon, **columns} if geometry else columns


def _write_table(path: Path, columns: Mapping[str, Any], metadata: Mapping[str, Any]) -> None:
    rest = {k: v for k, v in columns.items() if k != "geometry"}
    write_geoparquet(path, columns["geometry"], rest, metadata)


def _write_piece_file(path: Path, sim: SimulationResult, fate: str, metadata: Mapping[str, Any]) -> None:
    """The table of the pieces with `fate` (`piece_table`), built and written one row group at a time."""
    ids = np.flatnonzero(sim.mask(fate))

    def table_of(group: np.ndarray) -> tuple[np.ndarray, dict[str, Any]]:
        columns = piece_table(sim, fate, group)
        return columns.pop("geometry"), columns

    groups = [ids[rows] for rows in row_groups(len(ids))]
    write_geoparquet_groups(path, groups, sim.polygons, table_of, metadata)


def _save_figures(result: RunRecord, folder: Path, keys: Iterable[str]) -> None:
    """The figures `keys` (of `FIGURES`) of `result` as PNG files in `folder`."""
    meta = result.provenance("figure")
    for key in keys:
        figure_process.save_png(
            figure_process.draw_figure(result.figure_call(key)), folder / FIGURES[key], meta
        )


@contextmanager
def _figures_alongside(
    result: RunRecord, folder: Path, worker: figure_process.FigureWorker | None
) -> Iterator[None]:
    """Draw the run's figures into `folder`, around the body that writes the other files.

    With a figure `worker` (`figure_worker`), or where `fork_for_figures` with one forked now (it imports
    matplotlib while the body runs): it is sent the figures as plain data, before the body if it waits for
    them, else after it (those it drew ahead with the same call and metadata are only saved), and answers
    after the body; its exception is raised here, an exception of the body kills it (the caller's
    temporary directory is discarded either way). Else all of them here after the body.
    """
    folder.mkdir()
    if worker is None and figure_process.fork_for_figures():
        worker = figure_process.start_figure_worker()
    if worker is None:
        yield
        _save_figures(result, folder, FIGURES)
        return
    meta = result.provenance("figure")
    jobs, saved = [], {}
    for key, name in FIGURES.items():
        call = result.figure_call(key)
        if key in worker.ahead and worker.ahead[key] == figure_process.pickled((call, meta)):
            saved[key] = folder / name
        else:
            jobs.append((call, folder / name, meta))
    with figure_process.jobs_alongside(worker, jobs, saved):
        yield


def check_output_directory(out: str | os.PathLike[str], overwrite: bool) -> Path:
    """Refuse (InputError on key "out") an existing `out` without `overwrite` or a missing parent; raise
    StorageError if the parent cannot be written (full, read-only, no permission)."""
    out = Path(out)
    if out.exists() and not overwrite:
        raise InputError("out", f"{str(out)!r} exists", allowed="a new path, or overwrite=True (--overwrite)")
    if out.exists() and not out.is_dir():
        raise InputError("out", f"{str(out)!r} is a file", allowed="a directory path")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("out", f"directory {str(parent)!r} does not exist", allowed="an existing directory")
    probe_directory(parent, out)  # a full, read-only or pseudo file system: StorageError before the run
    return out


def write_run_directory(
    result: RunRecord,
    out: str | os.PathLike[str],
    overwrite: bool = False,
    report: bool = True,
    figures: bool = True,
    directory_name: str | None = None,
    figure_worker: figure_process.FigureWorker | None = None,
) -> Path:
    """Write the run directory (see the module docstring) atomically and return its path.

    `figures=False` skips ``figures/`` (and the report then has none): for large studies and tests.
    `figure_worker`: the process `figure_worker` forked before the run, to draw the figures (ended here).
    """
    out = check_output_directory(out, overwrite)
    try:
        _write_run_files(result, out, overwrite, report, figures, directory_name, figure_worker)
    except OSError as error:
        storage = as_storage_error(error, out)
        if storage is None:
            raise
        raise storage from None
    return out


def _write_run_files(
    result: RunRecord,
    out: Path,
    overwrite: bool,
    report: bool,
    figures: bool,
    directory_name: str | None,
    worker: figure_process.FigureWorker | None,
) -> None:
    with atomic_directory(out, overwrite=overwrite, field="out") as temp:
        drawn = _figures_alongside(result, temp / "figures", worker) if figures else nullcontext()
        with drawn:
            for _, write in run_writers():
                write(result, temp)
        if report:
            from floebreak.output.report import write_report

            write_report(temp, directory_name=directory_name or out.name)
        summary_doc = json.loads((temp / "summary.json").read_text(encoding="utf-8"))
        summary_doc["files"] = file_checksums(temp)  # a resumed study re-runs a run whose files differ
        summary_doc = with_checksum(summary_doc)  # ... or whose summary was edited
        write_json(temp / "summary.json", summary_doc)


def write_field_file(result: RunRecord, folder: Path) -> None:
    """``field.parquet``: the initial field as simulated."""
    field_meta = {
        **result.provenance("floe_field"),
        "domain_m": list(result.field.domain_m),
        "field": dict(result.field.metadata),
    }
    _write_table(folder / "field.parquet", field_table(result.field), field_meta)


def write_fate_files(result: RunRecord, folder: Path) -> None:
    """``cusps.parquet``, ``flipped.parquet``, ``remaining.parquet``: the pieces by fate."""
    for fate, name in PIECE_FILES.items():
        _write_piece_file(folder / name, result.simulation, fate, result.provenance(fate))


def write_contacts_file(result: RunRecord, folder: Path) -> None:
    """``contacts.parquet``: the contact records (copied from the spool if the run streamed them)."""
    if result.contacts_file is not None and result.contact_records.columns is None:
        shutil.copyfile(result.contacts_file, folder / CONTACTS_FILE)  # the records streamed there
    else:
        write_contacts(folder / CONTACTS_FILE, result.contacts, result.provenance("contacts"))


def write_pieces_file(result: RunRecord, folder: Path) -> None:
    """``pieces.parquet``: every piece of the run with its life span (`pieces_table`)."""
    sim = result.simulation
    stepping = {"x_start_m": sim.params.x_start_m, "step_m": sim.params.step_m, "n_steps": sim.n_steps}
    columns = pieces_table(sim, result.contact_records, geometry=False)
    write_geoparquet_groups(
        folder / PIECES_FILE,
        row_groups(len(sim.piece_id)),
        sim.polygons,
        lambda rows: (sim.polygons(rows), {k: v[rows] for k, v in columns.items()}),
        {**result.provenance("pieces"), **stepping},
    )


def write_summary_file(result: RunRecord, folder: Path) -> None:
    """``summary.json`` without the files' checksums (added once every file is written)."""
    write_json(
        folder / "summary.json", jsonable({**result.summary, "provenance": result.provenance("summary")})
    )


def write_scenario_file(result: RunRecord, folder: Path) -> None:
    """``scenario.resolved.toml``: the scenario as run, with the version and the scenario hash."""
    header = (
        f"# resolved scenario written by floebreak {floebreak_version()}; "
        f"scenario_hash = {result.summary['scenario_hash']}\n"
    )
    (folder / "scenario.resolved.toml").write_text(header + result.scenario.to_toml(), encoding="utf-8")


def file_checksums(run_dir: Path, names: Iterable[str] | None = None) -> dict[str, str]:
    """SHA-256 of the files `names` (relative paths; default: every file but the top ``summary.json``,
    which records them) of a run directory; a missing file gets "missing"."""
    run_dir = Path(run_dir)
    if names is None:
        files = (p for p in run_dir.rglob("*") if p.is_file() and p != run_dir / "summary.json")
        names = [p.relative_to(run_dir).as_posix() for p in files]
    sums = {}
    for name in sorted(names):
        digest = hashlib.sha256()
        try:
            with (run_dir / name).open("rb") as file:
                for block in iter(lambda: file.read(1 << 20), b""):
                    digest.update(block)
        except FileNotFoundError:
            sums[name] = "missing"
            continue
        sums[name] = digest.hexdigest()
    return sums
