"""Force and torque per cusp volume by interpolation through (0, 0) and the FEM points.

thesis §6.1.3, Eqs. 23–26 (Newton divided differences); notes erratum 24: with k = 5 points (origin + 4
FEM cusps) the Newton polynomial has degree k − 1 = 4 (quartic, not cubic). `"pchip"` is the monotone
piecewise-cubic Hermite alternative (scipy PchipInterpolator), free of overshoot.

Beyond the largest table volume V_max the policy is explicit:
"clamp" (the value at V_max), "extrapolate" (evaluate the interpolant), "flag" (NaN: no load is claimed).
Whatever the policy, callers report which cusps lay beyond V_max.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from floebreak.errors import InputError

INTERPOLATIONS = ("newton", "pchip")
BEYOND_POLICIES = ("clamp", "extrapolate", "flag")


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


@dataclass(frozen=True)
class VolumeInterpolant:
    """y(V) through (0, 0) and the table points (x_m3, y) with the given method and beyond-policy."""

    x_m3: np.ndarray
    y: np.ndarray
    method: str = "newton"
    beyond: str = "clamp"

    def __post_init__(self) -> None:
        check_options(self.method, self.beyond)

    @classmethod
    def through_origin(cls, volume_m3, values, method="newton", beyond="clamp") -> VolumeInterpolant:
        x = np.concatenate([[0.0], np.asarray(volume_m3, dtype=float)])
        y = np.concatenate([[0.0], np.asarray(values, dtype=float)])
        return cls(x, y, method, beyond)

    @property
    def max_volume_m3(self) -> float:
        return float(self.x_m3[-1])

    def _raw(self, v: np.ndarray) -> np.ndarray:
        if self.method == "newton":
            return newton_evaluate(self.x_m3, divided_differences(self.x_m3, self.y), v)
        return PchipInterpolator(self.x_m3, self.y, extrapolate=True)(v)

    def __call__(self, volume_m3) -> np.ndarray:
        v = np.asarray(volume_m3, dtype=float)
        if np.any(v < 0.0):
            raise InputError("volume_m3", "negative cusp volume", value=float(v[v < 0].min()), allowed=">= 0")
        beyond = v > self.max_volume_m3
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
