"""The drive reacts (floebreak.shaft.drive). Expected values come from the rigid-shaft equation solved by hand
here (steady states, linearised second-order response, deceleration at the torque limit), from the blade-
passage arithmetic, and from the linear openTorsion model (the small-signal check)."""

import math

import numpy as np
import pytest

from floebreak.app.inputs import load_shaft_line
from floebreak.errors import InputError
from floebreak.shaft.drive import (
    DriveTrain,
    MotorDrive,
    drive_for_line,
    rigid_train,
    simulate_drive,
    train_from_line,
)
from floebreak.shaft.excitation import ExcitationCase
from floebreak.shaft.line import with_operating_point
from floebreak.shaft.response import station_torque_n_m

J, RPM, Z, Q_MEAN = 1000.0, 100.0, 4, 1.0e4  # rigid inertia [kg m²], set speed, blades, mean torque [N m]
OMEGA = 2 * math.pi * RPM / 60
PASSAGE_S = 60 / (RPM * Z)
C_H = Q_MEAN / OMEGA**2  # Q_hydro = c_h ω²
RPM_AG = 140.0  # the Agulhas II line's speed
STEP = ExcitationCase(0, 1.0, 360.0 / Z, 1)  # rectangular pulses over one blade passage: a constant torque


def run(q_ice, n_impacts, *, kp=2000.0, ki=0.0, limit=1e6, arrival=1.0, **kw):
    drive = MotorDrive(rpm_set=RPM, torque_limit_n_m=limit, kp_n_m_s_per_rad=kp, ki_n_m_per_rad=ki)
    kw.setdefault("pulse", "rectangular")
    kw.setdefault("case", STEP)
    return simulate_drive(
        rigid_train(J),
        drive,
        [arrival],
        [n_impacts],
        lambda c, rpm: q_ice,
        mean_torque_n_m=Q_MEAN,
        blades=Z,
        **kw,
    )


def omega_of(result):
    return result.rpm * 2 * math.pi / 60


def test_steady_speed_drop_under_a_step_below_the_limit():
    q_ice, kp = 2000.0, 2000.0  # proportional control only: a steady speed error remains
    r = run(q_ice, 60, kp=kp)
    during = (r.time_s > r.impact_time_s[-1] - 0.2) & (r.time_s < r.impact_time_s[-1])
    omega = omega_of(r)[during].mean()
    # by hand: Q_mean + K_p (ω_s − ω) = c_h ω² + Q_ice, a quadratic in ω
    exact = (-kp + math.sqrt(kp**2 + 4 * C_H * (Q_MEAN + kp * OMEGA - q_ice))) / (2 * C_H)
    assert omega == pytest.approx(exact, rel=1e-6)
    # linearised: Δω = Q_ice / (K_p + 2 Q_mean/ω_s); its error is of order Δω/ω_s (here 5 %) of Δω
    linear = q_ice / (kp + 2 * Q_MEAN / OMEGA)
    assert OMEGA - omega == pytest.approx(linear, rel=0.03)
    assert r.motor_torque_n_m[during].mean() == pytest.approx(Q_MEAN + kp * (OMEGA - exact), rel=1e-6)


def test_pi_step_response_matches_the_linearised_second_order_equation():
    q_ice, kp, ki = 100.0, 2000.0, 4000.0  # 1 % of the mean torque: the ω² law is linear to 0.1 %
    r = run(q_ice, 30, kp=kp, ki=ki)
    t0 = r.impact_time_s[0]
    # J δω'' + (K_p + c_p) δω' + K_i δω = −Q δ(t): δω = −Q/(J ω_d) e^{−σ t} sin(ω_d t)
    sigma = (kp + 2 * Q_MEAN / OMEGA) / (2 * J)
    omega_d = math.sqrt(ki / J - sigma**2)
    t = r.time_s - t0
    window = (t > 0) & (t < r.impact_time_s[-1] - t0)
    expected = -q_ice / (J * omega_d) * np.exp(-sigma * t[window]) * np.sin(omega_d * t[window])
    error = np.abs(omega_of(r)[window] - OMEGA - expected)
    assert error.max() < 0.01 * np.abs(expected).max()


def test_speed_recovers_to_the_set_point_during_and_after_the_ice():
    r = run(3000.0, 40, kp=2000.0, ki=4000.0, tail_s=8.0)
    end_ice = r.impact_time_s[-1] + PASSAGE_S
    drop = OMEGA - omega_of(r).min()
    assert drop > 0.05  # it did slow down
    during = (r.time_s > end_ice - 0.3) & (r.time_s < end_ice)
    assert np.abs(r.rpm[during] - RPM).max() < 0.02 * drop * 60 / (2 * math.pi)  # integral action
    assert r.rpm[-1] == pytest.approx(RPM, abs=1e-3)
    assert r.motor_torque_n_m[-1] == pytest.approx(Q_MEAN, rel=1e-4)


def test_above_the_limit_the_speed_falls_at_the_torque_deficit_then_stalls_without_reversing():
    limit, q_ice = 1.5 * Q_MEAN, 2.0 * Q_MEAN
    r = run(q_ice, 200, kp=2000.0, ki=4000.0, limit=limit, duration_s=4.0)
    omega = omega_of(r)
    falling = (r.time_s > 1.3) & (omega > 0.3 * OMEGA)
    assert falling.sum() > 20
    np.testing.assert_allclose(r.motor_torque_n_m[falling], limit)
    i = np.flatnonzero(falling)[:-1]
    rate = (omega[i + 1] - omega[i]) / r.dt_s
    mid = 0.5 * (omega[i] + omega[i + 1])
    np.testing.assert_allclose(rate, -(q_ice + C_H * mid**2 - limit) / J, rtol=2e-3)
    # the motor cannot overcome the ice: the propeller stops and stays, the ice holding it
    assert r.rpm.min() == 0.0
    stalled = r.time_s > r.time_s[np.argmax(r.rpm == 0.0)]
    assert np.all(r.rpm[stalled] == 0.0)
    np.testing.assert_allclose(r.ice_torque_n_m[stalled][5:], limit, rtol=1e-9)
    assert not r.complete
    assert r.stalled_at_s == pytest.approx(r.time_s[np.argmax(r.rpm == 0.0)], abs=1.5 * r.dt_s)
    # without a given duration the run ends `tail_s` after the stall
    short = run(q_ice, 200, kp=2000.0, ki=4000.0, limit=limit, tail_s=0.5)
    assert short.stalled_at_s == pytest.approx(r.stalled_at_s)
    assert short.time_s[-1] == pytest.approx(short.stalled_at_s + 0.5, abs=2 * r.dt_s)


def test_impacts_at_the_blade_passages_when_the_speed_holds():
    r = run(1.0, 5, kp=2e5, ki=0.0, arrival=0.33, pulse="half_sine", case=1)  # 1 N m: rpm unchanged
    first = math.ceil(0.33 / PASSAGE_S)
    np.testing.assert_allclose(r.impact_time_s, (first + np.arange(5)) * PASSAGE_S, atol=1e-6)
    np.testing.assert_allclose(r.impact_rpm, RPM, rtol=1e-6)
    np.testing.assert_allclose(r.impact_torque_n_m, 0.75)  # case 1: C_q = 0.75


def test_impacts_come_later_when_the_propeller_slows():
    r = run(8000.0, 12, kp=500.0, pulse="half_sine", case=2)
    gaps = np.diff(r.impact_time_s)
    assert gaps[-1] > 1.05 * PASSAGE_S  # slowed by more than 5 %
    angle = np.concatenate([[0.0], np.cumsum(omega_of(r)) * r.dt_s])  # ∫ω dt on the step grid
    at = np.interp(r.impact_time_s, np.arange(angle.size) * r.dt_s, angle)
    np.testing.assert_allclose(np.diff(at), 2 * math.pi / Z, rtol=2e-3)  # one blade passage apart
    # each amplitude was asked for at the rpm of its passage
    np.testing.assert_allclose(r.impact_rpm, np.interp(r.impact_time_s, r.time_s, r.rpm), rtol=1e-3)


def test_cusps_are_milled_one_at_a_time_in_arrival_order():
    drive = MotorDrive(rpm_set=RPM, torque_limit_n_m=1e6, kp_n_m_s_per_rad=2e5, ki_n_m_per_rad=0.0)
    arrival, impacts = [0.0, 0.05, 0.5, 0.3, 2.0], [3, 2, 1, 2, 1]
    seen = []
    r = simulate_drive(
        rigid_train(J),
        drive,
        arrival,
        impacts,
        lambda c, rpm: seen.append(c) or 1.0,
        mean_torque_n_m=Q_MEAN,
        blades=Z,
    )
    # by hand, passages every 0.15 s: cusp 0 at passages 0-2, cusp 1 (arrived 0.05) at 3-4, cusp 3
    # (arrived 0.3) at 5-6, cusp 2 (0.5) at 7; cusp 4 arrives at 2.0, the first passage after it is 14
    assert seen == [0, 0, 0, 1, 1, 3, 3, 2, 4]
    np.testing.assert_array_equal(r.impact_cusp, seen)
    np.testing.assert_allclose(r.milling_start_s, np.array([0, 3, 7, 5, 14]) * PASSAGE_S, atol=1e-6)
    np.testing.assert_allclose(r.milling_end_s, np.array([3, 5, 8, 7, 15]) * PASSAGE_S, atol=1e-6)
    at = lambda t: r.milled_cusp[np.argmin(np.abs(r.time_s - t))]  # noqa: E731
    assert [at(t) for t in (0.1, 0.5, 0.9, 1.1, 1.5, 2.15, 2.5)] == [0, 1, 3, 2, -1, 4, -1]


def test_small_signal_check_against_the_linear_shaft_line():
    line = with_operating_point(load_shaft_line("agulhas_ii"), mean_torque_n_m=1.05e5)
    drive = drive_for_line(load_shaft_line("agulhas_ii"))
    arrival = 1.0 + 0.6 * np.arange(4)
    r = simulate_drive(
        train_from_line(line), drive, arrival, [3] * 4, lambda c, rpm: 2.0e3, mean_torque_n_m=1.05e5, case=1
    )
    # the linear model (openTorsion state space, controller spring and damper, c_p = 2 Q/ω) fed the same
    # applied ice torque
    linear = station_torque_n_m(line, 1.05e5 + r.ice_torque_n_m, r.dt_s, "intermediate_shaft")
    dynamic = r.shaft_torque_n_m - 1.05e5
    assert np.abs(dynamic).max() > 1.0e3
    assert np.abs(r.shaft_torque_n_m - linear).max() < 0.03 * np.abs(dynamic).max()


def test_rigid_station_torque_and_speed_drop_against_the_flexible_line():
    line = load_shaft_line("agulhas_ii")
    drive = drive_for_line(line)
    args = ([1.0], [3], lambda c, rpm: 2.0e5)
    rigid = simulate_drive(train_from_line(line, rigid=True), drive, *args, mean_torque_n_m=1.05e5)
    flexible = simulate_drive(train_from_line(line), drive, *args, mean_torque_n_m=1.05e5)
    # averaged over a period of the first mode (7.76 Hz), the motor sees the rigid line's slow speed drop
    # (its speed loop is 0.5 Hz)
    width = round(1 / (7.76 * flexible.dt_s))
    slow = np.convolve(flexible.motor_rpm, np.ones(width) / width, mode="valid")
    drop_rigid = RPM_AG - rigid.motor_rpm.min()
    assert slow.min() == pytest.approx(rigid.motor_rpm.min(), abs=0.1 * drop_rigid)
    # rigid station torque: the motor torque minus the motor-side inertia's share, Q_m − J_up ω̇
    j = line.inertias_kg_m2
    omega = rigid.rpm * 2 * math.pi / 60
    accel = np.diff(omega) / rigid.dt_s  # over each step, against the trapezoid of the torques
    middle = lambda a: 0.5 * (a[1:] + a[:-1])  # noqa: E731
    expected = middle(rigid.motor_torque_n_m) - j[0] * accel
    # (to 2 %: a pulse that starts inside a step is a kink the trapezoid does not follow)
    assert np.abs(middle(rigid.shaft_torque_n_m) - expected).max() < 0.02 * rigid.impact_torque_n_m.max()


def test_drive_for_line_uses_the_rated_torque_and_the_lines_controller():
    line = load_shaft_line("agulhas_ii")
    drive = drive_for_line(line, overload_factor=1.5)
    rated = 4.5e6 / (2 * math.pi * 140 / 60)
    assert drive.torque_limit_n_m == pytest.approx(1.5 * rated)
    j_total = 20000 + 1500 + 7500 * 1.25
    assert drive.kp_n_m_s_per_rad == pytest.approx(2 * 0.7 * 2 * math.pi * 0.5 * j_total)
    assert drive.ki_n_m_per_rad == pytest.approx((2 * math.pi * 0.5) ** 2 * j_total)
    with pytest.raises(InputError, match="rated_torque_n_m"):
        drive_for_line(with_operating_point(line, mean_torque_n_m=1e5))


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"torque_limit_n_m": 0.0}, "torque_limit_n_m"),
        ({"torque_limit_n_m": -1.0}, "torque_limit_n_m"),
        ({"kp_n_m_s_per_rad": -1.0}, "kp_n_m_s_per_rad"),
        ({"ki_n_m_per_rad": -0.1}, "ki_n_m_per_rad"),
        ({"rpm_set": 0.0}, "rpm_set"),
    ],
)
def test_bad_drive_input_names_the_key(kwargs, key):
    base = {"rpm_set": RPM, "torque_limit_n_m": 1e5, "kp_n_m_s_per_rad": 1.0, "ki_n_m_per_rad": 1.0}
    with pytest.raises(InputError) as error:
        MotorDrive(**{**base, **kwargs})
    assert error.value.field == key


def test_bad_train_and_cusp_input_names_the_key():
    with pytest.raises(InputError) as error:
        rigid_train(0.0)
    assert error.value.field == "inertia_kg_m2"
    with pytest.raises(InputError) as error:
        DriveTrain((1.0, -2.0), (1e6,), (0.0,))
    assert error.value.field == "inertias_kg_m2[1]"
    with pytest.raises(InputError) as error:
        DriveTrain((1.0, 2.0), (0.0,), (0.0,))
    assert error.value.field == "stiffnesses_n_m_per_rad[0]"
    for arrival, impacts, key in (
        ([1.0], [0], "n_impacts"),
        ([1.0], [1.5], "n_impacts"),
        ([-1.0], [1], "arrival_s"),
        ([1.0, 2.0], [1], "n_impacts"),
    ):
        with pytest.raises(InputError) as error:
            simulate_drive(
                rigid_train(J),
                MotorDrive(RPM, 1e5, 1.0, 1.0),
                arrival,
                impacts,
                lambda c, r: 1.0,
                mean_torque_n_m=Q_MEAN,
            )
        assert error.value.field == key
    with pytest.raises(InputError) as error:
        run(1.0, 1, points_per_pulse=10)
    assert error.value.field == "points_per_pulse"
    with pytest.raises(InputError) as error:
        run(float("nan"), 1)
    assert error.value.field == "impact_torque_n_m"


def test_a_free_block_cannot_hold_a_stopped_propeller():
    """free_blocks: at the stop the cusp's pulses end and its remaining impacts are dropped; the next cusp
    is milled after the propeller has run up again (by hand: the same fall as above until the stop)."""
    limit, q_ice = 1.5 * Q_MEAN, 2.0 * Q_MEAN
    held = run(q_ice, 200, kp=2000.0, ki=4000.0, limit=limit, duration_s=12.0)
    free = simulate_drive(
        rigid_train(J),
        MotorDrive(rpm_set=RPM, torque_limit_n_m=limit, kp_n_m_s_per_rad=2000.0, ki_n_m_per_rad=4000.0),
        [1.0, 8.0],
        [200, 3],
        lambda c, rpm: q_ice,
        mean_torque_n_m=Q_MEAN,
        blades=Z,
        case=STEP,
        pulse="rectangular",
        tail_s=3.0,
        free_blocks=True,
    )
    assert free.stalled_at_s == pytest.approx(held.stalled_at_s, abs=1.5 * free.dt_s)
    first = free.impact_cusp == 0
    assert 0 < first.sum() < 200  # released at the stop, not milled through
    after = free.time_s > free.stalled_at_s + 0.2
    assert free.ice_torque_n_m[after & (free.time_s < 8.0)].max() == 0.0  # the block is gone
    assert free.rpm[(free.time_s > 7.5) & (free.time_s < 8.0)].min() > 0.99 * RPM  # ran up again
    assert (free.impact_cusp == 1).sum() == 3 and free.complete


def test_one_blade_pulse_rings_the_first_mode_of_the_agulhas_line():
    """The failing link of the §6.2 maximum (docs/shaft.md §6): case-1 pulses (0.75 Q over 90°, one per
    blade passage at 9.33 Hz) ring the line's 7.76 Hz mode. Small pulses (linear range): the station torque
    above the mean reaches 1.1–1.3 × the pulse peak for one pulse and ≥ 1.7 × for a train of three, while
    a rigid line, without that mode, passes less than the pulse peak to the intermediate shaft."""
    base = load_shaft_line("agulhas_ii")
    drive, line = drive_for_line(base), with_operating_point(base, None, 105e3)

    def amplification(n_impacts, rigid):
        train = train_from_line(line, "intermediate_shaft", rigid=rigid)
        r = simulate_drive(train, drive, [1.0], [n_impacts], lambda c, rpm: 20e3, mean_torque_n_m=105e3)
        return (r.shaft_torque_n_m.max() - 105e3) / (0.75 * 20e3)

    assert 1.1 < amplification(1, False) < 1.3
    assert amplification(3, False) >= 1.7
    assert amplification(3, True) < 0.9
