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
the process has ≥ 2 cores, no other thread and no pool parent (`_fork_for_figures`), a forked figure worker
draws them, from plain data (`Result.figure_call`), while this process writes the tables; at the write it
forks a child of its own (which inherits matplotlib) and draws half of them there. The command line forks
the worker before the run (`figure_worker`), so that it imports matplotlib while the engine runs, and sends
it the field's figure as soon as the field is generated (`floebreak.app.run.run`); a `Result.write`
without a worker forks one at the write. The files are the same as drawn serially (benchmarks/README.md,
"Issue 34 §6").
"""

from __future__ import annotations

import copyreg
import ctypes
import gc
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
PR_SET_PDEATHSIG = 1  # prctl(2)
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
    """Whether a figure worker may be forked: on Linux (macOS has fork, but its system libraries are not
    safe in a forked child, which is why Python spawns there), with ≥ 2 cores this process's, in the only
    thread of a process no pool started (a study's worker draws serially, as its pool already uses the
    cores; a child forked from a threaded process could inherit a held lock)."""
    if not sys.platform.startswith("linux") or multiprocessing.parent_process() is not None:
        return False
    if threading.active_count() > 1:
        return False
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    return cores >= 2


class FigureWorker:
    """A forked process that draws a run's figures (`_figure_worker`), this end of its pipe, the event it
    sets while it waits for a message, and the figures it was sent ahead of the write (`draw_ahead`: key
    → the pickled call and metadata).

    A message is sent only while the worker waits for one where that can be chosen: a figure's data
    (≈ 0.3 MB for a 250 m field) do not fit in the pipe's buffer, so a send blocks until the worker reads
    it, and the worker reads nothing while it imports matplotlib or draws.
    """

    def __init__(self, process: multiprocessing.Process, connection, waiting) -> None:
        self.process = process
        self.connection = connection
        self.waiting = waiting
        self.ahead: dict[str, bytes] = {}

    def draw_ahead(self, key: str, call: FigureCall, meta: Mapping[str, Any]) -> bool:
        """If the worker waits, have it draw the figure `key` now, into memory (the write saves it if the
        run's figure has the same call and metadata, `_figures_alongside`, and draws it anew otherwise);
        whether it was sent."""
        if not self.waiting.is_set():
            return False
        data = _dumps((call, dict(meta)))
        if self._send(("ahead", key, data)):
            self.ahead[key] = data
        return True

    def ahead_callback(self, key: str, call: FigureCall, meta: Mapping[str, Any]):
        """An engine callback (`floebreak.simulation.simulate`) that sends the figure `key` ahead
        (`draw_ahead`) at the first event at which the worker waits (it imports matplotlib first)."""

        def send_when_waiting(event: object) -> None:
            if key not in self.ahead:
                self.draw_ahead(key, call, meta)

        return send_when_waiting

    def _send(self, message: tuple) -> bool:
        """Send `message` pickled; False if the worker has died (`_answer` says so at the write)."""
        try:
            self.connection.send_bytes(_dumps(message))
        except (BrokenPipeError, ConnectionResetError):
            return False
        return True

    def end(self) -> None:
        """Kill the worker if it is still alive, reap it and close the pipe."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.connection.close()


@contextmanager
def figure_worker() -> Iterator[FigureWorker | None]:
    """Fork the process that will draw a run's figures now, before the engine, where `_fork_for_figures`
    (else None): it imports matplotlib on another core while this process imports and runs the engine,
    draws what it is sent ahead (`FigureWorker.draw_ahead`: the field, `floebreak.app.run.run`), then the
    rest at the write (`write_run_directory(..., figure_worker=)`). At exit a worker still alive (never
    used: the run failed, was interrupted or wrote no figures) is killed and reaped."""
    worker = _start_figure_worker() if _fork_for_figures() else None
    try:
        yield worker
    finally:
        if worker is not None:
            worker.end()


def _start_figure_worker() -> FigureWorker | None:
    """A forked figure worker, or None where no process can be had (EAGAIN, ENOMEM)."""
    context = multiprocessing.get_context("fork")
    here, there = context.Pipe()
    waiting = context.Event()
    process = context.Process(target=_figure_worker, args=(there, os.getpid(), waiting), daemon=True)
    try:
        process.start()
    except OSError:
        here.close()
        return None
    finally:
        there.close()
    return FigureWorker(process, here, waiting)


def _figure_worker(connection, parent: int, waiting) -> None:
    """The figure worker of the process `parent`: import the plotting modules, draw the figures sent
    ahead into memory, then, at the write (a message with the jobs, pickled `(FigureCall, path,
    metadata)`, and the paths of the figures drawn ahead), save those and draw the jobs, half of them in
    a child forked now (`_draw_halves`), and send None, or the exception (its traceback as a note).
    `waiting` (an Event) is set while it waits for a message."""
    _die_with(parent)
    # what it inherited lives until it exits: out of the collector's walks, which would otherwise copy
    # every page of the parent's heap (copy-on-write; benchmarks/README.md, "Issue 34 §6")
    gc.freeze()
    drawn: dict[str, bytes | BaseException] = {}
    try:
        from floebreak.plotting import field, pattern, spectra  # noqa: F401  (before the jobs come)

        message = _next_message(connection, waiting)
        while message[0] == "ahead":
            _, key, data = message
            drawn[key] = _drawn_png(*pickle.loads(data))
            message = _next_message(connection, waiting)
    except (EOFError, KeyboardInterrupt):  # not used, or the run was interrupted: the parent ends it
        return
    _, jobs, saved = message
    try:
        for key, path in saved.items():
            png = drawn[key]
            if isinstance(png, BaseException):
                raise png
            path.write_bytes(png)
        _draw_halves(jobs)
    except BaseException as error:  # the parent raises it
        _send_error(connection, error)
    else:
        connection.send(None)
    finally:
        connection.close()


def _next_message(connection, waiting) -> tuple:
    waiting.set()
    try:
        return pickle.loads(connection.recv_bytes())
    finally:
        waiting.clear()


def _drawn_png(call: FigureCall, meta: Mapping[str, Any]) -> bytes | BaseException:
    """The PNG file of `call`, or the exception drawing it raised (its traceback as a note)."""
    try:
        buffer = io.BytesIO()
        _save_png(draw_figure(call), buffer, meta)
        return buffer.getvalue()
    except Exception as error:
        return _noted(error)


def _draw_halves(jobs: list[tuple[FigureCall, Path, dict[str, Any]]]) -> None:
    """Draw and save `jobs`, the first half in a child forked now (it inherits matplotlib and the jobs:
    nothing is imported or sent twice), the rest here; the child's exception is raised here."""
    half = len(jobs) // 2
    reader, writer = multiprocessing.Pipe(duplex=False)
    gc.freeze()  # matplotlib and the jobs too, in both processes (as in `_figure_worker`)
    try:
        pid = os.fork() if half else None
    except OSError:  # no process to be had: all of them here
        pid = None
    if pid == 0:  # the child
        reader.close()
        try:
            _die_with(os.getppid())
            _save_jobs(jobs[:half])
        except BaseException as error:
            _send_error(writer, error)
        else:
            writer.send(None)
        finally:
            writer.close()
            os._exit(0)
    writer.close()
    try:
        _save_jobs(jobs if pid is None else jobs[half:])
    finally:
        error = None if pid is None else _answer_of_child(pid, reader)
        reader.close()
    if error is not None:
        raise error


def _answer_of_child(pid: int, reader) -> BaseException | None:
    """What the child `pid` of `_draw_halves` sent (None: its figures are saved), or why it sent nothing;
    it is reaped."""
    try:
        return reader.recv()
    except EOFError:
        return RuntimeError("a figure process ended without an answer")
    finally:
        os.waitpid(pid, 0)


def _save_jobs(jobs: Iterable[tuple[FigureCall, Path, Mapping[str, Any]]]) -> None:
    for call, path, meta in jobs:
        _save_png(draw_figure(call), path, meta)


def _noted(error: BaseException) -> BaseException:
    error.add_note("".join(traceback.format_exception(error)).rstrip())
    return error


def _send_error(connection, error: BaseException) -> None:
    """Send `error` with its traceback as a note, or a RuntimeError naming it if it does not pickle."""
    try:
        connection.send(_noted(error))
    except Exception:
        connection.send(RuntimeError(f"drawing the figures failed: {type(error).__name__}: {error}"))


def _die_with(parent: int) -> None:
    """Have Linux kill this process when `parent` ends, however it ends (SIGKILL too: it would otherwise
    wait for figures forever, as it inherited the other end of the pipe)."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    except (OSError, AttributeError):  # no prctl: the parent's `FigureWorker.end` alone ends it
        pass
    if os.getppid() != parent:  # it ended before prctl
        os._exit(0)


def _dumps(value: Any) -> bytes:
    """`value` pickled; the read-only mappings of the field and bow metadata as themselves."""
    buffer = io.BytesIO()
    pickler = pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = {**copyreg.dispatch_table, MappingProxyType: _reduce_mapping_proxy}
    pickler.dump(value)
    return buffer.getvalue()


def _reduce_mapping_proxy(mapping: MappingProxyType):
    return _mapping_proxy, (dict(mapping),)


def _mapping_proxy(items: dict[str, Any]) -> MappingProxyType:
    return MappingProxyType(items)


@contextmanager
def _figures_alongside(result: Result, folder: Path, worker: FigureWorker | None) -> Iterator[None]:
    """Draw the run's figures into `folder`, around the body that writes the other files.

    With a figure `worker` (`figure_worker`), or where `_fork_for_figures` with one forked now (it imports
    matplotlib while the body runs): it is sent the figures as plain data, before the body if it waits for
    them, else after it (those it drew ahead with the same call and metadata are only saved), and answers
    after the body; its exception is raised here, an exception of the body kills it (the caller's
    temporary directory is discarded either way). Else all of them here after the body.
    """
    folder.mkdir()
    if worker is None and _fork_for_figures():
        worker = _start_figure_worker()
    if worker is None:
        yield
        _save_figures(result, folder, FIGURES)
        return
    meta = result.provenance("figure")
    jobs, saved = [], {}
    for key, name in FIGURES.items():
        call = result.figure_call(key)
        if key in worker.ahead and worker.ahead[key] == _dumps((call, meta)):
            saved[key] = folder / name
        else:
            jobs.append((call, folder / name, meta))
    with _jobs_alongside(worker, jobs, saved):
        yield


@contextmanager
def figures_drawn_alongside(
    calls: Mapping[str, FigureCall], folder: Path, worker: FigureWorker | None
) -> Iterator[None]:
    """Draw `calls` (PNG file name → `FigureCall`) into the new directory `folder` around the body, saved
    as `floebreak.io.figures.save_figure` saves them (for the other commands' figures: the propeller and
    shaft analyses). With a figure `worker` (`figure_worker`): it is sent the jobs and answers after the
    body, errors as the run directory's; else drawn here after the body."""
    folder.mkdir()
    jobs = [(call, folder / name, None) for name, call in calls.items()]
    if worker is None:
        yield
        _save_jobs(jobs)
        return
    with _jobs_alongside(worker, jobs, {}):
        yield


@contextmanager
def _jobs_alongside(
    worker: FigureWorker, jobs: list[tuple[FigureCall, Path, Any]], saved: Mapping[str, Path]
) -> Iterator[None]:
    """Send `worker` the `jobs` and the paths of the figures it drew ahead to save (`_figure_worker`)
    around the body and take its answer after it: its exception is raised here, an exception of the
    body kills it."""
    try:
        sent = worker.waiting.is_set() and worker._send(("write", jobs, saved))
        yield  # a worker still importing or drawing is sent its jobs after the body (a send would block)
        if not sent:
            worker._send(("write", jobs, saved))
        error = _answer(worker.process, worker.connection)
    finally:
        worker.end()
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
    figure_worker: FigureWorker | None = None,
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
    result: Result,
    out: Path,
    overwrite: bool,
    report: bool,
    figures: bool,
    directory_name: str | None,
    worker: FigureWorker | None,
) -> None:
    with atomic_directory(out, overwrite=overwrite, field="out") as temp:
        drawn = _figures_alongside(result, temp / "figures", worker) if figures else nullcontext()
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
