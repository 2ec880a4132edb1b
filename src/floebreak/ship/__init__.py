"""The ship: bow ice waterlines, panels, normals and panel angles; built-in hulls."""

from floebreak.ship.bow import Bow, ice_waterline_heights
from floebreak.ship.hulls import (
    HULLS,
    agulhas_ii,
    get_hull,
    parametric_bow,
    polarstern,
    stem_angle_from_thesis,
)

__all__ = [
    "HULLS",
    "Bow",
    "agulhas_ii",
    "get_hull",
    "ice_waterline_heights",
    "parametric_bow",
    "polarstern",
    "stem_angle_from_thesis",
]
