"""Propeller load torque in time: mean hydrodynamic torque plus blade-impact ice torque (docs/shaft.md).

Each cusp reaches the propeller at t = t_lead + (x_bow − x_bow,first)/v (bow position x_bow when it broke
off, ship speed v; the constant bow-to-propeller delay is left out). It is milled in a sequence of
blade impacts starting at the first blade passage after its arrival, one per blade passage 1/(Z n), for
N_Q = 2 h revolutions (h: cusp thickness [m], at least one impact). Each impact has the rule's half-sine
shape (physics-notes §7.3, formulas **as recalled** from the FSICR/IACS UR I3 fatigue section):

    Q(φ) = C_q · Q_cusp · sin(φ · 180°/α_i)   for 0 ≤ φ ≤ α_i of propeller rotation, else 0

with Q_cusp the magnitude of the cusp's FEM torque. Cases: 1 (C_q 0.75, α_i 90°), 2 (1.0, 135°),
3 (0.5, 45°, two ice blocks: a second sequence shifted by 360°/(2Z)), 4 (0.5, 45°). The propeller mills one
cusp at a time: a cusp arriving while another is milled waits until that sequence ends (``overlap="queue"``,
the default; cusps broken at the same bow position would otherwise hit the blades simultaneously and their
torques add up to many times the largest FEM torque); ``overlap="superpose"`` lets sequences overlap and add.

The series is sampled at `samples_per_blade_passage` (≥ 20) points per blade passage, in float64, built
without a Python loop per sample (impacts are scattered with `numpy.bincount`, in blocks of
`IMPACT_BLOCK` impacts): 8 bytes per sample, e.g. 37 MB for a 3 h transit at 140 rpm, Z = 4, 40 points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.ruleform import rule_impacts_per_cusp
from floebreak.propeller.spec import MAX_PROPELLER_RPM

MIN_SAMPLES_PER_BLADE_PASSAGE = 20
IMPACT_BLOCK = 65_536
OVERLAP_POLICIES = ("queue", "superpose")


@dataclass(frozen=True)
class ExcitationCase:
    """One rule excitation case (physics-notes §7.3, as recalled)."""

    number: int
    c_q: float
    alpha_deg: float
    blocks: int


EXCITATION_CASES = {
    1: ExcitationCase(1, 0.75, 90.0, 1),
    2: ExcitationCase(2, 1.0, 135.0, 1),
    3: ExcitationCase(3, 0.5, 45.0, 2),
    4: ExcitationCase(4, 0.5, 45.0, 1),
}


def excitation_case(number) -> ExcitationCase:
    if number not in EXCITATION_CASES:
        raise InputError("excitation_case", f"no case {number!r}", value=number, allowed="1, 2, 3, 4")
    return EXCITATION_CASES[number]


def mean_torque_per_passage_n_m(peak_n_m, case: int | ExcitationCase, blades: int) -> np.ndarray:
    """The mean ice torque over one blade passage (360°/Z) of a steady impact train of the case [N·m]:
    blocks × peak × (2/π) × α_i/(360°/Z) (a half sine's mean is 2/π of its peak; pulses longer than a
    passage overlap and add). `peak_n_m`: C_q · Q_imp."""
    spec = case if isinstance(case, ExcitationCase) else excitation_case(case)
    return spec.blocks * np.asarray(peak_n_m, dtype=float) * (2.0 / math.pi) * spec.alpha_deg * blades / 360.0


def arrival_times_s(bow_x_m, speed_m_s: float, lead_s: float = 2.0) -> np.ndarray:
    """t = t_lead + (x_bow − min x_bow)/v [s] for each cusp (module docstring)."""
    speed = require_range("speed_m_s", speed_m_s, low=0.0, unit="m/s")
    x = np.asarray(bow_x_m, dtype=float).reshape(-1)
    if not np.all(np.isfinite(x)):
        raise InputError("bow_x_m", "non-finite bow position", allowed="finite positions [m]")
    return lead_s + (x - (x.min() if x.size else 0.0)) / speed


def impacts_per_cusp(thickness_m, blades: int) -> np.ndarray:
    """Z·N_Q blade impacts with N_Q = 2 h revolutions (h in m; physics-notes §7.3), at least 1."""
    return rule_impacts_per_cusp(thickness_m, blades)


def milling_starts(first_passage, n_impacts) -> np.ndarray:
    """Start passages when cusps (in arrival order) are milled one after another: a cusp's sequence
    starts at its first passage or when the previous sequence ends, whichever is later.

    end_i = max(a_i, end_{i−1}) + d_i has the closed form end_i = D_i + max_{j≤i}(a_j − D_{j−1}) with
    D_i = d_1 + … + d_i (a cumulative maximum: no loop over cusps).
    """
    a = np.asarray(first_passage, dtype=np.int64)
    d = np.asarray(n_impacts, dtype=np.int64)
    cum = np.cumsum(d)
    end = cum + np.maximum.accumulate(a - (cum - d))
    return end - d


def _cusp_arrays(arrival_s, torque_amplitude_n_m, thickness_m):
    """Validated per-cusp (arrival, |torque|, thickness), sorted by arrival (stable)."""
    arrival = np.asarray(arrival_s, dtype=float).reshape(-1)
    amplitude = np.abs(np.asarray(torque_amplitude_n_m, dtype=float).reshape(-1))
    if amplitude.shape != arrival.shape:
        raise InputError("torque_amplitude_n_m", f"{amplitude.size} values for {arrival.size} cusps")
    try:
        thickness = np.broadcast_to(np.asarray(thickness_m, dtype=float), arrival.shape)
    except ValueError:
        raise InputError("thickness_m", f"{np.size(thickness_m)} values for {arrival.size} cusps") from None
    if np.any(arrival < 0.0) or not np.all(np.isfinite(arrival)):
        raise InputError("arrival_s", "arrival times must be finite and ≥ 0 s", allowed="finite ≥ 0 s")
    if not np.all(np.isfinite(thickness) & (thickness >= 0.0)):
        raise InputError("thickness_m", "cusp thickness must be finite and ≥ 0 m", allowed="finite ≥ 0 m")
    amplitude = np.where(np.isfinite(amplitude), amplitude, 0.0)  # no load claimed ("flag" policy)
    order = np.argsort(arrival, kind="stable")
    return arrival[order], amplitude[order], thickness[order]


def _check(rpm, blades, samples_per_blade_passage) -> None:
    require_range("rpm", rpm, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
    if isinstance(blades, bool) or int(blades) != blades or blades < 1:
        raise InputError("blades", f"{blades!r} is not a positive integer", value=blades)
    if int(samples_per_blade_passage) != samples_per_blade_passage or (
        samples_per_blade_passage < MIN_SAMPLES_PER_BLADE_PASSAGE
    ):
        raise InputError(
            "samples_per_blade_passage",
            f"{samples_per_blade_passage!r}",
            value=samples_per_blade_passage,
            allowed=f"an integer ≥ {MIN_SAMPLES_PER_BLADE_PASSAGE}",
        )


def ice_torque_series(
    arrival_s,
    torque_amplitude_n_m,
    thickness_m,
    *,
    rpm: float,
    blades: int,
    case: int = 1,
    samples_per_blade_passage: int = 40,
    tail_s: float = 5.0,
    duration_s: float | None = None,
    overlap: str = "queue",
) -> tuple[np.ndarray, np.ndarray]:
    """(time [s], ice torque [N·m]) from plain per-cusp arrays (module docstring); time starts at 0.

    The series ends `tail_s` after the last impact, or at `duration_s` if given (impacts after it are cut).
    `overlap`: "queue" (a cusp arriving while another is milled waits for it: `milling_starts`) or
    "superpose" (sequences overlap and add).
    """
    _check(rpm, blades, samples_per_blade_passage)
    if overlap not in OVERLAP_POLICIES:
        raise InputError("overlap", f"unknown policy {overlap!r}", allowed=", ".join(OVERLAP_POLICIES))
    spec = excitation_case(case)
    arrival, amplitude, thickness = _cusp_arrays(arrival_s, torque_amplitude_n_m, thickness_m)
    s = int(samples_per_blade_passage)
    passage_rate_hz = blades * rpm / 60.0
    dt = 1.0 / (passage_rate_hz * s)
    n_imp = impacts_per_cusp(thickness, blades)
    first = np.ceil(arrival * passage_rate_hz - 1e-9).astype(np.int64)  # first passage after arrival
    if overlap == "queue":
        first = milling_starts(first, n_imp)
    first = first * s  # as sample index
    # impact starts: per cusp first + j·s for j < n_imp; a second block shifted by half a passage
    cusp = np.repeat(np.arange(arrival.size), n_imp)
    within = np.arange(cusp.size) - np.repeat(np.cumsum(n_imp) - n_imp, n_imp)
    starts = first[cusp] + within * s
    weights = spec.c_q * amplitude[cusp]
    if spec.blocks == 2:
        starts = np.concatenate([starts, starts + s // 2])
        weights = np.concatenate([weights, weights])
    width = spec.alpha_deg / 360.0 * blades * s  # impact length in samples (α_i of a revolution)
    k = np.arange(math.floor(width) + 1)
    shape = np.sin(np.pi * k / width)
    last = int(starts.max()) + k.size if starts.size else 0
    n = last + round(tail_s / dt) if duration_s is None else round(duration_s / dt) + 1
    torque = np.zeros(n)
    for b in range(0, starts.size, IMPACT_BLOCK):
        index = (starts[b : b + IMPACT_BLOCK, None] + k[None, :]).ravel()
        value = (weights[b : b + IMPACT_BLOCK, None] * shape[None, :]).ravel()
        inside = index < n
        torque += np.bincount(index[inside], value[inside], minlength=n)
    return np.arange(n) * dt, torque
