"""The run directory's figures drawn by a forked worker and its own forked child, the worker
forked at the write or before the run (`figure_worker`, which may draw the field ahead): the same files as
the serial path, a failure in any of the processes fails the write with nothing left behind, and no
process outlives the run."""

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
from floebreak.errors import InputError
from floebreak.output import figure_process, run_directory

pytestmark = pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(), reason="no fork on this platform"
)

SMALL = ["field.length_m=60.0"]
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def result():
    return floebreak.run(overrides=SMALL)


def _write(result, out, monkeypatch, fork: bool, early: bool = False, ahead=None):
    """Write `result` to `out`: serially, or (`fork`) with a worker forked at the write or (`early`)
    before, sent the field figure's call `ahead` (a FigureCall) before the write if given."""
    monkeypatch.setattr(figure_process, "fork_for_figures", lambda: fork)
    if not early:
        return result.write(out, directory_name="run")
    with figure_process.figure_worker() as worker:
        assert worker is not None
        if ahead is not None:
            assert worker.waiting.wait(timeout=60)  # it has imported matplotlib
            assert worker.draw_ahead("field", ahead, result.provenance("figure"))
        return result.write(out, directory_name="run", figure_worker=worker)


def _started_workers(monkeypatch) -> list:
    """The figure workers' processes the code under test starts (filled as they start)."""
    started = []
    start = figure_process.start_figure_worker

    def recording():
        worker = start()
        started.append(worker.process)
        return worker

    monkeypatch.setattr(figure_process, "start_figure_worker", recording)
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


WAYS = {
    "forked at the write": {"early": False},
    "forked before the run": {"early": True},
    "field drawn ahead": {"early": True, "ahead": "same"},
    "another field drawn ahead": {"early": True, "ahead": "another"},
}


@pytest.mark.parametrize("way", WAYS)
def test_figure_workers_write_the_same_files_as_the_serial_path(result, tmp_path, monkeypatch, way):
    """A field figure drawn ahead is saved only if its call is the run's; another one is drawn anew."""
    options = dict(WAYS[way])
    if "ahead" in options:
        module, function, args, kwargs = result.figure_call("field")
        title = kwargs["title"] if options["ahead"] == "same" else "not this run's field"
        options["ahead"] = (module, function, args, {**kwargs, "title": title})
    serial = _files(_write(result, tmp_path / "serial", monkeypatch, fork=False))
    forked = _files(_write(result, tmp_path / "forked", monkeypatch, fork=True, **options))
    assert {name for name in forked if name.startswith("figures/")} == {
        f"figures/{name}" for name in run_directory.FIGURES.values()
    }
    assert forked.keys() == serial.keys()
    different = [name for name in serial if serial[name] != forked[name]]
    assert different == []  # PNG bytes too: the provenance text chunks are the same


def test_the_figure_calls_are_plain_data_that_pickle(result):
    """A worker forked before the run gets each figure as pickled data (`figure_process.pickled`), not
    the Result."""
    import pickle

    for key in run_directory.FIGURES:
        module, function, args, kwargs = pickle.loads(figure_process.pickled(result.figure_call(key)))
        assert (module, function) == result.figure_call(key)[:2]
        assert not any(isinstance(value, type(result)) for value in (*args, *kwargs.values()))


def _fail_in_the_child(monkeypatch, error):
    """`figure_process.save_png` raises `error` for the breaking pattern, one of the first worker's
    figures."""
    save = figure_process.save_png
    child_figure = run_directory.FIGURES[next(iter(run_directory.FIGURES))]

    def failing(figure, path, meta):
        if path.name == child_figure:
            assert os.getpid() != parent  # it is the child that fails
            raise error
        save(figure, path, meta)

    parent = os.getpid()
    monkeypatch.setattr(figure_process, "save_png", failing)


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
    monkeypatch.setattr(figure_process, "_figure_worker", lambda *args: os._exit(3))
    with pytest.raises(RuntimeError, match="exit code 3"):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []


def test_the_worker_s_own_child_that_dies_fails_the_write_and_leaves_nothing(result, tmp_path, monkeypatch):
    """The breaking pattern is drawn by the child the worker forks at the write (`_draw_halves`)."""
    save = figure_process.save_png
    parent = os.getpid()

    def dying(figure, path, meta):
        if path.name == run_directory.FIGURES["breaking_pattern"] and os.getppid() != parent:
            os._exit(3)  # the worker's child, not the worker
        save(figure, path, meta)

    monkeypatch.setattr(figure_process, "save_png", dying)
    started = _started_workers(monkeypatch)
    with pytest.raises(RuntimeError, match="a figure process ended without an answer"):
        _write(result, tmp_path / "out", monkeypatch, fork=True)
    assert list(tmp_path.iterdir()) == []
    _assert_ended(started)


@pytest.mark.parametrize("early", [False, True], ids=["forked at the write", "forked before the run"])
def test_a_failure_in_the_parent_stops_the_child_and_leaves_nothing(result, tmp_path, monkeypatch, early):
    def slow_child(*args):
        time.sleep(60)  # killed by the parent long before

    def broken_tables(result, temp):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(figure_process, "_figure_worker", slow_child)
    monkeypatch.setattr(run_directory, "run_writers", lambda: (("tables", broken_tables),))
    workers = _started_workers(monkeypatch)
    started = time.perf_counter()
    with pytest.raises(RuntimeError, match="disk on fire"):
        _write(result, tmp_path / "out", monkeypatch, fork=True, early=early)
    assert time.perf_counter() - started < 30.0  # the child was killed, not waited for
    assert list(tmp_path.iterdir()) == []
    _assert_ended(workers)


def test_workers_of_a_run_that_fails_are_ended(tmp_path, monkeypatch):
    """The command line forks the workers before the run; a run that fails never uses them."""
    from floebreak.cli import run as cli_run
    from floebreak.config.scenario import Scenario

    def failing_run(*args, **kwargs):
        raise InputError("simulation.step_m", "-1", allowed="> 0")

    monkeypatch.setattr(figure_process, "fork_for_figures", lambda: True)
    monkeypatch.setattr(floebreak.api, "run", failing_run)
    workers = _started_workers(monkeypatch)
    with pytest.raises(InputError):
        cli_run._execute(Scenario.from_dict({}), tmp_path / "out", False, True, "test")
    assert len(workers) == 1
    _assert_ended(workers)
    assert not (tmp_path / "out").exists()


def test_workers_not_used_are_ended():
    """`figure_worker` without a write (`--no-report`-like paths, a refused output, Ctrl-C)."""
    with figure_process.figure_worker() as worker:
        if worker is None:
            pytest.skip("this machine gives no second core to fork onto")
    _assert_ended([worker.process])
    assert multiprocessing.active_children() == []


def test_the_command_line_leaves_matplotlib_to_the_workers(tmp_path):
    """`floebreak run` on ≥ 2 cores: this process never imports matplotlib (the workers draw)."""
    out = str(tmp_path / "out")
    argv = ["floebreak", "run", "examples/reference.toml", "--quiet", "--out", out]
    argv += ["--set", "field.length_m=40"]
    code = (
        "import sys; from floebreak import cli; from floebreak.output import figure_process\n"
        "if not figure_process.fork_for_figures(): print('serial'); raise SystemExit\n"
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
    assert figure_process.fork_for_figures() is False
    monkeypatch.undo()
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert figure_process.fork_for_figures() is False
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
        "import sys, time; from floebreak.output import figure_process\n"
        "figure_process.fork_for_figures = lambda: True\n"
        "with figure_process.figure_worker() as worker:\n"
        "    print(worker.process.pid, flush=True)\n"
        "    time.sleep(600)\n"
    )
    victim = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        pids = [int(pid) for pid in victim.stdout.readline().split()]
    finally:
        victim.kill()
        victim.wait()
        victim.stdout.close()
    assert len(pids) == 1
    deadline = time.monotonic() + 30
    while not all(_gone(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert all(_gone(pid) for pid in pids)


def test_a_run_sends_its_field_ahead_and_the_write_only_saves_it(tmp_path, monkeypatch):
    """`run(..., figure_worker=)`: the field's figure is drawn while the engine runs, and the write sends
    no job for it (the field was not shifted for initial contact, so the call is the same)."""
    monkeypatch.setattr(figure_process, "fork_for_figures", lambda: True)
    sent = []
    send = figure_process.FigureWorker._send

    def recording(self, message):
        sent.append(message)
        return send(self, message)

    monkeypatch.setattr(figure_process.FigureWorker, "_send", recording)
    with figure_process.figure_worker() as worker:
        assert worker.waiting.wait(timeout=60)  # else the field is sent at the first event it waits at
        ran = floebreak.run(overrides=SMALL, figure_worker=worker)
        assert ran.summary["field_shift_m"] == 0.0
        assert list(worker.ahead) == ["field"]
        out = ran.write(tmp_path / "out", directory_name="run", figure_worker=worker)
    [(_, jobs, saved)] = [message for message in sent if message[0] == "write"]
    assert list(saved) == ["field"]
    assert sorted(path.name for _, path, _ in jobs) == sorted(
        name for key, name in run_directory.FIGURES.items() if key != "field"
    )
    serial = _files(_write(ran, tmp_path / "serial", monkeypatch, fork=False))
    assert _files(out) == serial


def test_nothing_is_sent_ahead_while_the_worker_is_busy(result, monkeypatch):
    """A figure's data fill the pipe: sent to a worker still importing matplotlib, the send would block
    the engine until the import ends; it is not sent (the write draws that figure)."""
    monkeypatch.setattr(figure_process, "fork_for_figures", lambda: True)
    monkeypatch.setattr(figure_process, "_figure_worker", lambda *args: time.sleep(60))
    with figure_process.figure_worker() as worker:
        started = time.perf_counter()
        callback = worker.ahead_callback("field", result.figure_call("field"), result.provenance("figure"))
        callback(object())
        assert not worker.draw_ahead("field", result.figure_call("field"), result.provenance("figure"))
        assert worker.ahead == {}
        assert time.perf_counter() - started < 5.0
