"""The forked process that draws figures while the command computes (`figure_worker`), and drawing a
figure from plain data (`FigureCall`, `draw_figure`).

On Linux, when the process has ≥ 2 cores, no other thread and no pool parent (`fork_for_figures`), a
command forks the worker before its computation (`figure_worker`): the worker imports matplotlib on the
other core meanwhile, draws what it is sent ahead (a run's field figure), and at the write draws the rest,
half of them in a child it forks then (which inherits matplotlib). The run directory
(`floebreak.output.run_directory`) and the propeller and shaft analyses (`figures_drawn_alongside`) use it.
Kept apart from the run directory so that a command that draws figures without running the engine (the
propeller and shaft analyses) does not import the engine.
"""

from __future__ import annotations

import copyreg
import ctypes
import gc
import importlib
import io
import multiprocessing
import os
import pickle
import signal
import sys
import threading
import traceback
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from types import MappingProxyType
from typing import Any

from floebreak.io.jsonable import to_json

PR_SET_PDEATHSIG = 1  # prctl(2)


def save_png(figure, path: Path, meta: Mapping[str, Any] | None) -> None:
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


def fork_for_figures() -> bool:
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
        data = pickled((call, dict(meta)))
        if self._send(("ahead", key, data)):
            self.ahead[key] = data
        return True

    def ahead_callback(self, key: str, call: FigureCall, meta: Mapping[str, Any]):
        """An engine callback (`floebreak.engine.loop.simulate`) that sends the figure `key` ahead
        (`draw_ahead`) at the first event at which the worker waits (it imports matplotlib first)."""

        def send_when_waiting(event: object) -> None:
            if key not in self.ahead:
                self.draw_ahead(key, call, meta)

        return send_when_waiting

    def _send(self, message: tuple) -> bool:
        """Send `message` pickled; False if the worker has died (`_answer` says so at the write)."""
        try:
            self.connection.send_bytes(pickled(message))
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
    """Fork the process that will draw a run's figures now, before the engine, where `fork_for_figures`
    (else None): it imports matplotlib on another core while this process imports and runs the engine,
    draws what it is sent ahead (`FigureWorker.draw_ahead`: the field, `floebreak.app.run.run`), then the
    rest at the write (`write_run_directory(..., figure_worker=)`). At exit a worker still alive (never
    used: the run failed, was interrupted or wrote no figures) is killed and reaped."""
    worker = start_figure_worker() if fork_for_figures() else None
    try:
        yield worker
    finally:
        if worker is not None:
            worker.end()


def start_figure_worker() -> FigureWorker | None:
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
    # every page of the parent's heap (copy-on-write; benchmarks/README.md)
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
        save_png(draw_figure(call), buffer, meta)
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
            save_jobs(jobs[:half])
        except BaseException as error:
            _send_error(writer, error)
        else:
            writer.send(None)
        finally:
            writer.close()
            os._exit(0)
    writer.close()
    try:
        save_jobs(jobs if pid is None else jobs[half:])
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


def save_jobs(jobs: Iterable[tuple[FigureCall, Path, Mapping[str, Any]]]) -> None:
    for call, path, meta in jobs:
        save_png(draw_figure(call), path, meta)


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


def pickled(value: Any) -> bytes:
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
        save_jobs(jobs)
        return
    with jobs_alongside(worker, jobs, {}):
        yield


@contextmanager
def jobs_alongside(
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
