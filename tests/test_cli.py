"""Command line: observations, field, demo; bad input exits with code 2 and leaves no file."""

from __future__ import annotations

import subprocess
import sys

import pytest

from floebreak.io.field_files import load_field


def run(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", "from floebreak.cli import main; main()", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


def test_observations_lists_table1():
    result = run("observations")
    assert result.returncode == 0
    assert "2019-12-18T20:20" in result.stdout and "2020-01-03T17:40" in result.stdout


def test_field_writes_parquet_and_figure(tmp_path):
    out = tmp_path / "field.parquet"
    result = run(
        "field",
        "--obs",
        "2019-12-18T20:20",
        "--length",
        "100",
        "--width",
        "50",
        "--seed",
        "1",
        "--out",
        str(out),
        "--figure",
        str(tmp_path / "field.png"),
    )
    assert result.returncode == 0, result.stderr
    assert load_field(out).n_floes > 0
    assert (tmp_path / "field.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["--obs", "1999-01-01T00:00"], "observation"),
        (
            [
                "--concentration",
                "1.5",
                "--mean-thickness",
                "1",
                "--diameters",
                "5,10",
                "--percentages",
                "50,50",
            ],
            "concentration",
        ),
        (
            [
                "--concentration",
                "0.5",
                "--mean-thickness",
                "1",
                "--diameters",
                "5,10",
                "--percentages",
                "50,40",
            ],
            "percentages",
        ),
        (
            [
                "--concentration",
                "0.5",
                "--mean-thickness",
                "-1",
                "--diameters",
                "5,10",
                "--percentages",
                "50,50",
            ],
            "thickness",
        ),
        (["--obs", "2019-12-18T20:20", "--width", "10"], "width_m"),
    ],
)
def test_bad_input_exit_code_2_names_field_and_writes_nothing(tmp_path, args, field):
    out = tmp_path / "field.parquet"
    result = run("field", *args, "--out", str(out))
    assert result.returncode == 2, result.stderr
    assert field in result.stderr
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_unwritable_output_path(tmp_path):
    result = run("field", "--obs", "2019-12-18T20:20", "--out", str(tmp_path / "no" / "f.parquet"))
    assert result.returncode == 2 and "out" in result.stderr


def test_demo_writes_a_complete_directory(tmp_path):
    result = run("demo", "--out", str(tmp_path / "demo"))
    assert result.returncode == 0, result.stderr
    assert {p.name for p in (tmp_path / "demo").iterdir()} >= {"field.parquet", "field.geojson", "figures"}
    assert (tmp_path / "demo" / "figures" / "field.png").exists()
