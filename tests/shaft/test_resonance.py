"""Resonance margin (floebreak.shaft.resonance): crossings and margins computed here from the two-inertia
natural frequency and the blade-passage arithmetic."""

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.shaft.line import shaft_line_from_dict
from floebreak.shaft.resonance import campbell, campbell_from_frequencies

J1, J2, K = 1000.0, 100.0, 1e7  # motor, propeller [kg m²], shaft [N m/rad]


def two_inertia(rpm=140.0):
    return shaft_line_from_dict(
        {
            "name": "two",
            "rpm": rpm,
            "mean_torque_n_m": 1e4,
            "elements": [
                {"name": "motor", "inertia_kg_m2": J1, "stiffness_n_m_per_rad": K, "shaft": "shaft"},
                {"name": "propeller", "inertia_kg_m2": J2},
            ],
        }
    )


def test_crossings_and_margins_of_a_two_inertia_line():
    f_n = math.sqrt(K * (J1 + J2) / (J1 * J2)) / (2 * math.pi)  # 52.8 Hz
    c = campbell(two_inertia(), blades=4)
    assert c.natural_frequency_hz == pytest.approx([f_n], rel=1e-9)
    np.testing.assert_array_equal(c.orders, [4, 8, 12])
    np.testing.assert_allclose(c.crossing_rpm[:, 0], [f_n / (k * 4) * 60 for k in (1, 2, 3)])
    f_op = np.array([4, 8, 12]) * 140 / 60
    np.testing.assert_allclose(c.margin[:, 0], np.abs(f_n - f_op) / f_op)
    assert c.rpm[0] == 0.0
    assert c.rpm[-1] == pytest.approx(154.0)  # 110 % of 140 rpm
    np.testing.assert_allclose(c.order_frequency_hz[1], 8 * c.rpm / 60)
    # 52.8 Hz is reached by order 12 at 264 rpm and by order 4 at 792 rpm: no crossing on 0-154 rpm
    assert not c.crossing_in_range.any()
    assert not c.warning


def test_a_warning_inside_the_required_margin():
    # 9.8 Hz against the first order at 140 rpm, Z = 4 (9.333 Hz): margin 5 %
    c = campbell_from_frequencies([9.8, 30.0], 140.0, blades=4, required_margin=0.2)
    assert c.margin[0, 0] == pytest.approx(abs(9.8 - 28 / 3) / (28 / 3))
    np.testing.assert_array_equal(c.within_margin, [[True, False], [False, False], [False, True]])
    # 30 Hz against order 12 (28 Hz): margin 7 %, inside; against order 8 (18.67 Hz): 61 %, outside
    assert c.warning
    text = c.warnings()
    assert len(text) == 2
    assert "mode 1 (9.80 Hz)" in text[0] and "order 4" in text[0] and "147.0 rpm" in text[0]
    assert not campbell_from_frequencies([9.8], 140.0, required_margin=0.04).warning


def test_crossing_inside_the_operating_range():
    c = campbell_from_frequencies([7.76], 140.0, blades=4)
    assert c.crossing_rpm[0, 0] == pytest.approx(7.76 / 4 * 60)  # 116.4 rpm, on the 0-154 rpm grid
    np.testing.assert_array_equal(c.crossing_in_range[:, 0], [True, True, True])  # 58.2 and 38.8 rpm too


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"required_margin": -0.1}, "required_margin"),
        ({"harmonics": (0, 1)}, "harmonics"),
        ({"blades": 0}, "blades"),
        ({"points": 1}, "points"),
        ({"rpm_fraction": (0.5, 0.4)}, "rpm_fraction[1]"),
    ],
)
def test_bad_input_names_the_key(kwargs, key):
    with pytest.raises(InputError) as error:
        campbell_from_frequencies([9.0], 140.0, **kwargs)
    assert error.value.field == key
    with pytest.raises(InputError) as error:
        campbell_from_frequencies([0.0], 140.0)
    assert error.value.field == "natural_frequency_hz"
    with pytest.raises(InputError) as error:
        campbell_from_frequencies([9.0], 0.0)
    assert error.value.field == "operating_rpm"
