"""Ship surge in ice: speed and time along the transit from the longitudinal ice force (docs/model.md,
"Ship surge").

The contact and failure models are quasi-static (no speed or strain-rate term), so the ice force at a bow
position does not depend on how fast the bow got there: the stepping loop runs as before and the surge is
computed afterwards, exactly, from the force series. With x the bow position and E = ½·m·V² the kinetic
energy (m the effective mass),

    dE/dx = m·V·dV/dx = T_net(V) − F_ice(x),        t(x) = ∫ dx / V,

regular at V = 0 (where dV/dx is not): the ship is stuck where E reaches 0, which needs F_ice above the
bollard pull T_net(0).

**The force series.** At every step k the engine evaluates the pieces in contact at x_k; a failing piece is
replaced by its pieces, evaluated again at x_k. So the force at x_k has two values: on arrival (the pieces
present before the step's breaks, each at its first evaluation: the load that breaks them) and after the
breaks (the evaluations that did not fail). Between x_(k−1) and x_k the force is taken as rising linearly
from the one after the breaks at x_(k−1) to the one on arrival at x_k (second order in the step). A piece's
longitudinal force is Σ F_h,i·n_x,i over its panel rows (the horizontal panel forces along the panels'
outward normals, as the contact model sums them).
"""

from __future__ import annotations

from array import array
from dataclasses import dataclass

import numpy as np

from floebreak.ship.propulsion import Propulsion, net_thrust_n


def longitudinal_ice_force_n(
    n_steps: int,
    step: np.ndarray,
    piece_id: np.ndarray,
    panel: np.ndarray,
    f_h_n: np.ndarray,
    failed: np.ndarray,
    parent_piece_id: np.ndarray,
    panel_normal_x: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The longitudinal ice force on the bow at each step [N] (positive: against the ship's motion), on
    arrival and after the step's breaks (module docstring).

    Rows are contact records (one per floe–panel pair of an evaluation:
    `floebreak.engine.records.CONTACT_COLUMNS`);
    `failed`: the row's evaluation broke the piece or took it out of the field; `parent_piece_id` per piece
    of the run (−1 for initial floes); `panel_normal_x`: x of each panel's outward unit normal.
    """
    step = np.asarray(step, dtype=np.int64)
    piece_id = np.asarray(piece_id, dtype=np.int64)
    failed = np.asarray(failed, dtype=bool)
    force_x = np.asarray(f_h_n, dtype=float) * np.asarray(panel_normal_x, dtype=float)[np.asarray(panel)]
    # the step at which each piece was born: its parent's failed evaluation (−1: an initial floe)
    never = -1
    break_step = np.full(len(parent_piece_id), never, dtype=np.int64)
    break_step[piece_id[failed]] = step[failed]
    parents = np.asarray(parent_piece_id, dtype=np.int64)
    born = np.where(parents >= 0, break_step[np.maximum(parents, 0)], never)
    on_arrival = born[piece_id] != step
    arrival = np.bincount(step[on_arrival], weights=force_x[on_arrival], minlength=n_steps)
    after = np.bincount(step[~failed], weights=force_x[~failed], minlength=n_steps)
    return arrival[:n_steps], after[:n_steps]


@dataclass(frozen=True, eq=False)
class SurgeResult:
    """Speed and time of the ship along its transit; arrays per step reached (and the stop, if stuck)."""

    bow_x_m: np.ndarray
    time_s: np.ndarray
    speed_m_s: np.ndarray
    ice_force_x_n: np.ndarray  # on arrival at bow_x_m
    ice_force_x_after_breaks_n: np.ndarray
    stuck: bool
    stuck_at_bow_x_m: float | None
    mean_ice_resistance_n: float  # time average of the ice force over the transit sailed
    ice_work_per_metre_n: float  # distance average: the work against the ice per metre

    def summary(self) -> dict:
        distance = float(self.bow_x_m[-1] - self.bow_x_m[0])
        duration = float(self.time_s[-1] - self.time_s[0])
        return {
            "stuck": self.stuck,
            "stuck_at_bow_x_m": self.stuck_at_bow_x_m,
            "mean_ice_resistance_n": self.mean_ice_resistance_n,
            "ice_work_per_metre_n": self.ice_work_per_metre_n,
            "distance_m": distance,
            "transit_time_s": duration,
            "mean_speed_m_s": distance / duration if duration > 0.0 else 0.0,
            "min_speed_m_s": float(self.speed_m_s.min()),
            "final_speed_m_s": float(self.speed_m_s[-1]),
            "max_ice_force_x_n": float(self.ice_force_x_n.max(initial=0.0)),
        }


def _energy_step(
    propulsion: Propulsion, mass_kg: float, energy_j: float, h_m: float, force0_n: float, slope_n_m: float
) -> float:
    """E after advancing `h_m` from E = `energy_j` under the force F(s) = force0 + slope·s: one classical
    Runge–Kutta step of dE/dx = T_net(V(E)) − F (E < 0 on the way counts as rest)."""

    def rate(energy: float, s: float) -> float:
        speed = np.sqrt(2.0 * max(energy, 0.0) / mass_kg)
        return float(net_thrust_n(propulsion, speed)) - (force0_n + slope_n_m * s)

    k1 = rate(energy_j, 0.0)
    k2 = rate(energy_j + 0.5 * h_m * k1, 0.5 * h_m)
    k3 = rate(energy_j + 0.5 * h_m * k2, 0.5 * h_m)
    k4 = rate(energy_j + h_m * k3, h_m)
    return energy_j + h_m * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0


class SurgeIntegrator:
    """The ship's speed and time advanced one step of the transit at a time (`integrate_surge`, and the
    stepping loop under ``simulation.ice_motion = "dynamic"``, whose engine needs the speed of each interval
    before it runs it: docs/model.md, "Ship surge").

    Per step, `substeps` Runge–Kutta steps of the energy equation; a stop inside a step is located by
    Brent's method on the energy. Time per substep: Δt = 2·Δx/(V_a + V_b), exact under constant
    deceleration (V² linear in x), which keeps it finite at a stop.
    """

    def __init__(
        self,
        propulsion: Propulsion,
        initial_speed_m_s: float,
        bow_x0_m: float,
        force_arrival0_n: float = 0.0,
        substeps: int = 4,
    ):
        self.propulsion, self.substeps = propulsion, substeps
        self.mass_kg = propulsion.effective_mass_kg
        self.energy_j = 0.5 * self.mass_kg * initial_speed_m_s**2
        # typed arrays: 8 bytes a value, not a list slot and a float object (a series per contact search)
        self._x, self._speeds = array("d", [bow_x0_m]), array("d", [initial_speed_m_s])
        self._times, self._arrival = array("d", [0.0]), array("d", [force_arrival0_n])
        self._after = array("d")
        self.impulse_n_s = 0.0  # ∫ F dt
        self.stuck_at_bow_x_m: float | None = None

    @property
    def speed_m_s(self) -> float:
        """The speed at the last position reached (0 once stuck)."""
        return self._speeds[-1]

    def advance(self, bow_x_m: float, force_after_n: float, force_arrival_n: float) -> bool:
        """Sail from the last position reached to `bow_x_m` under a force rising linearly from
        `force_after_n` (after the breaks there) to `force_arrival_n` (on arrival at `bow_x_m`); False (and
        the stop recorded) if the ship stops on the way."""
        propulsion, mass, x_prev = self.propulsion, self.mass_kg, self._x[-1]
        dx = bow_x_m - x_prev
        slope = (force_arrival_n - force_after_n) / dx
        f0, h = force_after_n, dx / self.substeps
        t, v, energy = self._times[-1], self._speeds[-1], self.energy_j
        self._after.append(force_after_n)
        for j in range(self.substeps):
            s0 = j * h
            f_a = f0 + slope * s0
            new = _energy_step(propulsion, mass, energy, h, f_a, slope)
            if new <= 0.0:
                self._stop(energy, v, t, f_a, slope, s0, h, (x_prev, bow_x_m, force_arrival_n))
                return False
            v_new = float(np.sqrt(2.0 * new / mass))
            dt = 2.0 * h / (v + v_new)
            self.impulse_n_s += 0.5 * (2.0 * f_a + slope * h) * dt
            t, v, energy = t + dt, v_new, new
        self.energy_j = energy
        self._x.append(bow_x_m)
        self._speeds.append(v)
        self._times.append(t)
        self._arrival.append(force_arrival_n)
        return True

    def _stop(self, energy, v, t, f_a, slope, s0, h, step) -> None:
        """Locate the stop inside the substep starting at `s0` and record it as the last point."""
        from scipy.optimize import brentq

        x_prev, x_next, force_arrival_n = step
        length = brentq(
            lambda s: _energy_step(self.propulsion, self.mass_kg, energy, s, f_a, slope), 0.0, h, xtol=1e-9
        )
        dt = 2.0 * length / v
        self.impulse_n_s += 0.5 * (2.0 * f_a + slope * length) * dt
        stuck_at = float(x_prev + s0 + length)
        # the force where the ship stops: the linear rise towards the next position
        fraction = (stuck_at - x_prev) / (x_next - x_prev)
        after = self._after[-1]
        at_stop = after + fraction * (force_arrival_n - after)
        self.stuck_at_bow_x_m, self.energy_j = stuck_at, 0.0
        self._x.append(stuck_at)
        self._speeds.append(0.0)
        self._times.append(t + dt)
        self._arrival.append(at_stop)
        self._after.append(at_stop)

    def result(self, force_after_last_n: float = 0.0) -> SurgeResult:
        """The surge so far; `force_after_last_n`: the force after the breaks at the last position reached
        (not used once stuck, where the series ends at the stop)."""
        after = self._after if self.stuck_at_bow_x_m is not None else [*self._after, force_after_last_n]
        positions = np.array(self._x, dtype=float)
        arrival, after = np.array(self._arrival, dtype=float), np.array(after, dtype=float)
        work = float(np.sum(0.5 * (after[:-1] + arrival[1:]) * np.diff(positions)))
        distance, duration = positions[-1] - positions[0], self._times[-1]
        return SurgeResult(
            bow_x_m=positions,
            time_s=np.array(self._times),
            speed_m_s=np.array(self._speeds),
            ice_force_x_n=arrival,
            ice_force_x_after_breaks_n=after,
            stuck=self.stuck_at_bow_x_m is not None,
            stuck_at_bow_x_m=self.stuck_at_bow_x_m,
            mean_ice_resistance_n=self.impulse_n_s / duration if duration > 0.0 else 0.0,
            ice_work_per_metre_n=work / distance if distance > 0.0 else 0.0,
        )


def integrate_surge(
    bow_x_m: np.ndarray,
    force_arrival_n: np.ndarray,
    force_after_n: np.ndarray,
    propulsion: Propulsion,
    initial_speed_m_s: float,
    substeps: int = 4,
) -> SurgeResult:
    """Speed and time along the transit x_0 < x_1 < … under the ice force series (module docstring;
    numerics: `SurgeIntegrator`)."""
    x = np.asarray(bow_x_m, dtype=float)
    surge = SurgeIntegrator(propulsion, initial_speed_m_s, x[0], force_arrival_n[0], substeps)
    for k in range(1, len(x)):
        if not surge.advance(x[k], force_after_n[k - 1], force_arrival_n[k]):
            break
    return surge.result(force_after_n[len(x) - 1])
