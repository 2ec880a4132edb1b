"""Time-domain shaft torque at a measurement station for a propeller load torque series (docs/shaft.md).

The line's state-space model x' = A x + B u (x = angles and speeds) comes from openTorsion
(``Assembly.state_space``), and its exact zero-order-hold discretisation x[k+1] = A_d x[k] + B_d u[k] from
``Assembly.continuous_2_discrete``. openTorsion's own time stepper ``Assembly.dsim`` is not used: it works
on the minimal (shaft-torque, speed) state, which cannot hold the motor's controller spring to ground;
it steps in a Python loop per sample and keeps the whole state history. (scipy.signal.dlsim/lsim loop per
sample in Python as well.) Instead A_d is diagonalised, A_d = V Λ V⁻¹, and each modal coordinate
z_j[k+1] = λ_j z_j[k] + (V⁻¹ B_d u)_j[k] is a first-order recursive filter run by scipy.signal.lfilter (in
C), in blocks of `BLOCK` samples carrying the filter state, so memory stays O(block).

The load torque Q(t) [N·m] acts against the rotation at the propeller (u = −Q at the last element). The
shaft torque at station i, k_i(θ_i − θ_{i+1}) + c_i(θ̇_i − θ̇_{i+1}), is positive when the shaft drives the
propeller. The simulation starts from the static equilibrium under Q[0], so a constant Q gives a constant
shaft torque Q (static gain 1).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve

from floebreak.errors import InputError, require_range
from floebreak.shaft.line import ShaftLine, assembly

BLOCK = 1 << 20


def station_torque_n_m(line: ShaftLine, load_torque_n_m, dt_s: float, station: str | None = None):
    """Shaft torque [N·m] at `station` for the propeller load torque series `load_torque_n_m` sampled
    every `dt_s` seconds (module docstring). Returns an array of the same length."""
    from scipy.signal import lfilter  # here: the drive model never calls it

    dt = require_range("dt_s", dt_s, low=0.0, unit="s")
    q = np.asarray(load_torque_n_m, dtype=float).reshape(-1)
    if not np.all(np.isfinite(q)):
        raise InputError("load_torque_n_m", "non-finite torque", allowed="finite values [N m]")
    i = line.station_index(station)
    asm = assembly(line, time_domain=True)
    n = line.inertias_kg_m2.size
    a, b, _, _ = asm.state_space()
    ad, bd = asm.continuous_2_discrete(a, b, dt)
    b_prop = -bd[:, n - 1]  # load torque acts against the rotation at the propeller
    k, c = line.stiffnesses_n_m_per_rad[i], line.damping_n_m_s_per_rad[i]
    out_row = np.zeros(2 * n)
    out_row[[i, i + 1]] = k, -k
    out_row[[n + i, n + i + 1]] = c, -c
    if q.size == 0:
        return q.copy()
    theta0 = solve(asm.K, np.eye(n)[:, n - 1] * -q[0])  # static equilibrium under Q[0]
    x0 = np.concatenate([theta0, np.zeros(n)])
    lam, vec = np.linalg.eig(ad)
    modal_in = np.linalg.solve(vec, b_prop)
    modal_out = out_row @ vec
    state = np.linalg.solve(vec, x0).astype(complex)
    # A_d is real: its complex modes come in conjugate pairs whose outputs are conjugate; one of each
    # pair, counted twice (real part), gives the real output at half the cost
    weight = np.where(np.abs(lam.imag) <= 1e-12 * np.abs(lam), 1.0, np.where(lam.imag > 0, 2.0, 0.0))
    modes = np.flatnonzero(weight)
    out = np.empty(q.size)
    for start in range(0, q.size, BLOCK):
        u = q[start : start + BLOCK].astype(complex)
        y = np.zeros(u.size)
        for j in modes:
            z, zf = lfilter([0.0, modal_in[j]], [1.0, -lam[j]], u, zi=[state[j]])
            y += weight[j] * np.real(modal_out[j] * z)
            state[j] = zf[0]
        out[start : start + u.size] = y
    return out
