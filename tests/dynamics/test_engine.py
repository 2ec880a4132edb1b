"""Checks a dynamics engineer would run, expectations computed here, independently."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely import affinity

from floebreak.dynamics import IceMotionEngine, IceMotionSettings

FAR_HULL = shapely.box(-500.0, -1.0, -499.0, 1.0)  # a hull out of the way, at rest


def _momenta(engine: IceMotionEngine, ids) -> tuple[np.ndarray, float]:
    """Total linear momentum and angular momentum about the origin, from masses recomputed here."""
    s = engine.settings
    linear, angular = np.zeros(2), 0.0
    for pid in ids:
        st = engine.state(pid)
        poly = engine.polygon(pid)
        m = (1 + s.added_mass_coefficient) * s.ice_density_kg_m3 * 1.0 * poly.area
        inertia = (1 + s.added_inertia_coefficient) * s.ice_density_kg_m3 * 1.0 * 8.0 * (16 + 4) / 12
        linear += m * np.array([st.vx_m_s, st.vy_m_s])
        angular += inertia * st.angular_velocity_rad_s + m * (st.x_m * st.vy_m_s - st.y_m * st.vx_m_s)
    return linear, angular


@pytest.mark.parametrize(("friction", "angular_rel"), [(0.0, 1e-12), (0.35, 1e-3)])
def test_collision_conserves_linear_and_angular_momentum(friction, angular_rel):
    """Linear momentum exactly. Angular momentum exactly without friction; with friction, to the lever of
    the friction impulse across the overlap depth (Chipmunk applies it at the two bodies' own contact
    points, which lie the overlap apart along the normal): 3e-4 of L here."""
    settings = IceMotionSettings(window_side_m=1e3, window_ahead_m=1e3, ice_ice_friction=friction)
    engine = IceMotionEngine(FAR_HULL, (0.0, 0.0), settings, water=False)
    engine.add_piece(1, shapely.box(0, 0, 4, 2), 1.0, velocity_m_s=(2.0, 0.3), angular_velocity_rad_s=0.2)
    engine.add_piece(2, affinity.rotate(shapely.box(7, 0.8, 11, 2.8), 20.0), 1.0)
    p0, l0 = _momenta(engine, [1, 2])
    for _ in range(300):
        engine.step(0.01)
    assert engine.state(2).vx_m_s > 0.5  # they did collide
    p1, l1 = _momenta(engine, [1, 2])
    assert np.allclose(p1, p0, rtol=1e-12, atol=1e-12 * np.abs(p0).max())
    assert l1 == pytest.approx(l0, rel=angular_rel)


def test_drag_decay_matches_analytic_solution():
    s = IceMotionSettings(window_ahead_m=1e3)
    h, side, u0 = 0.5, 6.0, 2.0
    engine = IceMotionEngine(FAR_HULL, (0.0, 0.0), s)
    engine.add_piece(1, shapely.box(0, 0, side, side), h, velocity_m_s=(u0, 0.0))
    m_eff = (1 + s.added_mass_coefficient) * s.ice_density_kg_m3 * side * side * h
    draft = h * s.ice_density_kg_m3 / s.water_density_kg_m3
    k = (
        0.5
        * s.water_density_kg_m3
        * (s.form_drag_coefficient * draft * side + s.skin_drag_coefficient * side**2)
    )
    dt, n = 0.01, 3000
    for _ in range(n):
        engine.step(dt)
    t = dt * n
    u_exact = u0 / (1 + k * u0 * t / m_eff)
    x_exact = side / 2 + m_eff / k * math.log(1 + k * u0 * t / m_eff)
    st = engine.state(1)
    assert u_exact < 0.5 * u0  # the test spans a real decay
    assert st.vx_m_s == pytest.approx(u_exact, rel=0.01)
    assert st.x_m == pytest.approx(x_exact, rel=0.01)


def _panel_push(alpha_deg: float, mu: float) -> tuple[float, float]:
    """A wide panel whose face normal is at α from +x, moving at 3 m/s in +x, pushing a square floe whose
    face lies flush with it; returns the floe's direction of motion [deg] and speed after 10 s."""
    s = IceMotionSettings(ice_hull_friction=mu, window_ahead_m=1e3, window_side_m=1e3, hull_contact="engine")
    panel = affinity.rotate(shapely.box(-1.0, -40.0, 0.0, 40.0), alpha_deg, origin=(0, 0))
    floe = affinity.rotate(shapely.box(0.05, -1.0, 2.05, 1.0), alpha_deg, origin=(0, 0))
    engine = IceMotionEngine(panel, (3.0, 0.0), s)
    engine.add_piece(1, floe, 1.0)
    for _ in range(500):
        engine.step()
    st = engine.state(1)
    return math.degrees(math.atan2(st.vy_m_s, st.vx_m_s)), math.hypot(st.vx_m_s, st.vy_m_s)


def test_floe_pushed_by_inclined_panel_slides_on_the_friction_cone():
    # sliding (tan α > μ): the contact force lies on the cone's edge, at atan μ from the normal towards the
    # panel's tangential motion; with drag opposite the velocity, the velocity has that direction, and its
    # normal part equals the panel's, V cos α
    alpha, mu, speed = 60.0, 0.3, 3.0
    direction, magnitude = _panel_push(alpha, mu)
    assert direction == pytest.approx(alpha - math.degrees(math.atan(mu)), abs=0.5)
    assert magnitude == pytest.approx(speed * math.cos(math.radians(alpha)) * math.hypot(1.0, mu), rel=0.01)


def test_floe_pushed_by_inclined_panel_sticks_inside_the_friction_cone():
    direction, magnitude = _panel_push(10.0, 0.3)  # tan 10° = 0.18 < μ: carried along with the panel
    assert direction == pytest.approx(0.0, abs=0.5)
    assert magnitude == pytest.approx(3.0, rel=0.01)


def _floe_after_a_panel_push(hull_contact: str, **changed: float):
    """The square floe of `_panel_push` (panel at 60°, 3 m/s in +x) after 2 s, held against the panel as
    the stepping loop holds a piece in contact (`hold_against_hull`: 200 kN along the panel's normal at the
    floe's face, renewed every 5 steps), with the given ice–hull settings changed."""
    alpha = math.radians(60.0)
    normal = (math.cos(alpha), math.sin(alpha))
    face = (0.05 * normal[0], 0.05 * normal[1])
    s = IceMotionSettings(window_ahead_m=1e3, window_side_m=1e3, hull_contact=hull_contact, **changed)
    panel = affinity.rotate(shapely.box(-1.0, -40.0, 0.0, 40.0), alpha, origin=(0, 0), use_radians=True)
    floe = affinity.rotate(shapely.box(0.05, -1.0, 2.05, 1.0), alpha, origin=(0, 0), use_radians=True)
    engine = IceMotionEngine(panel, (3.0, 0.0), s)
    engine.add_piece(1, floe, 1.0)
    for _ in range(20):
        hull_x = engine.time_s * 3.0
        engine.hold_against_hull(1, (2e5 * normal[0], 2e5 * normal[1]), (face[0] + hull_x, face[1]))
        for _ in range(5):
            engine.step()
        engine.release_holds()
    return engine.state(1)


@pytest.mark.parametrize("changed", [{"ice_hull_friction": 1.5}, {"ice_hull_restitution": 0.9}])
def test_ice_hull_friction_and_restitution_act_only_through_the_engines_own_hull_contact(changed):
    """Under `hull_contact = "crushing"` the hull does not collide with the ice in the engine: the push is
    the hold along the normal, which takes neither μ_ih nor e_ih, so changing them changes nothing. Under
    "engine" Chipmunk's hull contact uses both."""
    crushing = _floe_after_a_panel_push("crushing")
    assert math.hypot(crushing.vx_m_s, crushing.vy_m_s) > 0.5  # the hold did push it
    # along the normal: no tangential force, so none of the friction cone's tilt (the test above)
    assert math.degrees(math.atan2(crushing.vy_m_s, crushing.vx_m_s)) == pytest.approx(60.0, abs=0.5)
    assert _floe_after_a_panel_push("crushing", **changed) == crushing
    assert _floe_after_a_panel_push("engine", **changed) != _floe_after_a_panel_push("engine")


def test_pinned_floe_does_not_move():
    engine = IceMotionEngine(FAR_HULL, (0.0, 0.0), IceMotionSettings(window_ahead_m=1e3), water=False)
    engine.add_piece(1, shapely.box(0, 0, 4, 2), 1.0, velocity_m_s=(2.0, 0.0))
    engine.add_piece(2, shapely.box(6, -1, 10, 3), 1.0, pinned=True)
    before = engine.polygon(2)
    for _ in range(300):
        engine.step(0.01)
    assert engine.state(1).vx_m_s < 0.0  # floe 1 bounced off the pinned one
    assert shapely.equals_exact(engine.polygon(2), before, tolerance=0.0)
    st = engine.state(2)
    assert (st.vx_m_s, st.vy_m_s, st.angular_velocity_rad_s) == (0.0, 0.0, 0.0)


def _hull_polygon() -> shapely.Polygon:
    return shapely.Polygon([(0, 0), (-8, 6), (-60, 6), (-60, -6), (-8, -6)])  # symmetric about y = 0


def _transit(floes: list[shapely.Polygon], seconds: float = 6.0) -> dict:
    engine = IceMotionEngine(_hull_polygon(), (3.0, 0.0), IceMotionSettings(hull_contact="engine"))
    for pid, floe in enumerate(floes):
        engine.add_piece(pid, floe, 0.8)
    for _ in range(round(seconds / engine.settings.time_step_s)):
        engine.step()
    return {pid: engine.state(pid) for pid in engine.piece_ids()}


def _field() -> list[shapely.Polygon]:
    floes = []
    for i in range(4):
        for j in range(5):
            x, y = 2.0 + 5.0 * i, -11.0 + 4.5 * j + 0.3 * i
            floes.append(affinity.rotate(shapely.box(x, y, x + 3.2, y + 2.6), 7.0 * (i + j)))
    return floes


def test_same_input_same_states():
    first, second = _transit(_field()), _transit(_field())
    assert first == second
    assert any(st.vx_m_s != 0.0 for st in first.values())


def test_mirror_symmetric_set_up_gives_mirrored_motion():
    upper = [affinity.rotate(shapely.box(2.0, 1.0, 5.0, 3.5), 15.0), shapely.box(9.0, 3.0, 12.0, 5.0)]
    lower = [affinity.scale(p, 1.0, -1.0, origin=(0, 0)) for p in upper]
    states = _transit(upper + lower)
    moved = 0
    for k in range(len(upper)):
        a, b = states[k], states[k + len(upper)]
        moved += a.vx_m_s != 0.0
        assert b.x_m == pytest.approx(a.x_m, abs=1e-6)
        assert b.y_m == pytest.approx(-a.y_m, abs=1e-6)
        assert b.angle_rad == pytest.approx(-a.angle_rad, abs=1e-6)
    assert moved


def test_pieces_outside_the_window_sleep_and_behind_it_retire():
    s = IceMotionSettings(window_ahead_m=10.0, window_behind_m=5.0, window_side_m=5.0, hull_contact="engine")
    engine = IceMotionEngine(_hull_polygon(), (3.0, 0.0), s)
    engine.add_piece(1, shapely.box(30, 8, 32, 10), 0.8)  # ahead of the window, off the hull's path
    engine.add_piece(2, shapely.box(0, 30, 2, 32), 0.8, velocity_m_s=(0.0, 1.0))  # beside it
    assert engine.awake_ids() == []
    assert engine.state(2).vy_m_s == 0.0  # frozen where it is
    for _ in range(round(8.0 / s.time_step_s)):  # the bow reaches x = 24: piece 1 is in the window
        engine.step()
    assert 1 in engine.awake_ids()
    assert engine.state(2).x_m == 1.0 and not engine.state(2).awake
    for _ in range(round(40.0 / s.time_step_s)):  # the stern (x = −60 + 144) has passed both by 5 m
        engine.step()
    retired = {st.piece_id for st in engine.drain_retired()}
    assert {1, 2} <= retired and engine.piece_ids() == []


def test_held_pieces_do_not_grow_with_the_transit():
    """Pieces added as the window reaches them and retired behind it: the count held stays bounded."""
    s = IceMotionSettings(
        window_ahead_m=10.0, window_behind_m=5.0, window_side_m=5.0, time_step_s=0.05, hull_contact="engine"
    )
    engine = IceMotionEngine(_hull_polygon(), (3.0, 0.0), s)
    held, next_x = [], 5.0
    for _ in range(round(150.0 / s.time_step_s)):  # 450 m
        while next_x < engine.window()[2] + 5.0:
            engine.add_piece(int(next_x), shapely.box(next_x, 8.0, next_x + 2.0, 10.0), 0.5)
            next_x += 5.0
        engine.step()
        engine.drain_retired()
        held.append(len(engine.piece_ids()))
    assert next_x > 400.0
    assert max(held[len(held) // 2 :]) <= max(held[: len(held) // 2])


def test_hull_impulse_is_the_momentum_given_to_the_floe():
    engine = IceMotionEngine(
        shapely.box(-10, -2, 0, 2), (3.0, 0.0), IceMotionSettings(hull_contact="engine"), water=False
    )
    engine.add_piece(1, shapely.box(1, -1, 3, 1), 1.0)
    total = np.zeros(2)
    for _ in range(40):
        engine.step()
        total += engine.hull_impulses().get(1, (0.0, 0.0))
    st = engine.state(1)
    m = (1 + engine.settings.added_mass_coefficient) * engine.settings.ice_density_kg_m3 * 4.0
    assert total[0] == pytest.approx(m * st.vx_m_s, rel=1e-9)
    assert st.vx_m_s == pytest.approx(3.0 * (1 + engine.settings.ice_hull_restitution), rel=1e-3)  # e = 0.1


def test_children_take_the_rigid_body_velocity_at_their_centroid():
    engine = IceMotionEngine(FAR_HULL, (0.0, 0.0), IceMotionSettings(window_ahead_m=1e3))
    engine.add_piece(1, shapely.box(0, 0, 4, 2), 1.0, velocity_m_s=(1.0, 0.5), angular_velocity_rad_s=0.25)
    assert engine.velocity_at(1, (3.0, 1.0)) == pytest.approx((1.0 - 0.25 * 0.0, 0.5 + 0.25 * 1.0))
    assert engine.velocity_at(1, (2.0, 2.0)) == pytest.approx((1.0 - 0.25 * 1.0, 0.5))


def test_a_retired_piece_leaves_its_last_outline():
    s = IceMotionSettings(window_ahead_m=10.0, window_behind_m=5.0, window_side_m=5.0)
    engine = IceMotionEngine(shapely.box(-10, -2, 0, 2), (3.0, 0.0), s)
    floe = shapely.box(-30.0, 20.0, -27.0, 22.0)  # behind the window from the start
    engine.add_piece(1, floe, 0.5)
    engine.step()
    [state] = engine.drain_retired()
    outline = engine.drain_retired_outlines()[1]
    assert state.piece_id == 1 and engine.piece_ids() == []
    assert shapely.hausdorff_distance(outline, floe) < 1e-12  # at rest: where it was added
    assert engine.drain_retired_outlines() == {}


@pytest.mark.parametrize(("speed_m_s", "stops"), [(5e-4, True), (2e-3, False)])
def test_a_creeping_piece_comes_to_rest_below_the_rest_speed(speed_m_s, stops):
    engine = IceMotionEngine(FAR_HULL, (0.0, 0.0), IceMotionSettings(window_ahead_m=1e3))
    engine.add_piece(1, shapely.box(0, 0, 2, 2), 0.5, velocity_m_s=(speed_m_s, 0.0))
    engine.step()
    assert (engine.state(1).vx_m_s == 0.0) == stops


def test_a_hull_hold_passes_its_whole_force_through_a_jammed_piece():
    """A small piece held by the hull with |F| pushes a large one in front of it: below the hull's speed
    the hold is a plain force, so the pair's momentum grows by exactly F·t (Newton's second law on the
    pair, no water), whatever the step; the small piece alone could take only m·V from a per-step cap."""
    s = IceMotionSettings(window_ahead_m=1e3, window_side_m=1e3, ice_ice_friction=0.0)
    for dt in (0.02, 0.005):
        engine = IceMotionEngine(FAR_HULL, (3.0, 0.0), s, water=False)
        engine.add_piece(1, shapely.box(0.0, 4.0, 2.0, 6.0), 1.0)  # 4 m², ≈ 4.0 t
        engine.add_piece(2, shapely.box(2.0, 0.0, 12.0, 10.0), 1.0)  # 100 m², ≈ 101 t, touching piece 1
        force_n, seconds = 2.0e4, 1.0
        engine.hold_against_hull(1, (force_n, 0.0), (1.0, 5.0))
        for _ in range(round(seconds / dt)):
            engine.step(dt)
        momentum = sum(engine.mass_kg(i) * engine.state(i).vx_m_s for i in (1, 2))
        assert momentum == pytest.approx(force_n * seconds, rel=1e-6)
        assert engine.state(2).vx_m_s > 0.9 * engine.state(1).vx_m_s  # pushed through the contact
        assert engine.state(1).vx_m_s < 3.0
        engine.release_holds()
        engine.step(dt)
        assert sum(engine.mass_kg(i) * engine.state(i).vx_m_s for i in (1, 2)) == pytest.approx(momentum)


def test_hold_impulses_report_what_the_hold_passed_on():
    """The impulse a hold reports is the momentum it gave (no water, one piece alone: Newton's second law):
    F·t while the piece is slower than the hull (|F| too small to bring it to V), only m·V once it moves at
    the hull's speed, however large |F|."""
    s = IceMotionSettings(window_ahead_m=1e3, window_side_m=1e3)
    for force_n, dt in ((2.0e3, 0.02), (1.0e7, 0.02), (1.0e7, 0.005)):
        engine = IceMotionEngine(FAR_HULL, (3.0, 0.0), s, water=False)
        engine.add_piece(1, shapely.box(0.0, 0.0, 2.0, 2.0), 1.0)
        engine.hold_against_hull(1, (force_n, 0.0), (1.0, 1.0))  # at the centroid: no turning
        seconds = 0.5
        for _ in range(round(seconds / dt)):
            engine.step(dt)
        [(given_n, impulse_n_s)] = engine.hold_impulses()[1]
        momentum = engine.mass_kg(1) * engine.state(1).vx_m_s
        assert given_n == force_n
        assert impulse_n_s == pytest.approx(momentum, rel=1e-9)
        if force_n * seconds < engine.mass_kg(1) * 3.0:
            assert impulse_n_s == pytest.approx(force_n * seconds, rel=1e-9)  # at its limit throughout
        else:
            assert engine.state(1).vx_m_s == pytest.approx(3.0, rel=1e-9)
            assert impulse_n_s == pytest.approx(engine.mass_kg(1) * 3.0, rel=1e-9)  # m·V ≪ F·t
        engine.release_holds()
        assert engine.hold_impulses() == {}
