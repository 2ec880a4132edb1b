"""The flow transport: cusps followed as rigid bodies under the hull (floebreak.propeller.cusp_flow)."""

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller import cusp_flow as cf
from floebreak.propeller.flow_transport import FlowParameters, flow_transport_cusps, hull_surface
from floebreak.propeller.hull_surface import HullSurface
from floebreak.propeller.transport import PATHS, TransportSettings

RHO_W, RHO_I, G = 1025.0, 917.0, 9.81
HULL = HullSurface(21.7, 7.65, 2.5, 27.0, 115.0, 15.0, 2.24)


def _plate(area=4.0, thickness=0.5, drag=0.0, friction=0.0):
    one = np.ones(1)
    return cf.CuspBodies(area * one, thickness * one, 0.0 * one, drag * one, friction * one)


def _run(bodies, field, pos, vel, dt, n):
    for _ in range(n):
        pos, vel, _ = cf.step(bodies, HULL, field, pos, vel, dt)
    return pos, vel


def test_free_plate_without_drag_rises_with_the_analytic_acceleration():
    """Beside the hull (no hull above), no drag, no friction: z(t) = z0 − ½ a t² with
    a = (ρ_w − ρ_i) g A h / (ρ_i A h + (8/3) ρ_w r³), r = √(A/π) (broadside disc added mass)."""
    area, h = 4.0, 0.5
    r = math.sqrt(area / math.pi)
    a = (RHO_W - RHO_I) * G * area * h / (RHO_I * area * h + 8.0 / 3.0 * RHO_W * r**3)
    pos, vel = np.array([[50.0, 15.0, 40.0]]), np.zeros((1, 3))
    t, dt = 3.0, 1e-3
    pos, vel = _run(_plate(area, h), cf.FlowField(0.0), pos, vel, dt, round(t / dt))
    assert pos[0, 2] == pytest.approx(40.0 - 0.5 * a * t * t, rel=1e-4)
    assert vel[0, 2] == pytest.approx(-a * t, rel=1e-4)
    assert pos[0, :2].tolist() == [50.0, 15.0]


def test_plate_reaches_the_terminal_velocities():
    """With drag: the rise tends to w = √(2 (ρ_w − ρ_i) g h / (ρ_w C_D)) (buoyancy = ½ ρ_w C_D A w²), and the
    plate drifts at the flow's speed along x."""
    h, c_d = 0.8, 1.2
    w = math.sqrt(2.0 * (RHO_W - RHO_I) * G * h / (RHO_W * c_d))
    pos, vel = np.array([[0.0, 20.0, 1000.0]]), np.zeros((1, 3))
    pos, vel = _run(_plate(3.0, h, drag=c_d), cf.FlowField(2.0), pos, vel, 0.05, 2000)
    assert -vel[0, 2] == pytest.approx(w, rel=1e-6)
    assert vel[0, 0] == pytest.approx(2.0, rel=1e-6)


def test_plate_on_the_flat_bottom_slides_at_the_drag_friction_balance():
    """Pressed against the flat bottom: friction μ (ρ_w − ρ_i) g A h balances the drag ½ ρ_w C_D (l h) u_rel²
    on its front face, so it slides at U − u_rel with u_rel = √(2 μ (ρ_w − ρ_i) g A / (ρ_w C_D l))."""
    area, h, c_d, mu, flow = 4.0, 0.5, 1.0, 0.1, 3.0
    u_rel = math.sqrt(2 * mu * (RHO_W - RHO_I) * G * area / (RHO_W * c_d * math.sqrt(area)))
    pos, vel = np.array([[20.0, 0.0, 7.65]]), np.array([[0.0, 0.0, 0.0]])
    pos, vel = _run(_plate(area, h, c_d, mu), cf.FlowField(flow), pos, vel, 0.05, 400)
    assert pos[0, 2] == 7.65 and vel[0, 2] == 0.0
    assert vel[0, 0] == pytest.approx(flow - u_rel, rel=1e-3)


def test_actuator_disc_inflow_conserves_mass():
    """div u = 0 of the disc's induced field inside and outside its cylinder (finite differences)."""
    discs = cf.Discs(100.0, np.array([5.5]), np.array([5.25]), np.array([2.15]), np.array([3.0]))
    field = cf.FlowField(2.5, discs)
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(90, 99.5, 200), rng.uniform(0, 11, 200), rng.uniform(1, 9.5, 200)])
    r = np.hypot(points[:, 1] - 5.5, points[:, 2] - 5.25)
    points = points[np.abs(r - 2.15) > 0.05]
    eps = 1e-5
    div = np.zeros(len(points))
    for axis in range(3):
        step = np.zeros(3)
        step[axis] = eps
        div += (field.velocity(points + step)[:, axis] - field.velocity(points - step)[:, axis]) / (2 * eps)
    assert np.abs(div).max() < 1e-5
    # on the axis at the disc: the wake plus u_a; far upstream: the wake alone
    on_axis = field.velocity(np.array([[100.0, 5.5, 5.25], [0.0, 5.5, 5.25]]))
    assert on_axis[:, 0] == pytest.approx([5.5, 2.5], abs=1e-3)


def _cusps(n, thickness, seed=0):
    rng = np.random.default_rng(seed)
    bow = rng.uniform(0.0, 300.0, n)
    side = rng.uniform(0.5, 3.5, n) * thickness**0.5 * 2.0
    return dict(
        bow_x_m=bow,
        centroid_x_m=bow - rng.uniform(0.0, 10.0, n),
        centroid_y_m=rng.uniform(-9.0, 9.0, n),
        area_m2=side**2,
        thickness_m=np.full(n, thickness),
    )


def _flow(cols, seed=1, **kw):
    settings = TransportSettings()
    return flow_transport_cusps(
        **cols,
        speed_m_s=3.0,
        induced_velocity_m_s=3.19,
        wake_fraction=0.14,
        rng=np.random.default_rng(seed),
        hull=settings.hull,
        arrangement=settings.arrangement(2, 2.15),
        **kw,
    )


def test_every_cusp_gets_one_outcome_and_keeps_its_size():
    cols = _cusps(300, 0.6)
    t = _flow(cols)
    assert sum(t.path_counts().values()) == 300 and set(t.path_counts()) == set(PATHS)
    reached = t.propeller_index >= 0
    y_lo, y_hi, z_lo, z_hi = (s[reached] for s in t.cross_section_m)
    assert z_hi - z_lo == pytest.approx(cols["thickness_m"][reached])
    side = np.sqrt(cols["area_m2"][reached])
    assert np.all(y_hi - y_lo >= side - 1e-9) and np.all(y_hi - y_lo <= math.sqrt(2) * side + 1e-9)
    assert np.all(np.isfinite(t.arrival_time_s[reached])) and np.all(np.isnan(t.arrival_time_s[~reached]))
    assert np.all(t.arrival_time_s[reached] > cols["bow_x_m"][reached] / 3.0)


def test_the_same_seed_gives_the_same_transport():
    cols = _cusps(120, 0.8)
    a, b, c = _flow(cols, seed=5), _flow(cols, seed=5), _flow(cols, seed=6)
    assert np.array_equal(a.propeller_index, b.propeller_index)
    assert np.array_equal(a.arrival_time_s, b.arrival_time_s, equal_nan=True)
    assert not np.array_equal(a.entry_radius_fraction, c.entry_radius_fraction, equal_nan=True)


def test_cusps_reach_the_propellers_at_every_thickness():
    """No thickness switches the loads off: a share reaches at every h in 0.3–1.5 m."""
    fractions = [_flow(_cusps(150, h)).fractions().sum() for h in np.arange(0.3, 1.51, 0.2)]
    assert min(fractions) > 0.05, fractions


def test_bad_flow_inputs_name_their_key():
    with pytest.raises(InputError) as info:
        FlowParameters(friction_range=(0.2, 0.1))
    assert info.value.field == "transport.flow.friction_range"
    with pytest.raises(InputError) as info:
        _flow(_cusps(3, 0.5), flow=FlowParameters(drag_coefficient_range=(0.05, 1.0)))
    assert info.value.field == "transport.flow.drag_coefficient_range"
    with pytest.raises(InputError) as info:
        flow_transport_cusps(
            **_cusps(3, 0.5), speed_m_s=3.0, induced_velocity_m_s=1.0, wake_fraction=0.1, rng=None
        )
    assert info.value.field == "transport.rng"
    settings = TransportSettings()
    surface = hull_surface(settings.hull, settings.arrangement(2, 2.15), 27.0)
    assert surface.buttock_rise_deg == pytest.approx(math.degrees(math.atan2(7.65 - 2.24, 15.0)))


def test_a_plate_whose_drag_is_below_friction_sticks_and_stalls():
    """Exact Coulomb friction: at rest on the flat bottom with ½ ρ_w C_D (l h) U² < μ (ρ_w − ρ_i) g A h the
    plate does not move at all, and `follow` ends it as stalled after one step, not at the time cap."""
    area, h, c_d, mu = 4.0, 0.5, 1.0, 0.1
    u_hold = math.sqrt(2 * mu * (RHO_W - RHO_I) * G * area / (RHO_W * c_d * math.sqrt(area)))
    field = cf.FlowField(0.9 * u_hold)
    start = np.array([[20.0, 0.0, 7.65]])
    pos, vel = _run(_plate(area, h, c_d, mu), field, start.copy(), np.zeros((1, 3)), 0.5, 50)
    assert pos.tolist() == start.tolist() and vel.tolist() == [[0.0, 0.0, 0.0]]
    result = cf.follow(
        _plate(area, h, c_d, mu), HULL, field, start, np.zeros((1, 3)), time_step_s=0.1, max_time_s=1e4
    )
    assert result.outcome.tolist() == [cf.STALLED] and result.time_s[0] <= cf.MAX_STEP_S  # its first step


def test_a_slow_plate_arrives_at_the_time_of_its_sliding_speed():
    """A plate sliding at the drag–friction balance V_s = U − u_rel (previous test's u_rel) reaches the plane
    after (x_p − l/2 − x0)/V_s, whether it slides at 2 cm/s or at 2 m/s (each cusp's own step). A hull whose
    stern run is a 1 cm step keeps the flat bottom to the plane."""
    area, h, c_d, mu = 4.0, 0.5, 1.0, 0.1
    hull = HullSurface(21.7, 7.65, 2.5, 27.0, 115.0, 0.5, 7.64)
    u_rel = math.sqrt(2 * mu * (RHO_W - RHO_I) * G * area / (RHO_W * c_d * math.sqrt(area)))
    for sliding in (0.02, 2.0):
        x0 = 100.0
        start, velocity = np.array([[x0, 0.0, 7.65]]), np.array([[sliding, 0.0, 0.0]])
        field = cf.FlowField(u_rel + sliding)
        result = cf.follow(
            _plate(area, h, c_d, mu), hull, field, start, velocity, time_step_s=0.1, max_time_s=1e5
        )
        assert result.outcome.tolist() == [cf.REACHED]
        expected = (115.0 - 1.0 - x0) / sliding
        assert result.time_s[0] == pytest.approx(expected, rel=2e-3), sliding
