"""A `Result` → its run directory, written atomically (temporary sibling, renamed when complete; a failed
run leaves no half directory):

- ``summary.json``: thesis Tables 5–8 columns (n_cusp, A_cusp^tot, n_flip, A_flip^tot, V̄_cusp, Ā_cusp), the
  area balance, contact/break counters, the maximum crushing force, wall time, provenance;
- ``cusps.parquet``, ``flipped.parquet``, ``remaining.parquet``, ``field.parquet`` (the initial field as
  simulated, i.e. after any shift for no initial contact): GeoParquet, ``"crs": null``, one row per piece;
- ``contacts.parquet``: one row per floe–panel contact evaluation (`floebreak.results.CONTACT_COLUMNS`);
- ``pieces.parquet``: every piece that existed in the run (initial floes, broken pieces, cusps, flipped and
  remaining pieces; GeoParquet, field frame; the geometry is empty for a piece created and broken at one bow
  position, which is never in the field between two steps) with ``piece_id``, ``parent_piece_id`` (−1 for
  initial floes), ``parent_floe_id``, ``fate`` (``broken``/``cusp``/``flipped``/``remaining``),
  ``created_step`` (−1 for initial floes), ``ended_step`` (the step it broke or left the field; −1 if it
  remains), ``thickness_m``, ``area_m2``, ``ended_by`` (the failure mode that broke the piece or took it out
  whole, "" if none; `floebreak.results.failure_chain` rebuilds a piece's chain); the metadata adds
  ``x_start_m``, ``step_m``, ``n_steps`` (bow x at step s = x_start_m + s·step_m). Enough to replay the
  transit (``floebreak animate``);
- ``poses.parquet`` (a `dynamic` run with ``simulation.pose_interval_steps``): the poses of the pieces the
  ice motion moved, every that many steps (`floebreak.app.poses`, `floebreak.io.poses`), for the animation;
- ``scenario.resolved.toml`` (every default filled in), ``figures/*.png``, ``report.html``.

Every file carries provenance (floebreak and library versions, the resolved scenario, its hash, the seed).

The figures take most of the writing (importing matplotlib, drawing, encoding the PNGs). On Linux, when
the process has ≥ 2 cores, no other thread and no pool parent (`_fork_for_figures`), `FIGURE_WORKERS`
forked workers draw them, each its share, sent as plain data (`Result.figure_call`), while this process
writes the tables. The command line forks them before the run (`figure_workers`), so that they import
matplotlib while the engine runs; a `Result.write` without them forks them at the write. The files are
the same as drawn serially (benchmarks/README.md, "Issue 34 §6").
"""

from __future__ import annotations

import copyreg
import ctypes
import hashlib
import importlib
import io
import multiprocessing
import os
import pickle
import shutil
import signal
import sys
import threading
import traceback
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager, nullcontext
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from floebreak.app.poses import write_pose_file
from floebreak.app.surge import write_surge_series
from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.io.atomic import atomic_directory
from floebreak.io.checksums import with_checksum
from floebreak.io.contacts import write_contacts
from floebreak.io.geoparquet import row_groups, write_geoparquet, write_geoparquet_groups
from floebreak.io.jsonable import jsonable, to_json
from floebreak.io.provenance import floebreak_version
from floebreak.io.storage import as_storage_error, probe_directory
from floebreak.io.writers import write_json
from floebreak.results import ContactRecords, oriented_box_dimensions_m, piece_table
from floebreak.simulation import SimulationResult

if TYPE_CHECKING:
    from floebreak.app.run import Result

PIECE_FILES = {"cusp": "cusps.parquet", "flipped": "flipped.parquet", "remaining": "remaining.parquet"}
PIECES_FILE = "pieces.parquet"  # every piece with its life span (replay / `floebreak animate`)
CONTACTS_FILE = "contacts.parquet"
FIGURES = {
    "breaking_pattern": "breaking_pattern.png",
    "cusp_volume_spectrum": "cusp_volume_spectrum.png",
    "crushing_force_spectrum": "crushing_force_spectrum.png",
    "field": "field.png",
}
FIGURE_WORKERS = 2  # forked processes drawing the figures, each its share (benchmarks/README.md, issue 34 §6)
PR_SET_PDEATHSIG = 1  # prctl(2)
FigureWorker = tuple[multiprocessing.Process, Any]  # a process and this end of its pipe
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
    children in the same step, `floebreak.simulation.simulate`). ``ended_step``: the step a cusp or flipped
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


def _save_png(figure, path: Path, meta: Mapping[str, Any] | None) -> None:
    """`figure` as PNG at 150 dpi; the text chunks name floebreak and hold `meta`, or (None) are
    matplotlib's, as `floebreak.io.figures.save_figure` saves a figure."""
    text = None
    if meta is not None:
        text = {"Software": f"floebreak {meta['floebreak_version']}", "Description": to_json(dict(meta))}
    figure.savefig(path, format="png", dpi=150, metadata=text)


FigureCall = tuple[str, str, tuple[Any, ...], dict[str, Any]]
"""A figure as plain data: a module of `floebreak.plotting`, its function and the call's arguments (numpy
arrays, shapely geometries, dataclasses: they pickle, so a figure worker can draw it;
`Result.figure_call`)."""


def draw_figure(call: FigureCall):
    """The matplotlib Figure of `call` (imports the plotting module, and so matplotlib, on first use)."""
    module, function, args, kwargs = call
    return getattr(importlib.import_module(f"floebreak.plotting.{module}"), function)(*args, **kwargs)


def _save_figures(result: Result, folder: Path, keys: Iterable[str]) -> None:
    """The figures `keys` (of `FIGURES`) of `result` as PNG files in `folder`."""
    meta = result.provenance("figure")
    for key in keys:
        _save_png(draw_figure(result.figure_call(key)), folder / FIGURES[key], meta)


def _fork_for_figures() -> bool:
    """Whether figure workers may be forked: on Linux (macOS has fork, but its system libraries are not
    safe in a forked child, which is why Python spawns there), with ≥ 2 cores this process's, in the only
    thread of a process no pool started (a study's worker draws serially, as its pool already uses the
    cores; a child forked from a threaded process could inherit a held lock)."""
    if not sys.platform.startswith("linux") or multiprocessing.parent_process() is not None:
        return False
    if threading.active_count() > 1:
        return False
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    return cores >= 2


@contextmanager
def figure_workers() -> Iterator[list[FigureWorker] | None]:
    """Fork the processes that will draw a run's figures now, before the engine, where `_fork_for_figures`
    (else None): each imports matplotlib on another core while this process imports and runs the engine,
    then waits for its figures (`write_run_directory(..., figure_workers=)`). At exit every worker still
    alive (never used: the run failed, was interrupted or wrote no figures) is killed and reaped."""
    workers = _start_figure_workers() if _fork_for_figures() else None
    try:
        yield workers
    finally:
        _end_figure_workers(workers or [])


def _start_figure_workers() -> list[FigureWorker]:
    """`FIGURE_WORKERS` forked figure workers, fewer where no process can be had (EAGAIN, ENOMEM)."""
    context = multiprocessing.get_context("fork")
    workers = []
    previous = None
    for _ in range(FIGURE_WORKERS):
        here, there = context.Pipe()
        imported = context.Event()
        args = (there, os.getpid(), previous, imported)
        process = context.Process(target=_figure_worker, args=args, daemon=True)
        previous = imported
        try:
            process.start()
        except OSError:
            here.close()
            break
        finally:
            there.close()
        workers.append((process, here))
    return workers


def _end_figure_workers(workers: list[FigureWorker]) -> None:
    for process, connection in workers:
        if process.is_alive():
            process.kill()
        process.join()
        connection.close()


def _figure_worker(connection, parent: int, after, imported) -> None:
    """A figure worker of the process `parent`: import the plotting modules once the worker before it has
    (`after`, an Event; one
    import at a time leaves the engine a core of its own) and say so (`imported`), wait for its figures
    (pickled `(FigureCall, path, metadata)` jobs), draw and save them, then send None, or the exception
    (its traceback as a note)."""
    _die_with(parent)
    try:
        if after is not None:
            after.wait()
        from floebreak.plotting import field, pattern, spectra  # noqa: F401  (before the jobs come)

        imported.set()
        jobs = pickle.loads(connection.recv_bytes())
    except (EOFError, KeyboardInterrupt):  # not used, or the run was interrupted: the parent ends it
        return
    try:
        for call, path, meta in jobs:
            _save_png(draw_figure(call), path, meta)
    except BaseException as error:  # the parent raises it
        error.add_note("".join(traceback.format_exception(error)).rstrip())
        try:
            connection.send(error)
        except Exception:  # an exception that does not pickle
            connection.send(RuntimeError(f"drawing the figures failed: {type(error).__name__}: {error}"))
    else:
        connection.send(None)
    finally:
        connection.close()


def _die_with(parent: int) -> None:
    """Have Linux kill this process when `parent` ends, however it ends (SIGKILL too: it would otherwise
    wait for figures forever, as it inherited the other ends of the pipes)."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    except (OSError, AttributeError):  # no prctl: the parent's `_end_figure_workers` alone ends it
        pass
    if os.getppid() != parent:  # it ended before prctl
        os._exit(0)


def _dumps(jobs: list[tuple[FigureCall, Path, dict[str, Any]]]) -> bytes:
    """`jobs` pickled; the read-only mappings of the field and bow metadata as themselves."""
    buffer = io.BytesIO()
    pickler = pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = {**copyreg.dispatch_table, MappingProxyType: _reduce_mapping_proxy}
    pickler.dump(jobs)
    return buffer.getvalue()


def _reduce_mapping_proxy(mapping: MappingProxyType):
    return _mapping_proxy, (dict(mapping),)


def _mapping_proxy(items: dict[str, Any]) -> MappingProxyType:
    return MappingProxyType(items)


@contextmanager
def _figures_alongside(result: Result, folder: Path, workers: list[FigureWorker] | None) -> Iterator[None]:
    """Draw the run's figures into `folder`, around the body that writes the other files.

    With figure `workers` (`figure_workers`), or where `_fork_for_figures` with workers forked now (they
    import matplotlib while the body runs): each is sent its share of the figures as plain data before the
    body, and answers after it; a worker's exception is raised here, an exception of the body kills the
    workers (the caller's temporary directory is discarded either way). Else all of them here after the body.
    """
    folder.mkdir()
    keys = list(FIGURES)
    if workers is None and _fork_for_figures():
        workers = _start_figure_workers()
    if not workers:
        yield
        _save_figures(result, folder, keys)
        return
    meta = result.provenance("figure")
    with _jobs_alongside([(result.figure_call(key), folder / FIGURES[key], meta) for key in keys], workers):
        yield


@contextmanager
def figures_drawn_alongside(
    calls: Mapping[str, FigureCall], folder: Path, workers: list[FigureWorker] | None
) -> Iterator[None]:
    """Draw `calls` (PNG file name → `FigureCall`) into the new directory `folder` around the body, saved
    as `floebreak.io.figures.save_figure` saves them (for the other commands' figures: the propeller and
    shaft analyses). With figure `workers` (`figure_workers`): each is sent its share before the body and
    answers after it, errors as the run directory's; else drawn here after the body."""
    folder.mkdir()
    jobs = [(call, folder / name, None) for name, call in calls.items()]
    if not workers:
        yield
        for call, path, meta in jobs:
            _save_png(draw_figure(call), path, meta)
        return
    with _jobs_alongside(jobs, workers):
        yield


@contextmanager
def _jobs_alongside(jobs: list[tuple[FigureCall, Path, Any]], workers: list[FigureWorker]) -> Iterator[None]:
    """Send each of `workers` its share of `jobs` (`_figure_worker`) before the body and take the answers
    after it: a worker's exception is raised here, an exception of the body kills the workers."""
    try:
        for index, (_, connection) in enumerate(workers):
            try:
                connection.send_bytes(_dumps(jobs[index :: len(workers)]))
            except (BrokenPipeError, ConnectionResetError):  # it died: `_answer` says so
                pass
        yield
        errors = [_answer(process, connection) for process, connection in workers]
    finally:
        _end_figure_workers(workers)
    for error in errors:
        if error is not None:
            raise error


def _answer(process, connection) -> BaseException | None:
    """What a figure worker sent (None: its figures are written), or why it sent nothing."""
    try:
        return connection.recv()
    except (EOFError, ConnectionResetError):  # reset: it died with figures it had not read
        process.join()
        return RuntimeError(f"the figure process ended without an answer (exit code {process.exitcode})")


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
    result: Result,
    out: str | os.PathLike[str],
    overwrite: bool = False,
    report: bool = True,
    figures: bool = True,
    directory_name: str | None = None,
    figure_workers: list[FigureWorker] | None = None,
) -> Path:
    """Write the run directory (see the module docstring) atomically and return its path.

    `figures=False` skips ``figures/`` (and the report then has none): for large studies and tests.
    `figure_workers`: the processes `figure_workers` forked before the run, to draw the figures.
    """
    out = check_output_directory(out, overwrite)
    try:
        _write_run_files(result, out, overwrite, report, figures, directory_name, figure_workers)
    except OSError as error:
        storage = as_storage_error(error, out)
        if storage is None:
            raise
        raise storage from None
    return out


def _write_run_files(
    result: Result,
    out: Path,
    overwrite: bool,
    report: bool,
    figures: bool,
    directory_name: str | None,
    workers: list[FigureWorker] | None,
) -> None:
    with atomic_directory(out, overwrite=overwrite, field="out") as temp:
        drawn = _figures_alongside(result, temp / "figures", workers) if figures else nullcontext()
        with drawn:
            summary_doc = _write_tables(result, temp)
        if report:
            from floebreak.report import write_report

            write_report(temp, directory_name=directory_name or out.name)
        summary_doc["files"] = file_checksums(temp)  # a resumed study re-runs a run whose files differ
        summary_doc = with_checksum(summary_doc)  # ... or whose summary was edited
        write_json(temp / "summary.json", summary_doc)


def _write_tables(result: Result, temp: Path) -> dict[str, Any]:
    """The run directory's tables, summary.json (without its checksums, which it returns) and
    scenario.resolved.toml."""
    field_meta = {
        **result.provenance("floe_field"),
        "domain_m": list(result.field.domain_m),
        "field": dict(result.field.metadata),
    }
    _write_table(temp / "field.parquet", field_table(result.field), field_meta)
    sim = result.simulation
    for fate, name in PIECE_FILES.items():
        _write_piece_file(temp / name, sim, fate, result.provenance(fate))
    if result.contacts_file is not None and result.contact_records.columns is None:
        shutil.copyfile(result.contacts_file, temp / CONTACTS_FILE)  # the records streamed there
    else:
        write_contacts(temp / CONTACTS_FILE, result.contacts, result.provenance("contacts"))
    stepping = {"x_start_m": sim.params.x_start_m, "step_m": sim.params.step_m, "n_steps": sim.n_steps}
    columns = pieces_table(sim, result.contact_records, geometry=False)
    write_geoparquet_groups(
        temp / PIECES_FILE,
        row_groups(len(sim.piece_id)),
        sim.polygons,
        lambda rows: (sim.polygons(rows), {k: v[rows] for k, v in columns.items()}),
        {**result.provenance("pieces"), **stepping},
    )
    write_surge_series(temp, result)  # surge.csv, only with ship.propulsion
    write_pose_file(temp, result, result.provenance("poses"))  # only with simulation.pose_interval_steps
    summary_doc = jsonable({**result.summary, "provenance": result.provenance("summary")})
    write_json(temp / "summary.json", summary_doc)
    header = (
        f"# resolved scenario written by floebreak {floebreak_version()}; "
        f"scenario_hash = {result.summary['scenario_hash']}\n"
    )
    (temp / "scenario.resolved.toml").write_text(header + result.scenario.to_toml(), encoding="utf-8")
    return summary_doc


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
