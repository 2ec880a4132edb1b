"""Bounded random ice thickness (thesis §5.3.3, erratum 6)."""

from __future__ import annotations

import numpy as np

from floebreak import constants as c
from floebreak.errors import InputError, require_range

BLOCK_VALUES = 1 << 20  # uniforms drawn at once (8 MB)


def bounded_random_thickness_m(
    rng: np.random.Generator,
    thickness_min_m: float,
    thickness_max_m: float,
    size: int,
    summands: int = c.THICKNESS_SUMMANDS_DEFAULT,
    thesis_sum_from_zero: bool = False,
) -> np.ndarray:
    """Draw `size` thicknesses h = h_min + (h_max − h_min) · mean of `summands` uniforms on [0, 1].

    This is the Bates distribution: bounded by [h_min, h_max], mean (h_min + h_max)/2 and standard
    deviation (h_max − h_min)/√(12 p_h). With ``thesis_sum_from_zero`` the thesis' literal formula is used:
    the sum runs over i = 0 … p_h (p_h + 1 terms) but is divided by p_h, which biases the mean upwards
    and can exceed h_max (erratum 6).
    """
    require_range("thickness_min_m", thickness_min_m, low=0.0, unit="m")
    require_range("thickness_max_m", thickness_max_m, low=0.0, unit="m")
    if thickness_max_m < thickness_min_m:
        raise InputError(
            "thickness_range_m",
            f"maximum {thickness_max_m:g} m is below minimum {thickness_min_m:g} m",
            allowed="h_min <= h_max",
        )
    if int(summands) < 1:
        raise InputError("thickness_summands", f"{summands} < 1", allowed=">= 1")
    terms = int(summands) + (1 if thesis_sum_from_zero else 0)
    # drawn in blocks of rows (the same stream as one (size, terms) array): memory O(BLOCK_VALUES), not
    # O(size · p_h)
    rows = max(1, BLOCK_VALUES // terms)
    fraction = np.empty(int(size))
    for start in range(0, int(size), rows):
        stop = min(start + rows, int(size))
        fraction[start:stop] = rng.random((stop - start, terms)).sum(axis=1)
    fraction /= int(summands)
    return thickness_min_m + (thickness_max_m - thickness_min_m) * fraction
