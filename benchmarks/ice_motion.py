"""Static vs dynamic ice motion in the stepping loop (issue 29 items 2 and 4): the cost ratio, in one run,
and what the motion changes.

The reference scenario (`default` profile, observation 2019-12-18T20:20, h = 1 m, `agulhas_ii`, 0.25 m
steps) on the 385 m × 100 m field and, with `--long`, the 1 km × 200 m field. For each motion: the CPU
time of `simulate` (field, bow and model built once beforehand, the numba kernels compiled), cusps per km,
and of the initial floes the hull touched (evaluated in contact at least once) the share that broke or left
the field, the rest being pushed aside (dynamic) or left where they lie untouched by failure (static).
With `--time-steps`, the engine-step convergence instead: dynamic motion on the 385 m field for
`ice_motion.time_step_s` 0.02 / 0.01 / 0.005 (and 0.0025 with `--fine`) and seeds 1–3 (1–N with
`--seeds N`), with the seeds' means and their change from one step to the next (measured, nothing tuned).
Run: `PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/ice_motion.py [--long | --time-steps [--fine]
[--seeds N]]`.
"""

from __future__ import annotations

import gc
import sys
import time

import numpy as np

from floebreak.app.build import build_bow, build_field, build_model_for, ice_motion_params
from floebreak.dynamics import engine
from floebreak.mechanics import compile_kernels
from floebreak.scenario import Scenario
from floebreak.simulation import ContactEvaluated, SimulationParams, simulate

# the motions compared: overrides of the reference scenario; the last takes one engine step per 0.25 m
# contact search (0.1 s at 3 m/s with the hull's travel per step allowed up to 0.5 m) instead of five
MOTIONS = {
    "static": ["simulation.ice_motion=static"],
    "dynamic": ["simulation.ice_motion=dynamic"],
    "dynamic, 1 step/search": [
        "simulation.ice_motion=dynamic",
        "ice_motion.time_step_s=0.1",
        "ice_motion.step_travel_fraction=0.5",
    ],
}


TIME_STEPS_S = (0.02, 0.01, 0.005)
SEEDS = (1, 2, 3)


def _measure(size: list[str], motion: list[str]) -> dict[str, float]:
    scenario = Scenario.reference([*size, *motion]).resolved()
    field = build_field(scenario, np.random.default_rng(scenario.seed))
    bow, model = build_bow(scenario, field), build_model_for(scenario)
    params = SimulationParams(step_m=scenario.ship.step_m, **ice_motion_params(scenario))
    touched: set[int] = set()

    def record(event) -> None:
        if isinstance(event, ContactEvaluated) and event.piece_id < field.n_floes:
            touched.add(event.piece_id)

    start = time.process_time()
    result = simulate(field, bow, model, params, callbacks=[record])
    cpu_s = time.process_time() - start
    ids = np.fromiter(touched, dtype=np.int64)
    broke = int(np.count_nonzero(result.fate[ids] != "remaining"))
    transit_km = (result.x_end_m - params.x_start_m) / 1000.0
    return {
        "cpu_s": cpu_s,
        "cusps_per_km": int(result.mask("cusp").sum()) / transit_km,
        "cusp_area_m2": result.area_m2("cusp"),
        "touched": len(ids),
        "broke_share": broke / max(len(ids), 1),
        "floes": field.n_floes,
    }


def compare(length_m: float, width_m: float) -> None:
    size = [f"field.length_m={length_m}", f"field.width_m={width_m}"]
    rows = {name: _measure(size, motion) for name, motion in MOTIONS.items()}
    for motion, row in rows.items():
        print(
            f"{length_m:.0f} m × {width_m:.0f} m, {motion:>22}: {row['floes']} floes, "
            f"CPU {row['cpu_s']:.1f} s, "
            f"{row['cusps_per_km']:.0f} cusps/km, cusp area {row['cusp_area_m2']:.0f} m², "
            f"{row['touched']} floes "
            f"touched: {100 * row['broke_share']:.0f} % broke or left, "
            f"{100 * (1 - row['broke_share']):.0f} % "
            "did not"
        )
    for name in list(MOTIONS)[1:]:
        print(f"  cost ratio {name} / static: {rows[name]['cpu_s'] / rows['static']['cpu_s']:.2f}")


def time_step_table(time_steps_s: tuple[float, ...], seeds: tuple[int, ...]) -> None:
    """Each seed at each time step, then the seeds' means and each mean's change from the step before."""
    size = ["field.length_m=385.0", "field.width_m=100.0"]
    rows: dict[float, list[dict[str, float]]] = {dt: [] for dt in time_steps_s}
    for seed in seeds:
        for dt_s in time_steps_s:
            motion = [*MOTIONS["dynamic"], f"ice_motion.time_step_s={dt_s}", f"seed={seed}"]
            row = _measure(size, motion)
            rows[dt_s].append(row)
            print(
                f"seed {seed}, time step {dt_s} s: {row['cusps_per_km']:.0f} cusps/km, "
                f"cusp area {row['cusp_area_m2']:.0f} m², {row['touched']} floes touched, "
                f"{100 * (1 - row['broke_share']):.1f} % pushed aside, CPU {row['cpu_s']:.1f} s",
                flush=True,
            )
    previous = None
    for dt_s in time_steps_s:
        mean = {key: float(np.mean([r[key] for r in rows[dt_s]])) for key in ("cusps_per_km", "cusp_area_m2")}
        pushed = 100 * (1 - float(np.mean([r["broke_share"] for r in rows[dt_s]])))
        change = (
            ""
            if previous is None
            else ", change from the step before: "
            + ", ".join(f"{key} {100 * (mean[key] / previous[key] - 1):+.1f} %" for key in mean)
        )
        print(
            f"mean of seeds, {dt_s} s: {mean['cusps_per_km']:.0f} cusps/km, "
            f"{mean['cusp_area_m2']:.0f} m², {pushed:.1f} % pushed aside{change}"
        )
        previous = mean


if __name__ == "__main__":
    compile_kernels()
    engine.compile_now()
    gc.freeze()
    if "--time-steps" in sys.argv:
        seeds = (
            tuple(range(1, int(sys.argv[sys.argv.index("--seeds") + 1]) + 1))
            if "--seeds" in sys.argv
            else SEEDS
        )
        time_step_table((*TIME_STEPS_S, 0.0025) if "--fine" in sys.argv else TIME_STEPS_S, seeds)
        sys.exit(0)
    compare(385.0, 100.0)
    if "--long" in sys.argv:
        compare(1000.0, 200.0)
