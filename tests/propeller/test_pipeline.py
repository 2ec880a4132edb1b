"""propeller_analysis end to end: files, numbers traceable to the tables, atomic refusal of bad input."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
import shapely
import xarray as xr

from floebreak.app.inputs import shipped_fem_tables, synthetic_torque_path
from floebreak.app.propeller import propeller_analysis
from floebreak.errors import InputError
from floebreak.io.geoparquet import write_geoparquet
from floebreak.propeller.pipeline import load_spectra, torque_ranges_above


def _cusps():
    # two runs; box volumes (l·w·h) include the four thesis cuboids and one beyond the table (15 m³)
    length = np.array([3.7073, 6.5232, 9.4535, 12.5043, 15.0, 2.0, 3.0, 1.0])
    width = np.ones(8)
    thickness = np.ones(8)
    area = 0.8 * length * width
    return {
        "volume_m3": area * thickness,
        "bbox_length_m": length,
        "bbox_width_m": width,
        "thickness_m": thickness,
        "area_m2": area,
        "run_id": np.array(["r1"] * 5 + ["r2"] * 3),
    }


# the thesis' path (FEM tables, every cusp reaches); the default is the milling model and the transport
THESIS_PATH = {"load_model": "fem", "transport": "all"}


def _rows(path):
    with open(path) as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def test_outputs_and_numbers(tmp_path):
    out = propeller_analysis(
        _cusps(),
        tmp_path / "prop",
        torque_csv=synthetic_torque_path(),
        polar_class="PC5",
        volume_basis="box",
        **THESIS_PATH,
    )
    summary = json.loads((out / "summary.json").read_text())
    for name in (
        "cusp_loads.csv",
        "volume_classes.csv",
        "spectra.nc",
        "load_spectrum.csv",
        "torque_spectrum.csv",
        "measured_torque_spectrum.csv",
        "figures/load_spectrum_log.png",
        "figures/torque_spectrum_linear.png",
        "figures/torque_comparison_log.png",
        "figures/torque_comparison_linear.png",
        "figures/ice_class_exceedance.png",
        "figures/volume_loads.png",
    ):
        assert (out / name).is_file(), name
    assert summary["propeller"]["pitch_angle_07R_deg"] == pytest.approx(27.57, abs=0.005)
    assert summary["propeller"]["pitch_angle_thesis_deg"] == pytest.approx(20.07, abs=0.005)
    rows = _rows(out / "cusp_loads.csv")
    assert len(rows) == 8
    # the thesis cuboids get the table values exactly (Table 10 / 11)
    assert float(rows[0]["force_kn_p0"]) == pytest.approx(240.55, rel=1e-9)
    assert float(rows[3]["torque_knm_p95"]) == pytest.approx(-1658.78, rel=1e-9)
    # beyond the table (15 m³ > 12.5043 m³): the power law through Table 11's three largest points,
    # anchored at the last, b = Σ a c / Σ a² with a = ln(V/V_max), c = ln(F/F_max), and reported
    a = np.log(np.array([6.5232, 9.4535]) / 12.5043)
    c = np.log(np.array([1058.27, 1434.74]) / 1686.20)
    b = np.sum(a * c) / np.sum(a * a)
    assert rows[4]["beyond_table_p95"] == "true" and rows[3]["beyond_table_p95"] == "false"
    assert float(rows[4]["force_kn_p95"]) == pytest.approx(1686.20 * (15.0 / 12.5043) ** b)
    assert summary["pitches"]["p95"]["n_beyond_table"] == 1
    # kinetic energy uses the cusp's own volume (0.8 of the box here): ½·917·V·3²
    assert float(rows[0]["kinetic_energy_kj"]) == pytest.approx(0.5 * 917 * 0.8 * 3.7073 * 9 / 1e3)
    # PC5 maximum torque (≈ 0.86 MN m with the default assumptions) is exceeded by the 95 % cusps ≥ 3.7 m³
    q_max_knm = summary["ice_class"]["max_torque_nm"] / 1e3
    assert 700 < q_max_knm < 1050
    flagged = [r["exceeds_max_torque_p95"] == "true" for r in rows]
    assert flagged == [abs(float(r["torque_knm_p95"])) > q_max_knm for r in rows]
    assert summary["pitches"]["p0"]["rule_exceedances"]["exceeds_max_torque"] == 0
    # measured synthetic series: the bulk lies around 105 kN m
    low, high = summary["measured_torque"]["envelope_above_threshold_knm"]
    assert 40 <= low <= 80 and 130 <= high <= 200


def test_spectra_netcdf_is_the_run_average(tmp_path):
    cusps = _cusps()
    out = propeller_analysis(cusps, tmp_path / "prop", force_bin_kn=50.0, torque_bin_knm=50.0, **THESIS_PATH)
    ds = xr.open_dataset(out / "spectra.nc")
    assert ds["pitch"].values.tolist() == [0.0, 95.0]
    assert ds["torque_density"].attrs["units"] == "kN-1 m-1"
    assert "floebreak_version" in ds.attrs["provenance"]
    # CF-1.8: force and torque have their own bin axes with bounds; every numeric variable has units
    assert ds.attrs["Conventions"] == "CF-1.8"
    assert ds["force_density"].dims == ("pitch", "force_kn") and ds["torque_density"].dims[1] == "torque_knm"
    assert ds["force_kn"].attrs["bounds"] == "force_kn_bounds"
    bounds = {v.attrs["bounds"] for v in ds.coords.values() if "bounds" in v.attrs}  # CF §7.1: inherit units
    for name, variable in {**ds.data_vars, **ds.coords}.items():
        if variable.dtype.kind in "fiu" and name not in bounds:
            assert "units" in variable.attrs, name
    rows = _rows(out / "cusp_loads.csv")
    width = 50.0
    bounds = ds["force_kn_bounds"].values
    edges = [*bounds[:, 0], bounds[-1, 1]]
    for pitch, label in ((0.0, "p0"), (95.0, "p95")):
        per_run = []
        for run in ("r1", "r2"):
            f = np.abs([float(r[f"force_kn_{label}"]) for r in rows if r["run_id"] == run])
            counts, _ = np.histogram(f, bins=edges)
            per_run.append(counts / (counts.sum() * width))
        expected = np.mean(per_run, axis=0)
        got = ds["force_density"].sel(pitch=pitch).values
        assert got == pytest.approx(expected)
        assert np.sum(got) * width == pytest.approx(1.0)
    ds.close()


def test_study_directory_and_options(tmp_path):
    cusps = _cusps()
    study = tmp_path / "study"
    for run in ("r1", "r2"):
        m = cusps["run_id"] == run
        columns = {k: v[m] for k, v in cusps.items() if k != "run_id"}
        (study / f"run_{run}").mkdir(parents=True)
        write_geoparquet(
            study / f"run_{run}" / "cusps.parquet",
            np.array([shapely.box(0, 0, 1, 1)] * int(m.sum()), dtype=object),
            columns,
            {},
        )
    # runs without a scenario cannot be shown to describe the same conditions: pooled only on request
    with pytest.raises(InputError, match=r"2 runs below .* differ in scenario\.resolved\.toml.*--pool"):
        propeller_analysis(study, tmp_path / "a")
    assert not (tmp_path / "a").exists()
    out = propeller_analysis(
        study,
        tmp_path / "a",
        interpolation="pchip",
        beyond="flag",
        pool=True,
        volume_basis="box",
        **THESIS_PATH,
    )
    rows = _rows(out / "cusp_loads.csv")
    assert [r["run_id"] for r in rows] == ["run_r1"] * 5 + ["run_r2"] * 3
    assert rows[4]["force_kn_p0"] == ""  # box volume 15 m³ > 12.5 m³: flagged, no load claimed
    assert float(rows[3]["force_kn_p0"]) == pytest.approx(362.60)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["options"]["interpolation"] == "pchip" and summary["n_runs"] == 2
    assert summary["pitches"]["p0"]["n_without_load"] == 1
    # the cusp's own volume (0.8 of the box, 12 m³) lies inside the table
    out = propeller_analysis(cusps, tmp_path / "b", beyond="flag", **THESIS_PATH)  # default: own volume
    assert _rows(out / "cusp_loads.csv")[4]["force_kn_p0"] != ""
    classes = _rows(out / "volume_classes.csv")
    assert [r["run_id"] for r in classes] == ["r1"] * 4 + ["r2"] * 4 + ["ALL"] * 4
    # box volumes 3.7, 6.5, 9.5, 12.5, 15 | 2, 3, 1 → classes (0,5]: 4 cusps, (5,8]: 1, (8,11]: 1, (11,14]: 1
    assert [int(r["n_cusps"]) for r in classes[-4:]] == [4, 1, 1, 1]
    assert float(classes[-4]["mean_box_volume_m3"]) == pytest.approx((3.7073 + 2 + 3 + 1) / 4)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"polar_class": "PC9"}, "polar_class"),
        ({"interpolation": "spline"}, "interpolation"),
        ({"beyond": "wrap"}, "beyond"),
        ({"torque_csv": "MISSING"}, "torque_csv"),
        ({"fem_table": "MISSING"}, "fem_table"),
        ({"volume_basis": "hull"}, "volume_basis"),
    ],
)
def test_bad_input_writes_nothing(tmp_path, kwargs, field):
    if kwargs.get("torque_csv") == "MISSING":
        kwargs = {"torque_csv": tmp_path / "missing.csv"}
    if kwargs.get("fem_table") == "MISSING":
        bad = tmp_path / "bad.csv"
        bad.write_text(
            "# pitch_percent: 5\nvolume_m3,length_m,width_m,height_m,force_kN,torque_kNm\n2,1,1,1,1,1\n"
            "1,1,1,1,1,1\n"
        )
        kwargs = {"fem_table": bad}
    with pytest.raises(InputError) as info:
        propeller_analysis(_cusps(), tmp_path / "out", **kwargs)
    assert info.value.field == field
    assert not (tmp_path / "out").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out")]


def test_existing_output_needs_overwrite(tmp_path):
    propeller_analysis(_cusps(), tmp_path / "out", **THESIS_PATH)
    with pytest.raises(InputError, match="exists"):
        propeller_analysis(_cusps(), tmp_path / "out", **THESIS_PATH)
    propeller_analysis(_cusps(), tmp_path / "out", overwrite=True, **THESIS_PATH)


def test_no_cusps(tmp_path):
    empty = {k: np.zeros(0) for k in ("volume_m3", "bbox_length_m", "bbox_width_m", "thickness_m", "area_m2")}
    out = propeller_analysis(empty, tmp_path / "out")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["n_cusps"] == 0


def test_load_spectra_weights_runs_equally_and_ranges_above():
    """|Q| = 5, 15 kN·m in run a and 15 kN·m in run b on 10 kN·m bins: run a has 0.05/kN·m in both bins,
    run b 0.1/kN·m in the second; the mean of the runs is 0.025 and 0.075/kN·m (pooling would give
    1/30 and 2/30)."""
    tables = shipped_fem_tables()
    torque = np.array([-5e3, -15e3, -15e3])
    loads = {"run_id": np.array(["a", "a", "b"], dtype=object)}
    for pitch in tables:
        loads[f"force_n_p{pitch:g}"] = -torque
        loads[f"torque_nm_p{pitch:g}"] = torque
    ds = load_spectra(loads, tables, 10.0, 10.0)
    assert ds["torque_density"].sel(pitch=0.0).values[:2] == pytest.approx([0.025, 0.075])
    assert ds["force_density"].sel(pitch=95.0).values[:2] == pytest.approx([0.025, 0.075])
    assert ds["n_loads"].sel(run="a").values.tolist() == [2, 2]
    assert torque_ranges_above(ds, 0.03) == {
        "p0": {"intervals_knm": [(10.0, 20.0)], "envelope_knm": (10.0, 20.0)},
        "p95": {"intervals_knm": [(10.0, 20.0)], "envelope_knm": (10.0, 20.0)},
    }
    assert torque_ranges_above(ds, 0.01)["p0"]["envelope_knm"] == (0.0, 20.0)


def test_far_loads_widen_the_bins_instead_of_making_millions():
    """An extrapolated quartic gave |Q| ≈ 5·10⁶ kN·m for thick ice: 10 kN·m bins would be 5·10⁵ bins (it
    took minutes and 0.9 GB). The bins widen by 1-2-5 steps until 2 000 cover the loads: 5·10⁶ / 2 000 =
    2 500 kN·m → 5 000 kN·m bins; loads within 20 000 kN·m keep the 10 kN·m bins."""
    from floebreak.propeller.spectra import MAX_BINS, fitting_width

    assert MAX_BINS == 2_000
    assert [fitting_width(np.array([top]), 10.0) for top in (5.0, 20_000.0, 20_001.0, 45_000.0, 5e6)] == [
        10.0,
        10.0,
        20.0,
        50.0,
        5_000.0,
    ]
    tables = shipped_fem_tables()
    torque = np.array([-5e3, -15e3, -5e9])  # N·m
    loads = {"run_id": np.array(["a", "a", "a"], dtype=object)}
    for pitch in tables:
        loads[f"force_n_p{pitch:g}"] = -torque / 10.0
        loads[f"torque_nm_p{pitch:g}"] = torque
    ds = load_spectra(loads, tables, 10.0, 10.0)
    assert ds.sizes["torque_knm"] <= MAX_BINS and ds.sizes["force_kn"] <= MAX_BINS
    assert ds.attrs["torque_bin_width_knm"] == 5_000.0 and ds.attrs["force_bin_width_kn"] == 500.0
    # densities stay per kN·m: the two small loads share the first bin, 2/3 of the runs' loads
    assert ds["torque_density"].sel(pitch=0.0).values[0] == pytest.approx(2 / 3 / 5_000.0)


def test_report_section_without_time_base(tmp_path):
    """A table of cusps has no transit distance: densities only, said so in the summary and the report."""
    from floebreak.output.report import propeller_section

    out = propeller_analysis(_cusps(), tmp_path / "prop", **THESIS_PATH)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["rates"] is None and not (out / "torque_exceedance.csv").exists()
    html = "\n".join(propeller_section(out))
    assert "No time base" in html and "rule_form.png" in html
    assert propeller_section(tmp_path / "nothing") == []
