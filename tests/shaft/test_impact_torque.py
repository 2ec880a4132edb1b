"""The drive's per-impact torque (`shaft.impact_torque.CuspTorques`) is the milling model's
(`propeller.milling.impact_loads`), to the bit, for any block and rpm (one call per blade
passage)."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.loads.milling import BladeGeometry, IceBlock, IceStrength, impact_loads
from floebreak.propeller.spec import PropellerSpec
from floebreak.shaft.impact_torque import CuspTorques


@pytest.mark.parametrize(
    "blade",
    [
        BladeGeometry.from_spec(PropellerSpec()),
        BladeGeometry(3.0, 5, 0.3, 1.1, 0.6, 0.08, pitch_percent=40.0, chord_distribution="constant"),
        BladeGeometry(2.0, 3, 0.25, 0.8, 0.5, 0.05, pitch_percent=0.0),
    ],
)
def test_torque_is_impact_loads_torque(blade):
    rng = np.random.default_rng(11)
    # thin to thicker than the blade span, short (cut once) to long, narrow to wide
    block = IceBlock(rng.uniform(0.05, 4.0, 30), rng.uniform(0.01, 6.0, 30), rng.uniform(0.1, 5.0, 30))
    ice = IceStrength(crushing_pressure_pa=2.0e6, area_exponent=-0.3)
    for speed in (0.0, 0.4, 3.0):
        torques = CuspTorques(block, blade, speed, ice=ice, strips=48)
        for cusp in range(block.thickness_m.size):
            one = IceBlock(*(a[cusp : cusp + 1] for a in (block.thickness_m, block.length_m, block.width_m)))
            for rpm in (0.0, 1e-3, 37.5, rng.uniform(0.0, 160.0), 140.0):
                expected = impact_loads(one, blade, rpm, speed, ice=ice, strips=48).torque_n_m[0]
                assert torques.torque_n_m(cusp, rpm) == expected, (cusp, rpm, speed)
    assert CuspTorques(block, blade, 3.0).torque_n_m(0, 140.0) > 0.0  # defaults: impact_loads' defaults


def test_rpm_outside_range_refused():
    blade = BladeGeometry.from_spec(PropellerSpec())
    torques = CuspTorques(IceBlock(np.array([1.0]), np.array([2.0]), np.array([1.0])), blade, 3.0)
    with pytest.raises(InputError, match="rpm"):
        torques.torque_n_m(0, -1.0)


def test_torque_with_engaged_intervals_is_impact_loads_torque():
    blade = BladeGeometry.from_spec(PropellerSpec())
    rng = np.random.default_rng(12)
    inner = rng.uniform(0.0, 2.2, 20)
    outer = inner + rng.uniform(0.0, 1.0, 20)
    inner[::4], outer[::4] = np.nan, np.nan  # tip placement among them
    block = IceBlock(
        rng.uniform(0.2, 2.0, 20), rng.uniform(0.5, 6.0, 20), rng.uniform(0.5, 3.0, 20), inner, outer
    )
    torques = CuspTorques(block, blade, 3.0)
    for cusp in range(20):
        one = IceBlock(
            *(a[cusp : cusp + 1] for a in (block.thickness_m, block.length_m, block.width_m, inner, outer))
        )
        for rpm in (60.0, 140.0):
            assert torques.torque_n_m(cusp, rpm) == impact_loads(one, blade, rpm, 3.0).torque_n_m[0]
