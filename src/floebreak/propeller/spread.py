"""Loads with their spread: loads per hour and the design ice torque as a median with a 5–95 % band over
the flow transport's parameter distributions and over the fields (runs) of an analysis.

A sample is one run's cusps under one draw of the flow transport: each cusp's tumble (yaw, lateral shift),
C_D and μ drawn again from their distributions (`flow_transport.flow_draws_of_runs`). The analysis' own
draw is the first sample of each run; `n_draws − 1` more per run follow. Per sample: loads per hour on one
propeller (cusps reaching a propeller / propellers / the run's hours), and per propeller and pitch the
design ice torque as the design-load table computes it (`design_loads.simulated_loads`: the rule-form x_max
over the operating profile where it fits, else the largest simulated load), from the milling model's loads
on that draw's engaged intervals. The band: the 5th, 50th and 95th percentiles of the samples (linear
interpolation between order statistics, `numpy.percentile`); with few samples it lies close to their range,
so `n_samples` is given with it. The kinematic transport ("hull") has no parameter distributions: its band
is over the fields alone.
"""

from __future__ import annotations

from typing import Final

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.design_values import design_value, simulated_loads

# samples per run: the analysis' draw and two more (their cost: docs/explanation/cusp-flow.md, "Cost")
SPREAD_DRAWS: Final = 3
BAND_PERCENTILES: Final = (5.0, 50.0, 95.0)
BAND_KEYS: Final = ("p5", "median", "p95")  # a band as a list [p5, median, p95] (the design-load rows)


def check_draws(n_draws) -> int:
    """`n_draws` as an int ≥ 1, else InputError naming "spread_draws"."""
    if isinstance(n_draws, bool) or int(n_draws) != n_draws or n_draws < 1:
        raise InputError("spread_draws", f"{n_draws!r}", value=n_draws, allowed="an integer ≥ 1")
    return int(n_draws)


def band(values) -> dict | None:
    """{"median", "p5", "p95", "n_samples"} of the finite `values`; None without any."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not v.size:
        return None
    low, median, high = (float(x) for x in np.percentile(v, BAND_PERCENTILES))
    return {"median": median, "p5": low, "p95": high, "n_samples": int(v.size)}


def band_text(entry: dict | None, spec: str = ".0f") -> str:
    """ "median (5–95 %: low–high, n samples)", or "–"."""
    if not entry:
        return "–"
    m, lo, hi = (format(entry[k], spec) for k in ("median", "p5", "p95"))
    return f"{m} (5–95 %: {lo}–{hi}, {entry['n_samples']} samples)"


def load_spread(samples, *, hours: dict, pitches, loads_of, profile_hours: float | None) -> dict:
    """The spread entry of a propeller analysis' summary. `samples`: run → [(rows, CuspTransport)] per draw
    (the analysis' own first); `hours`: run → hours in ice (a run without is left out of the rates);
    `loads_of(run, rows, transport)` → {pitch: (|F| [N], |Q| [N·m]) per cusp of `rows`}; `profile_hours`:
    the operating profile's hours (None: the design torque is the largest simulated load)."""
    per_hour, design = [], {}
    for run, draws in samples.items():
        run_hours = hours.get(run)
        for rows, moved in draws:
            index = moved.propeller_index
            if run_hours:
                per_hour.append(np.sum(index >= 0) / moved.n_propellers / run_hours)
            loads = loads_of(run, rows, moved)
            for p in range(moved.n_propellers):
                members = index == p
                rate = float(members.sum()) / run_hours if run_hours else None
                for pitch in pitches:
                    force, torque = loads[pitch]
                    sim = simulated_loads(force, torque, members.astype(float), rate, profile_hours)
                    key = (f"propeller {p + 1}", float(pitch))
                    design.setdefault(key, []).append(design_value(sim, "torque")[0] / 1e3)
    return {
        "n_draws_per_run": max((len(d) for d in samples.values()), default=0),
        "n_runs": len(samples),
        "percentiles": list(BAND_PERCENTILES),
        "loads_per_hour_per_propeller": band(per_hour),
        "design_torque_kn_m": [
            {"propeller": name, "pitch_percent": pitch, **(band(values) or {})}
            for (name, pitch), values in sorted(design.items())
        ],
    }
