"""The drive reacts: shaft speed under ice torque with a torque-limited, PI speed-controlled motor.

Nonlinear time-domain model of the shaft line (docs/shaft.md, "Drive dynamics and resonance margin"):
inertias J_i from the motor (0) to the propeller (last), joined by shafts k_i, c_i (`ShaftLine`), or one
rigid inertia (motor + shafts + propeller with entrained water):

    J_0 ω̇_0 = Q_motor − T_0,   J_i ω̇_i = T_{i−1} − T_i,   J_p ω̇_p = T_{p−1} − Q_hydro − Q_ice
    T_i = k_i (θ_i − θ_{i+1}) + c_i (ω_i − ω_{i+1})      (rigid: J ω̇ = Q_motor − Q_hydro − Q_ice)
    Q_motor = clip(K_p (ω_set − ω_0) + q_I, −Q_limit, Q_limit),   q̇_I = K_i (ω_set − ω_0)
    Q_hydro = c_h ω_p |ω_p|,   c_h = Q_mean / ω_set²

Anti-windup by conditional integration: q_I stops while Q_motor is clipped and the error drives it further
into the limit. The PI gains default to the pole placement K_p = 2 ζ_g ω_g J_tot, K_i = ω_g² J_tot: the
controller spring and damper of the linear model (`shaft.line.assembly`), so that for small ice torques this
model reduces to the linear one (the small-signal check in the tests).

Ice: cusps in arrival order, one at a time (a cusp arriving while another is milled waits, as
`excitation.milling_starts`). A cusp's first impact is at the first blade passage (propeller angle a multiple
of 2π/Z) at or after its arrival and after the previous cusp's last passage; its impacts follow at the next
passages, so they come later when the propeller slows. Each impact is the excitation case's pulse over α_i
of propeller rotation (`excitation.EXCITATION_CASES`): Q = C_q · Q_imp · sin(π (φ_p − φ_k)/α_i), with
Q_imp = `impact_torque_n_m(cusp_index, rpm)` at the passage's rpm. Ice torque resists the rotation only: at
ω_p ≤ 0 it is a reaction no larger than the torque that would turn the propeller forward (the propeller
stalls instead of reversing).

Integration: classical Runge–Kutta (4th order) at a fixed step, compiled with numba, stopping at each blade
passage so that the schedule (which cusp, which amplitude) is decided in Python at the passage's time and
rpm. The step resolves a pulse at the set speed with `points_per_pulse` (≥ 20) points and the line's highest
natural frequency with 20 points per period.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numba
import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.spec import MAX_PROPELLER_RPM
from floebreak.shaft.excitation import ExcitationCase, excitation_case
from floebreak.shaft.line import ShaftLine

# Momentary excess torque of 60 % for 15 s (polyphase induction motors): IEC 60034-1 §9.4 [recalled,
# medium]; the converter limit of the Agulhas II drive is not public and assumed equal.
DEFAULT_OVERLOAD_FACTOR = 1.6
MIN_POINTS_PER_PULSE = 20
POINTS_PER_PERIOD = 20  # of the highest natural frequency (RK4 phase error < 0.1 % per period)
_CROSSING, _END, _FULL, _STALL = 1, 0, 2, 3


@dataclass(frozen=True)
class MotorDrive:
    """Electric motor with a torque limit and a PI speed controller (module docstring)."""

    rpm_set: float
    torque_limit_n_m: float
    kp_n_m_s_per_rad: float
    ki_n_m_per_rad: float

    def __post_init__(self):
        require_range("rpm_set", self.rpm_set, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
        require_range("torque_limit_n_m", self.torque_limit_n_m, low=0.0, unit="N m")
        require_range("kp_n_m_s_per_rad", self.kp_n_m_s_per_rad, low=0.0, low_inclusive=True, unit="N m s")
        require_range("ki_n_m_per_rad", self.ki_n_m_per_rad, low=0.0, low_inclusive=True, unit="N m")
        if not (math.isfinite(self.kp_n_m_s_per_rad) and math.isfinite(self.ki_n_m_per_rad)):
            raise InputError("kp_n_m_s_per_rad", "controller gains must be finite", allowed="finite ≥ 0")

    @property
    def omega_set_rad_s(self) -> float:
        return 2.0 * math.pi * self.rpm_set / 60.0


@dataclass(frozen=True)
class DriveTrain:
    """Inertias [kg·m²] motor first, shafts between them [N·m/rad, N·m·s/rad]; one inertia = rigid.

    `station` is the shaft whose torque is output (rigid: Q_motor − J_up ω̇, J_up the inertia on the motor
    side of the station)."""

    inertias_kg_m2: tuple[float, ...]
    stiffnesses_n_m_per_rad: tuple[float, ...] = ()
    damping_n_m_s_per_rad: tuple[float, ...] = ()
    station: int = 0
    station_name: str = "shaft"
    upstream_inertia_kg_m2: float = 0.0

    def __post_init__(self):
        for i, j in enumerate(self.inertias_kg_m2):
            require_range(
                f"inertias_kg_m2[{i}]" if len(self.inertias_kg_m2) > 1 else "inertia_kg_m2",
                j,
                low=0.0,
                unit="kg m^2",
            )
        n = len(self.inertias_kg_m2)
        if n < 1 or len(self.stiffnesses_n_m_per_rad) != n - 1 or len(self.damping_n_m_s_per_rad) != n - 1:
            raise InputError("inertias_kg_m2", "n inertias need n − 1 stiffnesses and dampings")
        for i, k in enumerate(self.stiffnesses_n_m_per_rad):
            require_range(f"stiffnesses_n_m_per_rad[{i}]", k, low=0.0, unit="N m/rad")
        for i, c in enumerate(self.damping_n_m_s_per_rad):
            require_range(f"damping_n_m_s_per_rad[{i}]", c, low=0.0, low_inclusive=True, unit="N m s/rad")

    @property
    def total_inertia_kg_m2(self) -> float:
        return float(sum(self.inertias_kg_m2))

    def highest_natural_frequency_hz(self) -> float:
        """Of the free-free chain (0 for one inertia): eigenvalues of J⁻¹K."""
        n = len(self.inertias_kg_m2)
        if n == 1:
            return 0.0
        k = np.zeros((n, n))
        for i, s in enumerate(self.stiffnesses_n_m_per_rad):
            k[i : i + 2, i : i + 2] += s * np.array([[1.0, -1.0], [-1.0, 1.0]])
        lam = np.linalg.eigvals(k / np.asarray(self.inertias_kg_m2)[:, None])
        return float(np.sqrt(max(np.real(lam).max(), 0.0)) / (2.0 * math.pi))


def rigid_train(inertia_kg_m2: float, upstream_inertia_kg_m2: float = 0.0) -> DriveTrain:
    """One inertia: motor + shafts + propeller with entrained water [kg·m²]."""
    return DriveTrain((inertia_kg_m2,), upstream_inertia_kg_m2=float(upstream_inertia_kg_m2))


def train_from_line(line: ShaftLine, station: str | None = None, *, rigid: bool = False) -> DriveTrain:
    """The line's inertias (propeller with entrained water), stiffnesses and shaft dampers; `rigid` lumps
    them into one inertia (the station torque then follows from the motor side's inertia)."""
    i = line.station_index(station)
    j = line.inertias_kg_m2
    if rigid:
        return DriveTrain(
            (float(j.sum()),),
            station=i,
            station_name=line.stations[i],
            upstream_inertia_kg_m2=float(j[: i + 1].sum()),
        )
    return DriveTrain(
        tuple(map(float, j)),
        tuple(map(float, line.stiffnesses_n_m_per_rad)),
        tuple(map(float, line.damping_n_m_s_per_rad)),
        station=i,
        station_name=line.stations[i],
    )


def drive_for_line(
    line: ShaftLine,
    *,
    rated_torque_n_m: float | None = None,
    overload_factor: float = DEFAULT_OVERLOAD_FACTOR,
    rpm: float | None = None,
) -> MotorDrive:
    """The line's motor: set speed = the line's rpm, Q_limit = overload factor × rated torque (default
    P_rated/(2π n)), PI gains by pole placement on the whole line's inertia at the line's speed-control
    bandwidth ω_g and damping ratio ζ_g: K_p = 2 ζ_g ω_g J_tot, K_i = ω_g² J_tot (module docstring)."""
    rpm_set = line.rpm if rpm is None else rpm
    if rated_torque_n_m is None:
        if line.rated_power_w is None:
            raise InputError(
                "rated_torque_n_m", "the line has no rated power: give the rated torque", allowed="> 0 N m"
            )
        rated_torque_n_m = line.rated_power_w / (2.0 * math.pi * line.rpm / 60.0)
    require_range("rated_torque_n_m", rated_torque_n_m, low=0.0, unit="N m")
    require_range("overload_factor", overload_factor, low=0.0)
    omega_g = 2.0 * math.pi * line.speed_control_bandwidth_hz
    j_total = float(line.inertias_kg_m2.sum())
    return MotorDrive(
        rpm_set=rpm_set,
        torque_limit_n_m=overload_factor * rated_torque_n_m,
        kp_n_m_s_per_rad=2.0 * line.speed_control_damping_ratio * omega_g * j_total,
        ki_n_m_per_rad=omega_g**2 * j_total,
    )


@numba.njit(cache=True, nogil=True)
def _derivative(x, n, inertia, stiffness, damping, par, pulse_start, pulse_amp, dx, torques):
    """dx/dt of x = (θ_0..θ_p, ω_0..ω_p, q_I); torques = (Q_motor, Q_hydro, Q_ice). par = (ω_set, K_p, K_i,
    Q_limit, c_h, α_i [rad], rectangular)."""
    omega_set, kp, ki, q_limit, c_h, alpha, rectangular = par[:7]
    error = omega_set - x[n]
    q_cmd = kp * error + x[2 * n]
    q_motor = min(max(q_cmd, -q_limit), q_limit)
    windup = (q_cmd > q_limit and error > 0.0) or (q_cmd < -q_limit and error < 0.0)
    dx[2 * n] = 0.0 if windup else ki * error
    phi, omega_p = x[n - 1], x[2 * n - 1]
    q_ice = 0.0
    for j in range(pulse_start.size):
        s = phi - pulse_start[j]
        if 0.0 <= s < alpha:
            q_ice += pulse_amp[j] * (1.0 if rectangular > 0.0 else math.sin(math.pi * s / alpha))
    q_hydro = c_h * omega_p * abs(omega_p)
    into = q_motor
    for i in range(n - 1):
        shaft = stiffness[i] * (x[i] - x[i + 1]) + damping[i] * (x[n + i] - x[n + i + 1])
        dx[i] = x[n + i]
        dx[n + i] = (into - shaft) / inertia[i]
        into = shaft
    if omega_p <= 0.0:  # ice resists rotation only: a reaction up to the forward torque
        q_ice = min(q_ice, max(into - q_hydro, 0.0))
    dx[n - 1] = omega_p
    dx[2 * n - 1] = (into - q_hydro - q_ice) / inertia[n - 1]
    torques[0], torques[1], torques[2] = q_motor, q_hydro, q_ice


@numba.njit(cache=True, nogil=True)
def _advance(
    x,
    step,
    step_end,
    dt,
    phi_next,
    n,
    inertia,
    stiffness,
    damping,
    par,
    station,
    j_up,
    pulse_start,
    pulse_amp,
    out,
    row,
    watch_stall,
):
    """RK4 steps from `step` until `step_end`, the buffer `out` is full, or a step would carry the propeller
    past the angle `phi_next` (then that step is not taken). Each step records the state before it in
    out[row] = (ω_motor, ω_prop, Q_motor, Q_hydro, Q_ice, station torque). With `watch_stall`, also
    returns after the step in which the propeller came to a stop.
    Returns (status, step, row, crossing time, propeller speed at the crossing)."""
    m = x.size
    k1, k2, k3, k4 = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    y, torques, dummy = np.empty(m), np.empty(3), np.empty(3)
    while step < step_end:
        if row >= out.shape[0]:
            return 2, step, row, 0.0, 0.0
        _derivative(x, n, inertia, stiffness, damping, par, pulse_start, pulse_amp, k1, torques)
        for i in range(m):
            y[i] = x[i] + 0.5 * dt * k1[i]
        _derivative(y, n, inertia, stiffness, damping, par, pulse_start, pulse_amp, k2, dummy)
        for i in range(m):
            y[i] = x[i] + 0.5 * dt * k2[i]
        _derivative(y, n, inertia, stiffness, damping, par, pulse_start, pulse_amp, k3, dummy)
        for i in range(m):
            y[i] = x[i] + dt * k3[i]
        _derivative(y, n, inertia, stiffness, damping, par, pulse_start, pulse_amp, k4, dummy)
        for i in range(m):
            y[i] = x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        if y[n - 1] >= phi_next:
            frac = (phi_next - x[n - 1]) / (y[n - 1] - x[n - 1]) if y[n - 1] > x[n - 1] else 0.0
            return 1, step, row, (step + frac) * dt, x[2 * n - 1] + frac * (y[2 * n - 1] - x[2 * n - 1])
        out[row, 0], out[row, 1] = x[n], x[2 * n - 1]
        out[row, 2], out[row, 3], out[row, 4] = torques[0], torques[1], torques[2]
        if n > 1:
            s = station
            out[row, 5] = stiffness[s] * (x[s] - x[s + 1]) + damping[s] * (x[n + s] - x[n + s + 1])
        else:
            out[row, 5] = torques[0] - j_up * k1[n]
        for i in range(m):
            x[i] = y[i]
        step += 1
        row += 1
        if x[2 * n - 1] < 0.0:  # no reverse rotation (the ice holds the blade)
            x[2 * n - 1] = 0.0
            if watch_stall:
                return 3, step, row, 0.0, 0.0
    return 0, step, row, 0.0, 0.0


@dataclass(frozen=True)
class DriveResult:
    """Time series of `simulate_drive` (uniform step `dt_s`; each row is the state before that step)."""

    drive: MotorDrive
    station: str
    dt_s: float
    time_s: np.ndarray
    rpm: np.ndarray  # propeller
    motor_rpm: np.ndarray
    motor_torque_n_m: np.ndarray
    hydro_torque_n_m: np.ndarray
    ice_torque_n_m: np.ndarray  # as applied (a stalled propeller's ice torque is the reaction)
    shaft_torque_n_m: np.ndarray  # at `station`, positive when the shaft drives the propeller
    milled_cusp: np.ndarray  # per sample: index (input order) of the cusp being milled, −1 for none
    milling_start_s: np.ndarray  # per cusp (input order): its first impact's passage; NaN if never milled
    milling_end_s: np.ndarray  # the passage after its last impact; NaN if not reached
    impact_time_s: np.ndarray  # per impact (blade passage), in time order
    impact_cusp: np.ndarray
    impact_torque_n_m: np.ndarray  # peak of the pulse: C_q · impact_torque_n_m(cusp, rpm)
    impact_rpm: np.ndarray  # propeller rpm at the passage
    complete: bool  # every impact of every cusp started within the run
    stalled_at_s: float = math.nan  # when the propeller first came to a stop held by the ice (NaN: never)
    # every stop, once per blade passage (free blocks: the run goes on after each)
    stop_times_s: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def summary(self) -> dict[str, float]:
        """Extremes [rpm, N·m] and the time spent at the torque limit and at standstill [s]."""
        limit = self.drive.torque_limit_n_m
        at_limit = np.abs(self.motor_torque_n_m) >= limit * (1.0 - 1e-9)
        return {
            "min_rpm": float(self.rpm.min()),
            "max_rpm": float(self.rpm.max()),
            "peak_motor_torque_n_m": float(self.motor_torque_n_m.max()),
            "min_motor_torque_n_m": float(self.motor_torque_n_m.min()),
            "peak_shaft_torque_n_m": float(self.shaft_torque_n_m.max()),
            "min_shaft_torque_n_m": float(self.shaft_torque_n_m.min()),
            "peak_ice_torque_n_m": float(self.ice_torque_n_m.max()),
            "time_at_torque_limit_s": float(at_limit.sum() * self.dt_s),
            "time_stalled_s": float((self.rpm <= 0.0).sum() * self.dt_s),
            "stalled_at_s": self.stalled_at_s,
            "stops": int(self.stop_times_s.size),
        }

    def stall(self) -> dict | None:
        """The first stop (None: never): its time [s], the cusp milled then (input order), how many of
        that cusp's impacts had started, and their mean peak C_q·Q_imp [N·m] (from which
        `floebreak.shaft.analysis.drive_case_summary` gives the case's mean ice torque per passage)."""
        if not math.isfinite(self.stalled_at_s):
            return None
        row = min(round(self.stalled_at_s / self.dt_s) - 1, self.milled_cusp.size - 1)
        cusp = int(self.milled_cusp[max(row, 0)])
        mine = (self.impact_cusp == cusp) & (self.impact_time_s <= self.stalled_at_s)
        return {
            "time_s": self.stalled_at_s,
            "cusp": cusp,
            "impacts_of_cusp": int(mine.sum()),
            "mean_impact_peak_n_m": float(self.impact_torque_n_m[mine].mean()) if mine.any() else math.nan,
        }


def _cusp_inputs(arrival_s, n_impacts):
    arrival = np.asarray(arrival_s, dtype=float).reshape(-1)
    if not np.all(np.isfinite(arrival)) or np.any(arrival < 0.0):
        raise InputError("arrival_s", "arrival times must be finite and ≥ 0 s", allowed="finite ≥ 0 s")
    raw = np.asarray(n_impacts).reshape(-1)
    if raw.shape != arrival.shape:
        raise InputError("n_impacts", f"{raw.size} values for {arrival.size} cusps")
    if raw.size and (
        not np.all(np.isfinite(raw.astype(float))) or np.any(raw != np.rint(raw)) or raw.min() < 1
    ):
        raise InputError("n_impacts", "impacts per cusp must be integers ≥ 1", allowed="integers ≥ 1")
    return arrival, raw.astype(np.int64)


def _time_step_s(train: DriveTrain, drive: MotorDrive, alpha_deg: float, points_per_pulse: int) -> float:
    if int(points_per_pulse) != points_per_pulse or points_per_pulse < MIN_POINTS_PER_PULSE:
        raise InputError(
            "points_per_pulse",
            f"{points_per_pulse!r}",
            value=points_per_pulse,
            allowed=f"an integer ≥ {MIN_POINTS_PER_PULSE}",
        )
    pulse_s = alpha_deg / 360.0 * 60.0 / drive.rpm_set
    dt = pulse_s / points_per_pulse
    f_max = train.highest_natural_frequency_hz()
    return min(dt, 1.0 / (POINTS_PER_PERIOD * f_max)) if f_max > 0.0 else dt


class _Schedule:
    """Which cusp is milled and which impacts start, decided at each blade passage (module docstring)."""

    def __init__(self, arrival, n_impacts, torque_fn, spec, blades, rectangular):
        self.order = np.argsort(arrival, kind="stable")
        self.arrival, self.n_imp = arrival[self.order], n_impacts[self.order]
        self.torque_fn, self.spec, self.blades = torque_fn, spec, blades
        self.alpha = math.radians(spec.alpha_deg)
        self.rectangular = rectangular
        self.next_cusp, self.current, self.done = 0, -1, 0
        self.start_s = np.full(arrival.size, np.nan)
        self.end_s = np.full(arrival.size, np.nan)
        self.impacts: list[tuple[float, int, float, float]] = []
        self.pulse_start: list[float] = []
        self.pulse_amp: list[float] = []

    @property
    def finished(self) -> bool:
        return self.next_cusp == self.arrival.size and (
            self.current < 0 or self.done == self.n_imp[self.current]
        )

    def passage(self, m: int, time_s: float, omega_rad_s: float) -> None:
        """Blade passage m (propeller angle 2π m/Z) at `time_s`: close a finished cusp, start the next one if
        it has arrived, and start the current cusp's next impact."""
        if self.current >= 0 and self.done == self.n_imp[self.current]:
            self.end_s[self.current], self.current = time_s, -1
        if self.current < 0 and self.next_cusp < self.arrival.size:
            if self.arrival[self.next_cusp] <= time_s + 1e-9:
                self.current, self.done = self.next_cusp, 0
                self.start_s[self.current] = time_s
                self.next_cusp += 1
        if self.current < 0:
            return
        rpm = omega_rad_s * 60.0 / (2.0 * math.pi)
        cusp = int(self.order[self.current])
        value = float(self.torque_fn(cusp, rpm))
        if not math.isfinite(value):
            raise InputError(
                "impact_torque_n_m",
                f"{value!r} for cusp {cusp} at {rpm:g} rpm",
                allowed="a finite torque [N m]",
            )
        amplitude = self.spec.c_q * abs(value)
        phi = 2.0 * math.pi * m / self.blades
        for block in range(self.spec.blocks):  # a second block shifted by 360°/(2Z) (case 3)
            self.pulse_start.append(phi + block * math.pi / self.blades)
            self.pulse_amp.append(amplitude)
        self.impacts.append((time_s, cusp, amplitude, rpm))
        self.done += 1

    def release(self) -> None:
        """A free block cannot hold a stopped blade (the motor's torque pushes it out of the way): the
        current cusp's pulses end and its remaining impacts are dropped."""
        if self.current >= 0:
            self.done = int(self.n_imp[self.current])
        self.pulse_start, self.pulse_amp = [], []

    def active_pulses(self, phi_now: float) -> tuple[np.ndarray, np.ndarray]:
        """The pulses not yet over at the propeller angle `phi_now` (older ones dropped)."""
        keep = [i for i, s in enumerate(self.pulse_start) if s + self.alpha > phi_now]
        self.pulse_start = [self.pulse_start[i] for i in keep]
        self.pulse_amp = [self.pulse_amp[i] for i in keep]
        return np.array(self.pulse_start, dtype=float), np.array(self.pulse_amp, dtype=float)


def _initial_state(train: DriveTrain, drive: MotorDrive, mean_torque_n_m: float) -> np.ndarray:
    """Steady running at the set speed under the mean torque: every shaft twisted by Q_mean/k_i, the
    propeller at angle 0 (a blade passage), the integrator holding Q_mean."""
    n = len(train.inertias_kg_m2)
    twist = mean_torque_n_m / np.asarray(train.stiffnesses_n_m_per_rad, dtype=float)
    theta = np.concatenate([np.cumsum(twist[::-1])[::-1], [0.0]]) if n > 1 else np.zeros(1)
    return np.concatenate([theta, np.full(n, drive.omega_set_rad_s), [mean_torque_n_m]])


def _check_options(impact_torque_n_m, pulse, blades, case, tail_s) -> ExcitationCase:
    if not callable(impact_torque_n_m):
        raise InputError("impact_torque_n_m", "must be a function (cusp_index, rpm) -> torque [N m]")
    if pulse not in ("half_sine", "rectangular"):
        raise InputError("pulse", f"unknown shape {pulse!r}", allowed="half_sine, rectangular")
    if isinstance(blades, bool) or int(blades) != blades or blades < 1:
        raise InputError("blades", f"{blades!r} is not a positive integer", value=blades)
    require_range("tail_s", tail_s, low=0.0, low_inclusive=True, unit="s")
    spec = case if isinstance(case, ExcitationCase) else excitation_case(case)
    require_range("excitation_case.alpha_deg", spec.alpha_deg, low=0.0, high=360.0)
    return spec


def _kernel_arguments(train: DriveTrain, drive: MotorDrive, q_mean: float, schedule: _Schedule) -> tuple:
    """(n, J, k, c, par, station, J_up) for `_advance`; par as `_derivative` reads it."""
    omega = drive.omega_set_rad_s
    par = np.array([omega, drive.kp_n_m_s_per_rad, drive.ki_n_m_per_rad, drive.torque_limit_n_m])
    par = np.concatenate([par, [q_mean / omega**2, schedule.alpha, float(schedule.rectangular)]])
    return (
        len(train.inertias_kg_m2),
        np.asarray(train.inertias_kg_m2, float),
        np.asarray(train.stiffnesses_n_m_per_rad, float),
        np.asarray(train.damping_n_m_s_per_rad, float),
        par,
        train.station,
        train.upstream_inertia_kg_m2,
    )


def simulate_drive(
    train: DriveTrain,
    drive: MotorDrive,
    arrival_s,
    n_impacts,
    impact_torque_n_m: Callable[[int, float], float],
    *,
    mean_torque_n_m: float,
    blades: int = 4,
    case: int | ExcitationCase = 1,
    pulse: str = "half_sine",
    points_per_pulse: int = 40,
    tail_s: float = 5.0,
    duration_s: float | None = None,
    free_blocks: bool = False,
) -> DriveResult:
    """Shaft speed and torques while the propeller mills the cusps (module docstring).

    `arrival_s`: per cusp, when it reaches the propeller [s]; `n_impacts`: blade impacts per cusp (≥ 1);
    `impact_torque_n_m(cusp_index, rpm)`: the impact torque of that cusp (index in input order) at the
    propeller's rpm at the blade passage [N·m] (its magnitude, times the case's C_q, is the pulse peak);
    `mean_torque_n_m`: hydrodynamic torque at the set speed (calibrates Q_hydro ∝ ω²); `case`: a rule case
    number (`EXCITATION_CASES`) or an `ExcitationCase`; `pulse`: "half_sine" or "rectangular" (C_q Q_imp
    over α_i). The run ends `tail_s` after the last impact starts or after the propeller stalls (the ice
    holding it against the torque limit: `stalled_at_s`), or at `duration_s` if given. `free_blocks`: the
    cusps are free-floating blocks that cannot hold a stopped blade — at a stop the current cusp's pulses
    end and its remaining impacts are dropped (`_Schedule.release`), and the run goes on (`stalled_at_s`
    is the first stop).
    """
    spec = _check_options(impact_torque_n_m, pulse, blades, case, tail_s)
    q_mean = require_range("mean_torque_n_m", mean_torque_n_m, low=0.0, low_inclusive=True, unit="N m")
    arrival, n_imp = _cusp_inputs(arrival_s, n_impacts)
    dt = _time_step_s(train, drive, spec.alpha_deg, points_per_pulse)
    passage_s = 60.0 / (drive.rpm_set * blades)
    if duration_s is not None:
        cap = round(require_range("duration_s", duration_s, low=0.0, unit="s") / dt)
    else:
        last = arrival.max() if arrival.size else 0.0
        cap = math.ceil((last + 10.0 * (n_imp.sum() + 1) * passage_s + tail_s) / dt)
    schedule = _Schedule(arrival, n_imp, impact_torque_n_m, spec, int(blades), pulse == "rectangular")
    x = _initial_state(train, drive, q_mean)
    mech = _kernel_arguments(train, drive, q_mean, schedule)
    out = np.empty((min(cap, 1 << 16), 6))
    step, row, m, step_end, stalled_at, stops, stop_passages = 0, 0, 0, cap, math.nan, [], set()
    starts, amps = schedule.active_pulses(0.0)
    while True:
        status, step, row, t_cross, w_cross = _advance(
            x,
            step,
            step_end,
            dt,
            2.0 * math.pi * m / blades,
            *mech,
            starts,
            amps,
            out,
            row,
            free_blocks or math.isnan(stalled_at),
        )
        if status == _FULL:
            out = np.concatenate([out, np.empty((min(out.shape[0], cap - row), 6))])
        elif status == _END:
            break
        elif status == _STALL:
            if m not in stop_passages:  # once per blade passage (the line's ringing can stop it again)
                stops.append(step * dt)
                stop_passages.add(m)
            stalled_at = stops[0]
            if free_blocks:
                schedule.release()
                starts, amps = schedule.active_pulses(float(x[mech[0] - 1]))
            elif duration_s is None:
                step_end = min(step_end, step + math.ceil(tail_s / dt))
        else:
            schedule.passage(m, t_cross, w_cross)
            m += 1
            starts, amps = schedule.active_pulses(float(x[mech[0] - 1]))
            if duration_s is None and schedule.finished:
                step_end = min(step_end, math.ceil((t_cross + tail_s) / dt))
    return _result(schedule, drive, train, dt, out[:row], arrival.size, np.array(stops))


def _result(schedule: _Schedule, drive, train, dt, out, n_cusps, stops) -> DriveResult:
    to_rpm = 60.0 / (2.0 * math.pi)
    time = np.arange(out.shape[0]) * dt
    start, end = np.full(n_cusps, np.nan), np.full(n_cusps, np.nan)
    start[schedule.order], end[schedule.order] = schedule.start_s, schedule.end_s
    milled = np.full(time.size, -1, dtype=np.int64)
    started = np.flatnonzero(np.isfinite(schedule.start_s))  # in milling order = sorted order
    if started.size:
        k = np.searchsorted(schedule.start_s[started], time, side="right") - 1
        ends = np.where(np.isnan(schedule.end_s[started]), np.inf, schedule.end_s[started])
        inside = (k >= 0) & (time < ends[np.maximum(k, 0)])
        milled[inside] = schedule.order[started[k[inside]]]
    imp = np.array(schedule.impacts, dtype=float).reshape(-1, 4)
    return DriveResult(
        drive=drive,
        station=train.station_name,
        dt_s=dt,
        time_s=time,
        rpm=out[:, 1] * to_rpm,
        motor_rpm=out[:, 0] * to_rpm,
        motor_torque_n_m=out[:, 2].copy(),
        hydro_torque_n_m=out[:, 3].copy(),
        ice_torque_n_m=out[:, 4].copy(),
        shaft_torque_n_m=out[:, 5].copy(),
        milled_cusp=milled,
        milling_start_s=start,
        milling_end_s=end,
        impact_time_s=imp[:, 0],
        impact_cusp=imp[:, 1].astype(np.int64),
        impact_torque_n_m=imp[:, 2],
        impact_rpm=imp[:, 3],
        complete=schedule.finished,
        stalled_at_s=float(stops[0]) if stops.size else math.nan,
        stop_times_s=stops,
    )
