"""The chain rows of `validate thesis` judge correctly on synthetic series; the rows are
registered as must-hold for `default`. Expected values are worked out by hand from the series built here."""

import math

import numpy as np
import pytest

from floebreak.validation.chain_statements import (
    blade_load_rate,
    lifetime_max_ratio,
    shaft_range_measures,
)
from floebreak.validation.statements import STATEMENTS, verdict

BY_ID = {st.id: st for st in STATEMENTS}
CHAIN_IDS = ("S62.chain.max", "S62.chain.overlap", "S62.chain.end", "PC5.lifetime_max", "PC5.rate")


def judge(row_id: str, value: float) -> str:
    st = BY_ID[row_id]
    return verdict(value, st.thesis_value, st.tolerance)


def uniform_series(low_knm: float, high_knm: float, n: int = 100_000) -> np.ndarray:
    """Evenly spread values: density 1/(high − low) per kN·m, above 0.1 % while the band is < 1000 kN·m."""
    return np.linspace(low_knm, high_knm, n, endpoint=False)


def test_the_rows_are_must_hold_for_default_only():
    for row_id in CHAIN_IDS:
        assert BY_ID[row_id].must_hold == frozenset({"default"})
    # failing rows name their failing link as a note, with where it was measured
    for row_id in ("S62.chain.max", "S62.chain.overlap", "S62.chain.end"):
        assert "docs/explanation/shaft.md §6" in BY_ID[row_id].explained
    assert "307 kN·m" in BY_ID["S62.chain.overlap"].explained  # the computed mean, not the measured one
    assert "--polar-class PC5" in BY_ID["PC5.rate"].explained


def test_a_series_like_the_measured_one_passes_every_shaft_row():
    # 60–150 kN·m evenly (density 1/90 per kN·m, above 0.1 %), and a few peaks up to 400 kN·m
    q = np.concatenate([uniform_series(60.0, 150.0), [250.0, 400.0]])
    m = shaft_range_measures(q)
    assert m["chain_shaft_max_knm"] == 400.0
    assert (m["chain_range_start_knm"], m["chain_range_end_knm"]) == (60.0, 150.0)
    assert m["chain_range_overlap_knm"] == pytest.approx(150.0 - 60.0)  # inside 58–152
    assert judge("S62.chain.max", m["chain_shaft_max_knm"]) == "pass"
    assert judge("S62.chain.overlap", m["chain_range_overlap_knm"]) == "pass"
    assert judge("S62.chain.end", m["chain_range_end_knm"]) == "pass"


def test_a_series_like_the_default_chain_fails_max_and_end_but_not_overlap():
    q = np.concatenate([uniform_series(60.0, 550.0), [916.0]])  # density 1/490 > 0.1 % per kN·m
    m = shaft_range_measures(q)
    assert (m["chain_range_start_knm"], m["chain_range_end_knm"]) == (60.0, 550.0)
    assert m["chain_range_overlap_knm"] == pytest.approx(152.0 - 60.0)
    assert judge("S62.chain.max", m["chain_shaft_max_knm"]) == "fail"  # > 1.5 × 400
    assert judge("S62.chain.overlap", m["chain_range_overlap_knm"]) == "pass"
    assert judge("S62.chain.end", m["chain_range_end_knm"]) == "fail"  # > 1.5 × 152 = 228


@pytest.mark.parametrize(
    ("peak", "expected"), [(267.0, "fail"), (268.0, "pass"), (600.0, "pass"), (601.0, "fail")]
)
def test_the_maximum_band_is_400_times_0_67_to_1_5(peak, expected):
    assert judge("S62.chain.max", peak) == expected


def test_overlap_needs_half_the_measured_range():
    # 110–200 kN·m overlaps 58–152 by 42 kN·m < 47 (half of 94): fail; 100–200 by 52: pass
    assert shaft_range_measures(uniform_series(110.0, 200.0))["chain_range_overlap_knm"] == pytest.approx(42)
    assert judge("S62.chain.overlap", 42.0) == "fail" and judge("S62.chain.overlap", 52.0) == "pass"
    # nothing above the threshold (values spread over 2000 kN·m: density 0.05 %): no range, a missing row
    spread = shaft_range_measures(uniform_series(0.0, 2000.0))
    assert math.isnan(spread["chain_range_overlap_knm"])
    assert judge("S62.chain.overlap", spread["chain_range_overlap_knm"]) == "missing"


def test_pc5_rows():
    # every cusp 972 kN·m, Q_max 864 kN·m, no fit: the largest load is the lower bound, 1.125 × Q_max
    assert lifetime_max_ratio(np.full(5, 972.0), 864.0, None) == pytest.approx(972 / 864)
    assert judge("PC5.lifetime_max", 972 / 864) == "fail" and judge("PC5.lifetime_max", 0.9) == "pass"
    # a fit's lifetime x_max counts where it exceeds the largest load
    assert lifetime_max_ratio(np.array([100.0, 500.0]), 1000.0, 800.0) == pytest.approx(0.8)
    # 10 cusps on one propeller (weight 0.5 of 20), 3 impacts each, 4 blades, over 0.01 h: 750 per blade-hour
    rate = blade_load_rate(np.full(20, 0.5), np.full(20, 3), 4, 0.01)
    assert rate == pytest.approx(10 * 3 / 4 / 0.01)
    assert judge("PC5.rate", 2.9) == "pass" and judge("PC5.rate", 0.34) == "pass"
    assert judge("PC5.rate", 3.1) == "fail" and judge("PC5.rate", 0.3) == "fail"


def _small_default_run(path):
    """Six 0.4 m cusps of a `default`-profile run at 3 m/s, three on the port shaft's line (y = 5.5 m)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    path.mkdir()
    length = np.array([3.7, 6.5, 2.0, 9.4, 1.0, 3.0])
    bow_x = np.array([1.0, 5.0, 5.0, 12.0, 20.0, 31.0])
    columns = {
        "area_m2": 0.8 * length,
        "thickness_m": np.full(6, 0.4),
        "volume_m3": 0.8 * length * 0.4,
        "bbox_length_m": length,
        "bbox_width_m": np.ones(6),
        "step": np.arange(6),
        "bow_x_m": bow_x,
        "centroid_x_m": bow_x - 2.0,
        "centroid_y_m": np.array([5.5, -5.5, 5.5, 0.0, -5.5, 5.5]),
    }
    pq.write_table(pa.table(columns), path / "cusps.parquet")
    text = 'profile = "default"\n[ship]\nspeed_m_s = 3.0\n'
    (path / "scenario.resolved.toml").write_text(text, encoding="utf-8")
    return path


def test_the_chain_takes_the_propellers_own_mean_torque_and_the_numbers_of_floebreak_propeller(tmp_path, cli):
    """The §6.2 chain is the command's shaft analysis: the same Q_peak and range as `floebreak propeller
    --shaft-line agulhas_ii --speed-m-s 3` writes, on the propeller's own mean torque. Its open-water torque
    at the set pitch exceeds the motor's rating, so the controller holds the rated torque: 4.5 MW at 140 rpm,
    4.5e6 / (2π · 140/60) = 306.9 kN·m (physics-notes §7.2), not the measured 105 kN·m."""
    import json

    from floebreak.validation.chain_statements import chain_6_2_metrics

    run = _small_default_run(tmp_path / "run")
    metrics = chain_6_2_metrics(run)
    rated_knm = 4.5e6 / (2.0 * math.pi * 140.0 / 60.0) / 1e3
    assert metrics["chain_model_mean_torque_knm"] == pytest.approx(rated_knm, abs=0.5)
    assert 0.0 < metrics["chain_identified_pitch_ratio"] < 1.0  # 105 kN·m needs a lower pitch
    code, _, _ = cli(
        "propeller", run, "--out", tmp_path / "p", "--shaft-line", "agulhas_ii", "--speed-m-s", "3",
        "--excitation-cases", "1", "--mean-torque-knm", "105", "--quiet",
    )  # fmt: skip
    assert code == 0
    summary = json.loads((tmp_path / "p" / "shaft" / "summary.json").read_text(encoding="utf-8"))
    assert metrics["chain_shaft_max_knm"] == pytest.approx(summary["q_peak_knm"]["1"]["q_peak_knm"])
    envelope = summary["spectra_above_threshold_knm"]["shaft_case1"]["envelope"]
    assert [metrics["chain_range_start_knm"], metrics["chain_range_end_knm"]] == pytest.approx(envelope)
