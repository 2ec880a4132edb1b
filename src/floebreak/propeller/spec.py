"""Propeller description and pitch angle (thesis §6.1.2, Table 9; physics-notes §7.1, erratum 23)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from floebreak.errors import InputError, require_range
from floebreak.ship.agulhas_ii import (
    PROPELLER_BLADES,
    PROPELLER_DIAMETER_M,
    PROPELLER_MAX_PITCH_M,
    PROPELLER_PITCH_PERCENT,
    PROPELLER_RPM,
)

# propeller speeds: the Agulhas II's turns at 140 1/min (thesis §6.1.2); 1000 1/min is above any ice-going
# ship's propeller, and bounds the samples of a shaft analysis (they grow with the speed)
MAX_PROPELLER_RPM = 1000.0

if TYPE_CHECKING:
    from floebreak.propeller.open_water import OpenWaterTable

PITCH_ANGLE_RADII = ("r07", "thesis_r_prop")


@dataclass(frozen=True)
class PropellerSpec:
    """An open controllable-pitch propeller. Defaults: PSRV S.A. Agulhas II.

    radius_m, max_pitch_m: thesis Table 9 (r_prop = 2.15 m, P_0.7 = 5.15 m at 100 % pitch).
    pitch_percent: mean pitch of the 18/12/2019 20:20 slot (thesis §6.1.2: 95.8551 %, P = 4.9365 m).
    rpm: thesis §6.1.2 (140 rpm). The rest only feed the IACS UR I3 cross-check and are *assumptions*
    (notes §7.1): blades Z = 4, expanded area ratio EAR = 0.55 (0.45–0.65), hub ratio d/D = 0.30,
    blade thickness at 0.7R t_0.7 = 0.105 m (0.08–0.13 m). `bollard_pitch_m` is the UR I3 P_0.7 at MCR
    bollard condition; None uses the rule's fallback 0.7 × the maximum (free-running) pitch.
    `open_water_table`: the propeller's open-water curves as a table (`open_water.OpenWaterTable`, e.g. from
    `--open-water-table CSV`); None uses the Wageningen B-series (`propeller.operating`).
    """

    radius_m: float = PROPELLER_DIAMETER_M / 2.0
    max_pitch_m: float = PROPELLER_MAX_PITCH_M
    pitch_percent: float = PROPELLER_PITCH_PERCENT
    rpm: float = PROPELLER_RPM
    blades: int = PROPELLER_BLADES
    expanded_area_ratio: float = 0.55
    hub_ratio: float = 0.30
    blade_thickness_07_m: float = 0.105
    bollard_pitch_m: float | None = None
    # the open-water curves (None: the B-series polynomials, `propeller.open_water`)
    open_water_table: OpenWaterTable | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        require_range("propeller.radius_m", self.radius_m, low=0.0, unit="m")
        require_range("propeller.max_pitch_m", self.max_pitch_m, low=0.0, unit="m")
        require_range("propeller.pitch_percent", self.pitch_percent, low=0.0, high=100.0, low_inclusive=True)
        require_range("propeller.rpm", self.rpm, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
        if isinstance(self.blades, bool) or int(self.blades) != self.blades or self.blades < 2:
            raise InputError(  # one blade is no propeller (and no blade-passage order)
                "propeller.blades", f"{self.blades!r} is not an integer", value=self.blades, allowed=">= 2"
            )
        require_range("propeller.expanded_area_ratio", self.expanded_area_ratio, low=0.0, high=1.5)
        require_range(
            "propeller.hub_ratio", self.hub_ratio, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
        )
        require_range(
            "propeller.blade_thickness_07_m", self.blade_thickness_07_m, low=0.0, high=self.radius_m, unit="m"
        )
        if self.bollard_pitch_m is not None:
            require_range("propeller.bollard_pitch_m", self.bollard_pitch_m, low=0.0, unit="m")

    @property
    def diameter_m(self) -> float:
        return 2.0 * self.radius_m

    @property
    def r07_m(self) -> float:
        """R_0.7 = 0.7 r_prop (thesis §6.1.2)."""
        return 0.7 * self.radius_m

    @property
    def pitch_m(self) -> float:
        """Actual pitch P = P_0.7% · P_0.7 (thesis §6.1.2: 95.8551 % × 5.15 m = 4.9365 m)."""
        return self.pitch_percent / 100.0 * self.max_pitch_m

    @property
    def revolutions_per_s(self) -> float:
        return self.rpm / 60.0

    @property
    def rule_pitch_m(self) -> float:
        """UR I3 P_0.7 (bollard); fallback 0.7 × maximum pitch (notes §7.2)."""
        return self.bollard_pitch_m if self.bollard_pitch_m is not None else 0.7 * self.max_pitch_m


def pitch_angle_deg(pitch_m: float, radius_m: float) -> float:
    """Blade pitch angle δ_P = arctan(P / (2π r)) [deg] of a helix of pitch P at radius r (thesis Eq. 22)."""
    return math.degrees(math.atan2(pitch_m, 2.0 * math.pi * radius_m))


def propeller_pitch_angle_deg(spec: PropellerSpec, pitch_angle_radius: str = "r07") -> float:
    """Pitch angle at 0.7R (notes erratum 23).

    "r07" (default): r = R_0.7 = 0.7 r_prop, 27.57° for the Agulhas II at 95.8551 %.
    "thesis_r_prop": the thesis' evaluation with r = r_prop, 20.07° (thesis §6.1.2).
    """
    if pitch_angle_radius == "r07":
        return pitch_angle_deg(spec.pitch_m, spec.r07_m)
    if pitch_angle_radius == "thesis_r_prop":
        return pitch_angle_deg(spec.pitch_m, spec.radius_m)
    raise InputError(
        "pitch_angle_radius",
        f"unknown value {pitch_angle_radius!r}",
        value=pitch_angle_radius,
        allowed=", ".join(PITCH_ANGLE_RADII),
    )
