"""The stall of the drive under the rule's case 2: the case's mean ice torque per blade passage
by integrating the pulse train numerically, the stop time from the rigid-shaft equation solved by hand, and
the stall as the terminal and summary.json state it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.propeller.loads.milling import BladeGeometry, IceBlock
from floebreak.propeller.spec import PropellerSpec
from floebreak.shaft.analysis import (
    MilledCusps,
    ShaftResult,
    drive_case_summary,
    stall_message,
    with_stall_positions,
)
from floebreak.shaft.drive import MotorDrive, rigid_train, simulate_drive
from floebreak.shaft.excitation import EXCITATION_CASES, mean_torque_per_passage_n_m

J, RPM, Z, Q_MEAN, LIMIT = 30_875.0, 140.0, 4, 105e3, 491e3  # the Agulhas II line's inertia, rpm, drive
OMEGA = 2 * math.pi * RPM / 60
C_H = Q_MEAN / OMEGA**2


@pytest.mark.parametrize("case", [1, 2, 3, 4])
def test_mean_torque_per_passage_of_the_pulse_train(case):
    spec = EXCITATION_CASES[case]
    phi = np.linspace(0.0, 2 * math.pi * 20, 2_000_001)[:-1]  # 20 revolutions, far from the train's ends
    torque = np.zeros_like(phi)
    for k in range(-4 * Z, 20 * Z):  # one pulse per blade passage (and block), half a sine over α_i
        for block in range(spec.blocks):
            s = phi - (2 * math.pi * k / Z + block * math.pi / Z)
            inside = (s >= 0) & (s < math.radians(spec.alpha_deg))
            torque[inside] += 1e3 * np.sin(math.pi * s[inside] / math.radians(spec.alpha_deg))
    assert torque.mean() == pytest.approx(float(mean_torque_per_passage_n_m(1e3, case, Z)), rel=1e-4)


def _drive(kp=1e9):
    return MotorDrive(rpm_set=RPM, torque_limit_n_m=LIMIT, kp_n_m_s_per_rad=kp, ki_n_m_per_rad=0.0)


def test_case_2_stops_the_propeller_when_its_mean_ice_torque_exceeds_the_limit():
    # a stiff controller holds the motor at its limit from the first impact; with the mean ice torque Q_i
    # of the pulse train, J ω̇ = Q_lim − c_h ω² − Q_i, and a = Q_i − Q_lim > 0 the propeller stops after
    # t = J/√(a c_h) · atan(ω_0 √(c_h/a))
    q_imp = 600e3
    r = simulate_drive(
        rigid_train(J),
        _drive(),
        [1.0],
        [10_000],
        lambda c, rpm: q_imp,
        mean_torque_n_m=Q_MEAN,
        blades=Z,
        case=2,
    )
    a = float(mean_torque_per_passage_n_m(q_imp, 2, Z)) - LIMIT
    t_stop = J / math.sqrt(a * C_H) * math.atan(OMEGA * math.sqrt(C_H / a))
    assert r.stalled_at_s - r.impact_time_s[0] == pytest.approx(t_stop, rel=0.05)
    # below the limit the same train only slows the propeller: 400 kN·m → mean 382 + 105 < 491
    slow = simulate_drive(
        rigid_train(J), _drive(), [1.0], [200], lambda c, rpm: 400e3, mean_torque_n_m=Q_MEAN, blades=Z, case=2
    )
    assert math.isnan(slow.stalled_at_s) and slow.rpm.min() > 0.8 * RPM


def test_stall_names_the_cusp_its_impacts_and_why():
    torques = {0: 100e3, 1: 900e3}  # the first cusp passes, the second stops the propeller
    r = simulate_drive(
        rigid_train(J),
        _drive(kp=2e5),
        [1.0, 3.0],
        [8, 8],
        lambda c, rpm: torques[c],
        mean_torque_n_m=Q_MEAN,
        blades=Z,
        case=2,
        free_blocks=True,
    )
    stall = r.stall()
    assert stall["cusp"] == 1 and stall["time_s"] == r.stalled_at_s > 3.0
    assert 1 <= stall["impacts_of_cusp"] <= 8
    assert stall["mean_impact_peak_n_m"] == 900e3  # C_q = 1 times the cusp's torque
    assert r.stop_times_s[0] == r.stalled_at_s and np.all(np.diff(r.stop_times_s) > 0)
    d = drive_case_summary(r, 2, Z, Q_MEAN)
    assert d["stall"]["mean_ice_torque_per_passage_knm"] == pytest.approx(900 * 2 / math.pi * 1.5)
    assert d["stops"] == r.stop_times_s.size
    message = stall_message(2, d)
    assert message.startswith(f"case 2 stalls at t = {r.stalled_at_s:.2f} s, position: milling cusp 1,")
    assert "859 kN·m, plus the hydrodynamic 105 kN·m" in message and "491 kN·m limit" in message
    assert (
        stall_message(
            3,
            drive_case_summary(
                simulate_drive(
                    rigid_train(J), _drive(), [1.0], [4], lambda c, rpm: 1e3, mean_torque_n_m=Q_MEAN, blades=Z
                )
            ),
        )
        is None
    )


def test_stall_position_is_the_cusps_row_and_bow_position_in_the_run():
    r = simulate_drive(
        rigid_train(J), _drive(), [1.0], [50], lambda c, rpm: 900e3, mean_torque_n_m=Q_MEAN, blades=Z, case=2
    )
    blade = BladeGeometry.from_spec(PropellerSpec())
    milled = MilledCusps(
        np.array([1.0]),
        np.array([50]),
        IceBlock(np.ones(1), np.ones(1), np.ones(1)),
        blade,
        3.0,
        40,
        {},
        run_index=np.array([17]),
        bow_x_m=np.array([42.25]),
    )
    result = ShaftResult(
        line=None,
        station="s",
        cases=(2,),
        blades=Z,
        speed_m_s=3.0,
        samples_per_blade_passage=40,
        time_s=r.time_s,
        load_torque_n_m=np.zeros((1, 1)),
        shaft_torque_n_m=np.zeros((1, 1)),
        modes=None,
        n_cusps=1,
        model="drive",
        drive_summaries=(drive_case_summary(r, 2, Z, Q_MEAN),),
    )
    located = with_stall_positions(result, milled).drive_summaries[0]
    assert located["stall"]["run_cusp"] == 17 and located["stall"]["bow_x_m"] == 42.25
    assert "position: milling the run's cusp 17 (broken off at bow x = 42.2 m)" in stall_message(2, located)
