"""Command line: observations, field, run, demo, report, schema, validate; bad input exits with code 2 and
leaves no file; an internal error exits with code 1 and saves the scenario."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from floebreak.output.field_files import load_field

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def run(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "floebreak.cli", *args],  # the console command
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


def test_version_names_what_results_depend_on():
    from importlib.metadata import version

    result = run("--version")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == f"floebreak {version('floebreak')}"
    entries = dict(line.strip().split(" ", 1) for line in lines[1:])
    for name in ("numpy", "scipy", "shapely", "numba", "opentorsion", "rainflow", "pymunk"):
        assert entries[name] == version(name), name
    assert entries["blas"] != "none loaded"  # e.g. "openblas 0.3.30 SkylakeX (scipy.libs); …"


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


def test_demo_runs_the_reference_scenario(tmp_path):
    """`floebreak demo`: the reference scenario (the thesis' 385 m × 100 m field, h = 1 m) into a run
    directory."""
    out = tmp_path / "demo"
    result = run("demo", "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert {p.name for p in out.iterdir()} >= {
        "summary.json",
        "cusps.parquet",
        "flipped.parquet",
        "remaining.parquet",
        "field.parquet",
        "contacts.parquet",
        "scenario.resolved.toml",
        "figures",
        "report.html",
    }
    html = (out / "report.html").read_text()
    assert "<code>demo</code>" in html and ".tmp" not in html  # the final name, not the temporary one
    summary = json.loads((out / "summary.json").read_text())
    resolved = tomllib.loads((out / "scenario.resolved.toml").read_text())
    assert resolved["field"]["length_m"] == 385.0 and resolved["ice"]["thickness_m"] == 1.0
    assert resolved["field"]["observation"] == "2019-12-18T20:20" and resolved["ship"]["hull"] == "agulhas_ii"
    assert summary["area_balance_rel_error"] <= 1e-9 and summary["n_cusps"] > 0
    # the field covers the observation's 44 % of 385 m × 100 m within ±1 percentage point
    assert summary["initial_ice_area_m2"] / (385.0 * 100.0) == pytest.approx(0.44, abs=0.01)
    # wide enough for the largest floes: no run warning (the propeller's own warnings are its summary's)
    propeller_warnings = json.loads((out / "propeller" / "summary.json").read_text())["warnings"]
    others = [line for line in result.stderr.splitlines() if "warning" in line]
    assert summary["warnings"] == [] and len(others) == len(propeller_warnings)
    assert "cusps" in result.stdout and "wall time" in result.stdout
    check_demo_propeller(out, summary["n_cusps"], result.stdout + result.stderr)


def check_demo_propeller(out: Path, n_cusps: int, stdout: str) -> None:
    """`make demo` ends with the propeller spectra of the reference run, in OUT/propeller/."""
    import io

    import pyarrow.csv
    import xarray as xr

    prop = out / "propeller"
    for name in (
        "spectra.nc",
        "load_spectrum.csv",
        "torque_exceedance.csv",
        "cusp_loads.csv",
        "summary.json",
    ):
        assert (prop / name).is_file(), name
    for quantity in ("torque", "load"):
        for scale in ("linear", "log"):
            assert (prop / "figures" / f"{quantity}_spectrum_{scale}.png").stat().st_size > 0
    summary = json.loads((prop / "summary.json").read_text())
    # the default profile: the blade milling model at 0 % and the spec's pitch, the transport model decides
    # which cusps reach a propeller; those that do not carry no load
    assert summary["load_model"]["name"] == "milling" and summary["transport"]["rule"] == "flow"
    n_reaching = summary["transport"]["n_reaching"]
    assert 0 < n_reaching < n_cusps
    assert len(summary["transport"]["fraction_reaching_per_propeller"]) == 2
    with xr.open_dataset(prop / "spectra.nc") as ds:
        assert ds["pitch"].values.tolist() == [0.0, 95.8551]  # Agulhas II: neutral and its 95.86 % pitch
        assert ds["run"].values.tolist() == [out.name]  # the final folder name, not a temporary one
        assert ds["n_loads"].values.tolist() == [[n_reaching, n_reaching]]
        width = ds.attrs["torque_bin_width_knm"]
        # probability densities: each pitch integrates to 1 over its bins
        assert (ds["torque_density"].sum("torque_knm") * width).values == pytest.approx([1.0, 1.0])
        # rates: the field is 385 m long, sailed at 3 m/s (thesis §6.3); the cusps that reach are shared by
        # the two propellers (thesis §6.1): n/2 loads per propeller over 385 m / 3 m/s = 0.0356 h
        hours = 385.0 / 3.0 / 3600.0
        counts = ds["torque_count_run"].sum("torque_knm").values[0]
        assert counts.tolist() == [n_reaching, n_reaching]
        assert (ds["torque_rate_per_hour"].sum("torque_knm").values * hours) == pytest.approx(counts / 2)
        assert (ds["torque_rate_per_km"].sum("torque_knm").values * 0.385) == pytest.approx(counts / 2)
    assert summary["rates"]["loads_per_hour_per_propeller"] == pytest.approx(n_reaching / 2 / hours)
    text = (prop / "cusp_loads.csv").read_bytes()
    lines = [line for line in text.splitlines() if not line.startswith(b"#")]  # provenance comments
    loads = pyarrow.csv.read_csv(io.BytesIO(b"\n".join(lines))).to_pydict()
    assert len(loads["torque_knm_p95.8551"]) == n_cusps
    assert sum(v is not None for v in loads["torque_knm_p95.8551"]) == n_reaching
    assert not any(loads["beyond_table_p95.8551"])  # no table
    # each reaching cusp on the blade's engaged interval in its cross-section (hub 0.645 m to tip 2.15 m)
    assert summary["load_model"]["placement"] == "engaged interval from the transport"
    assert "milling model (engaged interval from the transport)" in stdout
    pairs = list(zip(loads["engaged_inner_radius_m"], loads["engaged_outer_radius_m"], strict=True))
    reached = [p for p, q in zip(pairs, loads["torque_knm_p95.8551"], strict=True) if q is not None]
    assert len(reached) == n_reaching and all(0.645 - 1e-9 <= a <= b <= 2.15 + 1e-9 for a, b in reached)
    assert sum(a is None for a, _ in pairs) == n_cusps - n_reaching
    # where users look: the terminal, the summary and the report state the model, the fraction reaching
    # and the warnings (a per-cusp torque above twice the rated 306.9 kN·m)
    assert "milling model" in stdout and "fraction of cusps reaching a propeller" in stdout
    assert "loads per hour" in stdout
    top = summary["pitches"]["p95.8551"]["torque_range_knm"][1]
    warned = top > 2 * 306.9
    assert any("rated torque" in w for w in summary["warnings"]) is warned
    assert ("rated torque (306.9" in stdout) is warned
    report = (out / "report.html").read_text()
    assert "<h2>Propeller loads</h2>" in report and "rule_form.png" in report
    assert "Per-cusp loads: milling model (engaged interval from the transport)" in report
    assert ("Warning:" in report) is bool(summary["warnings"])  # any warning (extrapolation too) shows
    assert "propeller spectra" in stdout and f"{prop}" in stdout


def test_demo_without_propeller_overwrite_and_failure(tmp_path, monkeypatch, cli):
    """A short reference field: --no-propeller skips OUT/propeller/; a failing propeller step leaves nothing
    (not even the run) and exit 1; --overwrite replaces an earlier demo as a whole."""
    pipeline = importlib.import_module("floebreak.propeller.pipeline")
    out = tmp_path / "demo"
    short = ("--set", "field.length_m=60.0", "-q")
    code, stdout, err = cli("demo", "--out", str(out), *short, "--no-propeller")
    assert code == 0, err
    assert (out / "cusps.parquet").is_file() and not (out / "propeller").exists()
    assert "spectra.nc" not in stdout

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    with monkeypatch.context() as patch:
        patch.setattr(pipeline, "analyse_cusp_loads", broken)
        code, _, err = cli("demo", "--out", str(tmp_path / "failed"), *short)
    assert code == 1 and "ZeroDivisionError" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo", "failed.failed-scenario.toml"]

    code, stdout, err = cli("demo", "--out", str(out), *short, "--overwrite")
    assert code == 0, err
    assert (out / "propeller" / "spectra.nc").is_file() and f"{out / 'propeller'}" in stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo", "failed.failed-scenario.toml"]


def test_run_report_and_schema_commands(tmp_path, cli):
    out = tmp_path / "run"
    args = ("run", str(EXAMPLES / "random_thickness.toml"), "--out", str(out), "--set", "field.length_m=60.0")
    code, stdout, err = cli(*args)
    assert code == 0, err
    assert "cusps" in stdout and "written" in stdout
    resolved = tomllib.loads((out / "scenario.resolved.toml").read_text())
    assert resolved["field"]["length_m"] == 60.0 and resolved["ice"]["thickness_range_m"] == [0.75, 1.25]
    assert "warning" not in err
    # a field narrower than B + 2 d_max = 51.7 m: the run goes on and says why its flips are biased
    narrow = ("run", str(EXAMPLES / "reference.toml"), "--out", str(tmp_path / "narrow"), "--quiet")
    code, _, err = cli(*narrow, "--set", "field.length_m=60.0", "--set", "field.width_m=50.0")
    assert code == 0, err
    assert "warning: field.width_m = 50 m" in err and "51.7 m" in err
    # a second run into the same directory is refused (exit 2, nothing changed)
    code, _, err = cli("run", str(EXAMPLES / "single_floe.toml"), "--out", str(out))
    assert code == 2 and "error: out:" in err and "--overwrite" in err
    (out / "report.html").unlink()
    code, _, err = cli("report", str(out))
    assert code == 0, err
    assert (out / "report.html").read_text().count("data:image/png;base64,") == 4
    code, schema, _ = cli("schema")
    assert code == 0
    assert "fracture_toughness_pa_sqrt_m" in json.loads(schema)["$defs"]["IceSection"]["properties"]
    code, _, err = cli("report", str(tmp_path))
    assert code == 2 and "error: run_dir:" in err


# --- in-process CLI calls for the many bad inputs (fast) --------------------------------------------


BAD_RUNS = [
    # (scenario text or None for a missing file, extra args, key that the message must name)
    ("seed = 1\n[ice\n", [], "scenario"),
    (None, [], "scenario"),
    ("[ice]\nthickness = 1.0\n", [], "ice.thickness"),
    ("[ice]\nthickness_m = 'thick'\n", [], "ice.thickness_m"),
    ("", ["--set", "ice.thickness_m=0"], "ice.thickness_m"),
    ("", ["--set", "ship.step_m=-1"], "ship.step_m"),
    ("", ["--set", "field.concentration=1.5"], "field.concentration"),
    ("", ["--set", "ice.fracture_toughness_pa_sqrt_m=-1.0"], "ice.fracture_toughness_pa_sqrt_m"),
    ("", ["--set", "ship.hull=titanic"], "ship.hull"),
    ("", ["--set", "ship.speed_m_s=0.0"], "ship.speed_m_s"),
    ("", ["--set", "propeller.fraction_reaching=1.5"], "propeller.fraction_reaching"),
    ("", ["--set", "propeller.fraction_reaching=0.0"], "propeller.fraction_reaching"),
    ("", ["--set", "propeller.count=0"], "propeller.count"),
    ("", ["--set", "failure.crack_criterion=shear"], "failure.crack_criterion"),
    ("", ["--set", "failure.size_effect_law=BZ9"], "failure.size_effect_law"),
    ("", ["--set", "profile=fast"], "profile"),
    ("", ["--set", "field.observation=1999-01-01T00:00"], "field.observation"),
    ("", ["--set", "ice.thickness_m"], "--set"),
    ("", ["--set", "ice.thickness_m=[1,"], "--set"),
    ("[field]\nfile = 'missing.parquet'\n", [], "field.file"),
    ("[field]\nfile = 'corrupt.parquet'\n", [], "field.file"),
    ("[ship]\nfile = 'missing.csv'\n", [], "ship.file"),
    ("[ship]\nfile = 'corrupt.csv'\n", [], "ship.file"),
]


@pytest.mark.parametrize(
    ("text", "args", "key"), BAD_RUNS, ids=[f"{i}-{b[2]}" for i, b in enumerate(BAD_RUNS)]
)
def test_bad_run_input_exit_2_one_line_nothing_written(tmp_path, text, args, key, cli):
    (tmp_path / "corrupt.parquet").write_bytes(b"PAR1 garbage")
    (tmp_path / "corrupt.csv").write_text("line,x_m,y_m\nupper,1,oops\n", encoding="utf-8")
    scenario = tmp_path / "s.toml"
    if text is not None:
        scenario.write_text(text + "[field]\nlength_m = 60.0\n" * (text == ""), encoding="utf-8")
    before = {p.name for p in tmp_path.iterdir()}
    code, _, err = cli("run", str(scenario), "--out", str(tmp_path / "out"), *args)
    assert code == 2, err
    assert err.strip().count("\n") == 0 and f"error: {key}:" in err
    assert {p.name for p in tmp_path.iterdir()} == before


def test_allowed_values_are_listed(tmp_path, cli):
    scenario = tmp_path / "s.toml"
    scenario.write_text("[failure]\ncrack_criterion = 'shear'\n", encoding="utf-8")
    _, _, err = cli("run", str(scenario), "--out", str(tmp_path / "out"))
    for name in ("point_load", "line_load", "tensile_stress", "flexural_stress"):
        assert name in err


def test_output_directory_problems(tmp_path, cli):
    scenario = tmp_path / "s.toml"
    scenario.write_text("[field]\nlength_m = 60.0\n", encoding="utf-8")
    (tmp_path / "exists").mkdir()
    code, _, err = cli("run", str(scenario), "--out", str(tmp_path / "exists"))
    assert code == 2 and "error: out:" in err and "--overwrite" in err
    assert list((tmp_path / "exists").iterdir()) == []
    code, _, err = cli("run", str(scenario), "--out", str(tmp_path / "no" / "out"))
    assert code == 2 and "error: out:" in err and not (tmp_path / "no").exists()


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write into read-only directories")
def test_unwritable_output_directory(tmp_path, cli):
    scenario = tmp_path / "s.toml"
    scenario.write_text("", encoding="utf-8")
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        code, _, err = cli("run", str(scenario), "--out", str(locked / "out"))
    finally:
        locked.chmod(0o700)
    assert code == 3 and "Permission denied" in err and str(locked / "out") in err


def test_internal_error_exit_1_saves_the_scenario(tmp_path, monkeypatch, cli):
    run_module = importlib.import_module("floebreak.app.run")

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(run_module, "simulate", broken)
    scenario = tmp_path / "s.toml"
    scenario.write_text("seed = 9\n[field]\nlength_m = 60.0\n", encoding="utf-8")
    code, _, err = cli("run", str(scenario), "--out", str(tmp_path / "out"), "-q")
    assert code == 1
    assert "internal error" in err and "ZeroDivisionError" in err
    saved = tmp_path / "out.failed-scenario.toml"
    assert saved.exists() and not (tmp_path / "out").exists()
    data = tomllib.loads(saved.read_text())
    assert data["seed"] == 9 and data["field"]["length_m"] == 60.0  # the resolved scenario
    assert "ZeroDivisionError" in saved.read_text()


def test_validate_single_floe_calls_the_study(tmp_path, monkeypatch, cli):
    study = importlib.import_module("floebreak.studies.single_floe")
    calls = []

    def fake(out_dir, overwrite=False):
        calls.append((out_dir, overwrite))
        return out_dir

    monkeypatch.setattr(study, "write_single_floe_matrix", fake)
    code, _, _ = cli("validate", "single-floe", "--out", str(tmp_path / "sf"), "--overwrite")
    assert code == 0 and calls == [(tmp_path / "sf", True)]
