"""Force and torque per cusp volume by interpolation through (0, 0) and the FEM points.

thesis §6.1.3, Eqs. 23–26 (Newton divided differences); notes erratum 24: with k = 5 points (origin + 4
FEM cusps) the Newton polynomial has degree k − 1 = 4 (quartic, not cubic). `"pchip"` is the monotone
piecewise-cubic Hermite alternative (scipy PchipInterpolator), free of overshoot.

Beyond the largest table volume V_max the policy is explicit:
"power_law" (default): y(V) = y(V_max) (V / V_max)^b, with b fitted by least squares in log–log to the
table's `UPPER_POINTS` largest points and anchored at the last (continuous at V_max). The physical reason:
the FEM load is a contact pressure times the blade–cusp contact area (thesis §6.3: "the pressure … is
approximately the same …, the resulting forces … increase with an increasing contact area"); for cusps of
similar shape the area grows as V^(2/3). Thesis Table 11 bears this out: F / (width · height) stays within
515–556 kN/m² over its four cusps; the fitted b are 0.69 (force) and 0.64 (torque) at 95 % pitch, 0.54 and
0.45 at 0 % (docs/propeller.md §2).
"clamp" (the value at V_max: every larger cusp gets the same load, a spike in the spectra),
"extrapolate" (evaluate the interpolant: a quartic grows without bound), "flag" (NaN: no load is claimed).
Whatever the policy, callers report which cusps lay beyond V_max.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError

INTERPOLATIONS = ("newton", "pchip")
BEYOND_POLICIES = ("power_law", "clamp", "extrapolate", "flag")
UPPER_POINTS = 3  # table points (with the largest) the power law beyond the table is fitted to


def divided_differences(x, y) -> np.ndarray:
    """Newton coefficients f[x_0], f[x_0,x_1], …, f[x_0..x_n] (thesis Eqs. 23–26, any number of points)."""
    x = np.asarray(x, dtype=float)
    table = np.array(y, dtype=float)
    coefficients = [table[0]]
    for order in range(1, x.size):
        table = (table[1:] - table[:-1]) / (x[order:] - x[:-order])
        coefficients.append(table[0])
    return np.asarray(coefficients)


def newton_evaluate(x_nodes, coefficients, v) -> np.ndarray:
    """p(v) = Σ_j c_j Π_{i<j} (v − x_i), evaluated by nested multiplication."""
    x_nodes = np.asarray(x_nodes, dtype=float)
    v = np.asarray(v, dtype=float)
    result = np.full(v.shape, coefficients[-1], dtype=float)
    for j in range(len(coefficients) - 2, -1, -1):
        result = result * (v - x_nodes[j]) + coefficients[j]
    return result


def power_law_exponent(x_m3, y, n_upper: int = UPPER_POINTS) -> float:
    """b of |y| ∝ V^b through the largest table point, least squares in log–log over the `n_upper` largest
    points: b = Σ a_i c_i / Σ a_i², a_i = ln(V_i/V_max), c_i = ln(|y_i|/|y_max|). InputError if the upper
    values are zero or change sign (no power law through them)."""
    x = np.asarray(x_m3, dtype=float)[-n_upper:]
    v = np.asarray(y, dtype=float)[-n_upper:]
    if x.size < 2 or np.any(v == 0.0) or np.any(np.sign(v) != np.sign(v[-1])) or np.any(x <= 0.0):
        raise InputError(
            "beyond",
            f"no power law through the table's upper points (volumes {x.tolist()}, values {v.tolist()})",
            allowed="non-zero values of one sign at the largest volumes, or beyond = clamp | flag",
        )
    a = np.log(x[:-1] / x[-1])
    cc = np.log(v[:-1] / v[-1])
    return float(np.sum(a * cc) / np.sum(a * a))


@dataclass(frozen=True)
class VolumeInterpolant:
    """y(V) through (0, 0) and the table points (x_m3, y) with the given method and beyond-policy."""

    x_m3: np.ndarray
    y: np.ndarray
    method: str = "newton"
    beyond: str = "power_law"

    def __post_init__(self) -> None:
        check_options(self.method, self.beyond)

    @classmethod
    def through_origin(cls, volume_m3, values, method="newton", beyond="power_law") -> VolumeInterpolant:
        x = np.concatenate([[0.0], np.asarray(volume_m3, dtype=float)])
        y = np.concatenate([[0.0], np.asarray(values, dtype=float)])
        return cls(x, y, method, beyond)

    @property
    def max_volume_m3(self) -> float:
        return float(self.x_m3[-1])

    def _raw(self, v: np.ndarray) -> np.ndarray:
        if self.method == "newton":
            return newton_evaluate(self.x_m3, divided_differences(self.x_m3, self.y), v)
        from scipy.interpolate import PchipInterpolator  # here: the Newton default needs no scipy

        return PchipInterpolator(self.x_m3, self.y, extrapolate=True)(v)

    def __call__(self, volume_m3) -> np.ndarray:
        v = np.asarray(volume_m3, dtype=float)
        if np.any(v < 0.0):
            raise InputError("volume_m3", "negative cusp volume", value=float(v[v < 0].min()), allowed=">= 0")
        beyond = v > self.max_volume_m3
        if self.beyond == "power_law":
            inside = self._raw(np.minimum(v, self.max_volume_m3))
            b = power_law_exponent(self.x_m3[1:], self.y[1:])
            with np.errstate(divide="ignore", invalid="ignore"):
                factor = np.where(beyond, (v / self.max_volume_m3) ** b, 1.0)
            return inside * factor
        if self.beyond == "clamp":
            return self._raw(np.minimum(v, self.max_volume_m3))
        out = self._raw(v)
        if self.beyond == "flag":
            out = np.where(beyond, np.nan, out)
        return out


def check_options(method: str, beyond: str) -> None:
    if method not in INTERPOLATIONS:
        raise InputError(
            "interpolation", f"unknown method {method!r}", value=method, allowed=", ".join(INTERPOLATIONS)
        )
    if beyond not in BEYOND_POLICIES:
        raise InputError(
            "beyond", f"unknown policy {beyond!r}", value=beyond, allowed=", ".join(BEYOND_POLICIES)
        )


GEOMETRIC_EXPONENT = 2.0 / 3.0  # contact area ∝ V^(2/3) for cusps of similar shape (power law, N-D tables)


def table_interpolant(table, quantity: str, method: str = "newton", beyond: str = "power_law"):
    """A function of the cusps' coordinates {"volume", "length", "width", "height": arrays} returning
    (load, beyond-table mask) for `quantity` "force" [N] or "torque" [N·m] of a `FemTable`.

    1-D tables (the thesis'): `VolumeInterpolant` through (0, 0). N-D tables: linear interpolation in the
    table's dimensions (`GridInterpolant`)."""
    values = table.force_n if quantity == "force" else table.torque_nm
    if tuple(table.dimensions) == ("volume",):
        curve = VolumeInterpolant.through_origin(table.volume_m3, values, method, beyond)

        def evaluate(coordinates):
            v = np.asarray(coordinates["volume"], dtype=float)
            return curve(v), v > table.max_volume_m3

        return evaluate
    return GridInterpolant(table, np.asarray(values, dtype=float), beyond)


@dataclass(frozen=True)
class GridInterpolant:
    """Linear interpolation of an N-D FEM table (fem.py: ``# dimensions:``) with zero load where any
    dimension is 0 (a cusp without extent, the thesis' boundary condition in N-D).

    A full grid uses scipy RegularGridInterpolator (axes extended by 0), scattered points
    LinearNDInterpolator (with the origin added). A cusp beyond the table (above an axis' range on a grid,
    outside the convex hull of the points and origin when scattered) is flagged; its load by `beyond`:
    "clamp" (coordinates clipped into the table's range; scattered: the nearest table point), "power_law"
    (the clamped load × (V / V_clamped)^(2/3): contact area ∝ V^(2/3)), "flag" (NaN). "extrapolate" is
    refused for N-D tables."""

    table: object
    values: np.ndarray
    beyond: str = "power_law"

    def __post_init__(self) -> None:
        if self.beyond == "extrapolate":
            raise InputError(
                "beyond", "N-D FEM tables are not extrapolated", allowed="power_law, clamp, flag"
            )
        check_options("newton", self.beyond)

    def _points(self) -> np.ndarray:
        return np.column_stack([self.table.coordinate(d) for d in self.table.dimensions])

    def _grid_axes(self):
        """Sorted axes (with 0) and the value grid if the points form a full grid, else None."""
        points = self._points()
        axes = [np.unique(points[:, j]) for j in range(points.shape[1])]
        if int(np.prod([a.size for a in axes])) != points.shape[0]:
            return None
        grid = np.zeros([a.size + 1 for a in axes])
        index = tuple(np.searchsorted(a, points[:, j]) + 1 for j, a in enumerate(axes))
        grid[index] = self.values
        return [np.r_[0.0, a] for a in axes], grid

    def __call__(self, coordinates) -> tuple[np.ndarray, np.ndarray]:
        from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator, RegularGridInterpolator

        x = np.column_stack([np.asarray(coordinates[d], dtype=float) for d in self.table.dimensions])
        grid = self._grid_axes()
        if grid is not None:
            axes, values = grid
            top = np.array([a[-1] for a in axes])
            beyond = np.any(x > top, axis=1)
            clamped = np.minimum(x, top)
            load = RegularGridInterpolator(axes, values)(clamped)
        else:
            points = np.vstack([np.zeros(x.shape[1]), self._points()])
            values = np.r_[0.0, self.values]
            load = LinearNDInterpolator(points, values)(x)
            beyond = ~np.isfinite(load)
            nearest = NearestNDInterpolator(points, np.arange(points.shape[0]))(x[beyond]).astype(int)
            clamped = x.copy()
            clamped[beyond] = points[nearest]
            load[beyond] = values[nearest]
        if self.beyond == "flag":
            load = np.where(beyond, np.nan, load)
        elif self.beyond == "power_law":
            load = load * np.where(beyond, self._volume_ratio(x, clamped) ** GEOMETRIC_EXPONENT, 1.0)
        return load, beyond

    def _volume_ratio(self, x: np.ndarray, clamped: np.ndarray) -> np.ndarray:
        dims = list(self.table.dimensions)
        with np.errstate(divide="ignore", invalid="ignore"):
            if "volume" in dims:
                j = dims.index("volume")
                ratio = x[:, j] / clamped[:, j]
            else:
                ratio = np.prod(x, axis=1) / np.prod(clamped, axis=1)
        return np.where(np.isfinite(ratio) & (ratio > 0.0), ratio, 1.0)
