"""The run pipeline and run directory: Python API, files, consistency, determinism."""

from __future__ import annotations

import importlib
import json
import os
import stat
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
import shapely

import floebreak
from floebreak.app import run as run_module
from floebreak.errors import InputError
from floebreak.output.field_files import load_field, save_field

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SMALL = ["field.length_m=60.0"]  # a short reference field (the full one is the CLI demo test)
PIECE_COLUMNS = {
    "geometry",
    "area_m2",
    "thickness_m",
    "volume_m3",
    "bbox_length_m",
    "bbox_width_m",
    "step",
    "bow_x_m",
    "parent_floe_id",
    "parent_piece_id",
    "failure_mode",
}
CONTACT_COLUMNS = {
    "step",
    "bow_x_m",
    "floe_id",
    "panel",
    "a_u_m2",
    "a_l_m2",
    "a_h_m2",
    "a_c_m2",
    "psi_deg",
    "f_c_n",
    "f_v_n",
    "f_h_n",
    "outcome",
}
SUMMARY_KEYS = {
    "floebreak_version",
    "profile",
    "seed",
    "scenario_hash",
    "model_hash",
    "n_floes_initial",
    "initial_ice_area_m2",
    "n_cusps",
    "cusp_area_m2",
    "mean_cusp_area_m2",
    "mean_cusp_volume_m3",
    "n_flipped",
    "flipped_area_m2",
    "remaining_ice_area_m2",
    "area_balance_rel_error",
    "n_contacts",
    "n_breaks",
    "breaks_by_mode",
    "crushing_force_max_n",
    "wall_time_s",
}


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    result = floebreak.run(overrides=SMALL)
    out = tmp_path_factory.mktemp("runs") / "small"
    result.write(out)
    return result, out


def _geometries(path: Path) -> np.ndarray:
    return shapely.from_wkb(pq.read_table(path).column("geometry").to_numpy(zero_copy_only=False))


def test_api_needs_no_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = floebreak.run(floebreak.Scenario.reference(SMALL))
    assert list(tmp_path.iterdir()) == []
    assert result.summary["n_cusps"] == len(result.cusps["geometry"]) > 0
    assert len(result.contacts["step"]) == result.summary["n_contact_records"]
    for figure in (
        result.plot_breaking_pattern(),
        result.plot_cusp_volume_spectrum(),
        result.plot_crushing_force_spectrum(),
        result.plot_field(),
    ):
        assert figure.axes


def test_run_directory_contents(small_run):
    _, out = small_run
    names = {p.name for p in out.iterdir()}
    assert names == {
        "summary.json",
        "cusps.parquet",
        "flipped.parquet",
        "remaining.parquet",
        "field.parquet",
        "contacts.parquet",
        "pieces.parquet",
        "scenario.resolved.toml",
        "figures",
        "report.html",
    }
    assert {p.name for p in (out / "figures").iterdir()} == {
        "breaking_pattern.png",
        "cusp_volume_spectrum.png",
        "crushing_force_spectrum.png",
        "field.png",
    }
    assert not list(out.parent.glob(".small.tmp-*"))  # no temporary leftovers
    summary = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= set(summary)
    assert summary["floebreak_version"] == floebreak.__version__
    assert summary["provenance"]["scenario"]["seed"] == 1


def test_run_directory_is_readable_like_any_other_files(small_run):
    # temporary files and directories are private (0600/0700); the finished run has the umask's modes
    _, out = small_run
    umask = os.umask(0)
    os.umask(umask)
    for path in [out, *out.rglob("*")]:
        expected = (0o777 if path.is_dir() else 0o666) & ~umask
        assert stat.S_IMODE(path.stat().st_mode) == expected, path


def test_parquet_files_are_geoparquet_with_provenance(small_run):
    result, out = small_run
    for name in ("cusps", "flipped", "remaining", "field"):
        table = pq.read_table(out / f"{name}.parquet")
        assert PIECE_COLUMNS <= set(table.column_names), name
        meta = table.schema.metadata
        geo = json.loads(meta[b"geo"])
        assert geo["columns"]["geometry"]["crs"] is None
        prov = json.loads(meta[b"floebreak"])
        assert prov["seed"] == 1 and prov["scenario_hash"] == result.summary["scenario_hash"]
        assert prov["scenario"]["field"]["length_m"] == 60.0
        assert "numpy" in prov["libraries"]
        assert np.all(shapely.is_valid(_geometries(out / f"{name}.parquet")))
    contacts = pq.read_table(out / "contacts.parquet")
    assert CONTACT_COLUMNS <= set(contacts.column_names)
    assert json.loads(contacts.schema.metadata[b"floebreak"])["kind"] == "contacts"
    # field.parquet is a loadable floe field (e.g. for `[field] file = ...`)
    assert load_field(out / "field.parquet").n_floes == result.summary["n_floes_initial"]


def test_summary_matches_the_parquet_files(small_run):
    _, out = small_run
    summary = json.loads((out / "summary.json").read_text())
    areas = {}
    for name in ("cusps", "flipped", "remaining", "field"):
        geometries = _geometries(out / f"{name}.parquet")
        table = pq.read_table(out / f"{name}.parquet")
        areas[name] = float(shapely.area(geometries).sum())  # independent of the stored area column
        np.testing.assert_allclose(table.column("area_m2").to_numpy(), shapely.area(geometries), rtol=1e-12)
        np.testing.assert_allclose(
            table.column("volume_m3").to_numpy(),
            shapely.area(geometries) * table.column("thickness_m").to_numpy(),
            rtol=1e-12,
        )
        if name == "cusps":
            assert table.num_rows == summary["n_cusps"]
            assert summary["mean_cusp_volume_m3"] == pytest.approx(
                table.column("volume_m3").to_numpy().mean()
            )
        if name == "flipped":
            assert table.num_rows == summary["n_flipped"]
        if name == "field":
            assert table.num_rows == summary["n_floes_initial"]
    assert areas["cusps"] == pytest.approx(summary["cusp_area_m2"], rel=1e-12)
    assert areas["flipped"] == pytest.approx(summary["flipped_area_m2"], rel=1e-12)
    assert areas["remaining"] == pytest.approx(summary["remaining_ice_area_m2"], rel=1e-12)
    assert areas["field"] == pytest.approx(summary["initial_ice_area_m2"], rel=1e-12)
    balance = abs(areas["field"] - areas["cusps"] - areas["flipped"] - areas["remaining"]) / areas["field"]
    assert balance <= 1e-9 and summary["area_balance_rel_error"] <= 1e-9
    contacts = pq.read_table(out / "contacts.parquet")
    assert contacts.num_rows == summary["n_contact_records"]
    assert summary["crushing_force_max_n"] >= contacts.column("f_c_n").to_numpy().max() > 0
    assert sum(summary["breaks_by_mode"].values()) >= summary["n_breaks"]


def test_report_is_self_contained(small_run):
    _, out = small_run
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") == 4
    assert "src='http" not in html and 'src="http' not in html
    assert "scenario_hash" in html and "2019-12-18T20:20" in html and "numpy" in html
    assert f"<code>{out.name}</code>" in html and ".tmp" not in html  # the final directory name


def test_same_scenario_and_seed_give_identical_parquet(tmp_path):
    outs = []
    for i in range(2):
        out = tmp_path / f"run{i}"
        floebreak.run(overrides=[*SMALL, "seed=4"]).write(out, figures=False, report=False)
        outs.append(out)
    for name in ("cusps", "flipped", "remaining", "field", "contacts", "pieces"):
        # byte-identical files (Table.equals would fail on the NaN bow_x_m of never-touched floes)
        assert (outs[0] / f"{name}.parquet").read_bytes() == (outs[1] / f"{name}.parquet").read_bytes(), name
        a, b = (pq.read_table(o / f"{name}.parquet") for o in outs)
        assert a.schema.metadata == b.schema.metadata and a.num_rows == b.num_rows
    other = floebreak.run(overrides=[*SMALL, "seed=5"])
    first = pq.read_table(outs[0] / "field.parquet")
    assert len(other.field.polygons) != first.num_rows or not np.array_equal(
        shapely.get_coordinates(other.field.polygons),
        shapely.get_coordinates(_geometries(outs[0] / "field.parquet")),
    )


@pytest.mark.parametrize(
    ("example", "overrides"),
    [
        ("reference.toml", SMALL),
        ("thesis_profile.toml", SMALL),
        ("polarstern.toml", ["field.length_m=120.0"]),
        ("random_thickness.toml", SMALL),
        ("single_floe.toml", []),
    ],
)
def test_each_example_runs(example, overrides):
    result = floebreak.run(EXAMPLES / example, overrides=overrides)
    s = result.summary
    assert s["area_balance_rel_error"] <= 1e-9
    assert s["n_cusps"] + s["n_flipped"] > 0
    total = s["cusp_area_m2"] + s["flipped_area_m2"] + s["remaining_ice_area_m2"]
    assert total == pytest.approx(s["initial_ice_area_m2"], rel=1e-9)
    if example == "random_thickness.toml":
        h = result.field.thickness_m
        assert h.min() >= 0.75 and h.max() <= 1.25 and h.std() > 0
    if example == "single_floe.toml":
        assert s["n_floes_initial"] == 3
        # inline floes: 64-gons inscribed in circles of 10, 20, 30 m (area (n/2π) sin(2π/n) π d²/4)
        n = 64
        expected = sum(n / 2 * np.sin(2 * np.pi / n) * (d / 2) ** 2 for d in (10.0, 20.0, 30.0))
        assert s["initial_ice_area_m2"] == pytest.approx(expected, rel=1e-12)
    if example == "polarstern.toml":
        assert s["bow"] == "polarstern"
        assert result.scenario.ice.thickness_m == pytest.approx(0.84)  # obs mean, thesis Table 1


def test_a_run_whose_pieces_degenerate_in_translation_completes():
    # found by a random sweep of scenarios: thin ice, long steps and the thesis profile's literal wedge make a
    # piece that the bow-frame translation left self-intersecting; GEOS then raised TopologyException (an
    # internal error for the user). Every piece must come out a valid polygon, the ice area conserved.
    overrides = [
        "seed=908717",
        "profile=thesis",
        "field.observation=2020-01-02T15:20",
        "field.length_m=96.6",
        "field.width_m=77.6",
        "field.generator=voronoi",
        "ice.thickness_m=0.114",
        "ice.fracture_toughness_pa_sqrt_m=440862.0",
        "ship.step_m=3.0",
        "failure.size_effect_law=BZ2",
        "failure.stress_mode=strength",
    ]
    result = floebreak.run(overrides=overrides)
    assert result.summary["area_balance_rel_error"] <= 1e-9
    assert shapely.is_valid(np.asarray(result.pieces["geometry"], dtype=object)).all()


def test_thickness_override_reaches_field_and_bow():
    result = floebreak.run(overrides=[*SMALL, "ice.thickness_m=0.8"])
    assert np.all(result.field.thickness_m == 0.8)
    # ice waterlines z_u = (1 − ρ_i/ρ_w) h, z_l = −(ρ_i/ρ_w) h: Δz = h
    bow = result.simulation.bow
    assert bow.z_upper_m - bow.z_lower_m == pytest.approx(0.8)


@pytest.mark.parametrize(
    ("overrides", "delta_z_m"),
    [
        ([], 0.4),  # default profile: the waterlines follow the ice (z_l = −ρ_i/ρ_w h)
        (["profile=thesis"], 1.0),  # thesis §3.1, Table 2: fixed for every thickness (its h = 1.0 m study)
        (["profile=thesis", "ship.waterlines=follow_thickness"], 0.4),
        (["ship.waterlines=fixed", "ship.waterline_ice_thickness_m=0.8"], 0.8),
    ],
)
def test_bow_waterlines_fixed_or_following_the_ice(overrides, delta_z_m):
    scenario = floebreak.Scenario.reference([*SMALL, "ice.thickness_m=0.4", *overrides]).resolved()
    bow = run_module.build_bow(scenario)
    assert bow.z_upper_m - bow.z_lower_m == pytest.approx(delta_z_m)


@pytest.mark.parametrize(("width_m", "warned"), [(50.0, True), (51.0, True), (52.0, False), (100.0, False)])
def test_a_field_narrower_than_beam_plus_two_largest_floes_is_named_in_the_warnings(width_m, warned):
    # Agulhas II: B = 21.7 m (thesis §3.1); the observation's largest floes: d = 15 m → B + 2 d = 51.7 m
    scenario = floebreak.Scenario.reference([*SMALL, f"field.width_m={width_m}"]).resolved()
    bow = run_module.build_bow(scenario)
    assert 2.0 * bow.half_breadth_m == pytest.approx(21.7, abs=0.05)
    warnings = run_module.set_up_warnings(scenario, bow)
    assert bool(warnings) is warned
    if warned:
        assert f"field.width_m = {width_m:g} m" in warnings[0] and "51.7 m" in warnings[0]


def test_a_narrow_field_warning_reaches_the_summary_and_a_field_file_has_none(tmp_path):
    result = floebreak.run(overrides=[*SMALL, "field.width_m=50.0"])
    assert len(result.summary["warnings"]) == 1
    save_field(result.field, tmp_path / "field.parquet")
    again = floebreak.run(overrides=[f'field.file="{tmp_path / "field.parquet"}"'])
    assert again.summary["warnings"] == []  # a given field's width is the user's, not a generation choice


def test_a_field_built_beforehand_gives_the_same_run():
    # a study builds each common field once and hands it to its runs (floebreak.studies.runner)
    scenario = floebreak.Scenario.reference([*SMALL, "seed=3"]).resolved()
    built = run_module.build_field(scenario, np.random.default_rng(scenario.seed))
    given, alone = floebreak.run(scenario, floe_field=built), floebreak.run(scenario)
    for column in ("area_m2", "bow_x_m", "step", "failure_mode"):
        assert list(given.cusps[column]) == list(alone.cusps[column]), column
    assert shapely.equals_exact(given.cusps["geometry"], alone.cusps["geometry"], tolerance=0.0).all()
    assert len(given.contacts["step"]) == len(alone.contacts["step"])
    assert run_module.field_key(scenario) == run_module.field_key(
        floebreak.Scenario.reference([*SMALL, "seed=3", "ice.fracture_toughness_pa_sqrt_m=230e3"]).resolved()
    )  # toughness does not enter the field
    assert run_module.field_key(scenario) != run_module.field_key(
        floebreak.Scenario.reference(SMALL).resolved()
    )


def test_field_file_source(small_run, tmp_path):
    base, _ = small_run
    save_field(base.field, tmp_path / "f.parquet")
    scenario = tmp_path / "s.toml"
    scenario.write_text("[field]\nfile = 'f.parquet'\n[ice]\nthickness_m = 1.0\n", encoding="utf-8")
    again = floebreak.run(scenario)
    for key in ("n_cusps", "n_flipped", "cusp_area_m2", "flipped_area_m2"):
        assert again.summary[key] == base.summary[key]


def test_run_directory_reruns_on_its_own_field(small_run):
    # the documented way to repeat a run exactly on another machine (docs/model.md §4, Reproducibility):
    # its resolved scenario with the field source replaced by its field.parquet
    base, out = small_run
    again = floebreak.run(out / "scenario.resolved.toml", overrides=['field.file="field.parquet"'])
    assert again.scenario.field.source == "file" and again.scenario.field.length_m is None
    for table in ("cusps", "flipped", "contacts"):
        for column, values in getattr(base, table).items():
            other = getattr(again, table)[column]
            if column == "geometry":
                assert shapely.equals_exact(values, other, tolerance=0.0).all(), table
            else:
                assert np.array_equal(np.asarray(values), np.asarray(other)), (table, column)


@pytest.mark.parametrize(
    ("setup", "field"),
    [
        ("missing_field", "field.file"),
        ("corrupt_field", "field.file"),
        ("missing_bow", "ship.file"),
        ("corrupt_bow", "ship.file"),
        ("overlapping_floes", "field.floes[1]"),
        ("small_field", "field.length_m"),
        ("hull_parameter", "ship.hull_parameters.beam_x"),
        ("panel_count", "ship.hull_parameters.n_panels_per_side"),
        # a bow these parameters make fails a check of its own node arrays: the parameters as a whole are
        # named (before, a key the user never wrote: ship.hull_parameters.lower_xy_m[0])
        ("crossing_waterline", "ship.hull_parameters"),
    ],
)
def test_bad_inputs_found_while_building(tmp_path, setup, field):
    (tmp_path / "corrupt.parquet").write_bytes(b"not parquet at all")
    (tmp_path / "corrupt.csv").write_text("x_m,y_m\n1,2,3\n", encoding="utf-8")
    data = {
        "missing_field": {"field": {"file": str(tmp_path / "none.parquet")}},
        "corrupt_field": {"field": {"file": str(tmp_path / "corrupt.parquet")}},
        "missing_bow": {"ship": {"file": str(tmp_path / "none.csv")}},
        "corrupt_bow": {"ship": {"file": str(tmp_path / "corrupt.csv")}},
        "overlapping_floes": {
            "field": {
                "floes": [
                    {"x_m": 10.0, "y_m": 0.0, "diameter_m": 10.0},
                    {"x_m": 15.0, "y_m": 0.0, "diameter_m": 10.0},
                ]
            },
            "ice": {"thickness_m": 1.0},
        },
        "small_field": {"field": {"length_m": 20.0, "width_m": 20.0}},
        "hull_parameter": {"ship": {"hull_parameters": {"beam_x": 3.0}}},
        "panel_count": {"ship": {"hull_parameters": {"n_panels_per_side": 1}}},
        "crossing_waterline": {
            "ice": {"thickness_m": 2.12},
            "ship": {
                "hull_parameters": {
                    "beam_m": 11.7,
                    "waterline_entrance_half_angle_deg": 86.1,
                    "stem_angle_deg": 63.1,
                }
            },
        },
    }[setup]
    with pytest.raises(InputError) as info:
        floebreak.run(data)
    assert info.value.field == field
    assert {p.name for p in tmp_path.iterdir()} == {"corrupt.csv", "corrupt.parquet"}  # nothing written


def test_existing_output_is_refused_and_overwrite_replaces(small_run, tmp_path):
    result, _ = small_run
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("x")
    with pytest.raises(InputError) as info:
        result.write(out)
    assert info.value.field == "out" and (out / "keep.txt").exists()
    result.write(out, overwrite=True, figures=False)
    assert not (out / "keep.txt").exists() and (out / "summary.json").exists()
    with pytest.raises(InputError) as info:
        result.write(tmp_path / "missing" / "out")
    assert info.value.field == "out"


def test_failed_write_leaves_nothing(small_run, tmp_path, monkeypatch):
    result, _ = small_run

    def broken(*args, **kwargs):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(importlib.import_module("floebreak.output.figure_process"), "save_png", broken)
    with pytest.raises(RuntimeError):
        result.write(tmp_path / "out")
    assert list(tmp_path.iterdir()) == []


def test_public_names_are_the_api_modules():
    # imported on first use (PEP 562); `floebreak.run` stays the function whatever else was imported
    importlib.import_module("floebreak.cli")
    assert floebreak.run is run_module.run and floebreak.Result is run_module.Result
    assert floebreak.generate_field is importlib.import_module("floebreak.ice.generation").generate_field
    assert {"run", "Result", "Scenario", "InputError"} <= set(dir(floebreak)) and set(
        floebreak.__all__
    ) <= set(dir(floebreak))
    with pytest.raises(AttributeError, match="no_such_name"):
        floebreak.no_such_name  # noqa: B018


@pytest.mark.parametrize(
    ("motion", "step_m", "warned"),
    [("dynamic", 0.25, True), ("dynamic", 0.125, True), ("dynamic", 0.0625, False), ("static", 0.25, False)],
)
def test_moving_ice_at_a_search_step_coarser_than_the_converged_one_is_named_in_the_warnings(
    motion, step_m, warned
):
    # docs/model.md, "Search-step convergence under moving ice": cusp statistics converged from 0.0625 m on
    scenario = floebreak.Scenario.reference(
        [*SMALL, f"simulation.ice_motion={motion}", f"ship.step_m={step_m}"]
    ).resolved()
    warnings = run_module.set_up_warnings(scenario, run_module.build_bow(scenario))
    assert bool(warnings) is warned
    if warned:
        assert f"ship.step_m = {step_m:g} m" in warnings[0] and "0.0625 m" in warnings[0]
