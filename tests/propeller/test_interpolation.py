"""Volume interpolation: Newton divided differences (thesis Eqs. 23–26, erratum 24) and monotone PCHIP."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.fem import shipped_fem_tables
from floebreak.propeller.interpolation import VolumeInterpolant, divided_differences, newton_evaluate

# thesis Table 10 (pitch 0 %), force in kN, with the origin the thesis adds
X = [0.0, 3.7073, 6.5232, 9.4535, 12.5043]
F = [0.0, 240.55, 263.11, 291.05, 362.60]


def hand_divided_differences(x, f):
    """Eqs. 23–26 written out term by term."""
    f1 = [(f[i + 1] - f[i]) / (x[i + 1] - x[i]) for i in range(4)]  # Eq. 23
    f2 = [(f1[i] - f1[i - 1]) / (x[i + 1] - x[i - 1]) for i in (1, 2, 3)]  # Eq. 24
    f3 = [(f2[1] - f2[0]) / (x[3] - x[0]), (f2[2] - f2[1]) / (x[4] - x[1])]  # Eq. 25, i = 1, 2
    f4 = (f3[1] - f3[0]) / (x[4] - x[0])  # Eq. 26, i = 2
    return [f[0], f1[0], f2[0], f3[0], f4]


def test_divided_differences_match_hand_calculation():
    expected = hand_divided_differences(X, F)
    assert np.allclose(divided_differences(X, F), expected, rtol=1e-13, atol=0)
    # first coefficient pair by hand: 240.55 / 3.7073 kN/m³
    assert divided_differences(X, F)[1] == pytest.approx(240.55 / 3.7073, rel=1e-14)


def test_newton_is_the_quartic_through_all_points():
    c = divided_differences(X, F)
    v = np.linspace(0.0, 14.0, 57)
    # the unique degree-4 polynomial through 5 points, from a Vandermonde solve
    coefficients = np.linalg.solve(np.vander(X, 5), F)
    assert np.allclose(newton_evaluate(X, c, v), np.polyval(coefficients, v), rtol=1e-9, atol=1e-9)
    assert len(c) == 5 and c[-1] != 0.0  # quartic, not cubic (erratum 24)


@pytest.mark.parametrize("pitch", [0.0, 95.0])
@pytest.mark.parametrize("method", ["newton", "pchip"])
def test_interpolants_reproduce_every_table_point(pitch, method):
    table = shipped_fem_tables()[pitch]
    for values in (table.force_n, table.torque_nm):
        f = VolumeInterpolant.through_origin(table.volume_m3, values, method, "extrapolate")
        assert f(0.0) == pytest.approx(0.0, abs=1e-6)
        assert np.allclose(f(table.volume_m3), values, rtol=1e-12)


def test_pchip_is_monotone_where_data_are():
    for table in shipped_fem_tables().values():
        v = np.linspace(0.0, table.max_volume_m3, 2001)
        force = VolumeInterpolant.through_origin(table.volume_m3, table.force_n, "pchip")(v)
        torque = VolumeInterpolant.through_origin(table.volume_m3, table.torque_nm, "pchip")(v)
        assert np.all(np.diff(force) >= -1e-9)
        assert np.all(np.diff(torque) <= 1e-9)
    # data with a plateau: PCHIP never overshoots, a Newton polynomial does
    x, y = [1.0, 2.0, 3.0, 4.0], [1.0, 1.0, 1.0, 5.0]
    v = np.linspace(0.0, 4.0, 401)
    pchip = VolumeInterpolant.through_origin(x, y, "pchip")(v)
    newton = VolumeInterpolant.through_origin(x, y, "newton")(v)
    assert np.all(np.diff(pchip) >= -1e-12) and pchip.max() <= 5.0 + 1e-12
    assert np.any(np.diff(newton) < 0.0)


def test_beyond_policies():
    x, y = [1.0, 2.0], [10.0, 30.0]  # through the origin: 0, 10, 30 → quadratic 5V² + 5V
    v = np.array([1.5, 3.0])
    clamp = VolumeInterpolant.through_origin(x, y, "newton", "clamp")(v)
    extra = VolumeInterpolant.through_origin(x, y, "newton", "extrapolate")(v)
    flag = VolumeInterpolant.through_origin(x, y, "newton", "flag")(v)
    assert clamp == pytest.approx([5 * 1.5**2 + 5 * 1.5, 30.0])
    assert extra == pytest.approx([5 * 1.5**2 + 5 * 1.5, 5 * 9 + 15])
    assert flag[0] == pytest.approx(clamp[0]) and np.isnan(flag[1])


def test_bad_options_name_the_field():
    with pytest.raises(InputError, match="interpolation"):
        VolumeInterpolant.through_origin([1.0, 2.0], [1.0, 2.0], "cubic")
    with pytest.raises(InputError, match="beyond"):
        VolumeInterpolant.through_origin([1.0, 2.0], [1.0, 2.0], "newton", "wrap")
