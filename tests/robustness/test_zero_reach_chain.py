"""A run whose cusps all miss the propellers (the kinematic transport at h = 0.8 m): the propeller and the
shaft analyses both say there is no ice load, in the terminal and in their summary.json, instead of
reporting the mean torque's peak as a result."""

from __future__ import annotations

import json
import subprocess
import sys


def _floebreak(*args):
    return subprocess.run(
        [sys.executable, "-m", "floebreak", *map(str, args)], capture_output=True, text=True
    )


def test_no_ice_load_is_said_by_the_propeller_and_the_shaft(tmp_path):
    run = tmp_path / "run"
    made = _floebreak(
        "run", "examples/reference.toml", "--out", run, "--quiet",
        "--set", "ice.thickness_m=0.8", "--set", "field.length_m=120",
    )  # fmt: skip
    assert made.returncode == 0, made.stderr
    out = tmp_path / "p"
    done = _floebreak("propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--speed-m-s", "3")
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    shaft = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))
    if summary.get("no_load_reason") is None:  # a field on which a cusp does reach tests nothing here
        assert shaft["transport"]["reaching_port"] > 0 or "no_ice_load" in shaft
        return
    assert shaft["transport"]["reaching_port"] == 0
    assert shaft["warnings"][0].startswith("no cusp reached the port propeller")
    said = done.stdout + done.stderr
    assert "no cusp reached the port propeller" in said and "no cusp reached a propeller" in said
