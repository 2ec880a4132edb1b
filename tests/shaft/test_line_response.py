"""Shaft line and time-domain response: the checks a torsional-vibration engineer would run. Expected values
are computed here from the textbook two-inertia formulas, not taken from floebreak."""

import math

import numpy as np
import opentorsion as ot
import pytest

from floebreak.app.inputs import load_shaft_line
from floebreak.errors import InputError
from floebreak.shaft.line import (
    modal_analysis,
    shaft_line_from_dict,
    solid_shaft_stiffness_n_m_per_rad,
    with_operating_point,
)
from floebreak.shaft.response import station_torque_n_m

J1, J2, K, ZETA = 1000.0, 100.0, 1e7, 0.02  # motor, propeller [kg m²], shaft [N m/rad], damping ratio


def two_inertia(zeta=ZETA, bandwidth_hz=0.5, mean_torque_n_m=0.0, **extra):
    return shaft_line_from_dict(
        {
            "name": "two",
            "rpm": 140.0,
            "mean_torque_n_m": mean_torque_n_m,
            "speed_control_bandwidth_hz": bandwidth_hz,
            "elements": [
                {
                    "name": "motor",
                    "inertia_kg_m2": J1,
                    "stiffness_n_m_per_rad": K,
                    "damping_ratio": zeta,
                    "shaft": "shaft",
                },
                {"name": "propeller", "inertia_kg_m2": J2},
            ],
            **extra,
        }
    )


def omega_n():
    return math.sqrt(K * (J1 + J2) / (J1 * J2))


def amplitude(y):
    return 0.5 * (y.max() - y.min())


def test_two_inertia_natural_frequency():
    modes = modal_analysis(two_inertia())
    assert modes.frequency_hz.size == 1
    assert modes.frequency_hz[0] == pytest.approx(omega_n() / (2 * math.pi), rel=1e-9)
    # mode shape: the inertias swing against each other with amplitudes in ratio J2/J1
    assert modes.shapes[0, 0] / modes.shapes[0, 1] == pytest.approx(-J2 / J1, rel=1e-9)
    assert modes.damping_ratio[0] == pytest.approx(ZETA, rel=1e-6)


@pytest.mark.parametrize("station", ["intermediate_shaft", "propeller_shaft"])
def test_constant_torque_gives_the_same_steady_shaft_torque(station):
    line = load_shaft_line("agulhas_ii")
    q = np.full(2000, 250e3)
    y = station_torque_n_m(line, q, 1e-3, station)
    np.testing.assert_allclose(y, 250e3, rtol=1e-9)
    # a step from 0 to Q settles at Q (static gain 1)
    q[:100] = 0.0
    y = station_torque_n_m(line, np.r_[q, np.full(40_000, 250e3)], 1e-3, station)
    assert y[-1] == pytest.approx(250e3, rel=1e-4)


def test_slow_input_passes_without_amplification():
    line = two_inertia()
    dt = 1e-3
    t = np.arange(0, 200.0, dt)
    q = 1e5 * np.sin(2 * math.pi * 0.02 * t)  # 0.02 Hz, far below the controller (0.5 Hz) and the shaft
    y = station_torque_n_m(line, q, dt)
    assert amplitude(y[t > 100]) / amplitude(q[t > 100]) == pytest.approx(1.0, abs=0.01)


def test_input_at_the_natural_frequency_is_amplified_by_one_over_two_zeta():
    line = two_inertia(bandwidth_hz=0.01)  # the controller's damper would add ≈ 0.0007 to ζ at 0.5 Hz
    wn = omega_n()
    dt = 2 * math.pi / wn / 200
    t = np.arange(0, 3.0, dt)  # decay time 1/(ζ ω_n) ≈ 0.15 s
    q = 1e4 * np.sin(wn * t)
    y = station_torque_n_m(line, q, dt)
    # J_red δ'' + c δ' + k δ = Q J1/(J1+J2), T = k δ + c δ'  →  |T/Q| at ω_n = J1/(J1+J2)·√(1+4ζ²)/(2ζ)
    expected = J1 / (J1 + J2) * math.sqrt(1 + 4 * ZETA**2) / (2 * ZETA)
    assert amplitude(y[t > 2.5]) / 1e4 == pytest.approx(expected, rel=0.02)
    assert expected == pytest.approx(1 / (2 * ZETA), rel=0.1)  # "about 1/(2ζ)" for J1 ≫ J2


def test_response_mean_equals_input_mean():
    rng = np.random.default_rng(7)
    line = load_shaft_line("agulhas_ii")
    dt = 2e-3
    q = 3e5 + np.repeat(rng.exponential(1e5, 5000), 20) * (rng.random(100_000) < 0.3)
    q[-20_000:] = q[0]  # a quiet end: the line comes back to rest
    y = station_torque_n_m(line, q, dt)
    assert y.mean() == pytest.approx(q.mean(), rel=1e-3)


def test_agrees_with_opentorsion_time_stepping():
    """openTorsion's own `dsim` on the same line, the controller's ground as a huge inertia."""
    line = load_shaft_line("agulhas_ii")
    j, k, c = line.inertias_kg_m2, line.stiffnesses_n_m_per_rad, line.damping_n_m_s_per_rad
    wg = 2 * math.pi * line.speed_control_bandwidth_hz
    kg, cg = j.sum() * wg**2, 2 * line.speed_control_damping_ratio * j.sum() * wg
    cp = 2 * line.mean_torque() / (2 * math.pi * line.rpm / 60)
    shafts = [ot.Shaft(0, 1, k=kg, c=cg)] + [ot.Shaft(i + 1, i + 2, k=k[i], c=c[i]) for i in range(k.size)]
    disks = [ot.Disk(0, I=1e15)] + [ot.Disk(i + 1, I=j[i]) for i in range(j.size)]
    disks[-1] = ot.Disk(j.size, I=j[-1], c=cp)
    assembly = ot.Assembly(shafts, disk_elements=disks)
    dt = 1e-3
    t = np.arange(4000) * dt
    q = 2e5 * np.clip(np.sin(2 * math.pi * 9.33 * t), 0, None) * (t < 2.0)  # starts at 0: dsim's x0 = 0
    excitation = ot.TransientExcitation(j.size + 1, t)
    excitation.add_transient(j.size, -q)
    torques, _, _ = assembly.dsim(excitation)
    for i, station in enumerate(line.stations):
        ours = station_torque_n_m(line, q, dt, station)
        np.testing.assert_allclose(ours, torques[i + 1], rtol=0, atol=1e-6 * np.abs(ours).max())


def test_entrained_water_and_damping_rule():
    line = shaft_line_from_dict(
        {
            "rpm": 100.0,
            "rated_power_w": 1e6,
            "entrained_water_fraction": 0.25,
            "elements": [
                {"name": "m", "inertia_kg_m2": 300.0, "stiffness_n_m_per_rad": 4e6, "damping_ratio": 0.05},
                {"name": "p", "inertia_kg_m2": 80.0},
            ],
        }
    )
    assert line.inertias_kg_m2[-1] == pytest.approx(100.0)
    assert line.damping_n_m_s_per_rad[0] == pytest.approx(2 * 0.05 * math.sqrt(4e6 * 300 * 100 / 400))
    assert line.mean_torque() == pytest.approx(1e6 / (2 * math.pi * 100 / 60))
    assert solid_shaft_stiffness_n_m_per_rad(0.1, 2.0) == pytest.approx(80e9 * math.pi * 1e-4 / 64)


def test_toml_overrides_a_builtin_line(tmp_path):
    path = tmp_path / "line.toml"
    path.write_text(
        '[shaft_line]\nbase = "agulhas_ii"\nrpm = 120\n'
        "[shaft_line.element_overrides.motor]\ninertia_kg_m2 = 30000\n",
        encoding="utf-8",
    )
    line = load_shaft_line(path)
    assert line.rpm == 120 and line.inertias_kg_m2[0] == 30000
    assert line.inertias_kg_m2[1] == load_shaft_line("agulhas_ii").inertias_kg_m2[1]


def _elements(**change):
    motor = {"name": "m", "inertia_kg_m2": 1.0, "stiffness_n_m_per_rad": 1.0, "damping_ratio": 0.1}
    prop = {"name": "p", "inertia_kg_m2": 1.0}
    for key, value in change.items():
        target, name = key.split("__")
        (motor if target == "m" else prop)[name] = value
    return [motor, prop]


@pytest.mark.parametrize(
    ("elements", "key"),
    [
        (_elements(m__inertia_kg_m2=0.0), "shaft_line.elements[0].inertia_kg_m2"),
        (_elements(p__inertia_kg_m2=-5.0), "shaft_line.elements[1].inertia_kg_m2"),
        (_elements(m__stiffness_n_m_per_rad=0.0), "shaft_line.elements[0].stiffness_n_m_per_rad"),
        (_elements(m__stiffness_n_m_per_rad=-1.0), "shaft_line.elements[0].stiffness_n_m_per_rad"),
        (_elements(m__damping_ratio=1.0), "shaft_line.elements[0].damping_ratio"),
        (_elements(m__damping_ratio=-0.1), "shaft_line.elements[0].damping_ratio"),
        (_elements()[1:], "shaft_line.elements"),
    ],
)
def test_bad_lines_name_the_key(elements, key):
    with pytest.raises(InputError) as info:
        shaft_line_from_dict({"rpm": 100.0, "mean_torque_n_m": 0.0, "elements": elements})
    assert info.value.field == key


def test_bad_station_and_rpm():
    line = load_shaft_line("agulhas_ii")
    with pytest.raises(InputError) as info:
        station_torque_n_m(line, np.zeros(10), 1e-3, "tail_shaft")
    assert info.value.field == "station" and "intermediate_shaft" in str(info.value)
    for rpm in (0.0, -10.0):
        with pytest.raises(InputError) as info:
            with_operating_point(line, rpm=rpm)
        assert info.value.field == "rpm"
