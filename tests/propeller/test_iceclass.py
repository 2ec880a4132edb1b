"""IACS UR I3 open-propeller loads (physics-notes §7.2) and the Weibull exceedance shape (§7.3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.iceclass import empirical_exceedance, ur_i3_loads, weibull_exceedance
from floebreak.propeller.spec import PropellerSpec


def test_agulhas_pc5_by_hand():
    spec = PropellerSpec(expanded_area_ratio=0.45, blade_thickness_07_m=0.08)
    loads = ur_i3_loads(spec, "pc5")
    d, nd, h = 4.3, 140 / 60 * 4.3, 2.0
    # D = 4.3 m > 0.85·2^1.4 = 2.24 m → second F_b branch; ≤ 2·2/0.7 = 5.71 m → first F_f branch
    f_b = 23 * 1.1 * nd**0.7 * (0.45 / 4) ** 0.3 * d * h**1.4
    f_f = 250 * (0.45 / 4) * d**2
    # D > 1.8·2 = 3.6 m → second torque branch; P_0.7 = 0.7 × 5.15 m (rule fallback)
    q = 202 * 0.7 * 1.15 * h**1.1 * (0.7 * 5.15 / d) ** 0.16 * (0.08 / d) ** 0.6 * nd**0.17 * d**1.9
    assert loads.backward_force_n == pytest.approx(f_b * 1e3, rel=1e-12)
    assert loads.forward_force_n == pytest.approx(f_f * 1e3, rel=1e-12)
    assert loads.max_torque_nm == pytest.approx(q * 1e3, rel=1e-12)
    # the notes' ranges for the Agulhas II at PC5 (F_b 750–840 kN, F_f 520–750 kN, Q 0.73–1.03 MNm)
    assert 740e3 < loads.backward_force_n < 760e3
    assert loads.forward_force_n == pytest.approx(520.1e3, rel=1e-3)
    assert 0.72e6 < loads.max_torque_nm < 0.75e6
    assert loads.backward_branch.startswith("D >") and loads.forward_branch.startswith("D <=")


def test_small_propeller_takes_the_first_branches():
    spec = PropellerSpec(radius_m=1.0, max_pitch_m=2.0, rpm=300.0, blade_thickness_07_m=0.05)
    loads = ur_i3_loads(spec, "PC1")  # D = 2 m < 0.85·4^1.4 = 5.92 m, < 1.8·4 m
    d, nd = 2.0, 5.0 * 2.0
    assert loads.backward_force_n == pytest.approx(27 * 1.2 * nd**0.7 * (0.55 / 4) ** 0.3 * d**2 * 1e3)
    q = 105 * 0.7 * 1.15 * (1.4 / d) ** 0.16 * (0.05 / d) ** 0.6 * nd**0.17 * d**3
    assert loads.max_torque_nm == pytest.approx(q * 1e3)


def test_forward_force_second_branch():
    spec = PropellerSpec(hub_ratio=0.3)
    loads = ur_i3_loads(spec, "PC7")  # D_lim = 2·1.5/0.7 = 4.29 m < 4.3 m
    assert loads.forward_force_n == pytest.approx(500 * 1.5 * (0.55 / 4) * 4.3 / 0.7 * 1e3)


def test_unknown_polar_class():
    with pytest.raises(InputError) as info:
        ur_i3_loads(PropellerSpec(), "PC8")
    assert info.value.field == "polar_class"


def test_weibull_values_of_the_notes():
    # notes §7.3: N = 1e6, k = 0.75: exceedance 0.5 / 0.1 / 0.01 at x = 0.019 / 0.092 / 0.231
    p = weibull_exceedance([0.019, 0.092, 0.231], 1e6, 0.75)
    assert p == pytest.approx([0.5, 0.1, 0.01], rel=0.05)
    assert weibull_exceedance(1.0, 1e6) == pytest.approx(1e-6)
    assert weibull_exceedance(0.0, 50) == 1.0
    assert math.isclose(weibull_exceedance(0.5, 100, 1.0), math.exp(-0.5 * math.log(100)))


def test_empirical_exceedance():
    v, p = empirical_exceedance([3.0, 1.0, np.nan, 2.0])
    assert v.tolist() == [1.0, 2.0, 3.0] and p.tolist() == pytest.approx([1.0, 2 / 3, 1 / 3])
