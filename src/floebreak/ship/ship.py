"""A ship: the bow that breaks the ice, the underwater hull the cusps pass, the propellers they reach and
the shaft line that carries the torque. The parts are modelled by `ship.hulls` (bow), `propeller.transport`
(underwater hull, arrangement), `propeller.spec` and `shaft.line`; a `Ship` names them and holds the numbers
they share, so that one ship's numbers are written once (`ship.agulhas_ii`)."""

from __future__ import annotations

from dataclasses import dataclass

from floebreak.errors import require_range


@dataclass(frozen=True)
class Ship:
    """A ship's parts by name (`hull`: a built-in hull of `ship.hulls.HULLS`; `shaft_line`: a built-in line
    of `shaft.line`) and the numbers the propeller, transport and shaft models share."""

    name: str
    hull: str
    shaft_line: str
    propeller_count: int
    propeller_diameter_m: float
    shaft_depth_m: float  # immersion of the shaft axes below the waterline
    tip_clearance_m: float  # vertical gap between the hull and a disc's top
    rpm: float  # propeller speed [1/min]
    rated_power_w: float  # the drive's rated power, per shaft line

    def __post_init__(self) -> None:
        require_range("ship.propeller_diameter_m", self.propeller_diameter_m, low=0.0, unit="m")
        require_range("ship.shaft_depth_m", self.shaft_depth_m, low=0.0, unit="m")
        require_range("ship.tip_clearance_m", self.tip_clearance_m, low=0.0, low_inclusive=True, unit="m")
        require_range("ship.rpm", self.rpm, low=0.0, unit="1/min")
        require_range("ship.rated_power_w", self.rated_power_w, low=0.0, unit="W")

    @property
    def propeller_radius_m(self) -> float:
        return 0.5 * self.propeller_diameter_m
