"""The run directory's figures drawn half in a forked child (issue 34 §6): the same files as the serial
path, and a failure on either side fails the write with nothing left behind."""

from __future__ import annotations

import errno
import os
import threading
import time

import pytest

import floebreak
from floebreak.app import run_directory

pytestmark = pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(), reason="no fork on this platform"
)

SMALL = ["field.length_m=60.0"]


@pytest.fixture(scope="module")
def result():
    return floebreak.run(overrides=SMALL)


def _write(result, out, monkeypatch, fork: bool):
    monkeypatch.setattr(run_directory, "_fork_for_figures", lambda: fork)
    return result.write(out, directory_name="run")


def _files(folder):
    files = sorted(p for p in folder.rglob("*") if p.is_file())
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in files}


def test_a_forked_child_writes_the_same_files_as_the_serial_path(result, tmp_path, monkeypatch):
    serial = _files(_write(result, tmp_path / "serial", monkeypatch, fork=False))
    forked = _files(_write(result, tmp_path / "forked", monkeypatch, fork=True))
    assert {name for name in forked if name.startswith("figures/")} == {
        f"figures/{name}" for name in run_directory.FIGURES.values()
    }
    assert forked.keys() == serial.keys()
    different = [name for name in serial if serial[name] != forked[name]]
    assert different == []  # PNG bytes too: the provenance text chunks are the same


def _fail_in_the_child(monkeypatch, error):
    """`_save_png` raises `error` for the breaking pattern, one of the child's figures (`keys[0::2]`)."""
    save = run_directory._save_png
    child_figure = run_directory.FIGURES[next(iter(run_directory.FIGURES))]

    def failing(figure, path, meta):
        if path.name == child_figure:
            assert os.getpid() != parent  # it is the child that fails
            raise error
        save(figure, path, meta)

    parent = os.getpid()
    monkeypatch.setattr(run_directory, "_save_png", failing)


def test_a_child_s_exception_fails_the_write_and_leaves_nothing(result, tmp_path, monkeypatch):
    _fail_in_the_child(monkeypatch, ValueError("no such colour"))
    with pytest.raises(ValueError, match="no such colour") as info:
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert any("in failing" in note for note in info.value.__notes__)  # the child's traceback
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_in_the_child_is_a_storage_error(result, tmp_path, monkeypatch):
    from floebreak.io.storage import StorageError

    _fail_in_the_child(monkeypatch, OSError(errno.ENOSPC, "No space left on device"))
    with pytest.raises(StorageError):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []


def test_a_child_that_dies_fails_the_write_and_leaves_nothing(result, tmp_path, monkeypatch):
    monkeypatch.setattr(run_directory, "_figure_child", lambda *args: os._exit(3))
    with pytest.raises(RuntimeError, match="exit code 3"):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []


def test_a_failure_in_the_parent_stops_the_child_and_leaves_nothing(result, tmp_path, monkeypatch):
    def slow_child(*args):
        time.sleep(60)  # killed by the parent long before

    def broken_tables(result, temp):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(run_directory, "_figure_child", slow_child)
    monkeypatch.setattr(run_directory, "_write_tables", broken_tables)
    started = time.perf_counter()
    with pytest.raises(RuntimeError, match="disk on fire"):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert time.perf_counter() - started < 30.0  # the child was killed, not waited for
    assert list(tmp_path.iterdir()) == []


def test_no_process_to_be_had_draws_every_figure_here(result, tmp_path, monkeypatch):
    import multiprocessing.context

    def refuse(self):
        raise BlockingIOError(errno.EAGAIN, "Resource temporarily unavailable")

    monkeypatch.setattr(multiprocessing.context.ForkProcess, "start", refuse)
    out = _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert sorted(p.name for p in (out / "figures").iterdir()) == sorted(run_directory.FIGURES.values())


def test_one_core_or_a_second_thread_draws_serially(monkeypatch):
    if hasattr(os, "sched_getaffinity"):
        monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0})
    else:
        monkeypatch.setattr(os, "cpu_count", lambda: 1)
    assert run_directory._fork_for_figures() is False
    monkeypatch.undo()
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert run_directory._fork_for_figures() is False
    finally:
        stop.set()
        thread.join()
