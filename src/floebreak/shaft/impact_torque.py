"""The milling model's torque of one blade impact, cusp by cusp at any rpm, for the drive model.

The drive (`floebreak.shaft.drive`) asks for the torque of the cusp being milled at the rpm of each blade
passage, one passage at a time (the rpm there follows from the impacts before it, so the impacts cannot be
batched). `CuspTorques` evaluates `floebreak.propeller.milling.impact_loads`' torque for one cusp: the
blade strips each block covers (radial extent, overlap, mid radius, chord) do not depend on the rpm and are
computed once for all cusps; per call only the rpm-dependent part runs (cut depth, `section_contact`, the
pressure–area relation, `strip_forces`) with the same operations in the same order, so the torque is the
one `impact_loads` gives, to the bit (tests/shaft/test_impact_torque.py), at a fraction of its cost (no
block checks, no block motion, no impact counts).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller import milling
from floebreak.propeller.milling import BladeGeometry, IceBlock, IceStrength
from floebreak.propeller.spec import MAX_PROPELLER_RPM


@dataclass(frozen=True)
class CuspTorques:
    """Per-impact ice torque [N·m] of each of `block`'s cusps on `blade` at the advance speed, at any rpm
    (`torque_n_m`), as `impact_loads(block[i], blade, rpm, advance_speed_m_s, ice, strips)`."""

    block: IceBlock
    blade: BladeGeometry
    advance_speed_m_s: float
    ice: IceStrength = IceStrength()
    strips: int = milling.DEFAULT_STRIPS

    def __post_init__(self) -> None:
        _, overlap, mid = milling._strips_under_block(self.blade, self.block.thickness_m, int(self.strips))
        object.__setattr__(self, "_overlap", overlap)
        object.__setattr__(self, "_mid", mid)
        object.__setattr__(self, "_chord", self.blade.chord_m(mid))

    def torque_n_m(self, cusp: int, rpm: float) -> float:
        """Ice torque of one blade impact on cusp `cusp` (index into `block`) at `rpm` [N·m]."""
        if not 0.0 <= rpm <= MAX_PROPELLER_RPM:
            raise InputError("rpm", f"{rpm:g} is outside [0, {MAX_PROPELLER_RPM:g}]", value=rpm)
        blade, speed = self.blade, self.advance_speed_m_s
        overlap, mid = self._overlap[cusp], self._mid[cusp]
        length = self.block.length_m[cusp]
        cut = milling.cut_depth_m(speed, rpm, blade.blades)
        with np.errstate(divide="ignore", invalid="ignore"):
            fraction = np.where(cut > length, length / np.where(cut > 0.0, cut, 1.0), 1.0)
        nose, _, flank_length, alpha, beta, phi, _ = milling.section_contact(
            mid, self._chord[cusp], blade.thickness_07_m, blade.pitch_m, rpm, speed, blade.blades, fraction
        )
        nose_area, flank_area = nose * overlap, flank_length * overlap
        pressure = self.ice.pressure_pa(np.sum(nose_area + flank_area, axis=-1))
        friction = self.ice.friction
        resisting, _ = milling.strip_forces(pressure, nose_area, flank_area, alpha, beta, phi, friction)
        return float(np.sum(resisting * mid, axis=-1))
