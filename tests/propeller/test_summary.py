"""The rule-maximum horizon of the propeller summary: finite hours, or null / "never"."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from floebreak.propeller.summary import NEVER_HOURS, horizon_text, rule_form_entry, rule_maximum_horizon


def test_finite_horizon_by_hand():
    # λ = 100 kN·m, k = 0.75, rule maximum 800 kN·m: ln N* = 8^0.75 = 4.757, N* = 116.4 loads
    out = rule_maximum_horizon(800e3, 100e3, 0.75, per_hour=10.0)
    n_star = math.exp(8.0**0.75)
    assert out["loads_until_rule_maximum"] == pytest.approx(n_star, rel=1e-12)
    assert out["hours_until_rule_maximum"] == pytest.approx(n_star / 10.0, rel=1e-12)
    assert out["rule_maximum_never"] is False
    assert horizon_text(out["hours_until_rule_maximum"]) == "11.6 h"


def test_overflowing_horizon_is_null_and_never():
    # the 0 % pitch case: a tiny scale puts ln N* far beyond a float's range
    out = rule_maximum_horizon(750e3, 100.0, 0.75, per_hour=100.0)  # ln N* = 7500^0.75 = 802
    assert out == {
        "loads_until_rule_maximum": None,
        "hours_until_rule_maximum": None,
        "rule_maximum_never": True,
    }
    assert json.loads(json.dumps(out))["hours_until_rule_maximum"] is None
    assert horizon_text(out["hours_until_rule_maximum"], out["rule_maximum_never"]) == "never"
    # nearly equal loads give a steep fit (k ≈ 215): (rule max / λ)^k itself overflows a float
    steep = rule_maximum_horizon(795e3, 59.2, 214.6, per_hour=198.0)  # (1.3e4)^214.6 ≈ 10^885
    assert steep["rule_maximum_never"] is True and steep["loads_until_rule_maximum"] is None


def test_horizon_beyond_a_million_years_is_never():
    # ln N* = 30 → N* = 1.07e13 loads; at 1 load per hour that is 1.2e9 years
    out = rule_maximum_horizon(30.0, 1.0, 1.0, per_hour=1.0)
    assert out["loads_until_rule_maximum"] == pytest.approx(math.exp(30.0))
    assert out["hours_until_rule_maximum"] is None and out["rule_maximum_never"] is True
    # just inside: N* = 1e6 years of hours at one load per hour
    inside = rule_maximum_horizon(math.log(0.99 * NEVER_HOURS), 1.0, 1.0, per_hour=1.0)
    assert inside["hours_until_rule_maximum"] == pytest.approx(0.99 * NEVER_HOURS)
    assert NEVER_HOURS == pytest.approx(1e6 * 365.25 * 24)


def test_no_time_base_is_not_never():
    out = rule_maximum_horizon(800e3, 100e3, 0.75, per_hour=None)
    assert out["hours_until_rule_maximum"] is None and out["rule_maximum_never"] is False
    assert horizon_text(None) == "–"
    assert horizon_text(math.inf) == "never" and horizon_text(1.4e300) == "never"


def test_rule_form_entry_carries_the_horizon():
    rng = np.random.default_rng(3)
    amplitudes = 50e3 * rng.weibull(0.75, 200)  # λ = 50 kN·m
    entry = rule_form_entry(amplitudes, 1e3, 5.0, None, 1e9, None, 0.75)  # rule max 1 GN·m: never
    assert entry["hours_until_rule_maximum"] is None and entry["rule_maximum_never"] is True
    near = rule_form_entry(amplitudes, 1e3, 5.0, None, 400e3, None, 0.75)
    assert near["rule_maximum_never"] is False
    lam, k = near["scale"] * 1e3, near["k"]
    assert near["hours_until_rule_maximum"] == pytest.approx(math.exp((400e3 / lam) ** k) / 5.0, rel=1e-9)
