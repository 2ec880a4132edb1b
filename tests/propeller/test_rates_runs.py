"""Rates per hour and km (docs/propeller.md §6), run directories as input (transit distance, pooling
check) and the `floebreak propeller` command: hand-computed expectations."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely

from floebreak.app.inputs import shipped_fem_tables
from floebreak.app.propeller import read_runs, run_transit_distance_m
from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.io.geoparquet import write_geoparquet
from floebreak.propeller.pipeline import analyse_cusp_loads
from floebreak.propeller.rates import RateBasis, RunExposure, weighted_exceedance


def _cusps(run_ids, bow_x):
    n = len(run_ids)
    length = np.linspace(2.0, 3.5, n)
    return {
        "volume_m3": length * 1.5 * 0.8,
        "bbox_length_m": length,
        "bbox_width_m": np.full(n, 1.5),
        "thickness_m": np.ones(n),
        "area_m2": length * 1.5 * 0.8,
        "run_id": np.array(run_ids),
        "bow_x_m": np.asarray(bow_x, dtype=float),
    }


def test_weighted_exceedance_by_hand():
    # |values| 1, 2, 3, 3 with weights 0.5, 0.5, 1, 2: ≥ 0 → 4, ≥ 2 → 3.5, ≥ 3 → 3, ≥ 3.5 → 0
    got = weighted_exceedance([1.0, -2.0, 3.0, 3.0, np.nan], [0.5, 0.5, 1.0, 2.0, 9.0], [0.0, 2.0, 3.0, 3.5])
    assert got.tolist() == [4.0, 3.5, 3.0, 0.0]


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"speed_m_s": 0.0}, "ship.speed_m_s"),
        ({"speed_m_s": -3.0}, "ship.speed_m_s"),
        ({"speed_m_s": float("nan")}, "ship.speed_m_s"),
        ({"fraction_reaching": 0.0}, "propeller.fraction_reaching"),
        ({"fraction_reaching": 1.01}, "propeller.fraction_reaching"),
        ({"n_propellers": 0}, "propeller.count"),
        ({"n_propellers": 1.5}, "propeller.count"),
    ],
)
def test_rate_basis_refuses_bad_values(kwargs, field):
    with pytest.raises(InputError) as info:
        RateBasis(**kwargs)
    assert info.value.field == field


def test_rates_pool_runs_time_weighted():
    """Run a: 4 cusps in 300 m at 3 m/s (0.02778 h), all reaching, 2 propellers → 2 loads on one; run b:
    2 cusps in 600 m at 2 m/s (0.08333 h), half reaching, 1 propeller → 1 load. Pooled: 3 loads in
    0.1111 h and 0.9 km → 27 per hour and 3.333 per km on one propeller."""
    cusps = _cusps(["a", "a", "a", "a", "b", "b"], [40.0, 10.0, 30.0, 20.0, 5.0, 1.0])
    exposures = {
        "a": RunExposure(300.0, RateBasis(3.0, 1.0, 2)),
        "b": RunExposure(600.0, RateBasis(2.0, 0.5, 1)),
    }
    # fractions given: override
    result = analyse_cusp_loads(cusps, exposures=exposures, fem_tables=shipped_fem_tables())
    rates = result.summary["rates"]
    assert rates["hours_in_ice"] == pytest.approx(300 / 3 / 3600 + 600 / 2 / 3600)
    assert rates["loads_per_hour_per_propeller"] == pytest.approx(27.0)
    assert rates["loads_per_km_per_propeller"] == pytest.approx(3 / 0.9)
    ds = result.spectra
    assert ds["torque_rate_per_hour"].sum("torque_knm").values == pytest.approx([27.0, 27.0])
    assert ds["force_rate_per_km"].sum("force_kn").values == pytest.approx([3 / 0.9, 3 / 0.9])
    assert ds["torque_rate_per_hour"].attrs["units"] == "h-1"
    table = result.exceedance["torque_p95"]
    assert table["per_hour"][0] == pytest.approx(27.0) and np.all(np.diff(table["per_hour"]) <= 0)
    # per-cusp amplitudes in transit order (run, then bow position), with the loads per cusp on one propeller
    amp = result.amplitudes(95.0)
    assert amp.bow_x_m.tolist() == [10.0, 20.0, 30.0, 40.0, 1.0, 5.0]
    assert amp.weight.tolist() == [0.5] * 4 + [0.5] * 2
    assert amp.torque_nm.size == 6 and np.all(amp.torque_nm < 0)
    with pytest.raises(InputError, match="no RunExposure for run 'b'"):
        analyse_cusp_loads(cusps, exposures={"a": exposures["a"]})
    # a run without cusps still took its time: 900 m at 3 m/s more → 3 loads in (100 + 300 + 300) s
    quiet = {**exposures, "c": RunExposure(900.0, RateBasis(3.0, 1.0, 2))}
    rates = analyse_cusp_loads(cusps, exposures=quiet, fem_tables=shipped_fem_tables()).summary["rates"]
    assert rates["loads_per_hour_per_propeller"] == pytest.approx(3 / (700 / 3600))
    assert rates["loads_per_km_per_propeller"] == pytest.approx(3 / 1.8)


def _run_dir(path, scenario: Scenario, domain=(10.0, -25.0, 310.0, 25.0), n_steps=1001):
    path.mkdir(parents=True)
    cusps = _cusps(["x"] * 12, np.linspace(20.0, 200.0, 12))
    columns = {k: v for k, v in cusps.items() if k != "run_id"}
    boxes = np.array([shapely.box(0, 0, 1, 1)] * 12, dtype=object)
    write_geoparquet(path / "cusps.parquet", boxes, columns, {})
    write_geoparquet(path / "field.parquet", boxes[:1], {"floe_id": np.arange(1)}, {"domain_m": list(domain)})
    meta = {"x_start_m": 0.0, "step_m": 0.25, "n_steps": n_steps}
    write_geoparquet(path / "pieces.parquet", boxes[:1], {"piece_id": np.arange(1)}, meta)
    (path / "scenario.resolved.toml").write_text(scenario.resolved().to_toml())


def test_transit_distance_and_pooling(tmp_path):
    """Transit: stem from 0 to 0 + 1000 × 0.25 = 250 m through a field spanning x = 10 … 310 m → 240 m.
    Runs differing only in seed and field pool; a different ice thickness is refused unless pooled."""
    base = Scenario.reference()
    _run_dir(tmp_path / "s" / "r1", base)
    _run_dir(tmp_path / "s" / "r2", Scenario.reference(overrides=["seed=2", "field.length_m=300.0"]))
    assert run_transit_distance_m(tmp_path / "s" / "r1") == pytest.approx(240.0)
    inputs = read_runs(tmp_path / "s")
    assert sorted(inputs.exposures) == ["r1", "r2"] and inputs.differing_keys == ()
    assert inputs.exposures["r1"].basis == RateBasis(3.0, None, 2)  # the scenario defaults: no override
    _run_dir(
        tmp_path / "s" / "r3", Scenario.reference(overrides=["ice.thickness_m=0.4", "ship.speed_m_s=2.0"])
    )
    with pytest.raises(InputError, match=r"3 runs .* differ in ice\.thickness_m, ship\.speed_m_s.*--pool"):
        read_runs(tmp_path / "s")
    pooled = read_runs(tmp_path / "s", pool=True, fraction_reaching=0.5)
    assert pooled.differing_keys == ("ice.thickness_m", "ship.speed_m_s")
    assert pooled.exposures["r3"].basis == RateBasis(2.0, 0.5, 2)
    # a bad value written into a run's scenario file: the key and the file are named
    path = tmp_path / "s" / "r3" / "scenario.resolved.toml"
    path.write_text(path.read_text().replace("speed_m_s = 2.0", "speed_m_s = -2.0"))
    with pytest.raises(InputError, match=r"ship\.speed_m_s: .*r3/scenario\.resolved\.toml: -2 is outside"):
        read_runs(tmp_path / "s", pool=True)


FEM = (
    "volume_m3,length_m,width_m,height_m,force_kN,torque_kNm\n"
    "1,1,1,1,100,-90\n2,2,1,1,150,-140\n3,3,1,1,180,-170\n"
)


def test_propeller_command(tmp_path, cli):
    """Summary table, time base, pooling count; --fem-table PITCH=FILE; bad input → exit 2, nothing."""
    _run_dir(tmp_path / "s" / "r1", Scenario.reference())
    _run_dir(tmp_path / "s" / "r2", Scenario.reference(overrides=["seed=5"]))
    (tmp_path / "fem.csv").write_text(FEM)
    out = tmp_path / "prop"
    args = ("propeller", str(tmp_path / "s"), "--out", str(out), "--fem-table", f"0={tmp_path / 'fem.csv'}")
    args += ("--transport", "all")  # every cusp reaches (the default is the transport model)
    extra = ("--fem-table", f"50={tmp_path / 'fem.csv'}", "--sn-curve", "torque,3,100,1e6")
    extra += ("--hours-in-ice-per-year", "100", "--years", "2")
    code, stdout, err = cli(*args, *extra)
    assert code == 0, err
    assert "pooled 2 runs" in stdout and "propeller spectra" in stdout and "rule form" in stdout
    # 24 cusps / 2 propellers in 2 × 240 m at 3 m/s: 12 loads in 0.0444 h → 270 per hour, 25 per km
    assert "480 m of transit" in stdout and "270 loads per hour and 25 per km" in stdout
    summary = json.loads((out / "summary.json").read_text())
    assert sorted(summary["pitches"]) == ["p0", "p50"]
    hours = 480 / 3 / 3600
    assert summary["rates"]["loads_per_hour_per_propeller"] == pytest.approx(12 / hours)
    # Miner: every cusp counts 1/2 on one propeller, N(Q) = 10⁶ (100 kN·m / |Q|)³
    lines = [line for line in (out / "cusp_loads.csv").read_text().splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    q_knm = np.array([abs(float(row.split(",")[header.index("torque_knm_p50")])) for row in lines[1:]])
    damage = np.sum(0.5 / (1e6 * (100.0 / q_knm) ** 3))
    miner = summary["rule_form"]["p50"]["miner"]
    assert miner["damage_per_hour"] == pytest.approx(damage / hours)
    assert miner["damage_lifetime"] == pytest.approx(damage / hours * 200)
    assert "Miner sum (torque, pitch 50 %)" in stdout
    bad = [
        (["--fem-table", str(tmp_path / "fem.csv")], "pitch unknown"),  # no PITCH= and no comment line
        (
            ["--fem-table", f"0={tmp_path / 'fem.csv'}", "--fem-table", f"0={tmp_path / 'fem.csv'}"],
            "two tables",
        ),
        (["--fem-table", f"zero={tmp_path / 'fem.csv'}"], "is not a pitch"),
        (["--speed-m-s", "0"], "ship.speed_m_s"),
        (["--fraction-reaching", "1.5"], "propeller.fraction_reaching"),
        (["--years", "10"], "--hours-in-ice-per-year"),
        (["--sn-curve", "torque,5,x,1e7"], "--sn-curve"),
        (["--sn-curve", "thrust,5,1,1"], "sn_curve.quantity"),
        (["--hours-in-ice-per-year", "-1", "--years", "10"], "hours_in_ice_per_year"),
    ]
    for extra, message in bad:
        code, _, err = cli("propeller", str(tmp_path / "s"), "--out", str(tmp_path / "b"), *extra)
        assert code == 2 and message in err, (extra, err)
        assert not (tmp_path / "b").exists()
