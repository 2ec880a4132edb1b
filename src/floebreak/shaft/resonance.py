"""Resonance margin: the blade-passage orders against the shaft line's natural frequencies (Campbell data).

The ice excites the shaft at the blade-passage frequency and its harmonics, f_k(n) = k Z n/60 (k = 1, 2, 3;
Z blades; n [1/min]). Order k crosses mode j (free-free natural frequency f_j, `line.modal_analysis`) at

    n_kj = 60 f_j / (k Z)                                                       [1/min]

and the margin at the operating speed n_op is |f_j − f_k(n_op)| / f_k(n_op). A margin below the required one
raises a warning. The default required margin, 0.2, is a placeholder **to be replaced by the rule's value**
(the torsional-response requirements of IACS UR I3, being extracted from the rule text). See docs/shaft.md,
"Drive dynamics and resonance margin".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.spec import MAX_PROPELLER_RPM
from floebreak.shaft.line import ShaftLine, modal_analysis

DEFAULT_REQUIRED_MARGIN = 0.2  # placeholder: to be replaced by the rule's value (IACS UR I3)
DEFAULT_HARMONICS = (1, 2, 3)
DEFAULT_RPM_FRACTION = (0.0, 1.1)  # of the operating rpm: the Campbell diagram's range


@dataclass(frozen=True)
class Campbell:
    """Campbell data of a shaft line and its resonance margins at the operating speed."""

    rpm: np.ndarray  # grid [1/min]
    harmonics: np.ndarray  # k
    orders: np.ndarray  # k·Z: excitations per revolution
    order_frequency_hz: np.ndarray  # (order, rpm): k Z n/60
    natural_frequency_hz: np.ndarray  # (mode,)
    crossing_rpm: np.ndarray  # (order, mode): 60 f_j/(k Z), wherever it lies
    operating_rpm: float
    margin: np.ndarray  # (order, mode): |f_j − k Z n_op/60| / (k Z n_op/60)
    required_margin: float

    @property
    def crossing_in_range(self) -> np.ndarray:
        """(order, mode): the crossing lies on the rpm grid."""
        return (self.crossing_rpm >= self.rpm[0]) & (self.crossing_rpm <= self.rpm[-1])

    @property
    def within_margin(self) -> np.ndarray:
        """(order, mode): the operating speed lies within the required margin of a resonance."""
        return self.margin < self.required_margin

    @property
    def warning(self) -> bool:
        return bool(self.within_margin.any())

    def warnings(self) -> list[str]:
        """One sentence per (order, mode) inside the required margin."""
        out = []
        for i, j in zip(*np.nonzero(self.within_margin), strict=True):
            f_order = self.orders[i] * self.operating_rpm / 60.0
            out.append(
                f"mode {j + 1} ({self.natural_frequency_hz[j]:.2f} Hz) lies within "
                f"{self.margin[i, j]:.1%} of blade-passage order {self.orders[i]} ({f_order:.2f} Hz) at "
                f"{self.operating_rpm:g} rpm (required margin {self.required_margin:.0%}; the order crosses "
                f"it at {self.crossing_rpm[i, j]:.1f} rpm)"
            )
        return out


def _harmonics(harmonics) -> np.ndarray:
    k = np.asarray(harmonics).reshape(-1)
    if k.size == 0 or np.any(k != np.rint(k)) or np.any(k < 1):
        raise InputError("harmonics", f"{list(k)!r}", allowed="integers ≥ 1, at least one")
    return k.astype(np.int64)


def campbell_from_frequencies(
    natural_frequency_hz,
    operating_rpm: float,
    *,
    blades: int = 4,
    harmonics=DEFAULT_HARMONICS,
    rpm_fraction: tuple[float, float] = DEFAULT_RPM_FRACTION,
    points: int = 221,
    required_margin: float = DEFAULT_REQUIRED_MARGIN,
) -> Campbell:
    """Campbell data for given natural frequencies [Hz] (module docstring); the rpm grid runs over
    `rpm_fraction` of the operating rpm."""
    n_op = require_range("operating_rpm", operating_rpm, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
    if isinstance(blades, bool) or int(blades) != blades or blades < 1:
        raise InputError("blades", f"{blades!r} is not a positive integer", value=blades)
    margin_req = require_range("required_margin", required_margin, low=0.0, high=1.0, low_inclusive=True)
    low = require_range("rpm_fraction[0]", rpm_fraction[0], low=0.0, low_inclusive=True)
    high = require_range("rpm_fraction[1]", rpm_fraction[1], low=low)
    if int(points) != points or points < 2:
        raise InputError("points", f"{points!r}", value=points, allowed="an integer ≥ 2")
    f_n = np.asarray(natural_frequency_hz, dtype=float).reshape(-1)
    if not np.all(np.isfinite(f_n) & (f_n > 0.0)):
        raise InputError("natural_frequency_hz", "frequencies must be finite and > 0", allowed="> 0 Hz")
    k = _harmonics(harmonics)
    orders = k * int(blades)
    rpm = np.linspace(low * n_op, high * n_op, int(points))
    f_op = orders * n_op / 60.0
    return Campbell(
        rpm=rpm,
        harmonics=k,
        orders=orders,
        order_frequency_hz=orders[:, None] * rpm[None, :] / 60.0,
        natural_frequency_hz=f_n,
        crossing_rpm=60.0 * f_n[None, :] / orders[:, None],
        operating_rpm=n_op,
        margin=np.abs(f_n[None, :] - f_op[:, None]) / f_op[:, None],
        required_margin=margin_req,
    )


def campbell(line: ShaftLine, *, blades: int = 4, rpm: float | None = None, **options) -> Campbell:
    """Campbell data of `line` (its free-free natural frequencies, `modal_analysis`) at its rpm or `rpm`;
    `options` as `campbell_from_frequencies`."""
    modes = modal_analysis(line)
    return campbell_from_frequencies(
        modes.frequency_hz, line.rpm if rpm is None else rpm, blades=blades, **options
    )
