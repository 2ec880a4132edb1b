"""Field-generation benchmark (issue 2): relaxation at 1 000 / 10 000 floes, 44 % / 80 %, and SQP at 150.

Run: `.venv/bin/python benchmarks/field_generation.py` (or `make bench`). One core is enough: the
relaxation is single-threaded numpy/scipy. Diameter distribution of the reference observation
2019-12-18T20:20 (2.5/7.5/15 m: 20/40/40 %), field aspect L = 8 W sized to hold the requested count.
Last, the densest Table 1 row, 2019-12-18T22:30 (89 %, 7.5/15/60 m), in the tests' 480 m × 240 m field
(W = 4 d_max), placed by the corner-insertion fallback; mean over a few seeds.
"""

from __future__ import annotations

import time

import numpy as np

from floebreak.ice.generation import generate_field
from floebreak.ice.observations import Observation, get_observation
from floebreak.mechanics import compile_kernels

REFERENCE = get_observation("2019-12-18T20:20")
DENSE_SEEDS = (1, 2, 3, 4, 5)


def field_for(n_floes: int, concentration: float) -> tuple[Observation, float, float]:
    obs = Observation(concentration, 1.0, REFERENCE.diameter_classes_m, REFERENCE.percentages)
    d = np.asarray(obs.diameter_classes_m)
    mean_area = float(np.dot(np.pi * d**2 / 4.0, obs.fractions))
    area = n_floes * mean_area / concentration
    width = float(np.sqrt(area / 8.0))
    return obs, 8.0 * width, width


def timed(n_floes: int, concentration: float, generator: str, seed: int = 1) -> tuple[float, int, float]:
    obs, length, width = field_for(n_floes, concentration)
    start = time.perf_counter()
    field = generate_field(obs, length, width, np.random.default_rng(seed), generator=generator)
    return time.perf_counter() - start, field.n_floes, field.concentration


def main() -> None:
    print(f"{'generator':>9} {'floes':>6} {'target':>7} {'reached':>8} {'time [s]':>9}")
    for n, conc in [(1000, 0.44), (1000, 0.80), (10000, 0.44), (10000, 0.80)]:
        seconds, count, reached = timed(n, conc, "circles")
        print(f"{'circles':>9} {count:>6} {100 * conc:>6.0f}% {100 * reached:>7.2f}% {seconds:>9.2f}")
    sqp_s, count, reached = timed(150, 0.44, "sqp")
    print(f"{'sqp':>9} {count:>6} {44:>6.0f}% {100 * reached:>7.2f}% {sqp_s:>9.2f}")
    relax_s, count, reached = timed(150, 0.44, "circles")
    print(f"{'circles':>9} {count:>6} {44:>6.0f}% {100 * reached:>7.2f}% {relax_s:>9.2f}")
    print(f"speed ratio SQP / relaxation at {count} floes: {sqp_s / relax_s:.0f}×")
    dense = get_observation("2019-12-18T22:30")
    times = []
    for seed in DENSE_SEEDS:
        start = time.perf_counter()
        field = generate_field(dense, 480.0, 240.0, np.random.default_rng(seed))
        times.append(time.perf_counter() - start)
    print(
        f"{'circles':>9} {field.n_floes:>6} {100 * dense.concentration:>6.0f}% "
        f"{100 * field.concentration:>7.2f}% {np.mean(times):>9.2f}  (obs {dense.key}, 480 m × 240 m, "
        f"placement {field.metadata['placement']!r}, {len(times)} seeds, max {max(times):.2f} s)"
    )


if __name__ == "__main__":
    kernel_start = time.perf_counter()
    compile_kernels()  # the packing's energy is compiled: load numba and its cache before timing
    print(f"numba kernels ready in {time.perf_counter() - kernel_start:.2f} s (not in the figures below)")
    main()
