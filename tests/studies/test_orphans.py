"""After a SIGKILL of `floebreak study --workers 2`, the pool's workers and
multiprocessing's resource tracker outlived the parent (≈ 370 MB each). Now every process the study started
ends within seconds of its parent's death."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

STUDY = (
    'name = "orphans"\nn_fields = 6\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
    "length_m = 300.0\nwidth_m = 60.0\n"
)

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc (Linux)")


def _children(pid: int) -> set[int]:
    """The pids whose parent is `pid` (from /proc/*/stat)."""
    found = set()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
            found.add(int(entry.name))
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"  # a zombie has ended (its parent, init, reaps it)


def test_sigkill_of_a_study_leaves_no_worker_behind(tmp_path):
    (tmp_path / "study.toml").write_text(STUDY, encoding="utf-8")
    command = [sys.executable, "-m", "floebreak", "study", "study.toml", "--out", "out", "--workers", "2"]
    env = {
        **os.environ,
        "OMP_NUM_THREADS": "1",
        "PYTHONPATH": str(Path(__import__("floebreak").__file__).parents[1]),
    }
    parent = subprocess.Popen(
        command, cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    try:
        children: set[int] = set()
        deadline = time.monotonic() + 120.0
        while len(children) < 3 and time.monotonic() < deadline:  # two workers and the resource tracker
            assert parent.poll() is None, parent.stderr.read().decode()
            children |= _children(parent.pid)
            time.sleep(0.2)
        assert len(children) >= 3, children
        time.sleep(1.0)  # the workers past their start-up, in their runs
        children |= _children(parent.pid)
        parent.send_signal(signal.SIGKILL)
        parent.wait(timeout=10)
        deadline = time.monotonic() + 10.0
        while any(_alive(pid) for pid in children) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert [pid for pid in children if _alive(pid)] == []
    finally:
        if parent.poll() is None:
            parent.kill()
        parent.stderr.close()


def test_the_watchdog_ends_a_process_whose_parent_is_gone():
    # in a child: watch a parent id that is not its parent, as after the parent's death
    code = (
        "import time\nfrom floebreak.studies.executors import exit_with_parent\n"
        "exit_with_parent(1, poll_s=0.05)\ntime.sleep(30)\n"
    )
    started = time.monotonic()
    result = subprocess.run([sys.executable, "-c", code], timeout=30, env={**os.environ})
    assert result.returncode == 1 and time.monotonic() - started < 20.0
