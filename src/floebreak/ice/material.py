"""Ice plate material laws (thesis §3.2 Eq. 1, physics-notes §0 and §3.1).

Pure functions on floats or numpy arrays, SI units.
"""

from __future__ import annotations

import functools
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from floebreak import constants as c

CharacteristicLengthModel = Literal["eq1", "lu_13.5"]


def flexural_rigidity_n_m(
    thickness_m: ArrayLike,
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
) -> np.ndarray:
    """Flexural rigidity D = E h³ / (12 (1 − ν²)) in N·m (thesis §3.2; erratum 26: not kJ m³)."""
    h = np.asarray(thickness_m, dtype=float)
    return youngs_modulus_pa * h**3 / (12.0 * (1.0 - poisson_ratio**2))


def foundation_modulus_n_m3(
    seawater_density_kg_m3: float = c.SEAWATER_DENSITY_KG_M3, gravity_m_s2: float = c.GRAVITY_M_S2
) -> float:
    """Winkler foundation modulus k = ρ_w g in N/m³ (thesis §4.1)."""
    return seawater_density_kg_m3 * gravity_m_s2


def characteristic_length_m(
    thickness_m: ArrayLike,
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> np.ndarray:
    """Characteristic length ℓ = (D/k)^(1/4) in m (thesis Eq. 1). E = 2 GPa gives ℓ ≈ 11.62 h^(3/4)."""
    rigidity = flexural_rigidity_n_m(thickness_m, youngs_modulus_pa, poisson_ratio)
    return (rigidity / foundation_modulus) ** 0.25


def characteristic_length_lu_m(thickness_m: ArrayLike) -> np.ndarray:
    """ℓ = 13.5 h^(3/4) in m (Lu et al.), the thesis' value for the unbreakable threshold (errata 7, 8).

    It equals Eq. 1 with E ≈ 3.65 GPa (physics-notes §3.1).
    """
    h = np.asarray(thickness_m, dtype=float)
    return c.LU_CHARACTERISTIC_LENGTH_COEFFICIENT * h**0.75


def characteristic_length_by_name_m(
    thickness_m: ArrayLike,
    model: CharacteristicLengthModel = "eq1",
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> np.ndarray:
    """ℓ by model name: ``"eq1"`` (thesis Eq. 1, default) or ``"lu_13.5"`` (thesis Alg. 2)."""
    if model == "eq1":
        return characteristic_length_m(thickness_m, youngs_modulus_pa, poisson_ratio, foundation_modulus)
    if model == "lu_13.5":
        return characteristic_length_lu_m(thickness_m)
    raise ValueError(f"unknown characteristic-length model {model!r}; allowed: 'eq1', 'lu_13.5'")


def characteristic_length_scalar_m(
    thickness_m: float,
    model: CharacteristicLengthModel = "eq1",
    youngs_modulus_pa: float = c.YOUNGS_MODULUS_PA,
    poisson_ratio: float = c.POISSON_RATIO,
    foundation_modulus: float = c.FOUNDATION_MODULUS_N_M3,
) -> float:
    """`characteristic_length_by_name_m` for one thickness, as a float, cached per (h, model, E, ν, k).

    The failure modes and the classification ask for ℓ at every contact, almost always for the same few
    thicknesses; the value is the very same float as the array function's.
    """
    return _characteristic_length_cached(
        float(thickness_m), model, float(youngs_modulus_pa), float(poisson_ratio), float(foundation_modulus)
    )


@functools.lru_cache(maxsize=256)
def _characteristic_length_cached(
    thickness_m: float,
    model: CharacteristicLengthModel,
    youngs_modulus_pa: float,
    poisson_ratio: float,
    foundation_modulus: float,
) -> float:
    return float(
        characteristic_length_by_name_m(
            thickness_m, model, youngs_modulus_pa, poisson_ratio, foundation_modulus
        )
    )
