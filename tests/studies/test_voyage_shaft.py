"""Pooling of a voyage's shaft torque by time (`floebreak voyage --shaft-line`) against a hand computation."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.studies.voyage_shaft import RunShaft, pool_periods, time_above

# Period 0: T = 1 h, one run of 4 samples at 0.5 s (2 s): 100, 100, 120, 140 kN·m, 3 cycles.
# Period 1: T = 3 h, two runs of 2 samples at 1 s (4 s together): 100, 100 and 100, 130 kN·m, 1 cycle each.
# Period 2: T = 5 h without runs: no time, no torque.
# Time above 120 kN·m: period 0: 2 samples × 0.5 s = 1 s of 2 s (1/2); period 1: 1 s of 4 s (1/4).
# Hours above 120 over the voyage: 1 h × 1/2 + 3 h × 1/4 = 1.25 h of 4 h: a share of 0.3125.
# Above 140: 0.5 s of 2 s in period 0 (1/4), none in period 1: 0.25 h of 4 h = 0.0625.
# Cycles per hour: period 0: 3 in 2 s = 5400 /h; period 1: 2 in 4 s = 1800 /h; pooled (1 × 5400 +
# 3 × 1800) / 4 = 2700 /h.
RUNS = {
    0: [RunShaft(np.array([100.0, 100.0, 120.0, 140.0]), 0.5, 3.0, "drive", "s")],
    1: [
        RunShaft(np.array([100.0, 100.0]), 1.0, 1.0, "drive", "s"),
        RunShaft(np.array([100.0, 130.0]), 1.0, 1.0, "drive", "s"),
    ],
    2: [],
}
PERIODS = [{"index": 0, "duration_h": 1.0}, {"index": 1, "duration_h": 3.0}, {"index": 2, "duration_h": 5.0}]


def test_time_above_counts_samples_at_or_above():
    assert time_above(np.array([1.0, 2.0, 3.0]), 0.5, np.array([0.0, 2.0, 3.5])).tolist() == [1.5, 1.0, 0.0]


def test_shaft_statistics_pooled_by_the_periods_hours():
    pooled = pool_periods(PERIODS, RUNS)
    assert pooled["hours"] == 4.0  # period 2 has no runs
    assert pooled["max_shaft_torque_knm"] == 140.0 and pooled["min_shaft_torque_knm"] == 100.0
    levels = pooled["exceedance"]["level_knm"]
    share = dict(zip(levels.tolist(), pooled["exceedance"]["time_share_above"].tolist(), strict=True))
    hours = dict(zip(levels.tolist(), pooled["exceedance"]["hours_above"].tolist(), strict=True))
    assert share[100.0] == pytest.approx(1.0)
    assert share[120.0] == pytest.approx(0.3125) and hours[120.0] == pytest.approx(1.25)
    assert share[140.0] == pytest.approx(0.0625)
    assert pooled["cycles_per_hour"] == pytest.approx(2700.0)
    rows = pooled["periods"]
    assert [r["runs"] for r in rows] == [1, 2, 0]
    assert rows[1]["max_shaft_torque_knm"] == 130.0 and rows[1]["simulated_s"] == 4.0
    assert np.isnan(rows[2]["max_shaft_torque_knm"])
