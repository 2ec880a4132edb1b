"""The propeller's own operating point: open-water K_T and K_Q of the Wageningen B-series.

K_T = Σ C_T,i J^s (P/D)^t (A_E/A_0)^u Z^v and K_Q = Σ C_Q,i J^s (P/D)^t (A_E/A_0)^u Z^v, with the 39 thrust
and 47 torque terms of Oosterveld & van Oossanen (1975), "Further computer-analyzed data of the Wageningen
B-screw series", International Shipbuilding Progress 22(251), Table 1, at the series' Reynolds number
Re = 2·10⁶ (as tabulated again by Bernitsas, Ray & Kinley 1981, "K_T, K_Q and efficiency curves for the
Wageningen B-series propellers", Univ. of Michigan report 237). The fit holds for 2 ≤ Z ≤ 7,
0.30 ≤ A_E/A_0 ≤ 1.05, 0.5 ≤ P/D ≤ 1.4 and 0 ≤ J up to the advance ratio of zero thrust.

A **given table** replaces the polynomials (`OpenWaterTable`, CLI `--open-water-table CSV`): per pitch ratio
P/D, K_T and K_Q at advance ratios J (e.g. the propeller's own open-water test). K_T and K_Q are interpolated
linearly in J on each tabulated pitch, then linearly in P/D between the two neighbouring pitches; P/D outside
the tabulated pitches and J outside the J range of both neighbouring curves are refused (InputError naming
`propeller.pitch_ratio` or `propeller.advance_ratio`), not extrapolated.

At the advance ratio J = V_A/(n D), V_A = V (1 − w), the propeller's thrust is T = K_T ρ n² D⁴ and its torque
Q = K_Q ρ n² D⁵ (e.g. Carlton, "Marine Propellers and Propulsion", ch. 6). The induced axial velocity at the
disc follows from actuator-disc momentum theory (Rankine–Froude): T = 2 ρ A u_a (V_A + u_a), so
u_a = ½ (√(V_A² + 2T/(ρA)) − V_A), A = π D²/4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import brentq

from floebreak.errors import InputError, require_range

SEA_WATER_DENSITY_KG_M3 = 1025.0  # ITTC 2011 fresh and sea water properties, 15 °C, S = 35 g/kg: 1026 kg/m³

# the B-series fit's validity (Oosterveld & van Oossanen 1975)
PITCH_RATIO_RANGE = (0.5, 1.4)
AREA_RATIO_RANGE = (0.30, 1.05)
BLADES_RANGE = (2, 7)

# (C, s, t, u, v): C · J^s · (P/D)^t · (A_E/A_0)^u · Z^v
KT_TERMS = (
    (0.00880496, 0, 0, 0, 0), (-0.204554, 1, 0, 0, 0), (0.166351, 0, 1, 0, 0),
    (0.158114, 0, 2, 0, 0), (-0.147581, 2, 0, 1, 0), (-0.481497, 1, 1, 1, 0),
    (0.415437, 0, 2, 1, 0), (0.0144043, 0, 0, 0, 1), (-0.0530054, 2, 0, 0, 1),
    (0.0143481, 0, 1, 0, 1), (0.0606826, 1, 1, 0, 1), (-0.0125894, 0, 0, 1, 1),
    (0.0109689, 1, 0, 1, 1), (-0.133698, 0, 3, 0, 0), (0.00638407, 0, 6, 0, 0),
    (-0.00132718, 2, 6, 0, 0), (0.168496, 3, 0, 1, 0), (-0.0507214, 0, 0, 2, 0),
    (0.0854559, 2, 0, 2, 0), (-0.0504475, 3, 0, 2, 0), (0.010465, 1, 6, 2, 0),
    (-0.00648272, 2, 6, 2, 0), (-0.00841728, 0, 3, 0, 1), (0.0168424, 1, 3, 0, 1),
    (-0.00102296, 3, 3, 0, 1), (-0.0317791, 0, 3, 1, 1), (0.018604, 1, 0, 2, 1),
    (-0.00410798, 0, 2, 2, 1), (-0.000606848, 0, 0, 0, 2), (-0.0049819, 1, 0, 0, 2),
    (0.0025983, 2, 0, 0, 2), (-0.000560528, 3, 0, 0, 2), (-0.00163652, 1, 2, 0, 2),
    (-0.000328787, 1, 6, 0, 2), (0.000116502, 2, 6, 0, 2), (0.000690904, 0, 0, 1, 2),
    (0.00421749, 0, 3, 1, 2), (5.65229e-05, 3, 6, 1, 2), (-0.00146564, 0, 3, 2, 2),
)  # fmt: skip
KQ_TERMS = (
    (0.00379368, 0, 0, 0, 0), (0.00886523, 2, 0, 0, 0), (-0.032241, 1, 1, 0, 0),
    (0.00344778, 0, 2, 0, 0), (-0.0408811, 0, 1, 1, 0), (-0.108009, 1, 1, 1, 0),
    (-0.0885381, 2, 1, 1, 0), (0.188561, 0, 2, 1, 0), (-0.00370871, 1, 0, 0, 1),
    (0.00513696, 0, 1, 0, 1), (0.0209449, 1, 1, 0, 1), (0.00474319, 2, 1, 0, 1),
    (-0.00723408, 2, 0, 1, 1), (0.00438388, 1, 1, 1, 1), (-0.0269403, 0, 2, 1, 1),
    (0.0558082, 3, 0, 1, 0), (0.0161886, 0, 3, 1, 0), (0.00318086, 1, 3, 1, 0),
    (0.015896, 0, 0, 2, 0), (0.0471729, 1, 0, 2, 0), (0.0196283, 3, 0, 2, 0),
    (-0.0502782, 0, 1, 2, 0), (-0.030055, 3, 1, 2, 0), (0.0417122, 2, 2, 2, 0),
    (-0.0397722, 0, 3, 2, 0), (-0.00350024, 0, 6, 2, 0), (-0.0106854, 3, 0, 0, 1),
    (0.00110903, 3, 3, 0, 1), (-0.000313912, 0, 6, 0, 1), (0.0035985, 3, 0, 1, 1),
    (-0.00142121, 0, 6, 1, 1), (-0.00383637, 1, 0, 2, 1), (0.0126803, 0, 2, 2, 1),
    (-0.00318278, 2, 3, 2, 1), (0.00334268, 0, 6, 2, 1), (-0.00183491, 1, 1, 0, 2),
    (0.000112451, 3, 2, 0, 2), (-2.97228e-05, 3, 6, 0, 2), (0.000269551, 1, 0, 1, 2),
    (0.00083265, 2, 0, 1, 2), (0.00155334, 0, 2, 1, 2), (0.000302683, 0, 6, 1, 2),
    (-0.0001843, 0, 0, 2, 2), (-0.000425399, 0, 3, 2, 2), (8.69243e-05, 3, 3, 2, 2),
    (-0.0004659, 0, 6, 2, 2), (5.54194e-05, 1, 6, 2, 2),
)  # fmt: skip


@dataclass(frozen=True)
class BSeriesPropeller:
    """A Wageningen B-series propeller: diameter D [m], pitch ratio P/D, area ratio A_E/A_0, blades Z."""

    diameter_m: float
    pitch_ratio: float
    area_ratio: float
    blades: int

    def __post_init__(self) -> None:
        require_range("propeller.diameter_m", self.diameter_m, low=0.0, unit="m")
        require_range(
            "propeller.pitch_ratio", self.pitch_ratio, low=PITCH_RATIO_RANGE[0], high=PITCH_RATIO_RANGE[1],
            low_inclusive=True, high_inclusive=True,
        )  # fmt: skip
        require_range(
            "propeller.expanded_area_ratio", self.area_ratio,
            low=AREA_RATIO_RANGE[0], high=AREA_RATIO_RANGE[1], low_inclusive=True, high_inclusive=True,
        )  # fmt: skip
        if not BLADES_RANGE[0] <= self.blades <= BLADES_RANGE[1]:
            raise InputError(
                "propeller.blades", "outside the B-series fit", value=self.blades, allowed="2 to 7"
            )


@dataclass(frozen=True)
class OpenWaterTable:
    """Open-water curves as a table (module docstring): `pitch_ratios` sorted, and per pitch the advance
    ratios J (strictly increasing, ≥ 0) with K_T and K_Q. Build with `open_water_table_from_columns`."""

    pitch_ratios: tuple[float, ...]
    advance_ratios: tuple[np.ndarray, ...]
    thrust: tuple[np.ndarray, ...]
    torque: tuple[np.ndarray, ...]
    source: str = field(default="", compare=False)

    @property
    def pitch_range(self) -> tuple[float, float]:
        return self.pitch_ratios[0], self.pitch_ratios[-1]

    def _neighbours(self, pitch_ratio: float) -> tuple[int, int, float]:
        """The two tabulated pitches around `pitch_ratio` and its weight on the upper one."""
        p = np.asarray(self.pitch_ratios)
        low, high = self.pitch_range
        if not low - 1e-12 <= pitch_ratio <= high + 1e-12:
            raise InputError(
                "propeller.pitch_ratio",
                f"P/D = {pitch_ratio:.4g} lies outside the open-water table's pitches",
                value=round(pitch_ratio, 6),
                allowed=f"{low:g} to {high:g} ({self.source or 'the table'})",
            )
        upper = int(min(max(np.searchsorted(p, pitch_ratio), 1), p.size - 1)) if p.size > 1 else 0
        lower = max(upper - 1, 0)
        weight = 0.0 if upper == lower else (pitch_ratio - p[lower]) / (p[upper] - p[lower])
        return lower, upper, float(min(max(weight, 0.0), 1.0))

    def covered(self, pitch_ratio: float) -> tuple[float, float]:
        """The J range both neighbouring curves of `pitch_ratio` cover."""
        lower, upper, _ = self._neighbours(pitch_ratio)
        a, b = self.advance_ratios[lower], self.advance_ratios[upper]
        return float(max(a[0], b[0])), float(min(a[-1], b[-1]))

    def advance_ratio_limit(self, pitch_ratio: float) -> float:
        """The largest J both neighbouring curves cover."""
        return self.covered(pitch_ratio)[1]

    def coefficients(self, advance_ratio, pitch_ratio: float) -> tuple[np.ndarray, np.ndarray]:
        """(K_T, K_Q) at J and P/D, linear in J, then in P/D (module docstring)."""
        j = np.asarray(advance_ratio, dtype=float)
        lower, upper, weight = self._neighbours(pitch_ratio)
        low_j, high_j = self.covered(pitch_ratio)
        if np.any(j < low_j - 1e-12) or np.any(j > high_j + 1e-12):
            worst = float(np.max(j)) if np.any(j > high_j + 1e-12) else float(np.min(j))
            raise InputError(
                "propeller.advance_ratio",
                f"J = {worst:.4g} lies outside the open-water table's curves at P/D {pitch_ratio:.4g}",
                value=round(worst, 6),
                allowed=f"{low_j:g} to {high_j:g}",
            )
        out = []
        for values in (self.thrust, self.torque):
            a = np.interp(j, self.advance_ratios[lower], values[lower])
            b = np.interp(j, self.advance_ratios[upper], values[upper])
            out.append((1.0 - weight) * a + weight * b)
        return out[0], out[1]


OPEN_WATER_COLUMNS = ("pitch_ratio", "J", "K_T", "K_Q")


def open_water_table_from_columns(
    columns: dict[str, np.ndarray], source: str = "", key: str = "open_water_table"
) -> OpenWaterTable:
    """An `OpenWaterTable` from columns pitch_ratio, J, K_T and K_Q (or 10K_Q, divided by 10), one row per
    point; InputError naming `key` and what is wrong."""
    if "K_Q" not in columns and "10K_Q" in columns:
        columns = {**columns, "K_Q": np.asarray(columns["10K_Q"], dtype=float) / 10.0}
    missing = [c for c in OPEN_WATER_COLUMNS if c not in columns]
    if missing:
        raise InputError(key, f"{source}: no column {', '.join(missing)}", allowed="pitch_ratio, J, K_T, K_Q")
    p, j, kt, kq = (np.asarray(columns[c], dtype=float).reshape(-1) for c in OPEN_WATER_COLUMNS)
    bad = ~(np.isfinite(p) & np.isfinite(j) & np.isfinite(kt) & np.isfinite(kq))
    if bad.any() or p.size == 0:
        row = int(np.argmax(bad)) + 1 if bad.any() else 0
        raise InputError(key, f"{source}: row {row} is not four finite numbers", allowed="finite numbers")
    if np.any(p <= 0.0) or np.any(j < 0.0):
        raise InputError(
            key, f"{source}: a pitch ratio ≤ 0 or an advance ratio < 0", allowed="P/D > 0, J ≥ 0"
        )
    pitches, curves = tuple(float(v) for v in np.unique(p)), ([], [], [])
    for pitch in pitches:
        rows = np.flatnonzero(p == pitch)
        order = rows[np.argsort(j[rows], kind="stable")]
        if order.size < 2 or np.any(np.diff(j[order]) <= 0.0):
            raise InputError(
                key,
                f"{source}: the curve at P/D {pitch:g} has {order.size} point(s) or a repeated J",
                allowed="at least two points per pitch ratio, each J once",
            )
        for target, values in zip(curves, (j, kt, kq), strict=True):
            target.append(values[order].copy())
    return OpenWaterTable(pitches, tuple(curves[0]), tuple(curves[1]), tuple(curves[2]), source)


def parse_open_water_table(text: str, source: str = "", key: str = "open_water_table") -> OpenWaterTable:
    """An `OpenWaterTable` from CSV text: a header naming pitch_ratio, J, K_T and K_Q (or 10K_Q), one row
    per point; lines starting with '#' are comments. InputError naming `key` and the line."""
    import csv
    import io

    lines = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    if len(rows) < 2:
        raise InputError(key, f"{source}: no header and data rows", allowed="a CSV table")
    header = [name.strip() for name in rows[0]]
    values: dict[str, list[float]] = {name: [] for name in header}
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise InputError(key, f"{source}: line {number} has {len(row)} fields, not {len(header)}")
        for name, cell in zip(header, row, strict=True):
            try:
                values[name].append(float(cell))
            except ValueError:
                raise InputError(
                    key, f"{source}: line {number}, {name}: {cell.strip()!r} is not a number"
                ) from None
    return open_water_table_from_columns({k: np.asarray(v) for k, v in values.items()}, source, key)


@dataclass(frozen=True)
class TabulatedPropeller:
    """A propeller whose open-water curves are an `OpenWaterTable`: diameter D [m] and pitch ratio P/D."""

    diameter_m: float
    pitch_ratio: float
    table: OpenWaterTable

    def __post_init__(self) -> None:
        require_range("propeller.diameter_m", self.diameter_m, low=0.0, unit="m")
        self.table.advance_ratio_limit(self.pitch_ratio)  # a pitch outside the table names the key


def pitch_ratio_range(propeller) -> tuple[float, float]:
    """The pitch ratios the propeller's curves cover."""
    return propeller.table.pitch_range if isinstance(propeller, TabulatedPropeller) else PITCH_RATIO_RANGE


def with_pitch_ratio(propeller, pitch_ratio: float):
    """The same propeller at another pitch ratio (validated)."""
    return replace(propeller, pitch_ratio=pitch_ratio)


def _polynomial(terms, advance_ratio: np.ndarray, propeller: BSeriesPropeller) -> np.ndarray:
    j = np.asarray(advance_ratio, dtype=float)
    total = np.zeros_like(j)
    for c, s, t, u, v in terms:  # a fixed summation order: the same bits on every CPU
        total = total + c * j**s * propeller.pitch_ratio**t * propeller.area_ratio**u * propeller.blades**v
    return total


def thrust_coefficient(advance_ratio, propeller: BSeriesPropeller | TabulatedPropeller) -> np.ndarray:
    """K_T(J) of the B-series or the given table (module docstring)."""
    if isinstance(propeller, TabulatedPropeller):
        return propeller.table.coefficients(advance_ratio, propeller.pitch_ratio)[0]
    return _polynomial(KT_TERMS, advance_ratio, propeller)


def torque_coefficient(advance_ratio, propeller: BSeriesPropeller | TabulatedPropeller) -> np.ndarray:
    """K_Q(J) of the B-series or the given table (module docstring)."""
    if isinstance(propeller, TabulatedPropeller):
        return propeller.table.coefficients(advance_ratio, propeller.pitch_ratio)[1]
    return _polynomial(KQ_TERMS, advance_ratio, propeller)


def zero_thrust_advance_ratio(propeller: BSeriesPropeller | TabulatedPropeller) -> float:
    """J at K_T = 0: the end of the curves' range (a propeller beyond it brakes the ship); for a table, the
    first J of zero thrust on its curve, else the largest J it covers."""
    if isinstance(propeller, TabulatedPropeller):
        low, limit = propeller.table.covered(propeller.pitch_ratio)
        grid = np.linspace(low, limit, 2001)
        negative = np.flatnonzero(thrust_coefficient(grid, propeller) <= 0.0)
        return float(grid[negative[0]]) if negative.size else limit
    return float(brentq(lambda j: float(thrust_coefficient(j, propeller)), 0.0, 3.0))


@dataclass(frozen=True)
class OperatingPoint:
    """A propeller's open-water operating point (module docstring). SI units."""

    advance_ratio: float
    thrust_coefficient: float
    torque_coefficient: float
    thrust_n: float
    torque_n_m: float
    advance_speed_m_s: float
    induced_velocity_m_s: float

    @property
    def efficiency(self) -> float:
        """η_0 = J K_T / (2π K_Q)."""
        return self.advance_ratio * self.thrust_coefficient / (2.0 * math.pi * self.torque_coefficient)


def induced_velocity_m_s(
    thrust_n: float, diameter_m: float, advance_speed_m_s: float, density_kg_m3: float
) -> float:
    """Axial velocity the disc induces at its plane: u_a = ½ (√(V_A² + 2T/(ρA)) − V_A) (Rankine–Froude)."""
    area_m2 = 0.25 * math.pi * diameter_m**2
    return 0.5 * (
        math.sqrt(advance_speed_m_s**2 + 2.0 * max(thrust_n, 0.0) / (density_kg_m3 * area_m2))
        - advance_speed_m_s
    )


def operating_point(
    propeller: BSeriesPropeller,
    ship_speed_m_s: float,
    wake_fraction: float,
    rpm: float,
    density_kg_m3: float = SEA_WATER_DENSITY_KG_M3,
) -> OperatingPoint:
    """The open-water point at J = V (1 − w)/(n D); an advance ratio beyond zero thrust is an InputError."""
    require_range("ship.speed_m_s", ship_speed_m_s, low=0.0, low_inclusive=True, unit="m/s")
    require_range(
        "propeller.wake_fraction", wake_fraction, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
    )
    require_range("propeller.rpm", rpm, low=0.0, unit="1/min")
    n_per_s = rpm / 60.0
    advance_speed = ship_speed_m_s * (1.0 - wake_fraction)
    j = advance_speed / (n_per_s * propeller.diameter_m)
    j_zero = zero_thrust_advance_ratio(propeller)
    if j >= j_zero:
        raise InputError(
            "propeller.advance_ratio",
            f"J = {j:.3f} is at or beyond zero thrust or the end of the open-water curves "
            f"(P/D = {propeller.pitch_ratio:.3f})",
            value=round(j, 4),
            allowed=f"0 to {j_zero:.3f} (raise rpm or pitch, or lower the speed)",
        )
    kt = float(thrust_coefficient(j, propeller))
    kq = float(torque_coefficient(j, propeller))
    thrust = kt * density_kg_m3 * n_per_s**2 * propeller.diameter_m**4
    torque = kq * density_kg_m3 * n_per_s**2 * propeller.diameter_m**5
    u_a = induced_velocity_m_s(thrust, propeller.diameter_m, advance_speed, density_kg_m3)
    return OperatingPoint(j, kt, kq, thrust, torque, advance_speed, u_a)


def pitch_ratio_for_torque(
    torque_n_m: float,
    propeller: BSeriesPropeller,
    ship_speed_m_s: float,
    wake_fraction: float,
    rpm: float,
    density_kg_m3: float = SEA_WATER_DENSITY_KG_M3,
) -> float:
    """The P/D at which the open-water torque equals `torque_n_m`: one parameter identified from one number.

    An InputError names `mean_torque_knm` when no P/D within the fit's range gives that torque.
    """

    def excess(pitch_ratio: float) -> float:
        trial = with_pitch_ratio(propeller, pitch_ratio)
        n_per_s = rpm / 60.0
        j = ship_speed_m_s * (1.0 - wake_fraction) / (n_per_s * propeller.diameter_m)
        kq = float(torque_coefficient(j, trial))
        return kq * density_kg_m3 * n_per_s**2 * propeller.diameter_m**5 - torque_n_m

    low, high = pitch_ratio_range(propeller)
    if low == high or excess(low) * excess(high) > 0.0:
        raise InputError(
            "mean_torque_knm",
            "no pitch ratio of the B-series fit gives this mean torque at this speed and rpm",
            value=round(torque_n_m / 1e3, 3),
            allowed=f"{(excess(low) + torque_n_m) / 1e3:.0f} to {(excess(high) + torque_n_m) / 1e3:.0f} kN·m",
        )
    return float(brentq(excess, low, high, xtol=1e-10))
