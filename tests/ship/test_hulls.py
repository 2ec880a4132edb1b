"""Built-in parametric hulls against the example table of physics-notes §6.3 (Δz = 1 m, β_sh = 20°)."""

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.ship import HULLS, agulhas_ii, get_hull, parametric_bow, polarstern, stem_angle_from_thesis

# physics-notes §6.3 table: L_b [m], β_0 [deg], ψ_v stem [deg], ψ_v shoulder [deg], lower tip aft [m]
TABLE = {
    "agulhas_ii": (34.4, 51.1, 46.3, 20.0, 1.96),
    "polarstern": (39.6, 32.3, 28.1, 20.0, 1.00),
}


@pytest.mark.parametrize("name", sorted(TABLE))
def test_physics_notes_table(name):
    length_b, beta0, psi_stem, psi_shoulder, tip = TABLE[name]
    bow = get_hull(name)
    assert bow.length_bow_m == pytest.approx(length_b, abs=0.05)
    assert bow.parameters["frame_angle_stem_deg"] == pytest.approx(beta0, abs=0.05)
    assert bow.psi_stem_deg == pytest.approx(psi_stem, abs=0.05)
    assert bow.psi_shoulder_deg == pytest.approx(psi_shoulder, abs=0.05)
    assert -bow.lower_xy_m[bow.stem_index, 0] == pytest.approx(tip, abs=0.005)
    assert bow.lower_xy_m[bow.stem_index, 1] == 0.0
    assert bow.dz_m == pytest.approx(1.0)


def test_agulhas_inputs_from_the_thesis():
    bow = agulhas_ii()
    assert bow.half_breadth_m == pytest.approx(21.7 / 2)
    assert bow.parameters["waterline_entrance_half_angle_deg"] == pytest.approx(64.54 / 2)
    assert bow.parameters["stem_angle_deg"] == pytest.approx(27.0)
    assert polarstern().half_breadth_m == pytest.approx(12.5)


@pytest.mark.parametrize("make", [agulhas_ii, polarstern])
def test_mirror_symmetry(make):
    bow = make()
    mirror = np.array([1.0, -1.0])
    np.testing.assert_allclose(bow.upper_xy_m[::-1] * mirror, bow.upper_xy_m, atol=1e-12)
    np.testing.assert_allclose(bow.lower_xy_m[::-1] * mirror, bow.lower_xy_m, atol=1e-12)
    np.testing.assert_allclose(bow.panel_psi_rad[::-1], bow.panel_psi_rad, atol=1e-12)
    np.testing.assert_allclose(bow.panel_normals[::-1] * mirror, bow.panel_normals, atol=1e-12)
    assert bow.stem_index == (len(bow.upper_xy_m) - 1) // 2


def test_waterline_and_node_spacing_follow_section_6_3():
    n, b, a0, p = 16, 20.0, 30.0, 2.0
    bow = parametric_bow("t", b, a0, 30.0, n_panels_per_side=n, midbody_length_m=5.0)
    length_b = p * (b / 2) / np.tan(np.radians(a0))
    s = length_b * (1 - np.cos(np.pi * np.arange(n + 1) / (2 * n)))
    port = bow.upper_xy_m[: bow.stem_index + 1][::-1]  # stem → aft
    np.testing.assert_allclose(-port[: n + 1, 0], s, atol=1e-9)
    np.testing.assert_allclose(port[: n + 1, 1], (b / 2) * (1 - (1 - s / length_b) ** p), atol=1e-9)
    np.testing.assert_allclose(port[-1], [-(length_b + 5.0), b / 2])
    assert bow.n_panels == 2 * (n + 1)


def test_lower_line_offset_is_dz_tan_psi_along_the_normal():
    """Away from the stem the lower node is the upper node moved inward by Δz tan ψ_v(s)."""
    b, a0, phi, beta_sh, h = 21.7, 32.27, 27.0, 20.0, 1.4
    bow = parametric_bow("t", b, a0, phi, ice_thickness_m=h, n_panels_per_side=20, midbody_length_m=0.0)
    length_b = 2 * (b / 2) / np.tan(np.radians(a0))
    beta0 = np.arctan(np.tan(np.radians(a0)) / np.tan(np.radians(phi)))
    port_u = bow.upper_xy_m[: bow.stem_index + 1][::-1]
    port_l = bow.lower_xy_m[: bow.stem_index + 1][::-1]
    s = -port_u[:, 0]
    alpha = np.arctan(np.tan(np.radians(a0)) * (1 - s / length_b))
    beta = beta0 + (np.radians(beta_sh) - beta0) * s / length_b
    offset = h * np.tan(beta) * np.cos(alpha)  # Δz tan ψ_v
    expected = port_u - offset[:, None] * np.column_stack([np.sin(alpha), np.cos(alpha)])
    keep = expected[:, 1] > 0
    assert keep.sum() > 10
    np.testing.assert_allclose(port_l[keep], expected[keep], atol=1e-9)
    # the others collapse onto the lower stem tip at −Δz / tan φ_s
    np.testing.assert_allclose(port_l[~keep], [[-h / np.tan(np.radians(phi)), 0.0]] * int((~keep).sum()))


def test_wedge_with_constant_flare_has_constant_psi():
    """p = 1 gives straight sides (α = α_0); with β_sh = β_0 every bow panel has tan ψ = sin α_0 / tan φ_s."""
    a0, phi = 25.0, 35.0
    beta0 = np.degrees(np.arctan(np.tan(np.radians(a0)) / np.tan(np.radians(phi))))
    bow = parametric_bow(
        "w",
        10.0,
        a0,
        phi,
        shape_exponent=1.0,
        shoulder_frame_angle_deg=beta0,
        n_panels_per_side=6,
        midbody_length_m=0.0,
    )
    expected = np.degrees(np.arctan(np.sin(np.radians(a0)) / np.tan(np.radians(phi))))
    np.testing.assert_allclose(np.degrees(bow.panel_psi_rad), expected, atol=1e-9)
    assert bow.length_bow_m == pytest.approx(5.0 / np.tan(np.radians(a0)))


def test_ice_thickness_sets_waterline_heights():
    bow = agulhas_ii(ice_thickness_m=2.0)
    ratio = 917.0 / 1025.0
    assert bow.z_upper_m == pytest.approx((1 - ratio) * 2.0)
    assert bow.z_lower_m == pytest.approx(-ratio * 2.0)
    assert -bow.lower_xy_m[bow.stem_index, 0] == pytest.approx(2.0 / np.tan(np.radians(27.0)))


def test_stem_angle_interpretations():
    # physics-notes §6.2: (a) 90° − 63° = 27°; (b) arctan(sin 32.27° / tan 63°) = 15.2°
    assert stem_angle_from_thesis(63.0, 32.27) == pytest.approx(27.0)
    assert stem_angle_from_thesis(63.0, 32.27, "panel_psi") == pytest.approx(15.2, abs=0.05)
    bow = agulhas_ii(stem_angle_interpretation="panel_psi")
    assert bow.psi_stem_deg == pytest.approx(63.0, abs=0.05)  # then ψ_v at the stem is the thesis's 63°
    assert bow.parameters["stem_angle_interpretation"] == "panel_psi"
    with pytest.raises(InputError, match=r"stem_angle_interpretation.*buttock, panel_psi"):
        agulhas_ii(stem_angle_interpretation="other")


def test_overrides_and_registry():
    bow = agulhas_ii(shoulder_frame_angle_deg=10.0, n_panels_per_side=8, midbody_length_m=0.0)
    assert bow.psi_shoulder_deg == pytest.approx(10.0, abs=0.05)
    assert bow.n_panels == 16
    assert get_hull("polarstern", ice_thickness_m=0.5).dz_m == pytest.approx(0.5)
    assert set(HULLS) == {"agulhas_ii", "polarstern"}
    with pytest.raises(InputError, match=r"unknown hull.*agulhas_ii, polarstern"):
        get_hull("titanic")
    with pytest.raises(InputError, match=r"agulhas_ii\.colour"):
        agulhas_ii(colour="red")


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"beam_m": -1.0}, "beam_m"),
        ({"waterline_entrance_half_angle_deg": 90.0}, "waterline_entrance_half_angle_deg"),
        ({"stem_angle_deg": 0.0}, "stem_angle_deg"),
        ({"shape_exponent": 0.5}, "shape_exponent"),
        ({"ice_thickness_m": 0.0}, "ice_thickness_m"),
        ({"n_panels_per_side": 1}, "n_panels_per_side"),
        ({"midbody_length_m": float("nan")}, "midbody_length_m"),
    ],
)
def test_parametric_input_errors(kw, field):
    args = {
        "name": "t",
        "beam_m": 20.0,
        "waterline_entrance_half_angle_deg": 30.0,
        "stem_angle_deg": 30.0,
        **kw,
    }
    with pytest.raises(InputError, match=field):
        parametric_bow(**args)


def test_a_hull_parameter_name_renames_the_bow():
    # fuzz campaign: ship.hull_parameters = {name = "fuzz"} — an allowed parametric keyword —
    # collided with get_hull's own `name` (TypeError: got multiple values for argument 'name')
    from floebreak.api import build_bow
    from floebreak.config.scenario import Scenario

    bow = get_hull("polarstern", name="my bow", ice_thickness_m=0.5)
    assert bow.name == "my bow"
    assert bow.half_breadth_m == pytest.approx(25.0 / 2)  # still Polarstern's beam (physics-notes §6.1)
    scenario = Scenario.from_dict({"ship": {"hull": "agulhas_ii", "hull_parameters": {"name": "Ω bow"}}})
    assert build_bow(scenario.resolved()).name == "Ω bow"


@pytest.mark.parametrize(
    "kw",
    [
        {"waterline_entrance_half_angle_deg": 5e-324},  # ZeroDivisionError: tan(radians(5e-324)) = 0
        {"stem_angle_deg": 7.3e-245},  # lower stem tip 1e244 m aft: TypeError in the crossing check
        {"beam_m": 5e-324},
        {"thesis_stem_angle_deg": 89.9},  # a stem angle of 0.1° from the horizontal
    ],
)
def test_needle_and_flat_bows_are_refused_naming_the_parameter(kw):
    # fuzz campaign: angles and beams at the open edge of (0, …] crashed the hull's construction;
    # the ranges now start at a bow that exists (5°, 1 m; HULL_PARAMETER_BOUNDS)
    with pytest.raises(InputError) as info:
        agulhas_ii(**kw)
    assert info.value.field == next(iter(kw))


def test_a_vertical_stem_panel_is_a_vertical_stem():
    # ψ = 0 (the stem panel vertical) divided by tan ψ = 0 (fuzz campaign); tan ψ_v = sin α_0 / tan φ_s
    # (physics-notes §2.1) gives φ_s → 90° as ψ → 0
    assert stem_angle_from_thesis(0.0, 32.27, "panel_psi") == pytest.approx(90.0)
    assert stem_angle_from_thesis(1e-9, 32.27, "panel_psi") == pytest.approx(90.0)


def test_a_lower_waterline_collapsed_onto_its_tip_is_a_bow():
    # frame angles next to 90° move every lower node onto the lower stem tip (physics-notes §6.3): a line of
    # one point has no segment, and the self-intersection check raised TypeError on the empty list
    bow = polarstern(
        stem_angle_deg=5.0,
        shoulder_frame_angle_deg=89.99999999999999,
        midbody_frame_angle_deg=89.99999999999999,
    )
    tip = (-bow.dz_m / np.tan(np.radians(5.0)), 0.0)  # Δz / tan φ_s aft of the upper stem tip
    assert np.allclose(bow.lower_xy_m, tip)
    assert bow.hull_lower.area == 0.0
