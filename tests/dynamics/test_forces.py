"""The water forces of several pieces evaluated at once (`water_forces_and_moments`) against the drag law
written out here for one piece at a time."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely import affinity

from floebreak.dynamics import IceMotionSettings, body_geometry
from floebreak.dynamics.forces import drag_constants, drag_table, water_forces_and_moments


def _one_piece(side_a: float, side_b: float, h: float, angle: float, v, m: float, dt: float, s):
    """F = m(|u| − |u'|)/Δt against û, |u'| = |u|/(1 + k|u|Δt/m), k = ½ρ(C_d h ρ_i/ρ_w W + C_s A) with the
    width of an a × b rectangle across û at `angle` W = a|sin β| + b|cos β| (β: û from the body's x axis)."""
    speed = math.hypot(*v)
    beta = math.atan2(v[1], v[0]) - angle
    width = side_a * abs(math.sin(beta)) + side_b * abs(math.cos(beta))
    k = (
        0.5
        * s.water_density_kg_m3
        * (s.form_drag_coefficient * h * s.draft_ratio * width + s.skin_drag_coefficient * side_a * side_b)
    )
    u_next = speed / (1.0 + k * speed * dt / m)
    magnitude = m * (speed - u_next) / dt
    return -magnitude * v[0] / speed, -magnitude * v[1] / speed


def test_all_pieces_at_once_match_the_drag_law_of_each():
    s = IceMotionSettings()
    rng = np.random.default_rng(4)
    sizes = [(4.0, 2.0), (7.0, 3.0), (1.5, 1.0)]
    geometries = [body_geometry(shapely.box(0, 0, a, b)) for a, b in sizes]
    thickness = [1.0, 0.6, 1.2]
    masses, moments = [1.0e4, 2.0e4, 1.5e3], [3.0e4, 1.0e5, 400.0]
    table = drag_table(
        [g.ring_xy_m for g in geometries],
        [drag_constants(g, h, s) for g, h in zip(geometries, thickness, strict=True)],
        masses,
        moments,
    )
    angles = rng.uniform(-math.pi, math.pi, 3)
    velocity = rng.normal(0.0, 1.0, (3, 2))
    omega = np.array([0.2, -0.1, 0.0])
    fx, fy, moment = water_forces_and_moments(table, angles, velocity, omega, 0.02, s.water_density_kg_m3)
    for i, (a, b) in enumerate(sizes):
        expected = _one_piece(a, b, thickness[i], angles[i], velocity[i], masses[i], 0.02, s)
        assert (fx[i], fy[i]) == pytest.approx(expected, rel=1e-12)
    assert moment[0] < 0.0 < moment[1] and moment[2] == 0.0  # yaw drag opposes ω, none without ω


def test_a_piece_at_rest_feels_no_water():
    s = IceMotionSettings()
    g = body_geometry(affinity.rotate(shapely.box(0, 0, 3, 2), 20.0))
    table = drag_table([g.ring_xy_m], [drag_constants(g, 1.0, s)], [1.0e4], [2.0e4])
    fx, fy, moment = water_forces_and_moments(
        table, np.zeros(1), np.zeros((1, 2)), np.zeros(1), 0.02, s.water_density_kg_m3
    )
    assert (fx[0], fy[0], moment[0]) == (0.0, 0.0, 0.0)
