"""Blade-impact excitation (physics-notes §7.3, as recalled): shapes, timing, cases, queueing, bad input."""

import math

import numpy as np
import pytest
from scipy.signal import find_peaks

from floebreak.errors import InputError
from floebreak.shaft.excitation import arrival_times_s, ice_torque_series, milling_starts

RPM, Z = 140.0, 4


def one_cusp(case, q=1e5, h=0.5, **kw):
    return ice_torque_series([1.0], [q], [h], rpm=RPM, blades=Z, case=case, **kw)


@pytest.mark.parametrize(
    ("case", "c_q", "alpha_deg", "blocks"),
    [(1, 0.75, 90, 1), (2, 1.0, 135, 1), (3, 0.5, 45, 2), (4, 0.5, 45, 1)],
)
def test_half_sine_impacts_per_case(case, c_q, alpha_deg, blocks):
    q, h = 1e5, 0.5
    t, torque = one_cusp(case, q, h)
    dt = t[1] - t[0]
    assert dt == pytest.approx(60 / (RPM * Z * 40))  # 40 samples per blade passage (default)
    assert torque.max() == pytest.approx(c_q * q, rel=1e-3)
    # Z·2h impacts per block, each a half sine of α_i/(360 n) seconds: area C_q Q · 2τ/π
    tau = alpha_deg / 360 / (RPM / 60)
    n_impacts = round(Z * 2 * h) * blocks
    area = n_impacts * c_q * q * 2 * tau / math.pi
    assert torque.sum() * dt == pytest.approx(area, rel=5e-3)  # ≥ 20 samples per impact: Riemann sum
    # the first impact starts at the first blade passage at or after the arrival (1 s)
    passage = 60 / (RPM * Z)
    assert t[np.flatnonzero(torque > 0)[0]] == pytest.approx(math.ceil(1.0 / passage) * passage + dt)


def test_two_blocks_shifted_by_half_a_blade_passage():
    t, torque = one_cusp(3, h=0.125)  # one impact per block
    peaks, _ = find_peaks(torque, height=0.99 * torque.max())
    assert np.diff(t[peaks]) == pytest.approx([60 / (RPM * Z) / 2])  # 360°/(2Z) of rotation


def test_cusps_arriving_together_are_milled_one_after_another():
    _, queued = ice_torque_series([1.0, 1.0], [1e5, 2e5], 0.5, rpm=RPM, blades=Z, case=2)
    _, summed = ice_torque_series([1.0, 1.0], [1e5, 2e5], 0.5, rpm=RPM, blades=Z, case=2, overlap="superpose")
    assert queued.max() == pytest.approx(2e5, rel=1e-3)
    assert summed.max() == pytest.approx(3e5, rel=1e-3)
    assert queued.sum() == pytest.approx(summed.sum(), rel=1e-9)


def test_milling_starts_closed_form_equals_the_recurrence():
    rng = np.random.default_rng(3)
    first = np.sort(rng.integers(0, 200, 300))
    n = rng.integers(1, 9, 300)
    expected, end = [], -np.inf
    for a, d in zip(first, n, strict=True):
        start = max(a, end)
        expected.append(start)
        end = start + d
    np.testing.assert_array_equal(milling_starts(first, n), expected)


def test_arrival_times_from_bow_positions():
    np.testing.assert_allclose(arrival_times_s([10.0, 16.0, 13.0], 3.0, lead_s=2.0), [2.0, 4.0, 3.0])


def test_no_cusps_gives_a_quiet_series():
    t, torque = ice_torque_series([], [], [], rpm=RPM, blades=Z, tail_s=1.0)
    assert t.size > 0 and not torque.any()


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"rpm": 0.0}, "rpm"),
        ({"rpm": -140.0}, "rpm"),
        ({"samples_per_blade_passage": 19}, "samples_per_blade_passage"),
        ({"case": 5}, "excitation_case"),
        ({"overlap": "stack"}, "overlap"),
    ],
)
def test_bad_excitation_input(kwargs, key):
    args = {"rpm": RPM, "blades": Z, **kwargs}
    with pytest.raises(InputError) as info:
        ice_torque_series([1.0], [1e5], [0.5], **args)
    assert info.value.field == key


def test_bad_speed():
    with pytest.raises(InputError) as info:
        arrival_times_s([0.0, 1.0], 0.0)
    assert info.value.field == "speed_m_s"
