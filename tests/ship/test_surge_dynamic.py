"""Ship surge under moving ice (``simulation.ice_motion = "dynamic"``): the force the hull passes
to the ice (`SimulationResult.hull_force_on_ice_xy_n`) and the surge integrated in the stepping loop from it
(docs/model.md, "Ship surge", "The force the hull passes on"). Expectations are derived in the tests: the
closed-form open-water acceleration under the Juva–Riska net thrust, the water drag of a floe carried at the
hull's speed, the recorded crushing force of pieces held still, and a separate integration of the energy
equation to the stop."""

from __future__ import annotations

import csv
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest
import shapely
from scipy.integrate import solve_ivp

from floebreak import constants as c
from floebreak.app.run import run
from floebreak.config.profiles import build_model
from floebreak.config.scenario import Scenario
from floebreak.dynamics import IceMotionSettings
from floebreak.engine.loop import SimulationParams, StepDone, _Run, simulate
from floebreak.engine.records import ContactRecorder
from floebreak.errors import InputError
from floebreak.ice.field import FloeField, circle_polygons
from floebreak.mechanics.contact import BowContactGeometry, evaluate_contact
from floebreak.output.surge_file import SURGE_FILE, recorded_ice_force_series_n
from floebreak.ship.hulls import agulhas_ii
from floebreak.ship.propulsion import Propulsion, juva_riska_net_thrust_n

NO_BREAKING = {"policy": {"unbreakable": ["none"], "bending": ["none"], "cracking": ["none"]}}
SHORT = ["field.length_m=50", "simulation.ice_motion=dynamic"]  # the reference observation's floes


def _propulsion_overrides(bollard_pull_n: float, displacement_kg: float = 13.687e6) -> list[str]:
    return [
        "ship.propulsion.model=bollard_pull",
        f"ship.propulsion.displacement_kg={displacement_kg}",
        f"ship.propulsion.bollard_pull_n={bollard_pull_n}",
        "ship.propulsion.open_water_speed_m_s=8.23",
    ]


def _one_floe(polygon: shapely.Polygon) -> FloeField:
    return FloeField(
        np.array([polygon], dtype=object), np.ones(1), np.array([6.0]), np.zeros(1, int), polygon.bounds
    )


def test_in_open_water_the_ship_accelerates_to_the_thrust_resistance_balance_as_derived():
    """T_net = T_B(1 − u/3 − 2u²/3) = (2/3)T_B(1 − u)(u + 3/2), u = V/V_ow. From m V dV/dx = T_net:
    x(u) = L[−0.4 ln((1 − u)/(1 − u₀)) − 0.6 ln((u + 1.5)/(u₀ + 1.5))], L = 3mV_ow²/(2T_B)
    (u/((1 − u)(u + 1.5)) = 0.4/(1 − u) − 0.6/(u + 1.5)); from m dV/dt = T_net:
    t(u) = (3mV_ow/(2T_B))/2.5·[ln((u + 1.5)/(u₀ + 1.5)) − ln((1 − u)/(1 − u₀))]."""
    propulsion = Propulsion("bollard_pull", 1.0e5, 0.05, bollard_pull_n=1.0e5, open_water_speed_m_s=4.0)
    v0, v_ow, mass = 1.0, 4.0, 1.05e5
    far = shapely.box(1000.0, -3.0, 1006.0, 3.0)  # beyond the transit's end: open water all the way
    speeds = []
    params = SimulationParams(x_end_m=150.0, ice_motion="dynamic", speed_m_s=v0, propulsion=propulsion)
    sim = simulate(
        _one_floe(far),
        agulhas_ii(ice_thickness_m=1.0),
        build_model("default"),
        params,
        callbacks=[lambda e: speeds.append(e.ice_motion.speed_m_s) if isinstance(e, StepDone) else None],
    )
    surge = sim.surge
    assert not surge.stuck and sim.n_steps == 601 and np.all(sim.hull_force_on_ice_xy_n == 0.0)
    assert surge.speed_m_s[-1] == pytest.approx(v_ow, rel=1e-6)  # L = 25.2 m: 150 m is ≈ 6 L
    assert np.all(np.diff(surge.speed_m_s) > 0.0)
    # the hull in the engine sails at the surge's speed (the speed at each search)
    assert speeds == pytest.approx(list(surge.speed_m_s), rel=1e-12)
    u, u0 = surge.speed_m_s / v_ow, v0 / v_ow
    length = 3.0 * mass * v_ow**2 / (2.0 * 1.0e5)
    x = length * (-0.4 * np.log((1 - u) / (1 - u0)) - 0.6 * np.log((u + 1.5) / (u0 + 1.5)))
    t = (
        3.0
        * mass
        * v_ow
        / (2.0 * 1.0e5)
        / 2.5
        * (np.log((u + 1.5) / (u0 + 1.5)) - np.log((1 - u) / (1 - u0)))
    )
    resolved = 1.0 - u > 1e-3  # beyond, x(u) is ill-conditioned (a speed error of 1e-9 is metres)
    assert np.abs(x - surge.bow_x_m)[resolved].max() < 1e-6 * length
    assert surge.time_s[resolved] == pytest.approx(t[resolved], rel=1e-4)


def test_a_floe_carried_at_the_hulls_speed_passes_on_only_its_water_drag():
    """A 6 m square floe centred ahead of the stem, nothing breaking: once carried at V = 3 m/s the hull
    passes on only the form and skin drag k V², k = ½ρ_w(C_d·T·W + C_s·A) (W = 6 m across the motion,
    T = h ρ_i/ρ_w); before that, the floe's momentum m_eff·V. The crushing force recorded for it is ≫."""
    settings = IceMotionSettings()
    side, h, v = 6.0, 1.0, 3.0
    square = shapely.box(2.0, -side / 2, 2.0 + side, side / 2)
    model = build_model("default", failure=NO_BREAKING)
    params = SimulationParams(x_end_m=40.0, ice_motion="dynamic", speed_m_s=v)
    recorder = ContactRecorder()
    sim = simulate(_one_floe(square), agulhas_ii(ice_thickness_m=h), model, params, callbacks=[recorder])
    assert list(sim.fate) == ["remaining"]
    force = sim.hull_force_on_ice_xy_n
    rho_w = settings.water_density_kg_m3
    draft = h * settings.ice_density_kg_m3 / rho_w
    k = (
        0.5
        * rho_w
        * (settings.form_drag_coefficient * draft * side + settings.skin_drag_coefficient * side**2)
    )
    carried = force[-40:, 0]  # the last 10 m: long carried (a 36 t floe reaches V within metres)
    assert carried == pytest.approx(k * v**2, rel=1e-2)
    assert np.abs(force[:, 1]).max() < 1e-6 * k * v**2  # symmetric: no lateral force
    # the impulse to bring it to speed: its momentum plus the drag on the way (≤ k V² over that time)
    mass = (1 + settings.added_mass_coefficient) * settings.ice_density_kg_m3 * side**2 * h
    impulse = force[:, 0].sum() * params.step_m / v
    drag_meanwhile = k * v**2 * (sim.n_steps - 1) * params.step_m / v
    assert mass * v < impulse <= mass * v + drag_meanwhile * 1.01
    arrival, after = recorded_ice_force_series_n(
        SimpleNamespace(simulation=sim, contacts=recorder.records().columns)
    )
    assert np.mean(0.5 * (after[:-1] + arrival[1:])) > 20.0 * carried.mean()


def test_pieces_held_still_pass_on_the_whole_crushing_force():
    """With every piece pinned the hull cannot move the ice: the force over each interval is the crushing
    force of the pieces left in contact at the search that starts it, as the contact records give it."""
    result = run(Scenario.reference([*SHORT, "ice_motion.pin_all=true"]))
    _, after = recorded_ice_force_series_n(result)
    force = result.simulation.hull_force_on_ice_xy_n[:, 0]
    assert force[1:].max() > 1e6  # there is ice to push
    assert force[1:] == pytest.approx(after[:-1], rel=1e-9, abs=1e-6)


def test_a_weak_ship_is_stuck_in_ice_that_cannot_move_where_its_energy_is_spent():
    """Pinned floes resist the whole crushing force (MN), a 10 kN bollard pull cannot: the ship stops. The
    stop from a separate integration (scipy's RK45, tight tolerances) of dE/dx = T_net(V) − F under the
    force of each interval, the recorded crushing force of the pieces left in contact at its start."""
    pull, mass = 1.0e4, 1.0e6
    stuck = run(Scenario.reference([*SHORT, "ice_motion.pin_all=true", *_propulsion_overrides(pull, mass)]))
    surge, sim = stuck.simulation.surge, stuck.simulation
    assert surge.stuck and stuck.summary["surge"]["stuck"]
    x_stop = surge.stuck_at_bow_x_m
    assert stuck.summary["surge"]["stuck_at_bow_x_m"] == x_stop and surge.speed_m_s[-1] == 0.0
    step = sim.params.step_m
    assert sim.n_steps == math.floor((x_stop - sim.params.x_start_m) / step) + 1  # no search beyond it
    assert np.asarray(stuck.contacts["bow_x_m"]).max() < x_stop
    _, after = recorded_ice_force_series_n(stuck)
    m_eff = mass * 1.05
    energy, x = 0.5 * m_eff * 3.0**2, sim.params.x_start_m

    def rate(_, e, f):
        return [juva_riska_net_thrust_n(math.sqrt(2 * max(e[0], 0.0) / m_eff), pull, 8.23) - f]

    def empty(_, e, f):
        return e[0]

    empty.terminal = True
    for f in after:
        solution = solve_ivp(rate, (x, x + step), [energy], args=(f,), events=empty, rtol=1e-10, atol=1e-6)
        if solution.t_events[0].size:
            expected = float(solution.t_events[0][0])
            break
        energy, x = float(solution.y[0, -1]), x + step
    else:
        raise AssertionError("the separate integration does not stop")
    assert x_stop == pytest.approx(expected, abs=1e-6)
    # the same ice does not stop the Agulhas II-like ship (1.1 MN) that has ten times the entry energy
    strong = run(Scenario.reference([*SHORT, "ice_motion.pin_all=true", *_propulsion_overrides(1.1212e6)]))
    assert not strong.simulation.surge.stuck


def test_a_dynamic_surge_is_deterministic_and_its_summary_and_series_agree():
    overrides = [*SHORT, "seed=3", *_propulsion_overrides(1.1212e6)]
    first, again = run(Scenario.reference(overrides)), run(Scenario.reference(overrides))
    a, b = first.simulation.surge, again.simulation.surge
    for name in ("bow_x_m", "time_s", "speed_m_s", "ice_force_x_n", "ice_force_x_after_breaks_n"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    assert np.array_equal(first.simulation.hull_force_on_ice_xy_n, again.simulation.hull_force_on_ice_xy_n)
    assert first.summary["surge"] == again.summary["surge"]
    assert not np.all(a.speed_m_s == 3.0)  # the speed did follow the thrust and the ice
    # the series is the transmitted force: constant over each interval
    force = first.simulation.hull_force_on_ice_xy_n[:, 0]
    assert np.array_equal(a.ice_force_x_n[1:], force[1:]) and np.array_equal(
        a.ice_force_x_after_breaks_n[:-1], force[1:]
    )


def test_a_ship_faster_than_the_engine_step_resolves_is_refused_naming_the_step():
    """The ship may accelerate to its open-water speed: 20 m/s × 0.02 s = 0.4 m per engine step, beyond
    step_travel_fraction·smallest_floe_size_m = 0.25 m, refused before the run."""
    overrides = [*SHORT, *_propulsion_overrides(1.1212e6)]
    overrides[-1] = "ship.propulsion.open_water_speed_m_s=20"
    with pytest.raises(InputError) as error:
        run(Scenario.reference(overrides))
    assert error.value.field == "ice_motion.time_step_s"
    assert c.SHIP_SPEED_IN_ICE_M_S * 0.02 <= 0.25  # the entry speed alone would pass


def test_a_stuck_dynamic_run_writes_its_surge_up_to_the_stop(tmp_path):
    """surge.csv and the summary as under static: one row per search reached and the stop last."""
    overrides = [*SHORT, "ice_motion.pin_all=true", *_propulsion_overrides(1.0e4, 1.0e6)]
    result = run(Scenario.reference(overrides))
    out = result.write(tmp_path / "run", report=False, figures=False)
    summary = json.loads((out / "summary.json").read_text())["surge"]
    text = (out / SURGE_FILE).read_text()
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    x = np.array([float(r["bow_x_m"]) for r in rows])
    assert summary["stuck"] is True and x[-1] == pytest.approx(summary["stuck_at_bow_x_m"], abs=1e-9)
    assert len(rows) == result.simulation.n_steps + 1 and float(rows[-1]["speed_m_s"]) == 0.0
    assert "the force the hull passed to the ice" in text


def _lone_floe_run(failure_force: str):
    """A 6 m floe 8 m to port of the stem: the bow's flank carries it along at the hull's normal speed."""
    polygon = circle_polygons(np.array([[5.0, 8.0]]), np.array([3.0]), 64)
    field = FloeField(polygon, np.ones(1), np.array([6.0]), np.zeros(1, int), tuple(polygon[0].bounds))
    settings = IceMotionSettings(failure_force=failure_force)
    params = SimulationParams(x_end_m=60.0, ice_motion="dynamic", ice_motion_settings=settings)
    return simulate(field, agulhas_ii(ice_thickness_m=1.0), build_model("default"), params)


def test_with_the_lagged_transmitted_force_a_floe_carried_freely_is_pushed_aside_not_broken():
    """The floe moves with the hull and passes on little of the crushing force: judged on the whole force it
    fails in bending at the shoulder; judged on the share its contact passed on over the interval before,
    it is pushed aside whole."""
    crushing, lagged = _lone_floe_run("crushing"), _lone_floe_run("lagged_transmitted")
    assert crushing.n_breaks > 0 and crushing.fate[0] == "broken"
    assert lagged.n_breaks == 0 and list(lagged.fate) == ["remaining"] and lagged.n_contacts > 0


def test_the_failure_force_is_the_crushing_force_times_the_share_passed_on_before():
    field = _one_floe(shapely.box(2.0, -3.0, 8.0, 3.0))
    bow, model = agulhas_ii(ice_thickness_m=1.0), build_model("default")
    contact = evaluate_contact(
        shapely.box(-1.0, -3.0, 5.0, 3.0), 1.0, BowContactGeometry.from_bow(bow), model.contact
    )
    assert contact.in_contact
    for failure_force, share, expected in (
        ("crushing", 0.25, 1.0),
        ("lagged_transmitted", 0.25, 0.25),
        ("lagged_transmitted", 1.5, 1.0),  # never more than the crushing force
        ("lagged_transmitted", None, 1.0),  # not held over the interval before: the whole force
    ):
        settings = IceMotionSettings(failure_force=failure_force)
        params = SimulationParams(x_end_m=20.0, ice_motion="dynamic", ice_motion_settings=settings)
        motion = _Run(field, bow, model, params, ()).motion
        motion.load_share = {} if share is None else {0: share}
        seen = motion.failure_contact(0, contact)
        for zone, original in zip(seen.zones, contact.zones, strict=True):
            for name in ("f_c_n", "f_v_n", "f_h_n", "force_on_ice_xy_n"):
                assert np.array_equal(getattr(zone, name), getattr(original, name) * expected)


def test_an_unknown_failure_force_is_refused_naming_the_key():
    with pytest.raises(InputError) as error:
        Scenario.reference([*SHORT, "ice_motion.failure_force='transmitted'"])
    assert error.value.field == "ice_motion.failure_force"
