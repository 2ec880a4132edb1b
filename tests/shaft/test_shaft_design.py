"""The shaft's design outputs: rainflow histogram and Miner's damage in the shaft analysis, the
Campbell and rainflow figures, the terminal tables, the report's "Shaft line" section, CF bounds and
provenance on the shaft files."""

import io
import json
import shutil
from types import SimpleNamespace

import numpy as np
import pytest
import rainflow
import xarray as xr
from rich.console import Console

from floebreak.cli.tables import shaft_tables as _shaft_tables
from floebreak.output.report import render_report
from floebreak.propeller.ruleform import BasquinCurve
from floebreak.shaft.analysis import shaft_fatigue

from .test_cli_shaft import make_run

# ASTM E1049-85 (2011), Fig. 6 (rainflow counting example): peaks and valleys in units, with the counts
# of its Table: range 3 → 0.5, 4 → 1.5, 6 → 0.5, 8 → 1.0, 9 → 0.5 cycles
ASTM_SERIES = np.array([-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
ASTM_CYCLES = {3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5}
UNIT_N_M = 10e3  # one unit = 10 kN·m, so each range falls on the lower edge of its 10 kN·m bin


def _series_result(torque_n_m):
    """The attributes of a ShaftResult that `shaft_fatigue` reads, for a given shaft torque series."""
    torque = np.asarray(torque_n_m, dtype=float)
    return SimpleNamespace(
        cases=(2,), station="s", shaft_torque_n_m=torque[None, :], time_s=0.1 * np.arange(torque.size)
    )


def test_rainflow_histogram_of_the_astm_example():
    histogram, fatigue = shaft_fatigue(_series_result(UNIT_N_M * ASTM_SERIES))
    expected = np.zeros(9)  # bins of 10 kN·m up to the largest range, 90 kN·m (last bin closed)
    for units, count in ASTM_CYCLES.items():
        expected[min(units, 8)] += count
    assert histogram.counts.tolist() == expected.tolist()
    assert fatigue["histogram"]["n_cycles"] == 4.0
    assert fatigue["histogram"]["range_edges_kn_m"] == [10.0 * i for i in range(10)]
    assert fatigue["case"] == 2 and fatigue["damage"] is None
    assert fatigue["note"].startswith("no S–N curve given")


def test_miner_damage_of_the_astm_example_by_hand():
    # N(S) = 1e6 (10 kN·m / S)^3 with S the amplitude (half the range): D = Σ n (S/10 kN·m)^3 / 1e6
    curve = BasquinCurve(3.0, 10e3, 1e6, quantity="torque")
    _, fatigue = shaft_fatigue(_series_result(UNIT_N_M * ASTM_SERIES), curve)
    amplitude_over_reference = {units: units * UNIT_N_M / 2 / 10e3 for units in ASTM_CYCLES}
    by_hand = sum(n * amplitude_over_reference[u] ** 3 for u, n in ASTM_CYCLES.items()) / 1e6
    assert fatigue["damage"] == pytest.approx(by_hand, rel=1e-12)
    assert fatigue["sn_curve"]["reference_amplitude_kn_m"] == 10.0


def test_a_force_curve_gives_no_shaft_damage():
    _, fatigue = shaft_fatigue(_series_result(UNIT_N_M * ASTM_SERIES), BasquinCurve(3.0, 1e3, 1e6, "force"))
    assert fatigue["damage"] is None and "force curve" in fatigue["note"]


@pytest.fixture(scope="module")
def shaft_run(tmp_path_factory):
    """One `floebreak propeller RUN --out RUN/propeller --shaft-line agulhas_ii --sn-curve …` (drive)."""
    import subprocess
    import sys

    base = tmp_path_factory.mktemp("design")
    run = make_run(base / "run", speed_m_s=3.0, profile="default")
    args = ["propeller", str(run), "--out", str(run / "propeller"), "--shaft-line", "agulhas_ii"]
    args += ["--sn-curve", "torque,5,300,1e7", "--excitation-cases", "1,2"]
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", *args], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    return run, done.stdout


def test_summary_gives_the_rainflow_count_of_the_written_series(shaft_run):
    run, _ = shaft_run
    shaft = run / "propeller" / "shaft"
    summary = json.loads((shaft / "summary.json").read_text())
    with xr.open_dataset(shaft / "shaft_series.nc") as ds:
        torque = ds["shaft_torque"].sel(case=1).values * 1e3
    counted_cycles = [(r, c) for r, _, c, _, _ in rainflow.extract_cycles(torque.tolist()) if r > 0]
    counted = sum(c for _, c in counted_cycles)
    fatigue = summary["fatigue"]
    assert fatigue["histogram"]["n_cycles"] == pytest.approx(counted)
    assert sum(fatigue["histogram"]["cycle_counts"]) == pytest.approx(counted)
    assert fatigue["case"] == 1 and fatigue["damage"] > 0.0
    # Miner by hand from the counted cycles: N = 1e7 (300 kN·m / S)^5, S = range / 2
    damage = sum(c * (r / 2 / 300e3) ** 5 / 1e7 for r, c in counted_cycles)
    assert fatigue["damage"] == pytest.approx(damage, rel=1e-9)
    with open(shaft / "rainflow.csv", encoding="utf-8") as f:
        rows = [line for line in f if not line.startswith("#")]
    assert rows[0].strip() == "range_lower_knm,range_upper_knm,cycles"
    assert sum(float(r.split(",")[2]) for r in rows[1:]) == pytest.approx(counted)
    assert summary["provenance"]["command"] == "shaft_analysis"
    assert "rainflow" in summary["provenance"]["libraries"]


def test_campbell_and_rainflow_figures_exist(shaft_run):
    figures = shaft_run[0] / "propeller" / "shaft" / "figures"
    for name in ("campbell.png", "rainflow_histogram.png"):
        assert (figures / name).stat().st_size > 10_000, name


def test_shaft_spectra_netcdf_has_cf_bounds_and_provenance(shaft_run):
    shaft = shaft_run[0] / "propeller" / "shaft"
    with xr.open_dataset(shaft / "shaft_spectra.nc") as ds:
        bounds = ds["torque_knm_bounds"]
        assert ds["torque_knm"].attrs["bounds"] == "torque_knm_bounds"
        assert bounds.dims == ("torque_knm", "nv") and bounds.shape[1] == 2
        assert np.allclose(bounds.values[1:, 0], bounds.values[:-1, 1])  # contiguous bins
        assert np.allclose(ds["torque_knm"].values, bounds.values.mean(axis=1))
        assert ds["density_shaft_case1"].attrs["units"] == "kN-1 m-1"
        assert json.loads(ds.attrs["provenance"])["command"] == "shaft_analysis"
    with xr.open_dataset(shaft / "shaft_series.nc") as ds:
        assert "opentorsion" in json.loads(ds.attrs["provenance"])["libraries"]
    for name in ("shaft_series.csv", "shaft_spectra.csv", "modes.csv", "rainflow.csv"):
        text = (shaft / name).read_text(encoding="utf-8")
        assert "# provenance: {" in text, name


def test_terminal_prints_the_design_tables(shaft_run):
    _, stdout = shaft_run
    for text in ("first natural frequency", "7.76", "9.33", "16.8", "WARNING", "Q_peak [kN·m]"):
        assert text in stdout, text
    assert "min rpm [1/min]" in stdout and "no S–N curve given" not in stdout


def test_tables_fold_at_80_columns_and_say_when_no_curve_is_given(shaft_run):
    summary = json.loads((shaft_run[0] / "propeller" / "shaft" / "summary.json").read_text())
    summary["fatigue"] |= {"damage": None, "sn_curve": None}
    buffer = io.StringIO()
    piped = Console(file=buffer, width=80, force_terminal=False)
    for table in _shaft_tables(summary):
        piped.print(table)
    text = buffer.getvalue()
    assert "no S–N curve given" in text and "…" not in text
    assert max(len(line) for line in text.splitlines()) <= 80


def test_report_has_the_shaft_section(shaft_run, tmp_path):
    run = shutil.copytree(shaft_run[0], tmp_path / "run")
    (run / "summary.json").write_text(json.dumps({"scenario_hash": "0" * 16}), encoding="utf-8")
    page = render_report(run)
    assert "<h2>Shaft line</h2>" in page
    for name in ("campbell.png", "rainflow_histogram.png", "shaft_series.png", "mode_shapes.png"):
        assert f"alt='{name}'" in page, name
    assert "Q_peak [kN·m]" in page and "Miner" in page
    assert "<details><summary>Provenance of the shaft files</summary>" in page
    shutil.rmtree(run / "propeller" / "shaft")
    assert "Shaft line" not in render_report(run)
