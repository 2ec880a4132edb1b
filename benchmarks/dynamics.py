"""Rigid-body ice motion: 1 000 floes of the reference observation's sizes, a hull through them at 3 m/s for
128 s of simulated time (issue 29 item 4). Reports wall time, steps, awake and held pieces, peak memory.

The field is `generate_field` on observation 2019-12-18T20:20, 385 m × 100 m (190 floes, seed 1), copied
sideways at 100 m spacing until it holds 1 000 floes (a 600 m wide band); the hull is a 134 m × 22 m
waterline (the size of S.A. Agulhas II) with a 30 m wedge bow, its stem at x = 0, y = 0. Floes are added
when the awake window's front reaches them and retired behind it, as the stepping loop will do.

    PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/dynamics.py
"""

from __future__ import annotations

import resource
import time

import numpy as np
import shapely
from shapely import affinity

import floebreak
from floebreak.dynamics import IceMotionEngine, IceMotionSettings

N_FLOES = 1000
SPEED_M_S = 3.0
DURATION_S = 128.0


def _floes() -> tuple[list[shapely.Polygon], np.ndarray]:
    obs = floebreak.get_observation("2019-12-18T20:20")
    field = floebreak.generate_field(obs, length_m=385.0, width_m=100.0, rng=np.random.default_rng(1))
    polygons, thickness = [], []
    for copy in range(int(np.ceil(N_FLOES / field.n_floes))):
        dy = 100.0 * ((copy + 1) // 2) * (1 if copy % 2 else -1)
        polygons += [affinity.translate(p, 0.0, dy) for p in field.polygons]
        thickness += list(field.thickness_m)
    return polygons[:N_FLOES], np.asarray(thickness[:N_FLOES])


def _hull() -> shapely.Polygon:
    return shapely.Polygon([(0.0, 0.0), (-30.0, 11.0), (-134.0, 11.0), (-134.0, -11.0), (-30.0, -11.0)])


def main() -> None:
    polygons, thickness = _floes()
    order = np.argsort([p.bounds[0] for p in polygons], kind="stable")
    settings = IceMotionSettings(hull_contact="engine")  # the engine alone pushes the floes here
    start = time.perf_counter()
    engine = IceMotionEngine(_hull(), (SPEED_M_S, 0.0), settings)
    steps = round(DURATION_S / settings.time_step_s)
    k, awake, held, retired = 0, [], [], 0
    for _ in range(steps):
        front = engine.window()[2]
        while k < len(order) and polygons[order[k]].bounds[0] <= front:
            engine.add_piece(int(order[k]), polygons[order[k]], float(thickness[order[k]]))
            k += 1
        engine.step()
        retired += len(engine.drain_retired())
        awake.append(len(engine.awake_ids()))
        held.append(len(engine.piece_ids()))
    wall = time.perf_counter() - start
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"floes {len(polygons)}, added {k}, retired {retired}; {steps} steps of {settings.time_step_s} s")
    print(f"awake pieces: mean {np.mean(awake):.0f}, max {max(awake)}; held: max {max(held)}")
    print(f"wall time {wall:.1f} s ({1e3 * wall / steps:.2f} ms/step); peak memory (RSS) {peak_mb:.0f} MB")


if __name__ == "__main__":
    main()
