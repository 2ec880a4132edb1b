"""Moving ice in the stepping loop (`simulation.ice_motion = "dynamic"`; docs/model.md,
"Ice motion", "Coupling with breaking")."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from floebreak.app.run import run
from floebreak.config.profiles import build_model
from floebreak.config.scenario import Scenario
from floebreak.dynamics import IceMotionSettings
from floebreak.engine.loop import SimulationParams, _Run, simulate
from floebreak.errors import InputError
from floebreak.ice.field import FloeField, circle_polygons
from floebreak.ship.hulls import agulhas_ii

SHORT = ["field.length_m=50"]  # the reference observation's floes, 50 m × 100 m


def _reference(*overrides: str):
    return run(Scenario.reference([*SHORT, *overrides])).simulation


def _same_pieces(a, b) -> bool:
    return len(a.fate) == len(b.fate) and all(
        shapely.equals_exact(p, q, 0.0) for p, q in zip(a.polygon, b.polygon, strict=True)
    )


def test_every_piece_pinned_gives_exactly_the_static_results():
    static = _reference()
    pinned = _reference("simulation.ice_motion=dynamic", "ice_motion.pin_all=true")
    assert pinned.params.ice_motion == "dynamic"
    assert static.n_breaks > 10  # the comparison has breaks to compare
    assert (pinned.n_contacts, pinned.n_breaks) == (static.n_contacts, static.n_breaks)
    assert np.array_equal(pinned.fate, static.fate)
    assert pinned.area_m2("cusp") == static.area_m2("cusp")
    assert _same_pieces(static, pinned)


def test_a_dynamic_run_is_deterministic_and_conserves_area_through_breaks():
    first = _reference("simulation.ice_motion=dynamic")
    again = _reference("simulation.ice_motion=dynamic")
    assert _same_pieces(first, again)
    assert np.array_equal(first.fate, again.fate)
    static = _reference()
    moved = [
        i
        for i in range(first.field.n_floes)
        if first.fate[i] == "remaining" and not shapely.equals_exact(first.polygon[i], static.polygon[i], 0.0)
    ]
    assert moved  # the ice did move
    assert first.n_breaks > 0
    # each broken piece's children hold its area (cut from its current outline, a rigid motion of it)
    area, parents = first.piece_area_m2, first.parent_piece_id
    children = np.bincount(parents[parents >= 0], weights=area[parents >= 0], minlength=len(area))
    for parent in np.flatnonzero(first.fate == "broken"):
        assert children[parent] == pytest.approx(area[parent], rel=1e-9)
    final = sum(first.area_m2(fate) for fate in ("cusp", "flipped", "remaining"))
    assert final == pytest.approx(first.field.ice_area_m2, rel=1e-9)


def _lone_floe(thickness_m=1.0, diameter_m=6.0, offset_m=8.0):
    """One floe ahead of the bow, its centre `offset_m` to port of the stem: the bow's flank meets it."""
    polygon = circle_polygons(np.array([[diameter_m / 2 + 2.0, offset_m]]), np.array([diameter_m / 2]), 64)
    field = FloeField(
        polygon, np.array([thickness_m]), np.array([diameter_m]), np.array([0]), tuple(polygon[0].bounds)
    )
    return field, agulhas_ii(ice_thickness_m=thickness_m)


LONE_OFFSETS_M = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0)  # the floe's centre to port of the stem
HALF_BEAM_M = 21.7 / 2  # S.A. Agulhas II, B = 21.7 m


def _regular_polygon_area_m2(diameter_m: float, n: int = 64) -> float:
    """Area of the n-gon inscribed in a circle of `diameter_m` (the floes of `_lone_floe`)."""
    return n / 2 * (diameter_m / 2) ** 2 * math.sin(2 * math.pi / n)


def _lone_run(diameter_m: float, offset_m: float, step_m: float = 0.25):
    field, bow = _lone_floe(diameter_m=diameter_m, offset_m=offset_m)
    params = SimulationParams(x_end_m=60.0, ice_motion="dynamic", step_m=step_m)
    return field, simulate(field, bow, build_model("default"), params)


def _lone_fate(diameter_m: float, offset_m: float, step_m: float) -> str:
    """ "broken", "aside" (left whole, its nearest point at least the half-beam from the centreline once the
    bow is past), "in the lane" (left whole, not aside) or "cusp"."""
    _, result = _lone_run(diameter_m, offset_m, step_m)
    if result.fate[0] != "remaining":
        return str(result.fate[0])
    beside = np.abs(shapely.get_coordinates(result.polygon[0])[:, 1]).min() >= HALF_BEAM_M
    return "aside" if beside else "in the lane"


@pytest.mark.parametrize("offset_m", LONE_OFFSETS_M)
@pytest.mark.parametrize("diameter_m", [2.0, 4.0])
def test_a_lone_floe_below_the_unbreakable_area_never_breaks(diameter_m, offset_m):
    """Thesis Eq. 5: a floe of area ≤ A_rotate = 1 m · 13.5 h^¾ (13.5 m² at h = 1 m) is unbreakable, so it
    cannot break at any offset. Nor is it pushed aside (as one might expect): its failure mode
    is rotation, which takes it under the hull whole, as one cusp, at its first contact (§4.4; the default
    dispatch, docs/model.md §10), before the engine moves it (docs/model.md, "A lone floe off the stem")."""
    area = _regular_polygon_area_m2(diameter_m)
    assert area < 13.5 * 1.0**0.75
    _, result = _lone_run(diameter_m, offset_m)
    assert result.n_breaks == 0
    assert list(result.fate) == ["cusp"] and result.n_contacts == 1
    assert result.piece_area_m2[0] == pytest.approx(area, rel=1e-12)


@pytest.mark.parametrize("offset_m", LONE_OFFSETS_M)
@pytest.mark.parametrize("diameter_m", [5.0, 6.0])
def test_a_breakable_lone_floe_breaks_or_ends_beside_the_lane(diameter_m, offset_m):
    """Above A_rotate, at the default search step, whether the floe breaks or is pushed aside depends on
    the step near the border (docs/model.md, "A lone floe off the stem"; the two tests below assert the
    fates where they are converged). Either way the ice is kept, and a floe left whole was pushed aside,
    not carried in the lane: once the bow is past, its nearest point is at least the half-beam from the
    centreline."""
    field, result = _lone_run(diameter_m, offset_m)
    assert result.n_contacts > 0
    final = sum(result.area_m2(fate) for fate in ("cusp", "flipped", "remaining"))
    assert final == pytest.approx(field.ice_area_m2, rel=1e-9)
    if result.fate[0] == "remaining":
        assert result.n_breaks == 0
        assert np.abs(shapely.get_coordinates(result.polygon[0])[:, 1]).min() >= HALF_BEAM_M
    else:
        assert result.fate[0] == "broken" and result.n_breaks > 0


@pytest.mark.parametrize("step_m", [0.25, 0.0625])
def test_the_smallest_breakable_lone_floe_off_the_stem_is_pushed_aside_not_broken(step_m):
    """The check of the matrix, for the smallest floe of the matrix that can break at all (5 m, 19.6 m² >
    A_rotate = 13.5 m²; smaller ones go under whole, above): off the stem (centre 2–10 m to port) it is
    pushed aside whole, at the default search step and at a quarter of it, where the fates of the matrix no
    longer change with the step (next test). On the centreline (offset 0) it is not asserted: the hull
    meets it head on and carries it ahead (docs/model.md, "A lone floe off the stem")."""
    assert _regular_polygon_area_m2(5.0) > 13.5 * 1.0**0.75
    assert [_lone_fate(5.0, offset_m, step_m) for offset_m in LONE_OFFSETS_M[1:]] == ["aside"] * 5


def test_the_lone_floes_fates_are_converged_in_the_search_step():
    """Whether a breakable lone floe breaks or is pushed aside depends on the force the overlap builds over
    one contact search, so it moves with `ship.step_m` at 0.25 m; from 0.0625 m on it no longer does
    (docs/model.md, "A lone floe off the stem": the same fates for 5, 6 and 8 m floes down to 0.015625 m).
    The 6 m floe has its border inside the offsets (broken near the stem, aside near the shoulder): halving
    the step once more must not move it."""
    fates = {
        step_m: [_lone_fate(6.0, offset_m, step_m) for offset_m in LONE_OFFSETS_M]
        for step_m in (0.0625, 0.03125)
    }
    assert fates[0.0625] == fates[0.03125]
    assert {"broken", "aside"} <= set(fates[0.0625])


def test_a_floe_split_on_the_centreline_keeps_finite_valid_pieces():
    """A crash: a 6 m floe centred on the stem is cut along the centreline within 1e-15 m of two
    of its vertices; in a child's body frame such a vertex and the crack's end are one point. The run
    completes, the children hold their parents' area, and every piece is a valid polygon."""
    field, bow = _lone_floe(offset_m=0.0)
    params = SimulationParams(x_end_m=60.0, ice_motion="dynamic")
    result = simulate(field, bow, build_model("default"), params)
    assert result.n_breaks > 0
    assert all(p.is_valid and np.isfinite(shapely.get_coordinates(p)).all() for p in result.polygon)
    area, parents = result.piece_area_m2, result.parent_piece_id
    children = np.bincount(parents[parents >= 0], weights=area[parents >= 0], minlength=len(area))
    for parent in np.flatnonzero(result.fate == "broken"):
        assert children[parent] == pytest.approx(area[parent], rel=1e-9)
    final = sum(result.area_m2(fate) for fate in ("cusp", "flipped", "remaining"))
    assert final == pytest.approx(field.ice_area_m2, rel=1e-9)


def test_children_inherit_the_parents_rigid_body_velocity_at_their_centroids():
    field, bow = _lone_floe()  # the engine is not stepped: only the velocities set here act
    params = SimulationParams(x_end_m=60.0, ice_motion="dynamic")
    run_ = _Run(field, bow, build_model("default"), params, ())
    motion = run_.motion
    motion.advance_to(0.0)
    parent_polygon = field.polygons[0]
    v, omega = (1.5, -0.5), 0.2
    motion.leave(0)
    motion._add(0, v, omega)  # the parent moving at a known rigid-body velocity
    left = shapely.clip_by_rect(parent_polygon, -1e3, -1e3, 4.0, 1e3)
    right = shapely.clip_by_rect(parent_polygon, 4.0, -1e3, 1e3, 1e3)
    ids = [run_.pieces.add(part, 1.0, 0, 0, 0, 0.0) for part in (left, right)]
    motion.broken(0, ids)
    c = shapely.centroid(parent_polygon)
    for pid, part in zip(ids, (left, right), strict=True):
        p = shapely.centroid(part)
        expected = (v[0] - omega * (p.y - c.y), v[1] + omega * (p.x - c.x))  # v + ω ẑ × (p − c)
        state = motion.engine.state(pid)
        assert (state.vx_m_s, state.vy_m_s) == pytest.approx(expected, abs=1e-9)
        assert state.angular_velocity_rad_s == omega
    assert 0 not in motion.engine.piece_ids()


def test_dynamic_with_located_events_is_refused_naming_both_keys():
    with pytest.raises(InputError, match=r"simulation\.event_location") as error:
        SimulationParams(ice_motion="dynamic", event_location="root")
    assert error.value.field == "simulation.ice_motion"
    with pytest.raises(InputError, match=r"simulation\.ice_motion"):
        SimulationParams(ice_motion="moving")


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("ice_motion.form_drag_coefficient=0.0", "ice_motion.form_drag_coefficient"),
        ("ice_motion.window_ahead_m=-1.0", "ice_motion.window_ahead_m"),
        ("ice_motion.ice_hull_restitution=1.5", "ice_motion.ice_hull_restitution"),
        ("ice_motion.hull_contact='both'", "ice_motion.hull_contact"),
        ("ice_motion.wind_m_s=1.0", "ice_motion.wind_m_s"),
        ("simulation.ice_motion='moving'", "simulation.ice_motion"),
    ],
)
def test_bad_ice_motion_keys_name_the_key(override, key):
    with pytest.raises(InputError) as error:
        Scenario.reference([override])
    assert error.value.field == key


def test_the_ice_motion_table_reaches_the_settings():
    scenario = Scenario.reference(["simulation.ice_motion=dynamic", "ice_motion.time_step_s=0.01"])
    assert scenario.ice_motion_settings() == IceMotionSettings(time_step_s=0.01)


@pytest.mark.parametrize(("force_n", "lever_m"), [(1e9, 0.0), (1e9, 2.0), (1e3, 0.0)])
def test_the_crushing_impulse_stops_at_the_hulls_speed_at_its_point(force_n, lever_m):
    """Plastic contact: over a step the crushing force's impulse is |F|Δt, but at most the one that brings
    the piece's point under the force to the hull's speed along F̂, (v + ω ẑ × r)·F̂ = V: a piece is never
    driven faster than the hull pushes it, whatever the step."""
    field, bow = _lone_floe()
    params = SimulationParams(x_end_m=60.0, ice_motion="dynamic")
    motion = _Run(field, bow, build_model("default"), params, ()).motion
    motion.advance_to(0.0)
    motion.engine.water = False  # the check is of the contact impulse alone
    c = shapely.centroid(field.polygons[0])
    dt, speed = 0.02, params.speed_m_s
    motion.forces = {0: [(force_n, 0.0, c.x, c.y + lever_m)]}
    motion._push()
    motion.engine.step(dt)
    state = motion.engine.state(0)
    point_vx = state.vx_m_s - state.angular_velocity_rad_s * lever_m  # x of v + ω ẑ × (0, lever)
    if force_n > 1e6:  # |F|Δt far above what the hull's speed allows
        assert point_vx == pytest.approx(speed, rel=1e-9)
        assert (abs(state.angular_velocity_rad_s) > 1e-9) == (lever_m != 0.0)  # the lever turns it
    else:  # a small force acts whole: Δv = FΔt/m, m = (1 + C_a)·ρ_i·A·h
        s = IceMotionSettings()
        mass = (1 + s.added_mass_coefficient) * s.ice_density_kg_m3 * field.polygons[0].area * 1.0
        assert state.vx_m_s == pytest.approx(force_n * dt / mass, rel=1e-9)


def _mirrored(polygon):
    return shapely.transform(polygon, lambda xy: xy * np.array([1.0, -1.0]))  # y → −y: exact in floats


def _field_of(polygons) -> FloeField:
    polygons = np.array(polygons, dtype=object)
    diameters = 2.0 * np.sqrt(shapely.area(polygons) / np.pi)
    n = len(polygons)
    return FloeField(polygons, np.ones(n), diameters, np.arange(n), tuple(shapely.total_bounds(polygons)))


def _final_pieces(result) -> list[tuple[str, shapely.Polygon]]:
    pieces = [shapely.from_wkb(p) if isinstance(p, bytes) else p for p in result.polygon]
    return [(str(f), p) for f, p in zip(result.fate, pieces, strict=True) if f != "broken"]


def _mirror_gap(polygons, bow) -> tuple[float, list[str], list[str]]:
    """Run the floes and their mirror image (the bow is symmetric: checked); the largest distance from a
    final piece of the mirrored run to the mirror of its nearest counterpart, and both runs' fates."""
    assert shapely.equals(_mirrored(bow.hull_upper), bow.hull_upper)
    model, params = build_model("default"), SimulationParams(x_end_m=60.0, ice_motion="dynamic")
    run_a = _final_pieces(simulate(_field_of(polygons), bow, model, params))
    run_b = _final_pieces(simulate(_field_of([_mirrored(p) for p in polygons]), bow, model, params))
    gap = 0.0
    for _, piece in run_b:
        gap = max(gap, min(shapely.hausdorff_distance(piece, _mirrored(q)) for _, q in run_a))
    return gap, sorted(f for f, _ in run_a), sorted(f for f, _ in run_b)


def test_a_mirrored_push_is_the_mirror_of_the_push():
    """One floe pushed aside, no ice–ice contact: the only asymmetry is round-off (floebreak's contact
    force on the mirrored ring, whose vertices run the other way, differs by ≈ 1e-14 of itself; the body
    geometry is summed exactly). Over the ≈ 40 contacts and 10 m of travel that is ≈ 1e-12 m; 1e-9 m
    leaves a wide margin and still fails for any real asymmetry (a contact-order or sign error)."""
    field, bow = _lone_floe(offset_m=10.0)
    gap, fates_a, fates_b = _mirror_gap(list(field.polygons), bow)
    assert fates_a == fates_b == ["remaining"]
    assert gap < 1e-9


def test_a_mirrored_field_breaks_as_the_mirror_of_the_field_within_the_engines_slop():
    """Two floes, one broken into touching children: Chipmunk resolves their contacts by sequential
    impulses in the order it found the pairs, which the mirror changes, so the runs differ by the solver's
    residual, not by round-off. The engine resolves contact positions only to its collision slop (pymunk's
    default 0.1 m of overlap is let stand): every piece of the mirrored run must lie within it of the
    mirror of a piece of the run, with the same fates."""
    ring = 2 * np.pi * np.arange(40) / 40
    floes = [
        shapely.Polygon(np.c_[12.0 + 6 * np.cos(ring), 7.0 + 6 * np.sin(ring)]),
        shapely.Polygon(np.c_[30.0 + 5 * np.cos(ring), -9.0 + 4 * np.sin(ring)]),
    ]
    gap, fates_a, fates_b = _mirror_gap(floes, agulhas_ii(ice_thickness_m=1.0))
    assert fates_a == fates_b and len(fates_a) > 2  # it broke
    assert gap < 0.1
