"""Volume interpolation: Newton divided differences (thesis Eqs. 23–26, erratum 24) and monotone PCHIP."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.app.inputs import shipped_fem_tables
from floebreak.errors import InputError
from floebreak.propeller.interpolation import (
    VolumeInterpolant,
    divided_differences,
    newton_evaluate,
    power_law_exponent,
    table_interpolant,
)
from floebreak.propeller.loads.fem import parse_fem_table

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


def test_power_law_beyond_the_table():
    """A table on y = 3 V^0.6 (the origin added): the exponent fitted to the three largest points is 0.6,
    the loads beyond V_max follow 3 V^0.6, continuous at V_max; the default policy is the power law."""
    x = np.array([2.0, 4.0, 6.0, 8.0])
    y = 3.0 * x**0.6
    assert power_law_exponent(x, y) == pytest.approx(0.6, abs=1e-12)
    assert power_law_exponent(x, -y) == pytest.approx(0.6, abs=1e-12)  # torques are negative
    curve = VolumeInterpolant.through_origin(x, y, "pchip")
    assert curve.beyond == "power_law"
    v = np.array([8.0, 8.0 + 1e-9, 12.0, 30.0])
    assert curve(v) == pytest.approx(3.0 * v**0.6, rel=1e-9)
    # thesis Table 11 (95 %): b = Σ a c / Σ a² over its three largest cusps, anchored at 12.5043 m³
    t95 = shipped_fem_tables()[95.0]
    a = np.log(np.array([6.5232, 9.4535]) / 12.5043)
    c = np.log(np.array([1058.27, 1434.74]) / 1686.20)
    assert power_law_exponent(t95.volume_m3, t95.force_n) == pytest.approx(np.sum(a * c) / np.sum(a * a))
    with pytest.raises(InputError, match="no power law"):
        VolumeInterpolant.through_origin([1.0, 2.0, 3.0], [1.0, -1.0, 2.0])(np.array([4.0]))


def _table(text):
    return parse_fem_table(text, "t.csv")


GRID = """# pitch_percent: 95
# dimensions: volume, thickness
volume_m3,thickness_m,force_kN,torque_kNm
2,0.5,100,-90
4,0.5,200,-180
8,0.5,400,-360
2,1.0,200,-180
4,1.0,400,-360
8,1.0,800,-720
"""


def test_volume_by_thickness_grid():
    """Loads on F = 100 kN/m⁴ · V · h, exactly bilinear, so the RegularGridInterpolator reproduces them
    inside the grid and down to zero (the zero faces added): a 0.4 m thick cusp gets less load than a
    1 m thick one of the same volume. Beyond the grid: flagged, clamped value × (V / V_clamped)^(2/3)."""
    table = _table(GRID)
    assert table.dimensions == ("volume", "height")
    force = table_interpolant(table, "force")
    coords = {"volume": np.array([3.0, 3.0, 6.0, 1.0, 16.0]), "height": np.array([0.5, 0.75, 1.0, 0.25, 1.0])}
    load, beyond = force(coords)
    assert load[:4] == pytest.approx(100e3 * np.array([1.5, 2.25, 6.0, 0.25]))
    assert beyond.tolist() == [False, False, False, False, True]
    assert load[4] == pytest.approx(800e3 * 2.0 ** (2 / 3))
    flagged, _ = table_interpolant(table, "torque", beyond="flag")(coords)
    assert np.isnan(flagged[4]) and flagged[0] == pytest.approx(-135e3)
    with pytest.raises(InputError, match="not extrapolated"):
        table_interpolant(table, "force", beyond="extrapolate")


def test_scattered_length_width_height_table():
    """Scattered points of F = (10 l + 20 w + 30 h) kN (linear through the origin): LinearNDInterpolator
    reproduces it inside the hull of the points and the origin; outside, the nearest point, flagged."""
    rng = np.random.default_rng(3)
    points = rng.uniform(1.0, 4.0, (12, 3))
    rows = "\n".join(
        f"{lx},{w},{h},{10 * lx + 20 * w + 30 * h},{-(10 * lx + 20 * w + 30 * h)}" for lx, w, h in points
    )
    header = "length_m,width_m,height_m,force_kN,torque_kNm"
    text = f"# pitch_percent: 0\n# dimensions: length, width, height\n{header}\n{rows}\n"
    table = _table(text)
    inside = points.mean(axis=0)
    coords = {
        "length": np.array([inside[0], 50.0]),
        "width": np.array([inside[1], 1.0]),
        "height": np.array([inside[2], 1.0]),
    }
    load, beyond = table_interpolant(table, "force", beyond="clamp")(coords)
    assert load[0] == pytest.approx(1e3 * (10 * inside[0] + 20 * inside[1] + 30 * inside[2]))
    assert beyond.tolist() == [False, True]
    nearest = points[np.argmin(np.linalg.norm(points - [50.0, 1.0, 1.0], axis=1))]
    assert load[1] == pytest.approx(1e3 * (10 * nearest[0] + 20 * nearest[1] + 30 * nearest[2]))


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (GRID.replace("volume, thickness", "volume, colour"), "dimensions"),
        (GRID.replace("4,1.0,400", "4,1.0,nan"), r"row 5, column 'force_kN' is 'nan'"),
        (GRID.replace("4,1.0,400", "-4,1.0,400"), r"row 5, column 'volume_m3' must be > 0"),
        (GRID.replace("8,1.0,800", "4,1.0,800"), "appears twice"),
        (GRID.replace("thickness_m,", ""), "missing column.*height"),
        (GRID.replace("# pitch_percent: 95\n", ""), "pitch unknown"),
    ],
)
def test_bad_nd_tables(text, match):
    with pytest.raises(InputError, match=match):
        _table(text)
