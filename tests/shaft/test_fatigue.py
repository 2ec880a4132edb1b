"""Rainflow counting and Miner's damage of a shaft torque series (floebreak.shaft.fatigue)."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.ruleform import BasquinCurve
from floebreak.shaft.fatigue import miner_damage, rainflow_cycles, rainflow_histogram

# ASTM E1049-85 (2011) Fig. 6(a): the sample history A–I for rainflow counting, in load units
ASTM_HISTORY = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0]
# its rainflow count, Fig. 6(b)–(i) and Table 4 of the standard, written out by hand:
# range 3: 0.5 (A-B), range 4: 1.5 (B-C half, E-F full), range 6: 0.5 (H-I), range 8: 1.0 (C-D half,
# G-H half), range 9: 0.5 (D-G)
ASTM_COUNTS = {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def _cosine(amplitude: float, periods: int, samples_per_period: int = 40) -> np.ndarray:
    """A cosine from peak to peak, sampled on its peaks and troughs."""
    k = np.arange(periods * samples_per_period + 1)
    return 7.0e3 + amplitude * np.cos(2.0 * np.pi * k / samples_per_period)


def test_astm_e1049_example_counts():
    cycles = rainflow_cycles(ASTM_HISTORY)
    counted: dict[float, float] = {}
    for r, n in zip(cycles.range_n_m, cycles.count, strict=True):
        counted[float(r)] = counted.get(float(r), 0.0) + float(n)
    assert counted == ASTM_COUNTS
    assert cycles.total_count == 4.0


def test_astm_example_histogram_in_unit_bins():
    hist = rainflow_histogram(ASTM_HISTORY, 1.0)
    assert hist.range_edges_n_m.tolist() == [float(i) for i in range(10)]
    expected = np.zeros(9)
    for r, n in ASTM_COUNTS.items():
        expected[int(r) if r < 9 else 8] += n  # bin [r, r+1); the largest range 9 closes the last bin
    assert hist.counts.tolist() == expected.tolist()


def test_cosine_gives_n_full_cycles_of_twice_the_amplitude():
    amplitude, periods = 12.5e3, 25
    cycles = rainflow_cycles(_cosine(amplitude, periods))
    big = np.isclose(cycles.range_n_m, 2.0 * amplitude, rtol=1e-12)
    assert cycles.count[big].sum() == periods
    assert np.all(big)
    assert cycles.mean_n_m == pytest.approx(np.full(cycles.count.size, 7.0e3), rel=1e-12)
    hist = rainflow_histogram(_cosine(amplitude, periods), 10e3)
    assert hist.counts.tolist() == [0.0, 0.0, float(periods)]  # 25 kN·m lies in [20, 30) kN·m


def test_miner_damage_of_constant_amplitude_series():
    amplitude, periods = 300e3, 40
    curve = BasquinCurve(5.0, 1000e3, 1e7, quantity="torque")
    cycles = rainflow_cycles(_cosine(amplitude, periods))
    n_to_failure = 1e7 * (1000e3 / amplitude) ** 5.0  # amplitude convention
    assert miner_damage(cycles, curve) == pytest.approx(periods / n_to_failure, rel=1e-12)
    n_range = 1e7 * (1000e3 / (2.0 * amplitude)) ** 5.0  # the curve read as a range curve
    assert miner_damage(cycles, curve, measure="range") == pytest.approx(periods / n_range, rel=1e-12)


def test_miner_damage_counts_half_cycles_half():
    curve = BasquinCurve(3.0, 2.0, 1e3, quantity="torque")
    cycles = rainflow_cycles(ASTM_HISTORY)
    expected = sum(n / (1e3 * (2.0 / (r / 2.0)) ** 3.0) for r, n in ASTM_COUNTS.items())
    assert miner_damage(cycles, curve) == pytest.approx(expected, rel=1e-12)


def test_flat_and_short_series_have_no_cycles():
    assert rainflow_cycles([5.0]).total_count == 0.0
    hist = rainflow_histogram(np.full(10, 3.0), 1.0)
    assert hist.counts.tolist() == [0.0]
    assert miner_damage(hist.cycles, BasquinCurve(5.0, 1.0, 1e6)) == 0.0


def test_bad_inputs_name_the_parameter():
    with pytest.raises(InputError) as info:
        rainflow_histogram([0.0, 1.0], 0.0)
    assert info.value.field == "range_bin_n_m"
    with pytest.raises(InputError) as info:
        rainflow_cycles([0.0, np.nan, 1.0])
    assert info.value.field == "torque_n_m"
    cycles = rainflow_cycles(ASTM_HISTORY)
    with pytest.raises(InputError) as info:
        miner_damage(cycles, BasquinCurve(5.0, 1.0, 1e6, quantity="force"))
    assert info.value.field == "sn_curve.quantity"
    with pytest.raises(InputError) as info:
        miner_damage(cycles, BasquinCurve(5.0, 1.0, 1e6), measure="peak")
    assert info.value.field == "measure"


def test_histogram_as_dict_in_kn_m():
    out = rainflow_histogram(_cosine(5e3, 3), 2e3).as_dict()
    assert out["range_edges_kn_m"] == [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
    assert out["cycle_counts"][-1] == 3.0 and out["n_cycles"] == 3.0
    assert out["max_range_kn_m"] == pytest.approx(10.0)
