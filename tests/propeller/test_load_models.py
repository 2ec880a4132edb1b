"""The load model and the transport in the propeller analysis: profile defaults,
the fraction-reaching override, bad input, and the out-of-range warnings' thresholds by hand."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from floebreak.app.inputs import shipped_fem_tables
from floebreak.config.analysis import propeller_defaults
from floebreak.errors import InputError
from floebreak.propeller.load_models import (
    drive_rated_torque_n_m,
    extrapolation_warnings,
    force_warnings,
    torque_warnings,
)
from floebreak.propeller.loads.milling import BladeGeometry, IceBlock, impact_loads
from floebreak.propeller.pipeline import analyse_cusp_loads
from floebreak.propeller.rates import RateBasis, RunExposure
from floebreak.propeller.spec import PropellerSpec
from floebreak.propeller.transport import TransportParameters


def _cusps():
    """Three 2 m × 2 m × 1 m cusps made at the stem (centroid at the bow's x): on the port shaft line
    (y = 5.5 m), on the centre line (y = 0, between the discs) and on the bilge (y = 9 m > B/2 − r_bilge =
    8.35 m). The first rises at w = √(2 g h Δρ / (ρ_w C_D)) ≈ 1.33 m/s for 15 m / 3 m/s = 5 s, i.e. to the
    hull above the disc (z = 5.25 − 2.15 − 0.86 = 2.24 m): its cross-section [4.5, 6.5] × [2.24, 3.24] m
    lies 2.01 m < R = 2.15 m from the shaft axis (5.5, 5.25) and reaches. The second lies 4.5 m aside of
    either axis (> R): it misses both."""
    return {
        "volume_m3": np.full(3, 4.0),
        "bbox_length_m": np.full(3, 2.0),
        "bbox_width_m": np.full(3, 2.0),
        "thickness_m": np.ones(3),
        "area_m2": np.full(3, 4.0),
        "bow_x_m": np.array([10.0, 20.0, 30.0]),
        "centroid_x_m": np.array([10.0, 20.0, 30.0]),
        "centroid_y_m": np.array([5.5, 0.0, 9.0]),
        "run_id": np.array(["r"] * 3),
    }


EXPOSURE = {"r": RunExposure(300.0, RateBasis(3.0, None, 2))}  # 300 m at 3 m/s = 1/36 h
KINEMATIC_NEVER = {"surfaced": 0, "stalled": 0}  # paths only the flow transport gives


def test_transport_decides_which_cusps_load_and_count():
    result = analyse_cusp_loads(_cusps(), exposures=EXPOSURE, transport="hull")
    transport = result.summary["transport"]
    assert transport["rule"] == "hull" and transport["n_reaching"] == 1
    assert transport["paths"] == {"propeller": 1, "shoulder": 0, "bilge": 1, "missed": 1} | KINEMATIC_NEVER
    assert transport["fraction_reaching_per_propeller"] == pytest.approx([1 / 3, 0.0])
    # one load, shared by 2 propellers, in 1/36 h: 18 per hour and 1/0.3 km / 2 per km on one propeller
    assert result.summary["rates"]["loads_per_hour_per_propeller"] == pytest.approx(18.0)
    assert result.summary["rates"]["per_run"]["r"]["fraction_reaching"] == pytest.approx(1 / 3)
    amp = result.amplitudes(95.8551)
    assert np.isfinite(amp.torque_nm).tolist() == [True, False, False] and amp.weight.tolist() == [0.5, 0, 0]
    assert int(result.spectra["n_loads"].sum()) == 2  # one cusp, two pitches
    # the milling model at the spec's pitch, rpm and the ship speed, on the cusp's box (wiring check),
    # engaged straight up from the cross-section's lower face, 5.25 − 3.24 = 2.01 m above the axis, to the
    # tip (a slanted blade meets that face farther out: shorter)
    spec = PropellerSpec()
    blade = BladeGeometry.from_spec(spec)
    assert result.loads["engaged_inner_radius_m"][0] == pytest.approx(2.01)
    assert result.loads["engaged_outer_radius_m"][0] == pytest.approx(2.15)
    assert np.isnan(result.loads["engaged_inner_radius_m"][1:]).all()
    expected = impact_loads(IceBlock.from_box(2.0, 2.0, 1.0, 2.01, 2.15), blade, 140.0, 3.0)
    assert amp.torque_nm[0] == pytest.approx(-expected.torque_n_m[0])
    tip = impact_loads(IceBlock.from_box(2.0, 2.0, 1.0), blade, 140.0, 3.0)
    assert abs(amp.torque_nm[0]) < 0.5 * tip.torque_n_m[0]  # 0.14 m of blade instead of 1 m
    assert result.summary["load_model"]["name"] == "milling"
    assert result.summary["load_model"]["placement"] == "engaged interval from the transport"
    assert result.summary["options"]["pitches"] == [0.0, 95.8551]


def test_the_transport_discs_take_the_spec_radius():
    """A 5 m propeller (R = 2.5 m): its disc's bottom stays 0.25 m above the base line, so the shaft lies at
    z_s = 7.65 − 2.5 − 0.25 = 4.9 m and the hull 0.86 m above the disc at 4.9 − 2.5 − 0.86 = 1.54 m. The
    port cusp rises to that hull: cross-section [4.5, 6.5] × [1.54, 2.54] m, its lower face 4.9 − 2.54 =
    2.36 m above the axis (5.5, 4.9): engaged [2.36, 2.5] m. On the 4.3 m disc's axis (5.5, 5.25) the same
    blade would reach [2.01, 2.5] m, 0.35 m into the hull above it."""
    spec = replace(PropellerSpec(), radius_m=2.5)
    result = analyse_cusp_loads(_cusps(), exposures=EXPOSURE, propeller=spec, transport="hull")
    assert result.summary["transport"]["n_reaching"] == 1
    assert result.loads["engaged_inner_radius_m"][0] == pytest.approx(2.36)
    assert result.loads["engaged_outer_radius_m"][0] == pytest.approx(2.5)


def test_fraction_reaching_override_warns_and_loads_every_cusp():
    override = {"r": RunExposure(300.0, RateBasis(3.0, 0.5, 2))}
    result = analyse_cusp_loads(_cusps(), exposures=override)
    assert result.summary["transport"]["rule"] == "override"
    # 3 cusps × 0.5 / 2 propellers in 1/36 h = 27 per hour
    assert result.summary["rates"]["loads_per_hour_per_propeller"] == pytest.approx(27.0)
    assert any("is an override" in w for w in result.summary["warnings"])
    # no cusp geometry at the disc: tip placement, said so
    assert result.summary["load_model"]["placement"].startswith("tip placement (no cusp geometry")
    assert np.isnan(result.loads["engaged_inner_radius_m"]).all()
    tip = impact_loads(IceBlock.from_box(2.0, 2.0, 1.0), BladeGeometry.from_spec(PropellerSpec()), 140.0, 3.0)
    assert result.amplitudes(95.8551).torque_nm[0] == -tip.torque_n_m[0]
    # no override: no such warning; every cusp with transport "all" (the thesis rule)
    everyone = analyse_cusp_loads(
        _cusps(), exposures=EXPOSURE, transport="all", fem_tables=shipped_fem_tables()
    )
    assert not any("override" in w for w in everyone.summary["warnings"])
    assert everyone.summary["rates"]["loads_per_hour_per_propeller"] == pytest.approx(3 / 2 * 36)


def test_fem_tables_take_precedence_and_bad_choices():
    result = analyse_cusp_loads(_cusps(), fem_tables=shipped_fem_tables(), load_model="milling")
    assert result.summary["load_model"]["name"] == "fem" and result.pitches == (0.0, 95.0)
    assert "placement" not in result.summary["load_model"]
    assert "engaged_inner_radius_m" not in result.loads
    for key, kwargs in (("load_model", {"load_model": "x"}), ("transport", {"transport": "x"})):
        with pytest.raises(InputError) as info:
            analyse_cusp_loads(_cusps(), **kwargs)
        assert info.value.field == key
    no_centroids = {k: v for k, v in _cusps().items() if not k.startswith("centroid")}
    for transport in ("hull", "flow"):
        with pytest.raises(InputError, match="centroid_x_m, centroid_y_m"):
            analyse_cusp_loads(no_centroids, transport=transport)
    assert propeller_defaults("thesis") == ("fem", "all")
    assert propeller_defaults("default") == ("milling", "flow")


def test_rated_torque_and_torque_warnings_by_hand():
    # 4.5 MW at 140 rpm: 4.5e6 / (2π · 140/60) = 306 941 N·m
    rated = drive_rated_torque_n_m(PropellerSpec())
    assert rated == pytest.approx(4.5e6 / (2 * math.pi * 140 / 60)) and rated == pytest.approx(306_941, abs=1)
    info = {"p95": {"pitch_percent": 95.0, "torque_range_knm": [10.0, 614.0]}}
    assert len(torque_warnings(info, rated, None)) == 1  # 614 > 2 × 306.94 = 613.88 kN·m
    info["p95"]["torque_range_knm"][1] = 613.0
    assert torque_warnings(info, rated, None) == []
    assert len(torque_warnings(info, rated, 612.0e3)) == 1  # above Q_max = 612 kN·m
    assert torque_warnings(info, rated, 614.0e3) == []
    with pytest.raises(InputError, match="rated_torque_n_m"):
        drive_rated_torque_n_m(PropellerSpec(), 0.0)


# PC5 backward force by hand (UR I3 as the module writes it, D > 0.85 H_ice^1.4 = 2.24 m): 23 S_ice (nD)^0.7
# (EAR/Z)^0.3 D H_ice^1.4 = 23 · 1.1 · (140/60 · 4.3)^0.7 · (0.55/4)^0.3 · 4.3 · 2^1.4 = 795.4 kN
PC5_BACKWARD_FORCE_N = 23 * 1.1 * (140 / 60 * 4.3) ** 0.7 * (0.55 / 4) ** 0.3 * 4.3 * 2**1.4 * 1e3


def test_force_warnings_thresholds_by_hand():
    assert PC5_BACKWARD_FORCE_N == pytest.approx(795.4e3, abs=100)
    info = {"p0": {"pitch_percent": 0.0, "force_range_kn": [20.0, 1490.0]}, "p95": {"pitch_percent": 95.0}}
    warnings = force_warnings(info, 795.4e3, 1600.0e3)  # 1 490 kN: above F_b, below F_f
    assert len(warnings) == 1
    assert "pitch 0 %" in warnings[0] and "1490 kN" in warnings[0] and "F_b (795 kN)" in warnings[0]
    assert len(force_warnings(info, 795.4e3, 1400.0e3)) == 2  # above F_f too
    info["p0"]["force_range_kn"][1] = 795.0
    assert force_warnings(info, 795.4e3, 1600.0e3) == []


# PC7 backward force at 60 rpm by hand (D > 0.85 · 1.5^1.4 = 1.50 m):
# 23 · 1.0 · (60/60 · 4.3)^0.7 · (0.55/4)^0.3 · 4.3 · 1.5^1.4 = 267.1 kN
PC7_BACKWARD_FORCE_60_RPM_N = 23 * 1.0 * 4.3**0.7 * (0.55 / 4) ** 0.3 * 4.3 * 1.5**1.4 * 1e3


def test_blade_force_above_the_rule_warns_in_the_summary():
    # a 2 m × 2 m × 1 m block at 0 % pitch and 60 rpm (`impact_loads`) against PC7's F_b (by hand, above);
    # at 140 rpm and PC5 the flank contact capped at 0.2 c keeps the force (319 kN) below F_b (795 kN)
    assert PC7_BACKWARD_FORCE_60_RPM_N == pytest.approx(267.1e3, abs=100)
    spec = PropellerSpec(rpm=60.0)
    blade = BladeGeometry.from_spec(replace(spec, pitch_percent=0.0))
    block = IceBlock(np.ones(1), np.full(1, 2.0), np.full(1, 2.0))
    force_n = float(impact_loads(block, blade, 60.0, 3.0).force_n[0])
    # transport "all": every cusp at the tip (tip placement), the block above
    result = analyse_cusp_loads(_cusps(), polar_class="PC7", propeller=spec, transport="all")
    warned = [w for w in result.summary["warnings"] if w.startswith("pitch 0 %") and "F_b" in w]
    assert force_n > PC7_BACKWARD_FORCE_60_RPM_N and len(warned) == 1
    assert f"{force_n / 1e3:.0f} kN" in warned[0]
    unclassed = analyse_cusp_loads(_cusps(), propeller=spec).summary["warnings"]
    assert not [w for w in unclassed if "F_b" in w]  # no polar class: no rule check


def test_extrapolation_warning_threshold_by_hand():
    entry = {"validity_range": [100.0, 200.0], "x_max_per_hour": 301.0}  # 1.505 × the largest load
    rule_form = {"rule_n_ice": None, "p95": {"torque_knm": entry, "force_kn": {"fit": None}}}
    assert len(extrapolation_warnings(rule_form)) == 1
    entry["x_max_per_hour"] = 299.0
    assert extrapolation_warnings(rule_form) == []
    entry["x_max_lifetime"] = 350.0
    (warning,) = extrapolation_warnings(rule_form)
    assert "x_max_lifetime" in warning and "1.8 ×" in warning and "100–200" in warning


def test_transport_parameters_out_of_range():
    with pytest.raises(InputError) as info:
        TransportParameters(slip_factor=0.0)
    assert info.value.field == "transport.slip_factor"


@pytest.mark.parametrize(
    ("args", "key"),
    [
        (("--load-model", "cfd"), "--load-model"),
        (("--transport", "sideways"), "--transport"),
        (("--rated-torque-knm", "0"), "--rated-torque-knm"),
        (("--polar-class", "PC9"), "polar_class"),
        (("--propeller-geometry", "radius_m=0"), "propeller.radius_m"),  # D ≤ 0
        (("--propeller-geometry", "radius_m=3.3"), "propeller.radius_m"),  # disc + clearance > draught
        (("--propeller-geometry", "blades=1"), "propeller.blades"),  # Z < 2
        (("--propeller-geometry", "hub_ratio=1"), "propeller.hub_ratio"),
        (("--propeller-geometry", "max_pitch_m=0"), "propeller.max_pitch_m"),  # P/D ≤ 0
        (("--propeller-geometry", "expanded_area_ratio=0"), "propeller.expanded_area_ratio"),
        (("--propeller-geometry", "diameter=4"), "--propeller-geometry"),
    ],
)
def test_bad_input_exits_2_and_writes_nothing(tmp_path, cli, args, key):
    run = tmp_path / "run"
    run.mkdir()
    pq.write_table(pa.table({k: v for k, v in _cusps().items() if k != "run_id"}), run / "cusps.parquet")
    code, _, err = cli("propeller", run, "--out", tmp_path / "p", *args)
    assert code == 2 and key in err
    assert not (tmp_path / "p").exists()


@pytest.mark.parametrize(
    ("profile", "model", "rule"), [("default", "milling", "flow"), ("thesis", "fem", "all")]
)
def test_scenario_profile_chooses_the_path(tmp_path, cli, profile, model, rule):
    """A tiny reference run (60 m of field) per profile: the demo's propeller analysis follows it."""
    out = tmp_path / "demo"
    code, stdout, err = cli(
        "demo", "--out", out, "--set", "field.length_m=60.0", "--set", f'profile="{profile}"'
    )
    assert code == 0, err
    summary = json.loads((out / "propeller" / "summary.json").read_text())
    assert summary["load_model"]["name"] == model and summary["transport"]["rule"] == rule
    assert f"{model} model" in stdout
    n = summary["n_cusps"]
    reaching = summary["transport"].get("n_reaching", n)
    assert (reaching == n) is (rule == "all")
    assert not any("override" in w for w in summary["warnings"])
    # an explicit fraction on the command line is an override, said so in the terminal and the summary
    code, _, err = cli("propeller", out, "--out", tmp_path / "p", "--fraction-reaching", "0.5")
    assert code == 0, err
    assert "is an override" in err
    summary = json.loads((tmp_path / "p" / "summary.json").read_text())
    assert summary["transport"]["rule"] == "override"
