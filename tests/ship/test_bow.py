"""Bow geometry: validation, normals (thesis Eq. 20, erratum 22), ψ_v (notes §2.1), footprints, CSV."""

from importlib import resources

import numpy as np
import pytest
import shapely
from matplotlib.figure import Figure

from floebreak.errors import InputError
from floebreak.plotting.bow import plot_bow
from floebreak.ship import Bow, agulhas_ii, polarstern

EXAMPLE_CSV = resources.files("floebreak.data") / "example_bow.csv"


def wedge_bow(alpha_deg=30.0, phi_deg=40.0, length_m=12.0, dz_m=1.0):
    """A wedge bow with two plane hull sides: waterline half angle α, stem angle φ (from the horizontal).

    The lower stem tip lies Δz/tan φ aft of the upper one; each lower side is parallel to its upper side.
    """
    t = np.tan(np.radians(alpha_deg))
    tip = dz_m / np.tan(np.radians(phi_deg))
    b = length_m * t
    b_low = (length_m - tip) * t
    upper = np.array([[-length_m, b], [0.0, 0.0], [-length_m, -b]])
    lower = np.array([[-length_m, b_low], [-tip, 0.0], [-length_m, -b_low]])
    return Bow("wedge", upper, lower, 0.1 * dz_m, -0.9 * dz_m)


def psi_from_plane(p0, p1, p2):
    """ψ from the vertical of the plane through three 3-D points: ψ = arcsin |n_z| (physics-notes §2.1)."""
    n = np.cross(np.subtract(p1, p0), np.subtract(p2, p0))
    return np.degrees(np.arcsin(abs(n[2]) / np.linalg.norm(n)))


@pytest.mark.parametrize(("alpha_deg", "phi_deg"), [(30.0, 40.0), (32.27, 27.0), (20.0, 60.0), (45.0, 15.0)])
def test_wedge_psi_matches_independent_plane_calculation(alpha_deg, phi_deg):
    bow = wedge_bow(alpha_deg, phi_deg)
    z_u, z_l = bow.z_upper_m, bow.z_lower_m
    tip = 1.0 / np.tan(np.radians(phi_deg))
    # plane through the two upper port nodes and the lower stem tip (3-D)
    port = psi_from_plane(
        (-12.0, 12.0 * np.tan(np.radians(alpha_deg)), z_u), (0.0, 0.0, z_u), (-tip, 0.0, z_l)
    )
    starboard = psi_from_plane(
        (0.0, 0.0, z_u), (-12.0, -12.0 * np.tan(np.radians(alpha_deg)), z_u), (-tip, 0, z_l)
    )
    np.testing.assert_allclose(np.degrees(bow.panel_psi_rad), [port, starboard], rtol=1e-10)
    # and Lindqvist's relation tan ψ_v = sin α / tan φ (physics-notes §2.1)
    expected = np.degrees(np.arctan(np.sin(np.radians(alpha_deg)) / np.tan(np.radians(phi_deg))))
    assert bow.psi_stem_deg == pytest.approx(expected, rel=1e-10)


def test_wedge_normals_eq20_with_one_sided_ends():
    bow = wedge_bow(30.0, 40.0)
    a = np.radians(30.0)
    np.testing.assert_allclose(
        bow.panel_normals, [[np.sin(a), np.cos(a)], [np.sin(a), -np.cos(a)]], atol=1e-12
    )
    # end nodes: one-sided differences → the normal of their only panel; stem: central difference → +x
    np.testing.assert_allclose(
        bow.node_normals, [[np.sin(a), np.cos(a)], [1.0, 0.0], [np.sin(a), -np.cos(a)]], atol=1e-12
    )


@pytest.mark.parametrize("make", [agulhas_ii, polarstern, lambda: Bow.from_csv(EXAMPLE_CSV)])
def test_normals_unit_and_outward(make):
    bow = make()
    centroid = np.array(bow.hull_upper.centroid.coords[0])
    for normals, points in ((bow.node_normals, bow.upper_xy_m), (bow.panel_normals, bow.panel_midpoints_m)):
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, rtol=1e-12)
        assert (np.einsum("ij,ij->i", normals, points - centroid) > 0).all()
        # a point a little along the normal lies outside the hull
        outside = points + 1e-3 * normals
        assert not shapely.contains_xy(bow.hull_upper, outside[:, 0], outside[:, 1]).any()
    np.testing.assert_allclose(bow.node_normals[bow.stem_index], [1.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("make", [agulhas_ii, polarstern, lambda: Bow.from_csv(EXAMPLE_CSV), wedge_bow])
def test_footprints_tile_the_strip_between_the_waterlines(make):
    bow = make()
    strip = shapely.difference(bow.hull_upper, bow.hull_lower)
    union = shapely.union_all(bow.panel_footprints)
    assert union.area == pytest.approx(strip.area, rel=1e-6)
    assert shapely.symmetric_difference(union, strip).area <= 1e-6 * strip.area
    # footprints do not overlap: their areas add up to the strip
    assert sum(p.area for p in bow.panel_footprints) == pytest.approx(strip.area, rel=1e-6)
    assert len(bow.panel_footprints) == bow.n_panels == len(bow.upper_xy_m) - 1


def test_example_csv_against_its_stations():
    bow = Bow.from_csv(EXAMPLE_CSV)
    assert bow.name == "example_bow"
    assert bow.n_panels == 2 * 13
    assert bow.half_breadth_m == pytest.approx(10.85)
    assert bow.length_bow_m == pytest.approx(34.366)
    assert bow.dz_m == pytest.approx(1.0)
    # stem: α_0 from the first station, β_0 = 51.1°: ψ = arctan(tan β cos α); tip at −Δz tan β_0 / tan α_0
    alpha0 = np.arctan2(0.313, 0.5)
    beta0 = np.radians(51.1)
    assert bow.psi_stem_deg == pytest.approx(np.degrees(np.arctan(np.tan(beta0) * np.cos(alpha0))), abs=1e-9)
    np.testing.assert_allclose(bow.lower_xy_m[bow.stem_index], [-np.tan(beta0) / np.tan(alpha0), 0.0])
    assert bow.psi_shoulder_deg == pytest.approx(20.0, abs=0.05)
    # mirrored
    np.testing.assert_allclose(bow.upper_xy_m[::-1] * [1, -1], bow.upper_xy_m, atol=1e-12)


def test_csv_round_trip(tmp_path):
    bow = agulhas_ii(ice_thickness_m=1.3, n_panels_per_side=12)
    path = bow.to_csv(tmp_path / "bow.csv")
    again = Bow.from_csv(path)
    assert again.name == bow.name
    np.testing.assert_array_equal(again.upper_xy_m, bow.upper_xy_m)
    np.testing.assert_array_equal(again.lower_xy_m, bow.lower_xy_m)
    assert (again.z_upper_m, again.z_lower_m) == (bow.z_upper_m, bow.z_lower_m)
    np.testing.assert_array_equal(again.panel_psi_rad, bow.panel_psi_rad)
    assert again.length_bow_m == bow.length_bow_m


LINES_HEADER = "# z_upper_m = 0.1\n# z_lower_m = -0.9\nline,x_m,y_m\n"
GOOD_ROWS = [
    "upper,-10,5",
    "upper,0,0",
    "upper,-10,-5",
    "lower,-10,4.4",
    "lower,-1.2,0",
    "lower,-10,-4.4",
]


def write(tmp_path, rows, header=LINES_HEADER):
    path = tmp_path / "bow.csv"
    path.write_text(header + "\n".join(rows) + "\n")
    return path


def test_csv_format_a_reads(tmp_path):
    bow = Bow.from_csv(write(tmp_path, GOOD_ROWS))
    assert bow.n_panels == 2
    assert bow.dz_m == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("row_index", "replacement", "words"),
    [
        (2, "upper,-10,nan", "not a finite number"),  # non-finite
        (2, "upper,-10,inf", "not a finite number"),
        (0, "upper,-10,abc", "not a number"),
        (4, "lower,2.0,0", "outside"),  # lower tip ahead of the upper stem: outside H_u
        (3, "lower,-10,5.5", "outside"),  # lower port aft node outside H_u
        (1, "upper,0,0", None),  # control: unchanged
    ],
)
def test_csv_bad_value_names_row_and_column(tmp_path, row_index, replacement, words):
    rows = list(GOOD_ROWS)
    rows[row_index] = replacement
    path = write(tmp_path, rows)
    if words is None:
        Bow.from_csv(path)
        return
    with pytest.raises(InputError) as info:
        Bow.from_csv(path)
    # data rows counted from 1 after the header; the file has 2 comment lines and the header before them
    assert f"bow.csv, row {row_index + 1} (line {row_index + 4})" in str(info.value)
    assert words in str(info.value)
    assert "x_m" in str(info.value) or "y_m" in str(info.value)


def test_csv_self_intersection_names_row(tmp_path):
    rows = [
        "upper,-10,5",
        "upper,-4,3",
        "upper,0,0",  # row 3, line 6: the segment from here crosses the aft closure of the hull polygon
        "upper,-12,-1",
        "upper,-10,-5",
        "lower,-10,4",
        "lower,-4,2.5",
        "lower,-1,0",
        "lower,-11,-1",
        "lower,-10,-4",
    ]
    expected = r"bow.csv, row 3 \(line 6\): upper waterline \(columns x_m, y_m\): .*intersects itself"
    with pytest.raises(InputError, match=expected):
        Bow.from_csv(write(tmp_path, rows))
    rows = [
        "upper,-10,5",
        "upper,-2,5",  # the next segment runs back over the segment from row 1 (line 4)
        "upper,-6,5",
        "upper,0,0",
        "upper,-10,-5",
        "lower,-10,4",
        "lower,-3,4",
        "lower,-3,4",
        "lower,-1,0",
        "lower,-10,-4",
    ]
    with pytest.raises(InputError, match=r"row 1 \(line 4\): upper waterline.*intersects itself"):
        Bow.from_csv(write(tmp_path, rows))


def test_csv_wrong_columns_and_formats(tmp_path):
    with pytest.raises(InputError, match=r"bow.csv, header \(line 3\): unexpected columns") as info:
        Bow.from_csv(write(tmp_path, GOOD_ROWS, header=LINES_HEADER.replace("y_m", "y")))
    assert "allowed" in str(info.value)
    with pytest.raises(InputError, match=r"bow.csv, row 1 \(line 4\), column 'line': 'port' is not a"):
        Bow.from_csv(write(tmp_path, ["port,-10,5", *GOOD_ROWS[1:]]))
    with pytest.raises(InputError, match="z_upper_m"):
        Bow.from_csv(write(tmp_path, GOOD_ROWS, header="line,x_m,y_m\n"))
    with pytest.raises(InputError, match=r"bow.csv, row 1 \(line 4\): has 4 values, the header has 3"):
        Bow.from_csv(write(tmp_path, ["upper,-10,5,1", *GOOD_ROWS[1:]]))


def test_csv_stations_errors_name_row(tmp_path):
    header = "# ice_thickness_m = 1\nx_m,half_breadth_m,frame_angle_deg\n"
    good = ["0,0,40", "-5,2,35", "-10,3,30", "-20,3,30"]
    assert Bow.from_csv(write(tmp_path, good, header)).n_panels == 6
    for index, bad, words in [
        (1, "-5,nan,35", "column 'half_breadth_m'"),
        (2, "-10,3,95", "column 'frame_angle_deg'"),
        (2, "-4,3,30", "column 'x_m'"),
    ]:
        rows = list(good)
        rows[index] = bad
        # a comment line and the header before the stations: station `index` is row index + 1, line index + 3
        with pytest.raises(InputError, match=rf"row {index + 1} \(line {index + 3}\), {words}"):
            Bow.from_csv(write(tmp_path, rows, header))


def test_bow_validation_names_field_and_node():
    upper = np.array([[-10.0, 5.0], [0.0, 0.0], [-10.0, -5.0]])
    lower = np.array([[-10.0, 4.0], [-1.0, 0.0], [-10.0, -4.0]])
    with pytest.raises(InputError, match=r"upper_xy_m\[1\]"):
        Bow("b", upper + np.array([1.0, 0.0]), lower, 0.1, -0.9)  # stem not at the origin
    with pytest.raises(InputError, match="lower_xy_m"):
        Bow("b", upper, lower[:2], 0.1, -0.9)
    with pytest.raises(InputError, match=r"lower_xy_m\[1\]"):
        Bow("b", upper, [[-10.0, 4.0], [1.0, 0.0], [-10.0, -4.0]], 0.1, -0.9)
    with pytest.raises(InputError, match="z_lower_m"):
        Bow("b", upper, lower, 0.1, 0.2)
    with pytest.raises(InputError, match=r"upper_xy_m\[0\]"):
        Bow("b", upper[::-1], lower[::-1], 0.1, -0.9)  # starboard first
    with pytest.raises(InputError, match=r"upper_xy_m\[2\]"):
        Bow("b", [[-10, 5], [0, 0], [np.nan, -5]], lower, 0.1, -0.9)


def test_bow_is_frozen_and_read_only():
    bow = wedge_bow()
    with pytest.raises(AttributeError):
        bow.name = "other"
    with pytest.raises(ValueError):
        bow.upper_xy_m[0, 0] = 1.0
    with pytest.raises(TypeError):
        bow.parameters["x"] = 1


def test_panel_at_nearest_panel():
    bow = agulhas_ii(n_panels_per_side=10)
    for i in (0, 3, bow.stem_index - 1, bow.stem_index, bow.n_panels - 1):
        point = bow.panel_midpoints_m[i] + 0.2 * bow.panel_normals[i]
        assert bow.panel_at(point) == i
    np.testing.assert_array_equal(bow.panel_at(bow.panel_midpoints_m), np.arange(bow.n_panels))


def test_contact_consumer_accepts_bow():
    from floebreak.mechanics.contact import BowContactGeometry

    geometry = BowContactGeometry.from_bow(agulhas_ii())
    assert len(geometry.footprints) == len(geometry.panel_psi_rad)


def test_plot_bow_returns_figure_with_colorbar():
    figure = plot_bow(agulhas_ii(n_panels_per_side=8))
    assert isinstance(figure, Figure)
    main, colorbar = figure.axes
    assert colorbar.get_ylabel() == "ψ [deg]"
    assert main.get_xlabel() == "x [m]" and main.get_ylabel() == "y [m]"
    assert main.get_aspect() == 1.0
