"""Atomic writes (`floebreak.io.atomic`): all or nothing, and results readable like any other file."""

from __future__ import annotations

import os
import signal
import socket
import stat
import subprocess
import sys
import threading
import time
from hashlib import sha256

import pytest

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_directory, atomic_path, remove_dead_temporaries, scratch_directory


def umask() -> int:
    value = os.umask(0)
    os.umask(value)
    return value


def test_atomic_file_gets_the_umask_mode_not_the_private_temporary_one(tmp_path):
    target = tmp_path / "report.html"
    with atomic_path(target) as temp:
        temp.write_text("x")
    assert target.read_text() == "x"
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~umask()


def test_atomic_directory_gets_the_umask_mode(tmp_path):
    target = tmp_path / "run"
    with atomic_directory(target) as temp:
        (temp / "a.txt").write_text("a")
    assert stat.S_IMODE(target.stat().st_mode) == 0o777 & ~umask()


def test_a_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(RuntimeError), atomic_path(target) as temp:
        temp.write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(RuntimeError), atomic_directory(tmp_path / "dir") as temp:
        (temp / "half.txt").write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


# --- atomic also at the end -----------------------------------------------------------
def test_a_directory_created_meanwhile_is_not_replaced(tmp_path):
    target = tmp_path / "out"
    with pytest.raises(InputError, match="created by another process while this one was writing"):
        with atomic_directory(target) as temp:
            (temp / "mine.txt").write_text("mine")
            target.mkdir()  # another run finished first
            (target / "theirs.txt").write_text("theirs")
    assert [p.name for p in target.iterdir()] == ["theirs.txt"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # this run's temporary directory is gone


def test_of_two_concurrent_writers_without_overwrite_one_wins_and_one_is_refused(tmp_path):
    """Both pass the check at the start (the other has not finished yet); the second to finish is refused."""
    target = tmp_path / "out"
    both_inside = threading.Barrier(2)
    outcomes: dict[str, str] = {}

    def writer(name: str) -> None:
        try:
            with atomic_directory(target) as temp:
                (temp / "who.txt").write_text(name)
                both_inside.wait(timeout=30)
            outcomes[name] = "written"
        except InputError:
            outcomes[name] = "refused"

    threads = [threading.Thread(target=writer, args=(name,)) for name in ("a", "b")]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=60)
    assert sorted(outcomes.values()) == ["refused", "written"]
    winner = next(name for name, outcome in outcomes.items() if outcome == "written")
    assert (target / "who.txt").read_text() == winner
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_overwrite_still_replaces(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "old.txt").write_text("old")
    with atomic_directory(target, overwrite=True) as temp:
        (temp / "new.txt").write_text("new")
    assert [p.name for p in target.iterdir()] == ["new.txt"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_two_runs_on_one_out_give_one_result_and_exit_2(tmp_path):
    """The campaign's reproducer: two `floebreak run` on one --out, started together, no --overwrite."""
    (tmp_path / "s.toml").write_text("[field]\nlength_m = 30.0\n", encoding="utf-8")
    command = [sys.executable, "-m", "floebreak.cli", "run", "s.toml", "--out", "out", "-q"]
    runs = [
        subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    results = [(run.wait(timeout=600), *run.communicate()) for run in runs]
    codes = sorted(code for code, _, _ in results)
    assert codes == [0, 2], results
    refused = next(err for code, _, err in results if code == 2)
    assert "out" in refused and any(
        reason in refused
        for reason in ("exists", "created by another process", "being written by another floebreak process")
    ), refused
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "s.toml"]  # no temporary left


def _dead_pid() -> int:
    process = subprocess.Popen([sys.executable, "-c", "pass"])
    process.wait()
    return process.pid


def _host() -> str:
    return sha256(socket.gethostname().encode()).hexdigest()[:8]


def test_temporaries_of_dead_processes_are_removed_by_the_next_writer(tmp_path):
    dead, host = _dead_pid(), _host()
    stale = {
        "dead spool": tmp_path / f".out.spool-{dead}.{host}-ab12cd_3",
        "dead temporary directory": tmp_path / f".other.tmp-{dead}.{host}-zz9",
        "dead temporary file": tmp_path / f".f.png.tmp-{dead}.{host}-q1w2e3.png",
    }
    kept = {
        "live spool": tmp_path / f".out.spool-{os.getpid()}.{host}-ab12cd_3",
        "another host's": tmp_path / f".out.spool-{dead}.{'0' * 8 if host != '0' * 8 else '1' * 8}-xyz",
        "an old-style name (no pid)": tmp_path / ".out.spool-k2j3h4",
        "a user's hidden folder": tmp_path / ".out.spool-notes",
    }
    for path in [*stale.values(), *kept.values()]:
        if path.suffix == ".png":
            path.write_bytes(b"half")
        else:
            path.mkdir()
            (path / "contacts.part").write_bytes(b"records")
    with scratch_directory(tmp_path / "next") as spool:
        assert spool.exists()
    for what, path in stale.items():
        assert not path.exists(), what
    for what, path in kept.items():
        assert path.exists(), what
    assert remove_dead_temporaries(tmp_path) == []


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="needs SIGKILL")
def test_the_spool_of_a_killed_run_is_removed_by_the_next_run(tmp_path):
    """SIGKILL a `floebreak run` while its spool exists; the next run into the same folder removes it."""
    (tmp_path / "s.toml").write_text("[field]\nlength_m = 400.0\n", encoding="utf-8")
    command = [sys.executable, "-m", "floebreak.cli", "run", "s.toml", "-q", "--out"]
    victim = subprocess.Popen([*command, "first"], cwd=tmp_path, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 300
    while not list(tmp_path.glob(".first.spool-*")) and victim.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    victim.kill()
    victim.wait()
    spools = list(tmp_path.glob(".first.spool-*"))
    assert len(spools) == 1, "the run ended before its spool appeared"
    (tmp_path / "t.toml").write_text("[field]\nlength_m = 30.0\n", encoding="utf-8")
    second = subprocess.run(
        [sys.executable, "-m", "floebreak.cli", "run", "t.toml", "-q", "--out", "second"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert second.returncode == 0, second.stderr
    assert not spools[0].exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml", "second", "t.toml"]
