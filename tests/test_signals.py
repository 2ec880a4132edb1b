"""SIGTERM of `run` gave exit 143 and left the hidden ``.out.spool-*``
directory; under an inherited ignored SIGINT an interrupt printed ``KeyboardInterrupt:`` and exited 0.
SIGTERM now unwinds like Ctrl-C (clean-up, one line, exit 143), and a signal at any moment gives one line
and its code."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[1] / "src")
ENV = {**os.environ, "PYTHONPATH": SRC, "OMP_NUM_THREADS": "1"}


def test_sigterm_during_a_run_cleans_up_and_exits_143(tmp_path):
    (tmp_path / "s.toml").write_text("[field]\nlength_m = 3000.0\n", encoding="utf-8")
    command = [sys.executable, "-m", "floebreak", "run", "s.toml", "--out", "out", "--quiet"]
    process = subprocess.Popen(command, cwd=tmp_path, env=ENV, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120.0
        while not list(tmp_path.glob(".out.spool-*")):  # the run is stepping, its records spooled
            assert process.poll() is None and time.monotonic() < deadline, process.stderr.read()
            time.sleep(0.05)
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == 143, err
    assert err == "terminated (SIGTERM); nothing half-written was kept\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]  # no spool, no partial output


# the console command's main, started with SIGINT ignored (as a background job's is), and a SIGINT that
# arrives once the command has returned, in the interpreter's atexit callbacks (registered first: runs last)
AT_EXIT = textwrap.dedent(
    """
    import atexit, os, signal, sys
    atexit.register(lambda: os.kill(os.getpid(), signal.SIGINT))
    sys.argv = ["floebreak", "--version"]
    from floebreak.__main__ import main
    main()
    """
)


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_an_interrupt_under_an_inherited_ignored_sigint_exits_130_with_one_line():
    result = subprocess.run(
        [sys.executable, "-c", AT_EXIT],
        env=ENV,
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    assert result.returncode == 130, result.stderr
    assert result.stderr == "interrupted (Ctrl-C); nothing half-written was kept\n"
    assert "floebreak" in result.stdout  # the command itself had finished


def test_a_reported_sigterm_does_not_colour_a_later_ctrl_c():
    """The record is consumed when reported: a Ctrl-C after a reported SIGTERM in the same process (a test
    session, a notebook) exits 130, not 143."""
    import signal

    from floebreak.exit_codes import EXIT_INTERRUPTED, EXIT_TERMINATED, interruption, record_signal

    record_signal(signal.SIGTERM)
    assert interruption()[1] == EXIT_TERMINATED
    assert interruption()[1] == EXIT_INTERRUPTED
