"""The ice-class rule's exceedance form fitted to simulated load amplitudes, its lifetime extrapolation, the
rule's number of load cycles N_ice and a Miner damage sum (physics-notes §7.3; beyond the thesis).

Rule form (notes §7.3, *as recalled, verify against the rule text*): over N loads,

    P(X ≥ x) = exp(−(x / x_max)^k ln N),   k = 0.75 (open propeller), 1.0 (ducted).

This is a two-parameter Weibull distribution P(X ≥ x) = exp(−(x/λ)^k) with λ = x_max / (ln N)^(1/k): the
largest of N loads is x_max = λ (ln N)^(1/k) (P(X ≥ x_max) = 1/N). `fit_rule_form` estimates k and λ by
maximum likelihood; the expected-information (Wald) standard errors give confidence intervals for k and,
by the delta method on ln x_max, for x_max at any N.

Weighted fit (pooled voyages, where one simulated cusp stands for w_i loads): the weighted log-likelihood
Σ w_i ℓ(x_i) gives the same estimating equations with weighted means. Its curvature alone would treat Σ w
as the number of independent loads; the weights only rescale how often the few simulated cusps count, so
the intervals use the Kish effective sample size n_eff = (Σ w)² / Σ w² instead (n_eff = n for equal
weights). The weights' scale does not change the fit.

Rule N_ice (UR I3 2006/Rev.1 *as recalled*, physics-notes §7.4; verify against the rule text): the load
cycles on **one blade** over the ship's life (Z · N_ice on the propeller),

    N_ice = k_1 k_2 k_3 k_4 · N_class · n,   n the nominal propeller speed [1/s],

N_class per class in `N_CLASS`. k_1 (location): 1 for a centre propeller, more for a wing propeller, where
the two recollections disagree (1.35 or 2): both are kept (`RuleLoadCount.n_ice_low`, `.n_ice_high`). k_2
(submersion, `submersion_factor`) from f = (h_0 − H_ice)/(D/2) − 1, h_0 the depth of the propeller centreline
at the lowest ballast waterline. k_3 (machinery): fixed 1, azimuthing 1.2. k_4 was not recalled: 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.iceclass import POLAR_CLASSES, check_polar_class
from floebreak.propeller.spec import PropellerSpec
from floebreak.ship.agulhas_ii import SHAFT_DEPTH_M

EULER_GAMMA = 0.5772156649015329
# the standard normal's 97.5 % quantile as scipy.stats.norm.ppf(0.975) gives it, to the last bit (a test
# checks it): the summary's 95 % intervals without importing scipy.stats (benchmarks/README.md)
Z_95 = 1.959963984540054
N_CLASS = {  # load cycles per blade per unit propeller speed [1/s]: UR I3 as recalled (physics-notes §7.4)
    "PC1": 21e6,
    "PC2": 17e6,
    "PC3": 15e6,
    "PC4": 13e6,
    "PC5": 11e6,
    "PC6": 9e6,
    "PC7": 6e6,
}
# k_1 by propeller location (notes §7.4, as recalled): a wing propeller's two recollections, low and high
LOCATION_FACTORS = {"centre": (1.0, 1.0), "wing": (1.35, 2.0)}
MACHINERY_FACTORS = {"fixed": 1.0, "azimuthing": 1.2}  # k_3
K4_NOTE = "k_4 = 1: not recalled (physics-notes §7.4)"
MIN_SAMPLES = 10


@dataclass(frozen=True)
class RuleFormFit:
    """Maximum-likelihood fit of P(X ≥ x) = exp(−(x/λ)^k) to n positive amplitudes (SI units of X)."""

    shape_k: float
    scale: float
    n_samples: int
    cov_k_log_scale: tuple[tuple[float, float], tuple[float, float]]  # covariance of (k, ln λ)
    n_effective: float | None = None  # Kish (Σw)²/Σw² of a weighted fit; None: unweighted (n_samples)

    def x_max(self, n_loads: float) -> float:
        """Expected largest of `n_loads` loads: λ (ln N)^(1/k) (notes §7.3)."""
        return self.scale * math.log(n_loads) ** (1.0 / self.shape_k)

    def shape_interval(self, level: float = 0.95) -> tuple[float, float]:
        z = _two_sided_z(level)
        sd = math.sqrt(self.cov_k_log_scale[0][0])
        return (self.shape_k - z * sd, self.shape_k + z * sd)

    def x_max_interval(self, n_loads: float, level: float = 0.95) -> tuple[float, float]:
        """Delta-method interval of x_max(N): ln x_max = ln λ + ln(ln N)/k."""
        z = _two_sided_z(level)
        grad = np.array([-math.log(math.log(n_loads)) / self.shape_k**2, 1.0])
        sd = math.sqrt(float(grad @ np.asarray(self.cov_k_log_scale) @ grad))
        centre = self.x_max(n_loads)
        return (centre * math.exp(-z * sd), centre * math.exp(z * sd))

    def exceedance(self, x, n_loads: float | None = None) -> np.ndarray:
        """P(X ≥ x) of the fitted form (the same for every N: x_max and ln N change together)."""
        return np.exp(-((np.clip(np.asarray(x, dtype=float), 0.0, None) / self.scale) ** self.shape_k))


def _two_sided_z(level: float) -> float:
    """z with P(|Z| ≤ z) = `level` for a standard normal Z (`Z_95` for 95 %)."""
    if level == 0.95:
        return Z_95
    from scipy import stats

    return float(stats.norm.ppf(0.5 + level / 2.0))


def _positive_samples(amplitudes, weights, field: str) -> tuple[np.ndarray, np.ndarray | None]:
    """The finite amplitudes > 0 (absolute values) with a weight > 0, and those weights (None unweighted)."""
    x = np.abs(np.asarray(amplitudes, dtype=float))
    keep = np.isfinite(x) & (x > 0.0)
    if weights is None:
        return x[keep], None
    w = np.asarray(weights, dtype=float)
    if w.shape != x.shape:
        raise InputError(f"{field} weights", f"shape {w.shape} is not the amplitudes' {x.shape}")
    if not np.all(np.isfinite(w) & (w >= 0.0)):
        raise InputError(f"{field} weights", "a weight is negative or not finite", allowed="finite, ≥ 0")
    keep &= w > 0.0
    return x[keep], w[keep]


def fit_rule_form(amplitudes, field: str = "amplitudes", weights=None) -> RuleFormFit:
    """Maximum-likelihood Weibull fit (location 0) of the finite amplitudes > 0, optionally weighted.

    k solves the profile-likelihood equation Σ x^k ln x / Σ x^k − 1/k − mean(ln x) = 0 (scipy brentq),
    λ = (mean x^k)^(1/k). Covariance of (k, ln λ) from the expected Fisher information per sample
    [[((1−γ)² + π²/6)/k², −(1−γ)], [−(1−γ), k²]] (γ: Euler's constant) times n. With `weights` (≥ 0, one
    per amplitude) the sums and means are weighted (maximum of Σ w_i ℓ(x_i)) and n is the Kish effective
    sample size (Σw)²/Σw² (module docstring)."""
    x, w = _positive_samples(amplitudes, weights, field)
    n_distinct = np.unique(x).size
    if x.size < MIN_SAMPLES or n_distinct < 2:
        raise InputError(
            field,
            f"{x.size} positive amplitudes, {n_distinct} distinct",
            allowed=f"at least {MIN_SAMPLES} positive amplitudes, not all equal",
        )
    top = x.max()
    log_x = np.log(x / top)  # scaled: x^k stays ≤ 1 for any k

    def mean(values: np.ndarray) -> float:
        return values.mean() if w is None else np.sum(w * values) / np.sum(w)

    def profile(k: float) -> float:
        power = np.exp(k * log_x) if w is None else w * np.exp(k * log_x)
        return float(np.sum(power * log_x) / np.sum(power) - 1.0 / k - mean(log_x))

    low, high = 1e-3, 1.0
    while profile(high) < 0.0 and high < 1e3:
        high *= 2.0
    from scipy.optimize import brentq

    k = brentq(profile, low, high, xtol=1e-12)
    scale = top * float(mean(np.exp(k * log_x))) ** (1.0 / k)
    n_eff = x.size if w is None else float(np.sum(w) ** 2 / np.sum(w**2))
    info = n_eff * np.array(
        [
            [((1.0 - EULER_GAMMA) ** 2 + math.pi**2 / 6.0) / k**2, -(1.0 - EULER_GAMMA)],
            [-(1.0 - EULER_GAMMA), k**2],
        ]
    )
    cov = np.linalg.inv(info)
    return RuleFormFit(
        float(k), float(scale), int(x.size), tuple(map(tuple, cov.tolist())), None if w is None else n_eff
    )


def rule_n_ice(
    polar_class: str,
    revolutions_per_s: float,
    k1: float = 1.0,
    k2: float = 1.0,
    k3: float = 1.0,
    k4: float = 1.0,
) -> float:
    """N_ice = k_1 k_2 k_3 k_4 N_class n: load cycles per blade (UR I3 as recalled, notes §7.4)."""
    key = str(polar_class).strip().upper()
    if key not in N_CLASS:
        raise InputError("polar_class", f"unknown polar class {polar_class!r}", allowed=", ".join(N_CLASS))
    require_range("revolutions_per_s", revolutions_per_s, low=0.0, low_inclusive=True, unit="1/s")
    for name, k in (("k1", k1), ("k2", k2), ("k3", k3), ("k4", k4)):
        require_range(f"rule.{name}", k, low=0.0)
    return k1 * k2 * k3 * k4 * N_CLASS[key] * revolutions_per_s


def submersion_parameter(shaft_depth_m: float, ice_thickness_m: float, diameter_m: float) -> float:
    """f = (h_0 − H_ice)/(D/2) − 1 (notes §7.4): h_0 the propeller centreline's depth [m]."""
    require_range("rule.shaft_depth_m", shaft_depth_m, low=0.0, unit="m")
    require_range("propeller.diameter_m", diameter_m, low=0.0, unit="m")
    return (shaft_depth_m - ice_thickness_m) / (0.5 * diameter_m) - 1.0


def submersion_factor(f: float) -> float:
    """k_2 of the submersion parameter f (notes §7.4, as recalled): 0.8 − f (f < 0), 0.8 − 0.4 f
    (0 ≤ f ≤ 1), 0.6 − 0.2 f (1 < f ≤ 2.5), 0.1 (f > 2.5)."""
    if not math.isfinite(f):
        raise InputError("rule.submersion_f", f"{f!r}", value=f, allowed="finite")
    if f < 0.0:
        return 0.8 - f
    if f <= 1.0:
        return 0.8 - 0.4 * f
    if f <= 2.5:
        return 0.6 - 0.2 * f
    return 0.1


@dataclass(frozen=True)
class RuleArrangement:
    """Where the propeller sits, for the rule's N_ice: location ("centre" or "wing", k_1), the depth of its
    centreline [m] (k_2) and the machinery ("fixed" or "azimuthing", k_3). Default: the Agulhas II, two wing
    propellers on fixed shafts at 5.25 m (assumed, `floebreak.ship.agulhas_ii.SHAFT_DEPTH_M`)."""

    location: str = "wing"
    shaft_depth_m: float = SHAFT_DEPTH_M
    machinery: str = "fixed"

    def __post_init__(self) -> None:
        if self.location not in LOCATION_FACTORS:
            raise InputError("rule.location", f"{self.location!r}", allowed=", ".join(LOCATION_FACTORS))
        if self.machinery not in MACHINERY_FACTORS:
            raise InputError("rule.machinery", f"{self.machinery!r}", allowed=", ".join(MACHINERY_FACTORS))
        require_range("rule.shaft_depth_m", self.shaft_depth_m, low=0.0, unit="m")


@dataclass(frozen=True)
class RuleLoadCount:
    """The rule's N_ice per blade with its factors; low and high differ only by k_1 of a wing propeller."""

    polar_class: str
    n_class: float
    revolutions_per_s: float
    blades: int
    location: str
    k1: tuple[float, float]
    submersion_f: float
    k2: float
    k3: float
    k4: float

    def n_ice(self, k1: float) -> float:
        return rule_n_ice(self.polar_class, self.revolutions_per_s, k1, self.k2, self.k3, self.k4)

    @property
    def n_ice_low(self) -> float:
        """Load cycles per blade over the life at the lower k_1."""
        return self.n_ice(self.k1[0])

    @property
    def n_ice_high(self) -> float:
        return self.n_ice(self.k1[1])

    def as_dict(self) -> dict:
        return {
            "unit": "load cycles per blade over the ship's life (Z × on one propeller)",
            "polar_class": self.polar_class,
            "n_class": self.n_class,
            "revolutions_per_s": self.revolutions_per_s,
            "blades": self.blades,
            "location": self.location,
            "k1_low_high": list(self.k1),
            "submersion_f": self.submersion_f,
            "k2": self.k2,
            "k3": self.k3,
            "k4": self.k4,
            "k4_note": K4_NOTE,
            "n_ice_per_blade_low": self.n_ice_low,
            "n_ice_per_blade_high": self.n_ice_high,
            "source": "IACS UR I3 as recalled (physics-notes §7.4); verify against the rule text",
        }


def rule_load_count(
    polar_class: str, spec: PropellerSpec, arrangement: RuleArrangement | None = None
) -> RuleLoadCount:
    """The rule's N_ice of the propeller `spec` in `arrangement` (module docstring)."""
    key = check_polar_class(polar_class)
    where = RuleArrangement() if arrangement is None else arrangement
    f = submersion_parameter(where.shaft_depth_m, POLAR_CLASSES[key][0], spec.diameter_m)
    return RuleLoadCount(
        key,
        N_CLASS[key],
        spec.revolutions_per_s,
        int(spec.blades),
        where.location,
        LOCATION_FACTORS[where.location],
        f,
        submersion_factor(f),
        MACHINERY_FACTORS[where.machinery],
        1.0,
    )


def result_load_count(result) -> RuleLoadCount | None:
    """The rule's N_ice of a propeller analysis' result (its polar class, propeller and the arrangement in its
    options), None without a polar class."""
    if result.rule is None:
        return None
    where = RuleArrangement(**result.options.get("rule_arrangement", {}))
    return rule_load_count(result.rule.polar_class, result.propeller, where)


def rule_impacts_per_cusp(thickness_m, blades: int) -> np.ndarray:
    """Z·N_Q blade impacts on the propeller per cusp milled, N_Q = 2 h revolutions (h in m; notes §7.3),
    at least 1."""
    h = np.asarray(thickness_m, dtype=float)
    return np.maximum(1, np.rint(blades * 2.0 * h)).astype(np.int64)


@dataclass(frozen=True)
class OperatingProfile:
    """Hours in ice per year and years in service, for the lifetime number of loads."""

    hours_in_ice_per_year: float
    years: float

    def __post_init__(self) -> None:
        require_range("hours_in_ice_per_year", self.hours_in_ice_per_year, low=0.0, high=8766.0, unit="h")
        require_range("years", self.years, low=0.0, high=100.0, unit="a")  # ships serve 20–40 years

    @property
    def hours(self) -> float:
        return self.hours_in_ice_per_year * self.years


@dataclass(frozen=True)
class BasquinCurve:
    """S–N curve of a load amplitude: N(x) = n_ref (x_ref / x)^m cycles to failure (Basquin), x in SI."""

    exponent_m: float
    reference_amplitude: float
    reference_cycles: float
    quantity: str = "torque"

    def __post_init__(self) -> None:
        require_range("sn_curve.exponent_m", self.exponent_m, low=0.0)
        require_range("sn_curve.reference_amplitude", self.reference_amplitude, low=0.0)
        require_range("sn_curve.reference_cycles", self.reference_cycles, low=0.0)
        if self.quantity not in ("force", "torque"):
            raise InputError("sn_curve.quantity", f"unknown {self.quantity!r}", allowed="force, torque")

    def cycles_to_failure(self, amplitude) -> np.ndarray:
        a = np.abs(np.asarray(amplitude, dtype=float))
        with np.errstate(divide="ignore"):
            return self.reference_cycles * (self.reference_amplitude / a) ** self.exponent_m


def miner_damage(amplitudes, curve: BasquinCurve, cycles=1.0) -> float:
    """Palmgren–Miner sum D = Σ n_i / N(x_i) over the finite amplitudes > 0, amplitude i counted `cycles`
    (a number or one per amplitude, e.g. loads per cusp on one propeller) times."""
    a = np.abs(np.asarray(amplitudes, dtype=float))
    n = np.broadcast_to(np.asarray(cycles, dtype=float), a.shape)
    keep = np.isfinite(a) & (a > 0.0)
    return float(np.sum(n[keep] / curve.cycles_to_failure(a[keep])))
