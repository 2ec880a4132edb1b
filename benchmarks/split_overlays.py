"""What the cuts that separate nothing cost: every split of a run, replayed and timed by its outcome.

A cut that leaves every piece of ice on one side (the other side empty, or only slivers: the sliver rule,
docs/model.md §11) keeps the floe whole, and the floe is evaluated again at the next step. This script runs
the engine once (default profile, reference observation, 1 km × 200 m unless told otherwise), records the
arguments of every `cracking.split_by_line` and `bending.split_by_radius` call and every local-cracking
evaluation, then replays them `--rounds` times in this process and keeps each call's best CPU time: the
sum over the one-sided calls is what any cheaper test of "this cut separates nothing" could save at most.
On a shared machine this is steadier than timing whole runs: each call is timed many times, in one phase.

Run: `.venv/bin/python benchmarks/split_overlays.py [--length-m 1000 --width-m 200] [--rounds 5]`
"""

from __future__ import annotations

import argparse
import gc
import time

import numpy as np

from floebreak.config.profiles import build_model
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.failure import bending, cracking, local_cracking
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.mechanics import compile_kernels
from floebreak.ship.hulls import agulhas_ii


def record_run(length_m: float, width_m: float) -> tuple[list, float]:
    """(the run's split calls as (function, arguments), the engine's CPU time)."""
    calls = []

    def recording(function):
        def call(*args):
            calls.append((function, args))
            return function(*args)

        return call

    evaluate = local_cracking.LocalCracking.evaluate
    originals = cracking.split_by_line, bending.split_by_radius
    cracking.split_by_line, bending.split_by_radius = (recording(f) for f in originals)
    local_cracking.LocalCracking.evaluate = recording(evaluate)
    try:
        field = generate_field(
            get_observation("2019-12-18T20:20"), length_m, width_m, np.random.default_rng(1), thickness_m=1.0
        )
        model, bow = build_model("default"), agulhas_ii(ice_thickness_m=1.0)
        gc.freeze()
        start = time.process_time()
        simulate(field, bow, model, SimulationParams(step_m=0.25))
        engine_s = time.process_time() - start
    finally:
        cracking.split_by_line, bending.split_by_radius = originals
        local_cracking.LocalCracking.evaluate = evaluate
    return calls, engine_s


def outcome(result, call_args) -> str:
    if isinstance(result, tuple):  # a split: (one side's parts, the other's)
        return "one-sided" if bool(result[0]) != bool(result[1]) else "split"
    mode, inp, ctx = call_args  # local cracking: held by the bending gate (F_v ≤ P_f), or its cutter decided
    if not bending.bending_check(inp, ctx, mode.settings).fails:
        return "held by the bending gate"
    return f"cutter: {result.status}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--length-m", type=float, default=1000.0)
    parser.add_argument("--width-m", type=float, default=200.0)
    parser.add_argument("--rounds", type=int, default=5, help="replays; each call's best CPU time is kept")
    args = parser.parse_args()
    compile_kernels()
    calls, engine_s = record_run(args.length_m, args.width_m)
    best = [float("inf")] * len(calls)
    labels = [""] * len(calls)
    for _ in range(args.rounds):
        for i, (function, call_args) in enumerate(calls):
            start = time.process_time()
            result = function(*call_args)
            best[i] = min(best[i], time.process_time() - start)
            labels[i] = f"{function.__name__}: {outcome(result, call_args)}"
    print(f"{args.length_m:.0f} m × {args.width_m:.0f} m: engine {engine_s:.3f} s CPU (one run, recording)")
    for label in sorted(set(labels)):
        chosen = [b for b, lab in zip(best, labels, strict=True) if lab == label]
        print(f"  {label:<42} {len(chosen):5d} calls  {sum(chosen):.4f} s CPU (best of {args.rounds})")


if __name__ == "__main__":
    main()
