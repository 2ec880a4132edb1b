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
small-ρ behaviour S ≈ 1 − a ρ^(2/3), ξ_σ ≈ c ρ^(1/3) smooth (physics-notes §1.1, §1.2 step 4), with
scipy's `PchipInterpolator`.

Out of range: ρ < 0 (and non-finite ρ) raise InputError. ρ = 0 is the analytic point-load limit
(S = 1, ξ_σ = 0). Beyond the last table point ρ_max the functions continue with the semi-infinite beam
asymptote (physics-notes §1.1 "Confidence" paragraph) plus a 1/ρ correction matched at ρ_max:

    ρ S → e^(−π/4),   m_max → e^(−π/4),   ξ_σ − ρ → π/(2√2),   ξ_M − ρ → π/(2√2)   (ρ → ∞).

Capacity models (physics-notes §1.5, errata 11 and 13): see `bearing_capacity_n`.
"""

from __future__ import annotations

import functools
import importlib.resources
import math
from dataclasses import dataclass
from typing import Final, Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator

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
    i = int(np.argmax(np.abs(values)))
    lo = xs[max(i - 1, 0)]
    hi = xs[min(i + 1, xs.size - 1)]
    if hi <= lo:
        return float(xs[i]), float(abs(values[i]))
    from scipy.optimize import minimize_scalar  # here: only the table's generation solves the wedge

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
    # here, not at the top: only the table's generation solves the wedge, and scipy.integrate takes about
    # 0.6 s to import (benchmarks/README.md, "Start-up")
    from scipy.integrate import solve_bvp

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


@dataclass(frozen=True)
class _Interpolants:
    rho_max: float
    # PCHIPs in t = ρ^(1/3) of S, ξ_σ − ρ, m_max and ξ_M − ρ
    stress_factor: PchipInterpolator
    xi_sigma_offset: PchipInterpolator
    max_moment: PchipInterpolator
    xi_m_offset: PchipInterpolator
    # 1/ρ corrections of the beam asymptote, matched at rho_max
    tail_stress: float
    tail_xi_sigma: float
    tail_moment: float
    tail_xi_m: float

    def at(self, rho: float, which: str) -> float:
        """`_evaluate` for one ρ ≥ 0 as a float, for the bending check: the PCHIP's own call on a scalar
        (≈ 8 µs; `_evaluate`'s array handling costs ≈ 36 µs, ≈ 9 % end to end: benchmarks/README.md)."""
        if rho > self.rho_max:
            return float(_evaluate(rho, which))
        pchip = {
            "S": self.stress_factor,
            "xi_sigma": self.xi_sigma_offset,
            "m_max": self.max_moment,
            "xi_M": self.xi_m_offset,
        }[which]
        value = float(pchip(np.cbrt(rho)))
        if which == "xi_sigma":
            return 0.0 if rho == 0.0 else rho + value
        return rho + value if which == "xi_M" else value


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
    return _Interpolants(
        rho_max=rho_max,
        stress_factor=PchipInterpolator(t, table["stress_factor_S"]),
        xi_sigma_offset=PchipInterpolator(t, table["xi_sigma"] - rho),
        max_moment=PchipInterpolator(t, table["m_max"]),
        xi_m_offset=PchipInterpolator(t, table["xi_M"] - rho),
        tail_stress=(rho_max * s_end - BEAM_LIMIT_MAX_MOMENT) * rho_max,
        tail_xi_sigma=(xs_end - BEAM_LIMIT_MAX_MOMENT_OFFSET) * rho_max,
        tail_moment=(m_end - BEAM_LIMIT_MAX_MOMENT) * rho_max,
        tail_xi_m=(xm_end - BEAM_LIMIT_MAX_MOMENT_OFFSET) * rho_max,
    )


def _check_rho(rho: ArrayLike) -> np.ndarray:
    arr = np.asarray(rho, dtype=float)
    bad = ~np.isfinite(arr) | (arr < 0.0)
    if np.any(bad):
        value = float(arr[bad].flat[0])
        raise InputError("rho", f"{value:g} is not a finite value ≥ 0", value=value, allowed="[0, inf)")
    return arr


def _evaluate(rho: ArrayLike, which: str) -> np.ndarray | float:
    arr = _check_rho(rho)
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
    return _as_output(out)


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
        capacity = sigma_f * theta * (h * h) / (6.0 * _interpolants().at(rho, "S"))
    xi = _interpolants().at(rho, "xi_sigma" if mode == "max_stress" else "xi_M")
    return capacity, xi * ell
