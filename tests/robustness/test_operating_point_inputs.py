"""Bad inputs of the propeller's operating point through the command line: each exits 2, names the key and
writes nothing (the wake fraction, a pitch outside the open-water curves, an advance ratio beyond them)."""

from __future__ import annotations

import pytest
from tests.shaft.test_cli_shaft import make_run


@pytest.fixture
def run(tmp_path):
    return make_run(tmp_path / "run", speed_m_s=3.0, profile="default")


@pytest.mark.parametrize("value", ["1.0", "-0.1", "nan"])
def test_wake_fraction_outside_zero_to_one(run, tmp_path, cli, value):
    out = tmp_path / "out"
    args = ["--shaft-line", "agulhas_ii", "--wake-fraction", value]
    code, _, err = cli("propeller", run, "--out", out, *args)
    assert code == 2 and "--wake-fraction" in err and "[0, 1)" in err
    assert not out.exists()


def test_pitch_outside_the_curves(run, tmp_path, cli):
    # 20 % of the 5.15 m pitch over D = 4.3 m: P/D = 0.24, below the B-series' 0.5 (the flow transport
    # evaluates the curves at the propeller's geometry)
    out = tmp_path / "out"
    args = ["--transport", "flow", "--propeller-geometry", "pitch_percent=20"]
    code, _, err = cli("propeller", run, "--out", out, *args)
    assert code == 2 and "propeller.pitch_ratio" in err
    assert not out.exists()


def test_advance_ratio_beyond_zero_thrust(run, tmp_path, cli):
    # 16 m/s at 140 rpm, w ≈ 0.14: J ≈ 16 · 0.86/(2.333 · 4.3) = 1.37, beyond zero thrust at P/D 1.148 (1.24)
    out = tmp_path / "out"
    code, _, err = cli("propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--speed-m-s", "16")
    assert code == 2 and "propeller.advance_ratio" in err
    assert not out.exists()


def test_a_valid_wake_fraction_is_used(run, tmp_path, cli):
    import json

    out = tmp_path / "out"
    code, _, err = cli(
        "propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--wake-fraction", "0.25"
    )
    assert code == 0, err
    shaft = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))
    assert shaft["propeller_operating_point"]["wake_fraction"] == 0.25
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["options"]["wake_fraction"] == 0.25
