"""The run directory's figures drawn by forked workers (issue 34 §6), forked at the write or before the run
(`figure_workers`): the same files as the serial path, a failure on either side fails the write with
nothing left behind, and no worker outlives the run."""

from __future__ import annotations

import errno
import multiprocessing
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import floebreak
import floebreak.api
from floebreak.app import run_directory
from floebreak.errors import InputError

pytestmark = pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(), reason="no fork on this platform"
)

SMALL = ["field.length_m=60.0"]
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def result():
    return floebreak.run(overrides=SMALL)


def _write(result, out, monkeypatch, fork: bool, early: bool = False):
    """Write `result` to `out`: serially, or (`fork`) with workers forked at the write or (`early`) before."""
    monkeypatch.setattr(run_directory, "_fork_for_figures", lambda: fork)
    if not early:
        return result.write(out, directory_name="run")
    with run_directory.figure_workers() as workers:
        assert len(workers) == run_directory.FIGURE_WORKERS
        return result.write(out, directory_name="run", figure_workers=workers)


def _started_workers(monkeypatch) -> list:
    """The figure workers the code under test starts (filled as they start)."""
    started = []
    start = run_directory._start_figure_workers

    def recording():
        workers = start()
        started.extend(process for process, _ in workers)
        return workers

    monkeypatch.setattr(run_directory, "_start_figure_workers", recording)
    return started


def _assert_ended(processes) -> None:
    """Every process ended and was reaped (none left alive, none a zombie)."""
    assert processes
    for process in processes:
        assert not process.is_alive()
        with pytest.raises(ProcessLookupError):
            os.kill(process.pid, 0)


def _files(folder):
    files = sorted(p for p in folder.rglob("*") if p.is_file())
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in files}


@pytest.mark.parametrize("early", [False, True], ids=["forked at the write", "forked before the run"])
def test_figure_workers_write_the_same_files_as_the_serial_path(result, tmp_path, monkeypatch, early):
    serial = _files(_write(result, tmp_path / "serial", monkeypatch, fork=False))
    forked = _files(_write(result, tmp_path / "forked", monkeypatch, fork=True, early=early))
    assert {name for name in forked if name.startswith("figures/")} == {
        f"figures/{name}" for name in run_directory.FIGURES.values()
    }
    assert forked.keys() == serial.keys()
    different = [name for name in serial if serial[name] != forked[name]]
    assert different == []  # PNG bytes too: the provenance text chunks are the same


def test_the_figure_calls_are_plain_data_that_pickle(result):
    """A worker forked before the run gets each figure as pickled data (`_dumps`), never the Result."""
    import pickle

    for key in run_directory.FIGURES:
        module, function, args, kwargs = pickle.loads(run_directory._dumps(result.figure_call(key)))
        assert (module, function) == result.figure_call(key)[:2]
        assert not any(isinstance(value, type(result)) for value in (*args, *kwargs.values()))


def _fail_in_the_child(monkeypatch, error):
    """`_save_png` raises `error` for the breaking pattern, one of the first worker's figures."""
    save = run_directory._save_png
    child_figure = run_directory.FIGURES[next(iter(run_directory.FIGURES))]

    def failing(figure, path, meta):
        if path.name == child_figure:
            assert os.getpid() != parent  # it is the child that fails
            raise error
        save(figure, path, meta)

    parent = os.getpid()
    monkeypatch.setattr(run_directory, "_save_png", failing)


@pytest.mark.parametrize("early", [False, True], ids=["forked at the write", "forked before the run"])
def test_a_child_s_exception_fails_the_write_and_leaves_nothing(result, tmp_path, monkeypatch, early):
    _fail_in_the_child(monkeypatch, ValueError("no such colour"))
    started = _started_workers(monkeypatch)
    with pytest.raises(ValueError, match="no such colour") as info:
        _write(result, tmp_path / "out", monkeypatch, fork=True, early=early)
    assert any("in failing" in note for note in info.value.__notes__)  # the child's traceback
    assert list(tmp_path.iterdir()) == []
    _assert_ended(started)


def test_a_full_disk_in_the_child_is_a_storage_error(result, tmp_path, monkeypatch):
    from floebreak.io.storage import StorageError

    _fail_in_the_child(monkeypatch, OSError(errno.ENOSPC, "No space left on device"))
    with pytest.raises(StorageError):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []


def test_a_child_that_dies_fails_the_write_and_leaves_nothing(result, tmp_path, monkeypatch):
    monkeypatch.setattr(run_directory, "_figure_worker", lambda *args: os._exit(3))
    with pytest.raises(RuntimeError, match="exit code 3"):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("early", [False, True], ids=["forked at the write", "forked before the run"])
def test_a_failure_in_the_parent_stops_the_child_and_leaves_nothing(result, tmp_path, monkeypatch, early):
    def slow_child(*args):
        time.sleep(60)  # killed by the parent long before

    def broken_tables(result, temp):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(run_directory, "_figure_worker", slow_child)
    monkeypatch.setattr(run_directory, "_write_tables", broken_tables)
    workers = _started_workers(monkeypatch)
    started = time.perf_counter()
    with pytest.raises(RuntimeError, match="disk on fire"):
        _write(result, tmp_path / "out", monkeypatch, fork=True, early=early)
    assert time.perf_counter() - started < 30.0  # the child was killed, not waited for
    assert list(tmp_path.iterdir()) == []
    _assert_ended(workers)


def test_workers_of_a_run_that_fails_are_ended(tmp_path, monkeypatch):
    """The command line forks the workers before the run; a run that fails never uses them."""
    from floebreak import cli
    from floebreak.scenario import Scenario

    def failing_run(*args, **kwargs):
        raise InputError("simulation.step_m", "-1", allowed="> 0")

    monkeypatch.setattr(run_directory, "_fork_for_figures", lambda: True)
    monkeypatch.setattr(floebreak.api, "run", failing_run)
    workers = _started_workers(monkeypatch)
    with pytest.raises(InputError):
        cli._execute(Scenario.from_dict({}), tmp_path / "out", False, True, "test")
    assert len(workers) == run_directory.FIGURE_WORKERS
    _assert_ended(workers)
    assert not (tmp_path / "out").exists()


def test_workers_not_used_are_ended():
    """`figure_workers` without a write (`--no-report`-like paths, a refused output, Ctrl-C)."""
    with run_directory.figure_workers() as workers:
        if workers is None:
            pytest.skip("this machine gives no second core to fork onto")
        processes = [process for process, _ in workers]
    _assert_ended(processes)
    assert multiprocessing.active_children() == []


def test_the_command_line_leaves_matplotlib_to_the_workers(tmp_path):
    """`floebreak run` on ≥ 2 cores: this process never imports matplotlib (the workers draw)."""
    out = str(tmp_path / "out")
    argv = ["floebreak", "run", "examples/reference.toml", "--quiet", "--out", out]
    argv += ["--set", "field.length_m=40"]
    code = (
        "import sys; from floebreak import cli; from floebreak.app import run_directory\n"
        "if not run_directory._fork_for_figures(): print('serial'); raise SystemExit\n"
        f"sys.argv = {argv!r}\n"
        "try:\n    cli.main()\nexcept SystemExit:\n    pass\n"
        "print('matplotlib' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    if done.stdout.strip().endswith("serial"):
        pytest.skip("this machine gives no second core to fork onto")
    assert done.stdout.strip().splitlines()[-1] == "False"
    assert sorted(p.name for p in (tmp_path / "out" / "figures").iterdir()) == sorted(
        run_directory.FIGURES.values()
    )


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


def _gone(pid: int) -> bool:
    """No such process, or a zombie (ended; reaping it is its new parent's business)."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] == "Z"
    except FileNotFoundError:
        return True


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="reads /proc")
def test_workers_of_a_killed_run_end_with_it():
    """SIGKILL the process that forked the workers (it cannot end them): they end too."""
    code = (
        "import sys, time; from floebreak.app import run_directory\n"
        "run_directory._fork_for_figures = lambda: True\n"
        "with run_directory.figure_workers() as workers:\n"
        "    print(*[process.pid for process, _ in workers], flush=True)\n"
        "    time.sleep(600)\n"
    )
    victim = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        pids = [int(pid) for pid in victim.stdout.readline().split()]
    finally:
        victim.kill()
        victim.wait()
        victim.stdout.close()
    assert len(pids) == run_directory.FIGURE_WORKERS
    deadline = time.monotonic() + 30
    while not all(_gone(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert all(_gone(pid) for pid in pids)
