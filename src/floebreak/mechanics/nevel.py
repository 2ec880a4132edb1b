"""Nevel's narrow free infinite wedge on a Winkler foundation (physics-notes §1; thesis §4.1, Eq. 11).

A wedge of opening θ, truncated at the loading radius r, carries the vertical load P spread along the
arc x = r. Tangential bending is neglected (width b = θ x), so with ξ = x/ℓ, ρ = r/ℓ and
w = (P ℓ²/(D θ)) W(ξ) the problem is (physics-notes Eq. 1.2)

    (ξ W'')'' + ξ W = 0 ,   W''(ρ) = 0 ,   (ξ W'')'(ρ) = 1 ,   W, W' → 0 (ξ → ∞)

with M = −P ℓ ξ W'' and the surface stress σ = −(6 P/(θ h²)) W''. From the solution:

* S(ρ) = max |W''| — stress factor, σ_max = 6 P S/(θ h²)                    (Eq. 1.3)
* ξ_σ(ρ) — location of the stress maximum, measured from the apex, in units of ℓ   (Eq. 1.5)
* m_max(ρ) = max |M|/(P ℓ) = max |ξ W''| and its location ξ_M(ρ) from the apex.

`solve_wedge` solves the boundary-value problem with `scipy.integrate.solve_bvp` (physics-notes §1.2).
The shipped table `floebreak/data/nevel_table.csv` (written by `scripts/generate_nevel_table.py`) holds
these four functions on a ρ-grid; the interpolating functions use PCHIP in t = ρ^(1/3), which makes the
small-ρ behaviour S ≈ 1 − a ρ^(2/3), ξ_σ ≈ c ρ^(1/3) smooth (physics-notes §1.1, §1.2 step 4). The PCHIP
is `Pchip` (numpy; the same coefficients as scipy's `PchipInterpolator`), and scipy is imported only to
solve the wedge, so reading the table does not import `scipy.interpolate`/`scipy.integrate` at start-up.

Out of range: ρ < 0 (and non-finite ρ) raise InputError. ρ = 0 is the analytic point-load limit
(S = 1, ξ_σ = 0). Beyond the last table point ρ_max the functions continue with the semi-infinite beam
asymptote (physics-notes §1.1 "Confidence" paragraph) plus a 1/ρ correction matched at ρ_max:

    ρ S → e^(−π/4),   m_max → e^(−π/4),   ξ_σ − ρ → π/(2√2),   ξ_M − ρ → π/(2√2)   (ρ → ∞).

Capacity models (physics-notes §1.5, errata 11 and 13): see `bearing_capacity_n`.
"""

from __future__ import annotations

import bisect
import functools
import importlib.resources
import math
from dataclasses import dataclass
from typing import Final, Literal

import numpy as np
from numpy.typing import ArrayLike

from floebreak import constants as c
from floebreak.errors import InputError, require_range
from floebreak.ice.material import characteristic_length_m, characteristic_length_scalar_m

CapacityModel = Literal["nevel_narrow", "kashtelyan", "thesis_per_wedge"]
BreakingDistanceMode = Literal["max_stress", "max_moment"]

CAPACITY_MODELS: Final = ("nevel_narrow", "kashtelyan", "thesis_per_wedge")
BREAKING_DISTANCE_MODES: Final = ("max_stress", "max_moment")

# Semi-infinite beam limit (ρ → ∞) of the narrow wedge: |M|max = e^(−π/4) P ℓ at π/(2√2) ℓ from the load.
BEAM_LIMIT_MAX_MOMENT: Final = math.exp(-math.pi / 4.0)
BEAM_LIMIT_MAX_MOMENT_OFFSET: Final = math.pi / (2.0 * math.sqrt(2.0))

KASHTELYAN_COEFFICIENT: Final = 3.0  # C_f, physics-notes §1.5 [recalled, confidence low–medium]
THESIS_WEDGE_ANGLE_RAD: Final = math.radians(c.WEDGE_ANGLE_DEG)  # φ = 5°, thesis §4.1.2

# Solver settings (physics-notes §1.2)
DOMAIN_LENGTH: Final = 24.0  # solve on [ρ, ρ + 24]; the decaying mode is ≈ e^(−ξ/√2)
SOLVER_TOLERANCE: Final = 1e-8

TABLE_RESOURCE: Final = "nevel_table.csv"
TABLE_COLUMNS: Final = ("rho", "stress_factor_S", "xi_sigma", "xi_sigma_minus_rho", "m_max", "xi_M")


# --------------------------------------------------------------------------------------------------
# Boundary-value problem
# --------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class WedgeSolution:
    """Solution of Eq. 1.2 for one ρ = r/ℓ. All quantities are dimensionless (physics-notes §1.1).

    Arrays are on the solver mesh `xi` (from the apex, units of ℓ):
    ``deflection`` W, ``slope`` W', ``curvature`` W'' (σ = −6P/(θh²)·W''), ``moment`` u = ξW''
    (M = −Pℓ·u), ``shear`` u' ((ξW'')', = 1 at the loaded arc).
    """

    rho: float
    xi: np.ndarray
    deflection: np.ndarray
    slope: np.ndarray
    curvature: np.ndarray
    moment: np.ndarray
    shear: np.ndarray
    stress_factor: float  # S = max |W''|
    max_stress_distance: float  # ξ_σ
    max_moment: float  # m_max = max |ξ W''|
    max_moment_distance: float  # ξ_M
    converged: bool
    message: str


def _rhs(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """y = [W, W', u, u'] with u = ξW'': y' = [W', u/ξ, u', −ξW] (physics-notes §1.2 step 1).

    At ξ = 0 (only reached for ρ = 0) W'' = lim u/ξ = u'(0).
    """
    w, wp, u, up = y
    positive = x > 0.0
    safe_x = np.where(positive, x, 1.0)
    wpp = np.where(positive, u / safe_x, up)
    return np.vstack([wp, wpp, up, -x * w])


def _rhs_jacobian(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    n = x.size
    jac = np.zeros((4, 4, n))
    positive = x > 0.0
    safe_x = np.where(positive, x, 1.0)
    jac[0, 1] = 1.0
    jac[1, 2] = np.where(positive, 1.0 / safe_x, 0.0)
    jac[1, 3] = np.where(positive, 0.0, 1.0)
    jac[2, 3] = 1.0
    jac[3, 0] = -x
    return jac


def _bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
    """u(ρ) = 0 (M = 0), u'(ρ) = 1 (unit shear), W = W' = 0 at ρ + L (physics-notes §1.2 step 2)."""
    return np.array([ya[2], ya[3] - 1.0, yb[0], yb[1]])


def _bc_jacobian(ya: np.ndarray, yb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    dya = np.zeros((4, 4))
    dyb = np.zeros((4, 4))
    dya[0, 2] = 1.0
    dya[1, 3] = 1.0
    dyb[2, 0] = 1.0
    dyb[3, 1] = 1.0
    return dya, dyb


def _refine_max(func, xs: np.ndarray, values: np.ndarray) -> tuple[float, float]:
    """Location and value of max |func| sampled as `values` on `xs`, refined by bounded Brent search."""
    from scipy.optimize import minimize_scalar  # only for solving (regenerating the table): not at start-up

    i = int(np.argmax(np.abs(values)))
    lo = xs[max(i - 1, 0)]
    hi = xs[min(i + 1, xs.size - 1)]
    if hi <= lo:
        return float(xs[i]), float(abs(values[i]))
    res = minimize_scalar(
        lambda s: -abs(func(s)), bounds=(lo, hi), method="bounded", options={"xatol": 1e-10}
    )
    if -res.fun >= abs(values[i]):
        return float(res.x), float(-res.fun)
    return float(xs[i]), float(abs(values[i]))


def solve_wedge(
    rho0: float,
    *,
    domain_length: float = DOMAIN_LENGTH,
    tol: float = SOLVER_TOLERANCE,
    n_near: int = 400,
    n_far: int = 400,
) -> WedgeSolution:
    """Solve the narrow-wedge boundary-value problem (physics-notes Eq. 1.2, §1.2) for ρ0 = r/ℓ ≥ 0.

    Mesh: geometric near the loaded arc (ρ0 + geomspace(δ, 1)), then uniform to ρ0 + `domain_length`.
    S, ξ_σ, m_max and ξ_M are extracted on a dense resampling of the collocation solution and refined
    with a bounded scalar search. ρ0 = 0 is solved directly (the ξ = 0 limit W'' = u' is built into the
    right-hand side); there S = 1 and ξ_σ = 0 exactly.
    """
    from scipy.integrate import solve_bvp  # only for solving (regenerating the table): not at start-up

    rho = require_range("rho0", rho0, low=0.0, low_inclusive=True, high=1e6)
    require_range("domain_length", domain_length, low=4.0)
    sol = None
    # first try the physics-notes §1.2 mesh; if the collocation does not converge (it can for ρ ≲ 1e-4,
    # where W'' has a boundary layer of width ~ρ), retry with other near-apex spacings
    for first_over_rho, nodes in ((0.1, n_near), (0.01, n_near), (0.1, 2 * n_near), (1e-3, n_near)):
        first = min(1e-5, first_over_rho * rho) if rho > 0.0 else 1e-4
        near = rho + np.concatenate([[0.0], np.geomspace(first, 1.0, nodes)])
        far = np.linspace(rho + 1.0, rho + domain_length, n_far)[1:]
        mesh = np.concatenate([near, far])
        # initial guess: the beam-like decaying shape u ≈ s e^(−s/√2), s = ξ − ρ
        s = mesh - rho
        decay = np.exp(-s / math.sqrt(2.0))
        guess = np.zeros((4, mesh.size))
        guess[2] = s * decay
        guess[3] = (1.0 - s / math.sqrt(2.0)) * decay
        sol = solve_bvp(
            _rhs, _bc, mesh, guess, fun_jac=_rhs_jacobian, bc_jac=_bc_jacobian, tol=tol, max_nodes=20_000
        )
        if sol.success:
            break

    def curvature(xi):
        y = sol.sol(xi)
        xi = np.asarray(xi, dtype=float)
        return np.where(xi > 0.0, y[2] / np.where(xi > 0.0, xi, 1.0), y[3])

    def moment(xi):
        return sol.sol(xi)[2]

    start = max(1e-3 * rho, 1e-12) if rho > 0.0 else 1e-12
    dense = np.concatenate(
        [[rho], rho + np.geomspace(start, 1.0, 4000), np.linspace(rho + 1.0, rho + domain_length, 4000)[1:]]
    )
    if rho == 0.0:
        xi_sigma, s_max = 0.0, 1.0  # W''(0) = u'(0) = 1: the analytic point-load limit
    else:
        xi_sigma, s_max = _refine_max(curvature, dense, curvature(dense))
    xi_m, m_max = _refine_max(moment, dense, moment(dense))

    y = sol.y
    xi_mesh = sol.x
    return WedgeSolution(
        rho=rho,
        xi=xi_mesh,
        deflection=y[0],
        slope=y[1],
        curvature=curvature(xi_mesh),
        moment=y[2],
        shear=y[3],
        stress_factor=s_max,
        max_stress_distance=xi_sigma,
        max_moment=m_max,
        max_moment_distance=xi_m,
        converged=bool(sol.success),
        message=str(sol.message),
    )


# --------------------------------------------------------------------------------------------------
# Shipped table and interpolation
# --------------------------------------------------------------------------------------------------


def parse_table(text: str) -> dict[str, np.ndarray]:
    """Parse the CSV format of `nevel_table.csv`: '#' comment lines, one header line, float rows."""
    lines = [line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#")]
    header = [name.strip() for name in lines[0].split(",")]
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]], dtype=float)
    return {name: rows[:, j] for j, name in enumerate(header)}


@functools.lru_cache(maxsize=1)
def load_table() -> dict[str, np.ndarray]:
    """The shipped dimensionless Nevel table (read-only arrays, cached)."""
    text = importlib.resources.files("floebreak.data").joinpath(TABLE_RESOURCE).read_text(encoding="utf-8")
    table = parse_table(text)
    for arr in table.values():
        arr.setflags(write=False)
    return table


@dataclass(frozen=True, eq=False)
class Pchip:
    """Monotone piecewise-cubic Hermite interpolant (Fritsch–Carlson), the same as SciPy's
    `PchipInterpolator` for 1-D data, without importing `scipy.interpolate` at start-up.

    Derivatives: zero where the neighbouring slopes differ in sign or one is zero, else the weighted
    harmonic mean of the two slopes (w₁ = 2h_k + h_(k−1), w₂ = h_k + 2h_(k−1)); at the ends the one-sided
    three-point estimate, set to zero if its sign differs from the end slope's and limited to 3× the end
    slope where the first two slopes differ in sign (Moler, *Numerical Computing with MATLAB* §3.6; SciPy's
    `_edge_case`). Coefficients of each interval highest power first (SciPy's `PPoly` layout), computed with
    the operations of SciPy's `CubicHermiteSpline`, so they are the same floats. Evaluation outside
    [x₀, x_(n−1)] extrapolates with the end pieces.
    """

    x: np.ndarray  # breakpoints, strictly increasing, at least three
    c: np.ndarray  # (4, n − 1): c[0] s³ + c[1] s² + c[2] s + c[3], s = t − x_i on [x_i, x_(i+1))

    @classmethod
    def fit(cls, x: ArrayLike, y: ArrayLike) -> Pchip:
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        if x.ndim != 1 or x.shape != y.shape or x.size < 3:
            raise ValueError("Pchip.fit needs 1-D x and y of the same length, at least three points")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise ValueError("Pchip.fit needs finite x and y")
        h = np.diff(x)
        if np.any(h <= 0.0):
            raise ValueError("Pchip.fit needs strictly increasing x")
        m = (y[1:] - y[:-1]) / h
        sign = np.sign(m)
        flat = (sign[1:] != sign[:-1]) | (m[1:] == 0.0) | (m[:-1] == 0.0)
        w1 = 2.0 * h[1:] + h[:-1]
        w2 = h[1:] + 2.0 * h[:-1]
        with np.errstate(divide="ignore", invalid="ignore"):  # only where `flat`, which is not used
            harmonic = (w1 / m[:-1] + w2 / m[1:]) / (w1 + w2)
        d = np.zeros_like(y)
        d[1:-1][~flat] = 1.0 / harmonic[~flat]
        d[0] = _pchip_end_slope(h[0], h[1], m[0], m[1])
        d[-1] = _pchip_end_slope(h[-1], h[-2], m[-1], m[-2])
        t = (d[:-1] + d[1:] - 2.0 * m) / h
        return cls(x=x, c=np.stack((t / h, (m - d[:-1]) / h - t, d[:-1], y[:-1])))

    def __call__(self, t: ArrayLike) -> np.ndarray:
        """Values at `t` (array): s = t − x_i in the interval x_i ≤ t < x_(i+1) (the end pieces outside),
        c[3] + c[2] s + c[1] s² + c[0] s³ summed in that order, as `_pchip_at` and SciPy's `PPoly`."""
        t = np.asarray(t, dtype=float)
        i = np.clip(np.searchsorted(self.x, t, side="right") - 1, 0, self.x.size - 2)
        s = t - self.x[i]
        s2 = s * s
        c0, c1, c2, c3 = self.c[:, i]
        return c3 + c2 * s + c1 * s2 + c0 * (s2 * s)


def _pchip_end_slope(h0: float, h1: float, m0: float, m1: float) -> float:
    """One-sided three-point derivative at an end of a PCHIP, shape-preserving (`Pchip`)."""
    d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    if np.sign(d) != np.sign(m0):
        return 0.0
    if np.sign(m0) != np.sign(m1) and abs(d) > 3.0 * abs(m0):
        return 3.0 * m0
    return d


@dataclass(frozen=True)
class _Interpolants:
    rho_max: float
    stress_factor: Pchip
    xi_sigma_offset: Pchip  # ξ_σ − ρ
    max_moment: Pchip
    xi_m_offset: Pchip  # ξ_M − ρ
    # 1/ρ corrections of the beam asymptote, matched at rho_max
    tail_stress: float
    tail_xi_sigma: float
    tail_moment: float
    tail_xi_m: float
    # the same four PCHIPs as plain floats for one-point evaluation (`_pchip_at`): the breakpoints in
    # t = ρ^(1/3) (shared) and, per function ("S", "xi_sigma", "m_max", "xi_M"), the cubic coefficients of
    # each interval, highest power first (scipy's PPoly layout)
    knots: tuple[float, ...]
    pieces: dict[str, tuple[tuple[float, float, float, float], ...]]


@functools.lru_cache(maxsize=1)
def _interpolants() -> _Interpolants:
    table = load_table()
    rho = table["rho"]
    t = np.cbrt(rho)
    rho_max = float(rho[-1])
    s_end = float(table["stress_factor_S"][-1])
    xs_end = float(table["xi_sigma"][-1]) - rho_max
    m_end = float(table["m_max"][-1])
    xm_end = float(table["xi_M"][-1]) - rho_max
    interpolants = {
        "S": Pchip.fit(t, table["stress_factor_S"]),
        "xi_sigma": Pchip.fit(t, table["xi_sigma"] - rho),
        "m_max": Pchip.fit(t, table["m_max"]),
        "xi_M": Pchip.fit(t, table["xi_M"] - rho),
    }
    return _Interpolants(
        rho_max=rho_max,
        stress_factor=interpolants["S"],
        xi_sigma_offset=interpolants["xi_sigma"],
        max_moment=interpolants["m_max"],
        xi_m_offset=interpolants["xi_M"],
        tail_stress=(rho_max * s_end - BEAM_LIMIT_MAX_MOMENT) * rho_max,
        tail_xi_sigma=(xs_end - BEAM_LIMIT_MAX_MOMENT_OFFSET) * rho_max,
        tail_moment=(m_end - BEAM_LIMIT_MAX_MOMENT) * rho_max,
        tail_xi_m=(xm_end - BEAM_LIMIT_MAX_MOMENT_OFFSET) * rho_max,
        knots=tuple(float(v) for v in interpolants["S"].x),
        pieces={name: tuple(map(tuple, pp.c.T.tolist())) for name, pp in interpolants.items()},
    )


def _check_rho(rho: ArrayLike) -> np.ndarray:
    arr = np.asarray(rho, dtype=float)
    bad = ~np.isfinite(arr) | (arr < 0.0)
    if np.any(bad):
        value = float(arr[bad].flat[0])
        raise InputError("rho", f"{value:g} is not a finite value ≥ 0", value=value, allowed="[0, inf)")
    return arr


def _pchip_at(knots: tuple[float, ...], pieces: tuple[tuple[float, ...], ...], t: float) -> float:
    """One value of a PCHIP from its cubic pieces: the operations of scipy's `PPoly` evaluation (interval
    x_i ≤ t < x_(i+1), extrapolating with the end pieces; c3 + c2 s + c1 s² + c0 s³ summed in that order,
    s = t − x_i), so the float is the same, without scipy's per-call array overhead."""
    i = min(max(bisect.bisect_right(knots, t) - 1, 0), len(knots) - 2)
    c0, c1, c2, c3 = pieces[i]
    s = t - knots[i]
    s2 = s * s
    return c3 + c2 * s + c1 * s2 + c0 * (s2 * s)


def _evaluate_scalar(rho: float, which: str) -> float:
    """`_evaluate` for one ρ ≥ 0 given as a float (the hot path of the bending check): the same formulas."""
    ip = _interpolants()
    if rho <= ip.rho_max:
        value = _pchip_at(ip.knots, ip.pieces[which], float(np.cbrt(rho)))
    elif which == "S":
        return (BEAM_LIMIT_MAX_MOMENT + ip.tail_stress / rho) / rho
    elif which == "xi_sigma":
        value = BEAM_LIMIT_MAX_MOMENT_OFFSET + ip.tail_xi_sigma / rho
    elif which == "m_max":
        return BEAM_LIMIT_MAX_MOMENT + ip.tail_moment / rho
    else:
        value = BEAM_LIMIT_MAX_MOMENT_OFFSET + ip.tail_xi_m / rho
    if which == "xi_sigma":
        return 0.0 if rho == 0.0 else rho + value
    if which == "xi_M":
        return rho + value
    return value


def _evaluate(rho: ArrayLike, which: str) -> np.ndarray | float:
    arr = _check_rho(rho)
    if arr.ndim == 0:
        return _evaluate_scalar(float(arr), which)
    ip = _interpolants()
    inside = arr <= ip.rho_max
    t = np.cbrt(np.where(inside, arr, ip.rho_max))
    big = np.where(inside, ip.rho_max, arr)  # only used where ρ > ρ_max
    if which == "S":
        out = np.where(inside, ip.stress_factor(t), (BEAM_LIMIT_MAX_MOMENT + ip.tail_stress / big) / big)
    elif which == "xi_sigma":
        tail = BEAM_LIMIT_MAX_MOMENT_OFFSET + ip.tail_xi_sigma / big
        out = arr + np.where(inside, ip.xi_sigma_offset(t), tail)
        out = np.where(arr == 0.0, 0.0, out)
    elif which == "m_max":
        out = np.where(inside, ip.max_moment(t), BEAM_LIMIT_MAX_MOMENT + ip.tail_moment / big)
    else:
        out = arr + np.where(inside, ip.xi_m_offset(t), BEAM_LIMIT_MAX_MOMENT_OFFSET + ip.tail_xi_m / big)
    return out


def stress_factor(rho: ArrayLike) -> np.ndarray | float:
    """S(ρ) = max |W''| (physics-notes Eq. 1.3, table §1.3): σ_max = 6 P S/(θ h²). S(0) = 1."""
    return _evaluate(rho, "S")


def max_stress_distance(rho: ArrayLike) -> np.ndarray | float:
    """ξ_σ(ρ): distance of the stress maximum from the apex, in ℓ (physics-notes Eq. 1.5). ξ_σ(0) = 0."""
    return _evaluate(rho, "xi_sigma")


def max_moment(rho: ArrayLike) -> np.ndarray | float:
    """m_max(ρ) = max |M|/(P ℓ) (physics-notes §1.3 table)."""
    return _evaluate(rho, "m_max")


def max_moment_distance(rho: ArrayLike) -> np.ndarray | float:
    """ξ_M(ρ): distance of the moment maximum from the apex, in ℓ (physics-notes §1.3; erratum 11)."""
    return _evaluate(rho, "xi_M")


# --------------------------------------------------------------------------------------------------
# Dimensional results
# --------------------------------------------------------------------------------------------------


def _require_array(field: str, value: ArrayLike, *, low: float, low_inclusive: bool, unit: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    ok = np.isfinite(arr) & ((arr >= low) if low_inclusive else (arr > low))
    if not np.all(ok):
        bad = float(arr[~ok].flat[0])
        interval = f"{'[' if low_inclusive else '('}{low:g}, inf) {unit}".rstrip()
        raise InputError(field, f"{bad:g} is outside {interval}", value=bad, allowed=interval)
    return arr


def _as_output(arr: np.ndarray) -> np.ndarray | float:
    return float(arr) if np.ndim(arr) == 0 else arr


def bearing_capacity_n(
    thickness_m: ArrayLike,
    loading_radius_m: ArrayLike,
    opening_rad: ArrayLike,
    *,
    model: CapacityModel = "nevel_narrow",
    flexural_strength_pa: float = c.FLEXURAL_STRENGTH_PA,
    kashtelyan_coefficient: float = KASHTELYAN_COEFFICIENT,
    wedge_angle_rad: float = THESIS_WEDGE_ANGLE_RAD,
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> np.ndarray | float:
    """Vertical load [N] at which the ice fan of opening Θ = `opening_rad` fails in bending.

    * ``"nevel_narrow"`` (default): P_f = σ_f Θ h² / (6 S(r/ℓ)), physics-notes Eq. 1.4 with Θ the
      opening of the intact-ice fan (§1.5 recommendation, §2.5 step 5, erratum 13).
    * ``"kashtelyan"``: P_f = C_f (Θ/π)² σ_f h², C_f = `kashtelyan_coefficient` (default 3.0; §1.5).
      Independent of r.
    * ``"thesis_per_wedge"``: the thesis-literal capacity of ONE wedge of the discretisation angle
      φ = `wedge_angle_rad` (thesis Eq. 11/§4.1.2, erratum 13): P = σ_f φ h² / (6 S(r/ℓ)), independent
      of Θ. Evaluated directly from Eq. 1.4 instead of Erceg's tables (§1.7: no corner averaging, no h-index
      bug, P → 0 as h → 0, result in N not kN). Comparing the total F_v with it reproduces the thesis'
      "capacity reached in one wedge" (floes break at ≈ 8 kN for h = 1 m).

    ℓ = (D/k)^(1/4), D = E h³/(12(1 − ν²)) (thesis Eq. 1). Inputs broadcast as numpy arrays.
    """
    if model not in CAPACITY_MODELS:
        raise InputError(
            "model",
            f"unknown bending capacity model {model!r}",
            value=model,
            allowed=", ".join(CAPACITY_MODELS),
        )
    h = _require_array("thickness_m", thickness_m, low=0.0, low_inclusive=False, unit="m")
    r = _require_array("loading_radius_m", loading_radius_m, low=0.0, low_inclusive=True, unit="m")
    theta = _require_array("opening_rad", opening_rad, low=0.0, low_inclusive=False, unit="rad")
    if np.any(theta > 2.0 * math.pi):
        bad = float(theta[theta > 2.0 * math.pi].flat[0])
        raise InputError("opening_rad", f"{bad:g} exceeds 2π", value=bad, allowed="(0, 2π] rad")
    sigma_f = require_range("flexural_strength_pa", flexural_strength_pa, low=0.0, unit="Pa")
    if model == "kashtelyan":
        c_f = require_range("kashtelyan_coefficient", kashtelyan_coefficient, low=0.0)
        out = c_f * (theta / math.pi) ** 2 * sigma_f * h**2 * np.ones_like(r)
        return _as_output(out)
    if model == "thesis_per_wedge":
        angle = require_range("wedge_angle_rad", wedge_angle_rad, low=0.0, high=2.0 * math.pi, unit="rad")
        theta = np.full_like(theta, angle)
    ell = characteristic_length_m(h, youngs_modulus_pa, poisson_ratio, foundation_modulus)
    out = sigma_f * theta * h**2 / (6.0 * np.asarray(stress_factor(r / ell)))
    return _as_output(out)


def breaking_distance_from_apex_m(
    thickness_m: ArrayLike,
    loading_radius_m: ArrayLike,
    *,
    mode: BreakingDistanceMode = "max_stress",
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> np.ndarray | float:
    """Distance [m] of the breaking line from the wedge apex O: ξ(r/ℓ) · ℓ (physics-notes §1.6, §2.5 step 6).

    ``"max_stress"`` (default): ξ_σ, the maximum bending stress (physics-notes Eq. 1.5).
    ``"max_moment"``: ξ_M, the thesis-literal "maximum bending moment" of §4.1.2 (erratum 11, ≈ 1.6 ℓ).
    The breaking length from the loaded edge is this distance minus r.
    """
    if mode not in BREAKING_DISTANCE_MODES:
        raise InputError(
            "mode",
            f"unknown breaking-length mode {mode!r}",
            value=mode,
            allowed=", ".join(BREAKING_DISTANCE_MODES),
        )
    h = _require_array("thickness_m", thickness_m, low=0.0, low_inclusive=False, unit="m")
    r = _require_array("loading_radius_m", loading_radius_m, low=0.0, low_inclusive=True, unit="m")
    ell = characteristic_length_m(h, youngs_modulus_pa, poisson_ratio, foundation_modulus)
    xi = max_stress_distance(r / ell) if mode == "max_stress" else max_moment_distance(r / ell)
    return _as_output(np.asarray(xi) * ell)


def capacity_and_breaking_distance(
    thickness_m: float,
    loading_radius_m: float,
    opening_rad: float,
    *,
    model: CapacityModel = "nevel_narrow",
    mode: BreakingDistanceMode = "max_stress",
    flexural_strength_pa: float = c.FLEXURAL_STRENGTH_PA,
    kashtelyan_coefficient: float = KASHTELYAN_COEFFICIENT,
    wedge_angle_rad: float = THESIS_WEDGE_ANGLE_RAD,
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> tuple[float, float]:
    """(`bearing_capacity_n`, `breaking_distance_from_apex_m`) for one contact, as floats.

    The bending check's hot path: the same equations in the same order (P_f = σ_f Θ h² / (6 S(ρ)),
    physics-notes Eq. 1.4 and §1.5; distance ξ_σ(ρ) ℓ or ξ_M(ρ) ℓ, Eq. 1.5 and §1.6), so the same floats,
    with ℓ cached per thickness and ρ = r/ℓ computed once. Inputs outside the public functions' ranges
    (and unknown model names) are passed to them, which raise the `InputError`.
    """
    h, r, theta = float(thickness_m), float(loading_radius_m), float(opening_rad)
    valid = (
        0.0 < h < math.inf
        and 0.0 <= r < math.inf
        and 0.0 < theta <= 2.0 * math.pi
        and model in CAPACITY_MODELS
        and mode in BREAKING_DISTANCE_MODES
        and flexural_strength_pa > 0.0
    )
    if not valid:
        capacity = bearing_capacity_n(
            h,
            r,
            theta,
            model=model,
            flexural_strength_pa=flexural_strength_pa,
            kashtelyan_coefficient=kashtelyan_coefficient,
            wedge_angle_rad=wedge_angle_rad,
            youngs_modulus_pa=youngs_modulus_pa,
            poisson_ratio=poisson_ratio,
            foundation_modulus=foundation_modulus,
        )
        distance = breaking_distance_from_apex_m(
            h,
            r,
            mode=mode,
            youngs_modulus_pa=youngs_modulus_pa,
            poisson_ratio=poisson_ratio,
            foundation_modulus=foundation_modulus,
        )
        return float(capacity), float(distance)
    ell = characteristic_length_scalar_m(h, "eq1", youngs_modulus_pa, poisson_ratio, foundation_modulus)
    rho = r / ell
    sigma_f = flexural_strength_pa
    if model == "kashtelyan":
        c_f = require_range("kashtelyan_coefficient", kashtelyan_coefficient, low=0.0)
        ratio = theta / math.pi
        capacity = c_f * ratio**2 * sigma_f * (h * h)  # pow() and h·h, as numpy evaluates the array form
    else:
        if model == "thesis_per_wedge":
            theta = require_range("wedge_angle_rad", wedge_angle_rad, low=0.0, high=2.0 * math.pi, unit="rad")
        capacity = sigma_f * theta * (h * h) / (6.0 * _evaluate_scalar(rho, "S"))
    xi = _evaluate_scalar(rho, "xi_sigma" if mode == "max_stress" else "xi_M")
    return capacity, xi * ell
