"""Shaft-torque benchmark (issue 19): excitation and station torque of a long transit, one core.

A synthetic transit of `hours` hours at 3 m/s with one 0.4 m thick cusp every 0.5 s (torque amplitudes
exponential, mean 300 kN·m), Agulhas II line at 140 rpm, 40 samples per blade passage, case 1: the time to
build Q(t) and to compute the shaft torque, and the peak memory of the arrays (tracemalloc).
Run: `.venv/bin/python benchmarks/shaft.py [hours]`.
"""

from __future__ import annotations

import sys
import time
import tracemalloc

import numpy as np
import opentorsion  # noqa: F401  (imported here: its import, ≈ 1 s with matplotlib.pyplot, is not timed)

from floebreak.app.inputs import load_shaft_line
from floebreak.shaft.excitation import ice_torque_series
from floebreak.shaft.response import station_torque_n_m


def main(hours: float = 1.0) -> None:
    rng = np.random.default_rng(1)
    line = load_shaft_line("agulhas_ii")
    n_cusps = int(hours * 3600 / 0.5)
    arrival = np.sort(rng.uniform(0.0, hours * 3600, n_cusps))
    amplitude = rng.exponential(3e5, n_cusps)
    tracemalloc.start()
    start = time.perf_counter()
    t, q = ice_torque_series(arrival, amplitude, 0.4, rpm=line.rpm, blades=4, case=1, overlap="superpose")
    built = time.perf_counter()
    y = station_torque_n_m(line, line.mean_torque() + q, t[1] - t[0])
    done = time.perf_counter()
    peak = tracemalloc.get_traced_memory()[1]
    print(
        f"{hours:g} h: {t.size:,} samples; excitation {built - start:.2f} s, response {done - built:.2f} s, "
        f"peak {peak / 1e6:.0f} MB (series {q.nbytes / 1e6:.0f} MB each); Q_peak {y.max() / 1e3:.0f} kN m"
    )


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 1.0)
