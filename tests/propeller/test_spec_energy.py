"""Propeller description, pitch angle (erratum 23) and cusp kinetic energy (thesis Eqs. 27–28, §6.3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.cusps import kinetic_energy_j
from floebreak.propeller.spec import PropellerSpec, propeller_pitch_angle_deg


def test_agulhas_defaults_and_pitch():
    spec = PropellerSpec()
    assert spec.radius_m == 2.15 and spec.max_pitch_m == 5.15 and spec.rpm == 140.0
    assert spec.pitch_m == pytest.approx(4.9365, abs=5e-5)  # thesis §6.1.2
    assert spec.r07_m == pytest.approx(1.505)


def test_pitch_angles_thesis_and_corrected():
    spec = PropellerSpec()
    assert propeller_pitch_angle_deg(spec, "thesis_r_prop") == pytest.approx(20.07, abs=0.005)
    assert propeller_pitch_angle_deg(spec, "r07") == pytest.approx(27.57, abs=0.005)
    # at 100 % pitch: atan(5.15 / (2π·1.505)) = 28.573° (notes erratum 23 rounds it to 28.58°)
    full = PropellerSpec(pitch_percent=100.0)
    assert propeller_pitch_angle_deg(full) == pytest.approx(
        math.degrees(math.atan(5.15 / (2 * math.pi * 1.505)))
    )
    assert propeller_pitch_angle_deg(full) == pytest.approx(28.58, abs=0.01)
    with pytest.raises(InputError, match="pitch_angle_radius"):
        propeller_pitch_angle_deg(spec, "tip")


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"radius_m": -1.0}, "propeller.radius_m"),
        ({"rpm": 0.0}, "propeller.rpm"),
        ({"rpm": float("nan")}, "propeller.rpm"),
        ({"blades": 0}, "propeller.blades"),
        ({"blades": 2.5}, "propeller.blades"),
        ({"pitch_percent": 120.0}, "propeller.pitch_percent"),
        ({"hub_ratio": 1.0}, "propeller.hub_ratio"),
    ],
)
def test_bad_propeller_names_the_field(kwargs, field):
    with pytest.raises(InputError) as info:
        PropellerSpec(**kwargs)
    assert info.value.field == field


def test_kinetic_energy_of_the_exemplary_cusps():
    # thesis §6.3: 15.32, 26.90, 39.00, 51.59 kJ for the Table 10/11 volumes at 3 m/s, rho = 917 kg/m³.
    # ½·917·V·3² with the table volumes gives 15.30, 26.92, 39.01, 51.60 kJ: the thesis' rounding differs
    # by up to 0.02 kJ (0.14 %), hence the tolerance.
    volumes = np.array([3.7073, 6.5232, 9.4535, 12.5043])
    energy_kj = kinetic_energy_j(volumes, 3.0, 917.0) / 1e3
    assert energy_kj == pytest.approx([15.32, 26.90, 39.00, 51.59], abs=0.025)
    assert energy_kj[0] == pytest.approx(0.5 * 917 * 3.7073 * 9 / 1e3, rel=1e-12)
