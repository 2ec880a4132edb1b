"""Failure-mode classification of a floe in contact (thesis §3.2 Eqs. 1–5, Alg. 2; errata 7, 8).

The floe's bounding box is oriented by the bow panel at the contact: its *length* l is the extent along
the panel's outward normal (orthogonal to the bow section), its *width* w the extent along the panel.

- area ≤ A_rotate → "unbreakable" (fails by direct rotation; a cusp if in contact), Eq. 5;
- w > 2ℓ and l > 2ℓ → "bending" (Eq. 2);
- otherwise w ≤ l → "bending" (Eq. 3), w > l → "cracking" (Eq. 4); w = l (round floes) → "bending" as in
  Alg. 2, with a small relative tolerance (`aspect_tolerance`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numba
import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import require_range
from floebreak.ice.material import CharacteristicLengthModel, characteristic_length_scalar_m

FailureClass = Literal["unbreakable", "bending", "cracking"]
UnbreakableRule = Literal["thesis_1m_ell", "ell_squared", "bbox_lt_ell"]


@dataclass(frozen=True)
class ClassificationParams:
    """Parameters of Alg. 2.

    unbreakable_rule (erratum 8): ``"thesis_1m_ell"`` A ≤ 1 m · ℓ_u (thesis Eq. 5, the calibrated default),
    ``"ell_squared"`` A ≤ ℓ_u² (the thesis' own derivation), ``"bbox_lt_ell"`` l < ℓ_u and w < ℓ_u (Lu).
    unbreakable_ell (erratum 7): which ℓ_u the threshold uses: ``"lu_13.5"`` (13.5 h^(3/4), thesis Alg. 2)
    or ``"eq1"``. The 2ℓ rule always uses `bending_ell` (Eq. 1 by default).
    """

    unbreakable_rule: UnbreakableRule = "thesis_1m_ell"
    unbreakable_ell: CharacteristicLengthModel = "lu_13.5"
    bending_ell: CharacteristicLengthModel = "eq1"
    critical_length_factor: float = 2.0  # the "2ℓ" of Eqs. 2–4
    # w and l of a polygonised circle differ by up to 1 − cos(π/n) with orientation; "cracking" (w > l) needs
    # w > l (1 + tolerance) so round floes do not flip between classes with the panel direction.
    aspect_tolerance: float = 0.01
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA
    poisson_ratio: float = c.POISSON_RATIO
    foundation_modulus_n_m3: float = c.FOUNDATION_MODULUS_N_M3

    def __post_init__(self) -> None:
        require_range("classification.critical_length_factor", self.critical_length_factor, low=0.0)
        require_range("classification.aspect_tolerance", self.aspect_tolerance, low=0.0, low_inclusive=True)
        require_range("ice.youngs_modulus_pa", self.youngs_modulus_pa, low=0.0, unit="Pa")
        require_range(
            "ice.poisson_ratio",
            self.poisson_ratio,
            low=0.0,
            high=0.5,
            low_inclusive=True,
            high_inclusive=False,
        )

    def characteristic_length_m(
        self, thickness_m: float, model: CharacteristicLengthModel | None = None
    ) -> float:
        return characteristic_length_scalar_m(
            thickness_m,
            model or self.bending_ell,
            self.youngs_modulus_pa,
            self.poisson_ratio,
            self.foundation_modulus_n_m3,
        )


@dataclass(frozen=True)
class Classification:
    failure_class: FailureClass
    length_m: float  # extent along the panel normal (orthogonal to the bow section)
    width_m: float  # extent along the bow panel
    area_m2: float
    characteristic_length_m: float  # ℓ of the 2ℓ rule
    unbreakable_area_m2: float  # A_rotate used


def oriented_extent_m(polygon: shapely.Geometry, normal_xy: np.ndarray) -> tuple[float, float]:
    """(length along `normal_xy`, width along the perpendicular) of the polygon's oriented bounding box."""
    normal_x, normal_y = float(normal_xy[0]), float(normal_xy[1])
    norm = math.hypot(normal_x, normal_y)
    xs, ys = np.ascontiguousarray(shapely.get_coordinates(polygon).T)
    return box_extents(xs, ys, len(xs), normal_x / norm, normal_y / norm)


@numba.njit(cache=True, nogil=True)
def box_extents(xs, ys, n, normal_x, normal_y):
    """`oriented_extent_m` on the points (xs, ys)[:n] and a unit normal; compiled: it runs once per contact
    evaluation (also inside the contact kernel), where numpy's per-call overhead dominated."""
    low_n = low_t = np.inf
    high_n = high_t = -np.inf
    for i in range(n):
        along_normal = xs[i] * normal_x + ys[i] * normal_y
        along_tangent = ys[i] * normal_x - xs[i] * normal_y
        low_n, high_n = min(low_n, along_normal), max(high_n, along_normal)
        low_t, high_t = min(low_t, along_tangent), max(high_t, along_tangent)
    return high_n - low_n, high_t - low_t


def unbreakable_area_m2(thickness_m: float, params: ClassificationParams) -> float:
    """A_rotate of Eq. 5 (or the ℓ² variant) for this thickness [m²]; NaN for the bounding-box rule."""
    ell = params.characteristic_length_m(thickness_m, params.unbreakable_ell)
    if params.unbreakable_rule == "thesis_1m_ell":
        return 1.0 * ell  # 1 m × ℓ: the thesis compares an area with a length times 1 m (erratum 8)
    if params.unbreakable_rule == "ell_squared":
        return ell**2
    return float("nan")


def classify(
    polygon: shapely.Geometry,
    thickness_m: float,
    normal_xy: np.ndarray,
    params: ClassificationParams,
    extent_m: tuple[float, float] | None = None,
    area_m2: float | None = None,
) -> Classification:
    """Alg. 2: the failure class of a floe whose contact panel has outward normal `normal_xy`.

    `extent_m` (= `oriented_extent_m(polygon, normal_xy)`) and `area_m2` may be passed in where the contact
    kernel has measured them already.
    """
    length, width = oriented_extent_m(polygon, normal_xy) if extent_m is None else extent_m
    area = float(shapely.area(polygon)) if area_m2 is None else area_m2
    ell = params.characteristic_length_m(thickness_m)
    a_rotate = unbreakable_area_m2(thickness_m, params)
    if params.unbreakable_rule == "bbox_lt_ell":
        ell_u = params.characteristic_length_m(thickness_m, params.unbreakable_ell)
        unbreakable = length < ell_u and width < ell_u
    else:
        unbreakable = area <= a_rotate
    critical = params.critical_length_factor * ell
    if unbreakable:
        failure_class: FailureClass = "unbreakable"
    elif width <= critical or length <= critical:
        failure_class = "bending" if width <= length * (1.0 + params.aspect_tolerance) else "cracking"
    else:
        failure_class = "bending"
    return Classification(failure_class, length, width, area, ell, a_rotate)
