"""`floebreak study --out` a file is an input error (exit 2); an output the machine refuses (a pseudo or
read-only file system) is a storage error (exit 3) — as for `floebreak run`, before any run starts."""

from __future__ import annotations

import os
import subprocess

import pytest

STUDY = (
    'name = "out"\nn_fields = 1\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
    "length_m = 50.0\nwidth_m = 30.0\n"
    '[[sweeps]]\nname = "K"\nparameters = { "ice.fracture_toughness_pa_sqrt_m" = [120e3] }\n'
)


@pytest.fixture
def study_file(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(STUDY, encoding="utf-8")
    return path


def test_study_out_a_file_is_exit_2(cli, tmp_path, study_file):
    target = tmp_path / "taken"
    target.write_text("not a directory", encoding="utf-8")
    code, _, err = cli("study", study_file, "--out", target, "--workers", "1")
    assert code == 2, err
    assert "error: out:" in err and "is a file" in err and "Traceback" not in err
    assert target.read_text(encoding="utf-8") == "not a directory"


def test_study_out_under_a_file_is_exit_2(cli, tmp_path, study_file):
    (tmp_path / "taken").write_text("x", encoding="utf-8")
    code, _, err = cli("study", study_file, "--out", tmp_path / "taken" / "sub", "--workers", "1")
    assert code == 2, err
    assert "Traceback" not in err


def test_study_out_on_a_pseudo_file_system_is_exit_3(cli, study_file):
    code, _, err = cli("study", study_file, "--out", "/proc/floebreak-study", "--workers", "1")
    assert code == 3, err
    assert "cannot write '/proc/floebreak-study'" in err and "Traceback" not in err


@pytest.mark.skipif(os.geteuid() != 0, reason="mounting a read-only file system needs root")
def test_study_out_on_a_read_only_file_system_is_exit_3(cli, tmp_path, study_file):
    mount = tmp_path / "ro"
    mount.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=1m", "tmpfs", str(mount)], check=False)
    if done.returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        code, _, err = cli("study", study_file, "--out", mount / "study", "--workers", "1")
    finally:
        subprocess.run(["umount", str(mount)], check=False)
    assert code == 3, err
    assert "Read-only file system" in err and "Traceback" not in err
