"""A study ends within a few seconds of SIGINT or SIGTERM: the pool's workers are ended, not waited for
(each would otherwise finish its run, 10–15 s)."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest

STUDY = (
    'name = "signal"\nn_fields = 2\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
    "length_m = 385.0\nwidth_m = 100.0\n"
    '[[sweeps]]\nname = "K"\nparameters = { "ice.fracture_toughness_pa_sqrt_m" = [120e3] }\n'
)


@pytest.mark.parametrize(("signum", "code"), [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_study_ends_soon_after_a_signal(tmp_path, signum, code):
    study = tmp_path / "study.toml"
    study.write_text(STUDY, encoding="utf-8")
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "floebreak",
            "study",
            str(study),
            "--out",
            str(tmp_path / "s"),
            "--workers",
            "2",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert "runs on" in process.stdout.readline()
        time.sleep(8.0)  # the workers are started and inside their runs
        assert process.poll() is None
        sent = time.perf_counter()
        process.send_signal(signum)
        process.wait(timeout=30)
        waited = time.perf_counter() - sent
    finally:
        process.kill()
    assert process.returncode == code, process.stderr.read()
    assert waited < 3.0
