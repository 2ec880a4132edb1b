"""The milling model's torque of one blade impact, cusp by cusp at any rpm, for the drive model.

The drive (`floebreak.shaft.drive`) asks for the torque of the cusp being milled at the rpm of each blade
passage, one passage at a time: the rpm there follows from the impacts before it, so the impacts cannot be
batched. `CuspTorques` keeps one checked `IceBlock` per cusp and calls
`floebreak.propeller.milling.impact_loads` without the block's motion (`block_motion=None`: the torque does
not depend on it, only the impact count does), so the torque is `impact_loads`' own, to the bit
(tests/shaft/test_impact_torque.py), without the per-call block checks and throw-out counts.
"""

from __future__ import annotations

from dataclasses import dataclass

from floebreak.propeller import milling
from floebreak.propeller.milling import BladeGeometry, IceBlock, IceStrength


@dataclass(frozen=True)
class CuspTorques:
    """Per-impact ice torque [N·m] of each of `block`'s cusps on `blade` at the advance speed, at any rpm
    (`torque_n_m`), as `impact_loads(block[i], blade, rpm, advance_speed_m_s, ice, strips)`."""

    block: IceBlock
    blade: BladeGeometry
    advance_speed_m_s: float
    ice: IceStrength | None = None
    strips: int = milling.DEFAULT_STRIPS

    def __post_init__(self) -> None:
        sides = (self.block.thickness_m, self.block.length_m, self.block.width_m)
        blocks = tuple(IceBlock(*(a[i : i + 1] for a in sides)) for i in range(self.block.thickness_m.size))
        object.__setattr__(self, "_blocks", blocks)

    def torque_n_m(self, cusp: int, rpm: float) -> float:
        """Ice torque of one blade impact on cusp `cusp` (index into `block`) at `rpm` [N·m]."""
        block, speed = self._blocks[cusp], self.advance_speed_m_s
        loads = milling.impact_loads(block, self.blade, rpm, speed, self.ice, self.strips, block_motion=None)
        return float(loads.torque_n_m[0])
