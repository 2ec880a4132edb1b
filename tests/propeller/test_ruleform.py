"""Rule-form fit (notes §7.3), rule N_ice (as recalled) and Miner's sum: known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.ruleform import (
    BasquinCurve,
    OperatingProfile,
    RuleArrangement,
    fit_rule_form,
    miner_damage,
    rule_load_count,
    rule_n_ice,
    submersion_factor,
)
from floebreak.propeller.spec import PropellerSpec


@pytest.mark.parametrize(("k", "scale"), [(0.75, 300.0e3), (1.0, 50.0), (2.2, 1.0e6)])
def test_fit_recovers_known_parameters(k, scale):
    """Samples of P(X ≥ x) = exp(−(x/λ)^k) drawn with a seeded Generator (λ·Weibull(k)): with 20 000
    samples the MLE lies within 2 % of k and λ and its 95 % interval contains the true k."""
    rng = np.random.default_rng(20231218)
    x = scale * rng.weibull(k, 20_000)
    fit = fit_rule_form(x)
    assert fit.shape_k == pytest.approx(k, rel=0.02)
    assert fit.scale == pytest.approx(scale, rel=0.02)
    low, high = fit.shape_interval()
    assert low < k < high
    # the expected-information standard error of k is k·sqrt(6/π²/n) ≈ 0.0055·k for n = 20 000
    assert (high - low) / (2 * 1.959964) == pytest.approx(k * math.sqrt(6 / math.pi**2 / 20_000), rel=0.05)


def test_interval_coverage_is_near_95_percent():
    """200 seeded samples of 300: the 95 % intervals of k and of x_max(N = 10⁴) contain the truth in
    about 95 % of them (binomial sd 1.5 %: 90–99 % allowed)."""
    rng = np.random.default_rng(7)
    k, scale, n_loads = 0.75, 100.0, 1.0e4
    true_x_max = scale * math.log(n_loads) ** (1 / k)
    hits_k = hits_x = 0
    for _ in range(200):
        fit = fit_rule_form(scale * rng.weibull(k, 300))
        low, high = fit.shape_interval()
        hits_k += low < k < high
        low, high = fit.x_max_interval(n_loads)
        hits_x += low < true_x_max < high
    assert 0.90 <= hits_k / 200 <= 0.99
    assert 0.90 <= hits_x / 200 <= 0.99


def test_x_max_is_the_load_exceeded_once_in_n():
    """Rule form: P(X ≥ x_max) = exp(−ln N) = 1/N; notes §7.3: for N = 10⁶ and k = 0.75, x/x_max = 0.019,
    0.092, 0.231 are exceeded with probability 0.5, 0.1, 0.01."""
    rng = np.random.default_rng(1)
    fit = fit_rule_form(rng.weibull(0.75, 5000))
    n = 1e6
    assert fit.exceedance(fit.x_max(n)) == pytest.approx(1 / n, rel=1e-9)
    exact = type(fit)(0.75, 1.0, 100, ((1.0, 0.0), (0.0, 1.0)))
    x_max = exact.x_max(n)
    for share, probability in ((0.019, 0.5), (0.092, 0.1), (0.231, 0.01)):
        assert exact.exceedance(share * x_max) == pytest.approx(probability, rel=0.06)


def test_fit_refuses_too_few_or_equal_samples():
    with pytest.raises(InputError, match="at least 10"):
        fit_rule_form([1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="at least 10") as equal:
        fit_rule_form(np.full(50, 4.0))
    # uniform-thickness runs: 50 equal amplitudes are 50 samples but 1 distinct value (not "50 distinct")
    assert "50 positive amplitudes, 1 distinct" in str(equal.value)
    with pytest.raises(InputError, match="4 positive amplitudes, 2 distinct"):
        fit_rule_form([1.0, 2.0, 2.0, 0.0, -1.0])  # |−1| counts, 0 does not


def test_rule_n_ice_as_recalled():
    # physics-notes §7.4's worked number: PC5, 140 rpm, all k = 1 → 2.57e7 cycles per blade
    assert rule_n_ice("pc5", 140 / 60) == pytest.approx(2.57e7, rel=2e-3)
    # the class table, PC1..PC7 = 21, 17, 15, 13, 11, 9, 6 × 10⁶ per unit speed
    classes = ("PC1", "PC2", "PC3", "PC4", "PC5", "PC6", "PC7")
    for cls, n_class in zip(classes, (21, 17, 15, 13, 11, 9, 6), strict=True):
        assert rule_n_ice(cls, 1.0) == pytest.approx(n_class * 1e6)
    assert rule_n_ice("PC1", 2.0, k1=2.0, k2=0.5, k3=1.2) == pytest.approx(2 * 0.5 * 1.2 * 21e6 * 2)
    with pytest.raises(InputError, match="polar_class"):
        rule_n_ice("PC8", 2.0)
    with pytest.raises(InputError, match=r"rule\.k2"):
        rule_n_ice("PC5", 2.0, k2=-0.1)


@pytest.mark.parametrize(
    ("f", "k2"),
    [(-0.5, 1.3), (0.0, 0.8), (0.25, 0.7), (1.0, 0.4), (1.5, 0.3), (2.5, 0.1), (3.0, 0.1)],
)
def test_submersion_factor_branches(f, k2):
    assert submersion_factor(f) == pytest.approx(k2)


def test_rule_load_count_of_the_agulhas_ii():
    # wing propeller, centreline 5.25 m deep, D = 4.3 m, PC5 (H_ice 2 m): f = 3.25/2.15 − 1
    f = 3.25 / 2.15 - 1.0
    count = rule_load_count("PC5", PropellerSpec())
    assert count.submersion_f == pytest.approx(f)
    assert count.k2 == pytest.approx(0.8 - 0.4 * f)
    assert count.n_ice_low == pytest.approx(1.35 * (0.8 - 0.4 * f) * 11e6 * 140 / 60)
    assert count.n_ice_high == pytest.approx(2.0 * (0.8 - 0.4 * f) * 11e6 * 140 / 60)
    assert count.as_dict()["k4_note"].startswith("k_4 = 1: not recalled")
    # a shallow centre propeller: h0 = 3 m under 2 m of ice, f = 1/2.15 − 1 < 0, k2 = 0.8 − f
    shallow = rule_load_count("PC5", PropellerSpec(), RuleArrangement("centre", 3.0))
    assert shallow.k2 == pytest.approx(0.8 - (1.0 / 2.15 - 1.0))
    assert shallow.n_ice_low == shallow.n_ice_high
    with pytest.raises(InputError, match=r"rule\.location"):
        RuleArrangement("stern")
    with pytest.raises(InputError, match=r"rule\.machinery"):
        RuleArrangement(machinery="ducted")


def test_miner_damage_by_hand():
    """N(x) = 10⁶ (100/x)³: amplitudes 100 and 200 → 1/10⁶ + 8/10⁶; each counted 0.5 times → 4.5·10⁻⁶."""
    curve = BasquinCurve(exponent_m=3.0, reference_amplitude=100.0, reference_cycles=1e6)
    assert miner_damage([100.0, -200.0, np.nan, 0.0], curve, 0.5) == pytest.approx(4.5e-6)
    with pytest.raises(InputError, match=r"sn_curve\.exponent_m"):
        BasquinCurve(exponent_m=0.0, reference_amplitude=1.0, reference_cycles=1.0)
    with pytest.raises(InputError, match=r"sn_curve\.quantity"):
        BasquinCurve(3.0, 1.0, 1.0, quantity="thrust")


def test_operating_profile_validation():
    assert OperatingProfile(1000.0, 25.0).hours == 25_000.0
    with pytest.raises(InputError, match="hours_in_ice_per_year"):
        OperatingProfile(9000.0, 1.0)  # more than a year has
    with pytest.raises(InputError, match="years"):
        OperatingProfile(100.0, float("nan"))


def test_fit_is_scipys_weibull_maximum_likelihood():
    """The same maximum as scipy.stats.weibull_min.fit with the location fixed at 0 (an independent
    optimiser of the same likelihood)."""
    from scipy import stats

    rng = np.random.default_rng(11)
    x = 250.0 * rng.weibull(1.3, 800)
    shape, _, scale = stats.weibull_min.fit(x, floc=0.0)
    fit = fit_rule_form(x)
    assert fit.shape_k == pytest.approx(shape, rel=1e-4)
    assert fit.scale == pytest.approx(scale, rel=1e-4)


def test_integer_weights_fit_like_repeated_samples():
    """Σ w_i ℓ(x_i) with integer weights is the log-likelihood of the sample with x_i repeated w_i times:
    same k and λ. The intervals differ by design: the weighted fit counts n_eff = (Σw)²/Σw² samples,
    the repeated one Σw, so its covariance is the repeated one's × Σw / n_eff."""
    rng = np.random.default_rng(11)
    x = 40.0 * rng.weibull(0.9, 60)
    w = rng.integers(1, 5, x.size)
    weighted = fit_rule_form(x, weights=w)
    repeated = fit_rule_form(np.repeat(x, w))
    assert weighted.shape_k == pytest.approx(repeated.shape_k, rel=1e-9)
    assert weighted.scale == pytest.approx(repeated.scale, rel=1e-9)
    n_eff = w.sum() ** 2 / np.sum(w**2)
    assert weighted.n_effective == pytest.approx(n_eff)
    np.testing.assert_allclose(
        np.asarray(weighted.cov_k_log_scale),
        np.asarray(repeated.cov_k_log_scale) * w.sum() / n_eff,
        rtol=1e-8,
    )


def test_unit_weights_equal_the_unweighted_fit_and_zero_weights_drop_samples():
    rng = np.random.default_rng(12)
    x = 3.0 * rng.weibull(1.4, 80)
    plain = fit_rule_form(x)
    ones = fit_rule_form(x, weights=np.ones(x.size))
    assert ones.shape_k == pytest.approx(plain.shape_k, rel=1e-12)
    assert ones.scale == pytest.approx(plain.scale, rel=1e-12)
    np.testing.assert_allclose(ones.cov_k_log_scale, plain.cov_k_log_scale, rtol=1e-12)
    dropped = fit_rule_form(np.r_[x, 1e6], weights=np.r_[np.full(x.size, 2.5), 0.0])  # scale-free
    assert dropped.shape_k == pytest.approx(plain.shape_k, rel=1e-12)
    assert dropped.n_samples == x.size


@pytest.mark.parametrize("weights", [np.ones(5), np.r_[np.ones(29), -1.0], np.r_[np.ones(29), np.nan]])
def test_bad_weights_are_refused(weights):
    x = np.linspace(1.0, 30.0, 30)
    with pytest.raises(InputError, match="weights"):
        fit_rule_form(x, weights=weights)
