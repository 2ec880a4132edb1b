"""The milling model's torque of one blade impact, cusp by cusp at any rpm, for the drive model.

The drive (`floebreak.shaft.drive`) asks for the torque of the cusp being milled at the rpm of each blade
passage, one passage at a time: the rpm there follows from the impacts before it, so the impacts cannot be
batched. `CuspTorques` computes each cusp's blade strips once (`floebreak.propeller.loads.milling
.block_strips`: what depends on the block alone) and calls `floebreak.propeller.loads.milling
.impact_torque_n_m`, the torque part of `impact_loads` (the same function computes it there), so the
torque is `impact_loads`' own, to the bit (tests/shaft/test_impact_torque.py), without the block's
motion, impact count and other quantities.
"""

from __future__ import annotations

from dataclasses import dataclass

from floebreak.propeller.loads import milling
from floebreak.propeller.loads.milling import BladeGeometry, IceBlock, IceStrength


@dataclass(frozen=True)
class CuspTorques:
    """Per-impact ice torque [N·m] of each of `block`'s cusps on `blade` at the advance speed, at any rpm
    (`torque_n_m`), as `impact_loads(block[i], blade, rpm, advance_speed_m_s, ice, strips)` (the block's
    engaged interval included)."""

    block: IceBlock
    blade: BladeGeometry
    advance_speed_m_s: float
    ice: IceStrength | None = None
    strips: int = milling.DEFAULT_STRIPS

    def __post_init__(self) -> None:
        b = self.block
        strips = tuple(
            milling.block_strips(
                self.blade,
                *(a[i : i + 1] for a in (b.thickness_m, b.length_m)),
                self.strips,
                *(a[i : i + 1] for a in (b.inner_radius_m, b.outer_radius_m)),
            )
            for i in range(b.thickness_m.size)
        )
        object.__setattr__(self, "_strips", strips)
        object.__setattr__(self, "_ice", IceStrength() if self.ice is None else self.ice)

    def torque_n_m(self, cusp: int, rpm: float) -> float:
        """Ice torque of one blade impact on cusp `cusp` (index into `block`) at `rpm` [N·m]."""
        strip, speed = self._strips[cusp], self.advance_speed_m_s
        return float(milling.impact_torque_n_m(strip, self.blade, rpm, speed, self._ice)[0])
