"""Where the engine's time goes: a cProfile of `simulate` on the reference field, as shares of the run.

Cases: ``static`` (1 km × 200 m, step_end), ``dynamic`` (the same field, moving ice) and ``root`` (400 m ×
50 m, the field `compare.py` times located events on, with ``step_end`` alongside for the ratio). Each share
is the inclusive (cumulative) time of one function of the engine over the whole `simulate` call, under
cProfile: the profiler slows Python calls more than compiled code, so the shares of the Python layers are
somewhat too large, those of numba and GEOS too small. The CPU time of one unprofiled run is printed first.

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/where_time_goes.py [--case static|dynamic|root]``.
"""

from __future__ import annotations

import argparse
import cProfile
import gc
import pstats
import time

import numpy as np

from floebreak.config.profiles import build_model
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.mechanics import compile_kernels
from floebreak.ship.hulls import agulhas_ii

GEOS_OVERLAYS = (("shapely/set_operations.py", "intersection"), ("shapely/set_operations.py", "difference"))
# (label, ((file fragment, function name), ...)): inclusive time of these, as a share of `simulate`
PARTS = {
    "static": (
        ("contact evaluation (zones, areas, forces)", (("mechanics/contact.py", "evaluate_contacts"),)),
        ("judgement of failure (classify + modes)", (("engine/loop.py", "judge"),)),
        ("  cracking mode", (("failure/cracking.py", "evaluate"),)),
        ("  bending mode", (("failure/bending.py", "evaluate"),)),
        ("  local cracking mode", (("failure/local_cracking.py", "evaluate"),)),
        ("applying outcomes (new pieces, records)", (("engine/loop.py", "apply"),)),
        ("moving pieces into the bow frame (+ validity)", (("engine/loop.py", "_translate_pieces"),)),
        ("out-of-contact skip (`quiet`)", (("engine/loop.py", "quiet"),)),
        ("GEOS overlays (splits, zones: intersection, difference)", GEOS_OVERLAYS),
    ),
    "dynamic": (
        ("rigid-body engine between searches", (("engine/motion/dynamic.py", "advance_to"),)),
        ("  engine steps (water forces, Chipmunk, window)", (("dynamics/engine.py", "step"),)),
        ("  Chipmunk's step (C, with the hull-contact callbacks)", (("pymunk/space.py", "step"),)),
        ("  bodies of pieces entering the engine", (("dynamics/engine.py", "_enter"),)),
        ("  crushing forces as hull holds", (("engine/motion/dynamic.py", "_push"),)),
        ("  moved outlines and boxes written back", (("engine/motion/dynamic.py", "_write_back"),)),
        ("moved outlines stored before contact (`flush`)", (("engine/motion/dynamic.py", "flush"),)),
        ("moved pieces' out-of-contact skip", (("engine/loop.py", "_apart_after_moving"),)),
        ("contact evaluation", (("mechanics/contact.py", "evaluate_contacts"),)),
        ("judgement of failure", (("engine/loop.py", "judge"),)),
    ),
    "root": (
        ("located step (all evaluations of a search)", (("engine/events.py", "locate_step"),)),
        ("GEOS overlays (all)", GEOS_OVERLAYS),
        ("judgement of failure (all)", (("engine/loop.py", "judge"),)),
        ("contact evaluation (all)", (("mechanics/contact.py", "evaluate_contacts"),)),
        ("trials of the event location", (("engine/events.py", "_failed_at"),)),
        ("pieces moved into the bow frame one by one", (("engine/loop.py", "bow_frame"),)),
    ),
}
CASES = {
    "static": (1000.0, 200.0, {}),
    "dynamic": (1000.0, 200.0, {"ice_motion": "dynamic"}),
    "root": (400.0, 50.0, {"event_location": "root"}),
}


def _named(file: str, function: str, functions: tuple[tuple[str, str], ...]) -> bool:
    return any(function == name and file.endswith(path) for path, name in functions)


def _field(length_m: float, width_m: float):
    observation = get_observation("2019-12-18T20:20")
    return generate_field(observation, length_m, width_m, np.random.default_rng(1), thickness_m=1.0)


def _cpu_s(field, params: SimulationParams) -> float:
    model, bow = build_model("default"), agulhas_ii(ice_thickness_m=1.0)
    simulate(field, bow, model, params)  # warm: caches, lazily built tables
    start = time.process_time()
    simulate(field, bow, model, params)
    return time.process_time() - start


def profile(case: str) -> None:
    length_m, width_m, extra = CASES[case]
    field = _field(length_m, width_m)
    params = SimulationParams(step_m=0.25, **extra)
    print(f"== {case}: {length_m:.0f} m × {width_m:.0f} m, {extra or 'step_end'}")
    print(f"CPU time of one run, unprofiled: {_cpu_s(field, params):.2f} s")
    if case == "root":
        print(f"the same field with step_end:    {_cpu_s(field, SimulationParams(step_m=0.25)):.2f} s")
    profiler = cProfile.Profile()
    model, bow = build_model("default"), agulhas_ii(ice_thickness_m=1.0)
    profiler.enable()
    simulate(field, bow, model, params)
    profiler.disable()
    stats = pstats.Stats(profiler).stats
    total = max(cum for (_, _, _, cum, _) in stats.values())
    for label, functions in PARTS[case]:
        cum = sum(v[3] for (file, _, func), v in stats.items() if _named(file, func, functions))
        print(f"{label:<58} {100.0 * cum / total:5.1f} %")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=tuple(CASES), action="append")
    compile_kernels()
    gc.freeze()  # as the CLI does after loading the engine
    for case in parser.parse_args().case or tuple(CASES):
        profile(case)
