"""The shaft analysis's drive model uses the transport settings of the propeller analysis
(`--transport-parameter`, `milled_cusps(transport_settings=)`)."""

import json
import math

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from floebreak.propeller.transport import transport_settings
from floebreak.shaft.analysis import milled_cusps

# four stem cusps to port: two on the port shaft's line (y = 5.5 m), two further inboard (3.5 m, 4.5 m)
Y_M = np.array([5.5, 3.5, 4.5, 5.5])
LENGTH_M = np.array([3.0, 4.0, 5.0, 6.0])
# hull.bilge_radius_m = 6 m: the flat bottom's half-width is B/2 − r_bilge = 21.7/2 − 6 = 4.85 m, so the
# cusps beyond it (y = 5.5 m) lie on the bilge and rise beside the hull (docs/model.md, transport step 3)
BILGE = {"hull.bilge_radius_m": 6.0}
INBOARD = np.abs(Y_M) <= 21.7 / 2 - 6.0


def _columns():
    n = Y_M.size
    bow_x = 5.0 * np.arange(n) + 1.0
    return {
        "bow_x_m": bow_x,
        "step": np.arange(n),
        "bbox_length_m": LENGTH_M,
        "bbox_width_m": np.ones(n),
        "thickness_m": np.full(n, 0.4),
        "volume_m3": 0.32 * LENGTH_M,
        "centroid_x_m": bow_x - 2.0,  # 2 m aft of the stem: stem region
        "centroid_y_m": Y_M,
        "area_m2": 0.8 * LENGTH_M,
    }


def test_transport_settings_choose_the_milled_cusps():
    default = milled_cusps(_columns(), speed_m_s=3.0)
    assert default.arrival_s.size == Y_M.size  # all four reach the port disc by default
    wide_bilge = milled_cusps(_columns(), speed_m_s=3.0, transport_settings=transport_settings(BILGE))
    assert wide_bilge.arrival_s.size == int(INBOARD.sum()) == 2
    # the milled blocks are the inboard cusps' (box sides: length × 1 m)
    sides = np.maximum(wide_bilge.block.length_m, wide_bilge.block.width_m)
    assert sorted(sides) == sorted(LENGTH_M[INBOARD])
    assert wide_bilge.counts["bilge"] == int((~INBOARD).sum())
    assert wide_bilge.counts["settings"]["hull.bilge_radius_m"] == 6.0


def _run(path):
    path.mkdir()
    pq.write_table(pa.table(_columns()), path / "cusps.parquet")
    (path / "scenario.resolved.toml").write_text('profile = "default"\n', encoding="utf-8")
    return path


def test_transport_parameter_reaches_the_shaft_run(tmp_path, cli):
    run = _run(tmp_path / "run")
    summaries = {}
    # the kinematic transport (`--transport hull`, for the drive model too): the bilge geometry above
    for name, extra in (("default", []), ("bilge", ["--transport-parameter", "hull.bilge_radius_m=6"])):
        out = tmp_path / name
        code, _, err = cli(
            "propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--speed-m-s", "3",
            "--transport", "hull", *extra,
        )  # fmt: skip
        assert code == 0, err
        summaries[name] = json.loads((out / "shaft" / "summary.json").read_text())
    assert summaries["default"]["transport"]["reaching_port"] == Y_M.size
    assert summaries["bilge"]["transport"]["reaching_port"] == int(INBOARD.sum())
    assert summaries["bilge"]["transport"]["settings"]["hull.bilge_radius_m"] == 6.0
    assert summaries["default"]["transport"]["rule"] == "hull"
    impacts = [summaries[n]["drive"]["cases"]["1"]["impacts"] for n in ("default", "bilge")]
    assert impacts[1] < impacts[0]  # fewer cusps milled, fewer blade impacts


def test_voyage_shaft_run_uses_the_voyage_transport(tmp_path):
    from floebreak.studies.voyage_shaft import run_shaft

    run = _run(tmp_path / "run")
    (run / "scenario.resolved.toml").write_text(
        'profile = "default"\n[ship]\nspeed_m_s = 3.0\n', encoding="utf-8"
    )
    default = run_shaft(run, "agulhas_ii")
    wide_bilge = run_shaft(run, "agulhas_ii", BILGE)
    # two of four cusps milled: the ice torque ends sooner, the series is shorter
    assert wide_bilge.duration_s < default.duration_s


def test_milled_blocks_lie_on_the_engaged_interval_of_their_cross_section():
    # a 0.4 m cusp rises w = √(2 g h Δρ / (ρ_w C_D)) for 15 m / 3 m/s: its top face at 7.65 − 5 w, i.e.
    # 1.80 m above the shaft axis (5.25 m), its lower face 1.40 m; the first cusp (on the shaft line, area
    # 2.4 m²) spans y ∈ ±√2.4 / 2. The blade through the upper corner is the longest chord (steeper: shorter
    # by 0.4/cos θ; flatter: it leaves through the side): from the lower face at 1.40/cos θ to the corner
    w = math.sqrt(2 * 9.81 * 0.4 * (1025.0 - 917.0) / (1025.0 * 1.17))
    top = 5.25 - (7.65 - w * 15.0 / 3.0)
    half = math.sqrt(2.4) / 2.0
    corner = math.hypot(half, top)
    expected = ((top - 0.4) * corner / top, corner)
    engaged = milled_cusps(_columns(), speed_m_s=3.0)
    got = (engaged.block.inner_radius_m[0], engaged.block.outer_radius_m[0])
    assert got == pytest.approx(expected, abs=1e-9)
    assert engaged.counts["placement"] == "engaged interval from the transport"
    assert engaged.counts["engaged_zero_length"] == 0
    tip = milled_cusps(_columns(), speed_m_s=3.0, engaged=False)
    assert np.isnan(tip.block.inner_radius_m).all() and tip.counts["placement"] == "tip placement"
    assert engaged.impact_torque_n_m(0, 140.0) != tip.impact_torque_n_m(0, 140.0)


def test_drive_model_follows_the_default_flow_transport(tmp_path, cli):
    """The default profile's drive model mills the cusps the flow transport sends to the port propeller
    at the line's operating point (as `milled_cusps(flow_point=)`), and gives the first case's Q_peak over
    the transport's draws, the analysis' own draw first."""
    from floebreak.app.inputs import load_shaft_line
    from floebreak.propeller.operating import shaft_operating_point

    run = _run(tmp_path / "run")
    out = tmp_path / "p"
    code, stdout, err = cli("propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--speed-m-s", "3")
    assert code == 0, err
    summary = json.loads((out / "shaft" / "summary.json").read_text())
    point = shaft_operating_point(load_shaft_line("agulhas_ii"), 3.0, None)[0]
    expected = milled_cusps(_columns(), speed_m_s=3.0, flow_point=point)
    assert summary["transport"]["rule"] == "flow"
    assert summary["transport"]["reaching_port"] == expected.arrival_s.size
    spread = summary["q_peak_spread"]
    assert spread["case"] == 1 and spread["n_draws"] == len(spread["samples_knm"]) == 3
    assert spread["samples_knm"][0] == pytest.approx(summary["q_peak_knm"]["1"]["q_peak_knm"])
    assert spread["q_peak_knm"]["p5"] <= spread["q_peak_knm"]["median"] <= spread["q_peak_knm"]["p95"]
    assert "over 3 draws of the flow transport" in stdout
