"""Loads with their spread over the flow transport's parameter draws and the fields (propeller.spread)."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.flow_transport import flow_draws, flow_transport_cusps
from floebreak.propeller.pipeline import analyse_cusp_loads
from floebreak.propeller.rates import RateBasis, RunExposure
from floebreak.propeller.ruleform import OperatingProfile
from floebreak.propeller.spread import band

N = 40  # cusps per run


def _cusps(runs=("a", "b")):
    """`N` stem cusps per run, 1–3 m by 1–3 m, 0.6 m thick, across the port half of the bow (y from 0 to
    9 m)."""
    rng = np.random.default_rng(7)
    n = N * len(runs)
    bow_x = np.tile(np.linspace(5.0, 200.0, N), len(runs))
    length, width = rng.uniform(1.0, 3.0, n), rng.uniform(1.0, 3.0, n)
    return {
        "volume_m3": 0.6 * length * width,
        "bbox_length_m": length,
        "bbox_width_m": width,
        "thickness_m": np.full(n, 0.6),
        "area_m2": length * width,
        "bow_x_m": bow_x,
        "centroid_x_m": bow_x,
        "centroid_y_m": rng.uniform(0.0, 9.0, n),
        "run_id": np.repeat(np.array(runs), N),
    }


EXPOSURES = {r: RunExposure(300.0, RateBasis(3.0, None, 2)) for r in ("a", "b")}  # 1/36 h each


def test_band_is_the_5th_50th_and_95th_percentile():
    # 1, 2, …, 21: the p-th percentile (linear between order statistics) is 1 + 20 p / 100
    assert band(np.arange(1.0, 22.0)) == {"median": 11.0, "p5": 2.0, "p95": 20.0, "n_samples": 21}
    assert band([np.nan, 3.0]) == {"median": 3.0, "p5": 3.0, "p95": 3.0, "n_samples": 1}
    assert band([np.nan]) is None


def test_one_draw_of_the_stack_is_the_transport_itself():
    cols = [_cusps(("a",))[k] for k in ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")]
    kw = {"speed_m_s": 3.0, "induced_velocity_m_s": 3.0, "wake_fraction": 0.14}
    (alone,) = flow_draws(cols, 1, np.random.default_rng(3), **kw)
    direct = flow_transport_cusps(*cols, rng=np.random.default_rng(3), **kw)
    assert np.array_equal(alone.propeller_index, direct.propeller_index)
    assert np.array_equal(alone.arrival_time_s, direct.arrival_time_s, equal_nan=True)
    # more draws: each copy of the cusps draws its own parameters, so the draws differ
    draws = flow_draws(cols, 3, np.random.default_rng(3), **kw)
    assert len(draws) == 3 and all(d.n_cusps == N for d in draws)
    assert not np.array_equal(draws[1].arrival_time_s, draws[2].arrival_time_s, equal_nan=True)


def _analysed(draws, runs=("a", "b"), transport="flow"):
    exposures = {r: EXPOSURES[r] for r in runs}
    return analyse_cusp_loads(
        _cusps(runs),
        transport=transport,
        exposures=exposures,
        polar_class="PC5",
        operating_profile=OperatingProfile(1000.0, 25.0),
        spread_draws=draws,
    )


def test_the_analysis_own_draw_is_a_sample_of_the_spread():
    """One run, one draw: the band collapses onto the analysis' own loads per hour and design torques."""
    result = _analysed(1, runs=("a",))
    spread = result.summary["spread"]
    rate = spread["loads_per_hour_per_propeller"]
    assert rate["n_samples"] == 1 and spread["n_runs"] == 1 and spread["transport"] == "flow"
    assert rate["median"] == pytest.approx(result.summary["rates"]["loads_per_hour_per_propeller"])
    from floebreak.app.propeller import design_load_summary

    for entry in design_load_summary(result):
        for row in entry["rows"]:
            low, median, high = row["design_torque_band_kn_m"]
            assert low == median == high == pytest.approx(row["design_torque_kn_m"])


def test_spread_over_draws_and_fields():
    """Two runs × three draws: six samples of the rate and of each propeller's design torque; the band
    lies within the samples' range and holds the median."""
    spread = _analysed(3).summary["spread"]
    rate = spread["loads_per_hour_per_propeller"]
    assert rate["n_samples"] == 6 and spread["n_runs"] == 2 and spread["n_draws_per_run"] == 3
    assert 0.0 < rate["p5"] <= rate["median"] <= rate["p95"]
    for entry in spread["design_torque_kn_m"]:
        assert entry["n_samples"] == 6 and entry["p5"] <= entry["median"] <= entry["p95"]
    # the kinematic transport has no parameter distribution: one sample per field
    hull = _analysed(3, transport="hull").summary["spread"]
    assert hull["loads_per_hour_per_propeller"]["n_samples"] == 2 and hull["transport"] == "hull"
    # every cusp reaching (no transport): no spread
    assert "spread" not in _analysed(3, transport="all").summary


@pytest.mark.parametrize("draws", [0, 1.5, True])
def test_spread_draws_must_be_a_positive_integer(draws):
    with pytest.raises(InputError) as info:
        _analysed(draws, runs=("a",))
    assert info.value.field == "spread_draws"


def test_terminal_and_report_show_the_band():
    """The design-load table's "median (5–95 %)" row and the loads-per-hour line, in the terminal and in
    report.html, from a summary with a spread."""
    import io

    from rich.console import Console

    from floebreak.app.propeller import design_load_summary
    from floebreak.cli.tables import design_load_tables, spread_line
    from floebreak.output.report import design_load_parts

    result = _analysed(3)
    summary = {"design_loads": design_load_summary(result), **result.summary}
    band_row = summary["design_loads"][0]["rows"][-1]["design_torque_band_kn_m"]
    low, median, high = band_row
    buffer = io.StringIO()
    for table in design_load_tables(summary):
        Console(file=buffer, width=100, force_terminal=False).print(table)
    text = buffer.getvalue()
    assert "median (5–95 %)" in text and f"{median:.0f} ({low:.0f}–{high:.0f})" in text
    rate = summary["spread"]["loads_per_hour_per_propeller"]
    line = spread_line(summary)
    assert f"median {rate['median']:.0f}, 5–95 % {rate['p5']:.0f}–{rate['p95']:.0f} (6 samples)" in line
    html = "".join(design_load_parts(summary["design_loads"]))
    assert "design ice torque Q, median (5–95 %)" in html and f"{median:.4g} ({low:.4g}–{high:.4g})" in html
