"""Static vs dynamic ice motion in the stepping loop (issue 29 items 2 and 4): the cost ratio, in one run,
and what the motion changes.

The reference scenario (`default` profile, observation 2019-12-18T20:20, h = 1 m, `agulhas_ii`, 0.25 m
steps) on the 385 m × 100 m field and, with `--long`, the 1 km × 200 m field. For each motion: the CPU
time of `simulate` (field, bow and model built once beforehand, the numba kernels compiled), cusps per km,
and of the initial floes the hull touched (evaluated in contact at least once) the share that broke or left
the field, the rest being pushed aside (dynamic) or left where they lie untouched by failure (static).
With `--time-steps`, the engine-step convergence instead: dynamic motion on the 385 m field for
`ice_motion.time_step_s` 0.02 / 0.01 / 0.005 (and 0.0025 with `--fine`) and seeds 1–3 (1–N with
`--seeds N`; `--steps 0.04,0.02` other steps), with the seeds' means and their change from one step to the
next (measured, nothing tuned).
The motions alternate, each run `--repeat` times (3): the medians and their ratios, with the load average;
`--two` leaves out the coarser motion (3 engine steps per search instead of 5). `--window F` adds `dynamic`
with the awake window's distances (`ice_motion.window_ahead_m`, `window_behind_m`, `window_side_m`) scaled
by F; with `--seeds N` as well, instead: seeds 1–N on the 385 m field, `dynamic` at the default window and at
F, each seed's change in cusps/km and cusp area, and their mean ± standard deviation over the seeds.
`--windows A/B/S,A/B/S,…` (ahead/behind/side distances in m) runs `dynamic` on the 385 m field for each window
and each seed (`--seeds N`, from `--first-seed K`, default 1) and gives each window's mean paired change
against the last one (the reference, e.g. one spanning the field's whole width), ± its standard error.
`--search-steps S,S,…` (contact-search steps `ship.step_m` in m, the finest last) runs `dynamic` (`--static`:
`static`) on the 385 m field for each step and seed (`--seeds N`, from `--first-seed K`) and gives each step's
mean paired change against the finest; `--judged-at J` adds the finest step once more with the failure judged
only at the searches on multiples of J m (the hold forces still refreshed at every search), which separates
the coarse step's two effects: the judgements' spacing and the hold forces' lag; `--time-step T` sets
`ice_motion.time_step_s` in every row.
Run: `PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/ice_motion.py [[--long] [--repeat N] [--two]
[--window F] | --time-steps [--fine] [--seeds N] | --window F --seeds N | --windows W,… --seeds N
[--first-seed K] | --search-steps S,… [--static] [--judged-at J] [--time-step T] --seeds N [--first-seed K]]`.
"""

from __future__ import annotations

import gc
import os
import sys
import time
from contextlib import contextmanager

import numpy as np

from floebreak.app.build import build_bow, build_field, build_model_for, ice_motion_params
from floebreak.config.scenario import Scenario
from floebreak.dynamics import IceMotionSettings, engine
from floebreak.engine.loop import ContactEvaluated, SimulationParams, _Run, simulate
from floebreak.failure.base import intact
from floebreak.mechanics import compile_kernels

# the motions compared: overrides of the reference scenario; the last takes 3 engine steps of 0.028 s per
# 0.25 m contact search instead of 5 of 0.017 s (`time_step_s` 0.04: the convergence table of docs/model.md
# allows it)
MOTIONS = {
    "static": ["simulation.ice_motion=static"],
    "dynamic": ["simulation.ice_motion=dynamic"],
    "dynamic, 3 steps/search": ["simulation.ice_motion=dynamic", "ice_motion.time_step_s=0.04"],
}


def window_scaled(factor: float) -> list[str]:
    """The overrides scaling the awake window's three distances by `factor`."""
    defaults = IceMotionSettings()
    return [
        f"ice_motion.{key}={factor * getattr(defaults, key)!r}"
        for key in ("window_ahead_m", "window_behind_m", "window_side_m")
    ]


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


def compare(length_m: float, width_m: float, repeats: int, extra: dict[str, list[str]]) -> None:
    """Each motion `repeats` times, the motions alternating (static, dynamic, …, static, dynamic, …) so
    that a change in the machine's load reaches all of them; the median CPU time of each and the ratios
    of the medians. The counts are those of the last round (the runs are deterministic). `extra`: further
    motions, after the others."""
    size = [f"field.length_m={length_m}", f"field.width_m={width_m}"]
    table = {**MOTIONS, **extra}
    motions = [*(list(MOTIONS)[:2] if "--two" in sys.argv else list(MOTIONS)), *extra]
    times: dict[str, list[float]] = {name: [] for name in motions}
    rows: dict[str, dict[str, float]] = {}
    for _ in range(repeats):
        for name, motion in ((name, table[name]) for name in motions):
            rows[name] = _measure(size, motion)
            times[name].append(rows[name]["cpu_s"])
    for motion, row in rows.items():
        print(
            f"{length_m:.0f} m × {width_m:.0f} m, {motion:>22}: {row['floes']} floes, "
            f"CPU {float(np.median(times[motion])):.2f} s (runs: "
            f"{', '.join(f'{t:.2f}' for t in times[motion])}), "
            f"{row['cusps_per_km']:.0f} cusps/km, cusp area {row['cusp_area_m2']:.0f} m², "
            f"{row['touched']} floes "
            f"touched: {100 * row['broke_share']:.0f} % broke or left, "
            f"{100 * (1 - row['broke_share']):.0f} % "
            "did not"
        )
    static = float(np.median(times["static"]))
    for name in motions[1:]:
        print(f"  cost ratio {name} / static (medians): {float(np.median(times[name])) / static:.2f}")


def _load_average() -> str:
    return " ".join(f"{v:.1f}" for v in os.getloadavg())


def window_table(factor: float, seeds: tuple[int, ...]) -> None:
    """`dynamic` on the 385 m field at the default window and at its distances × `factor`, per seed; each
    seed's change, and the changes' mean ± standard deviation over the seeds."""
    size = ["field.length_m=385.0", "field.width_m=100.0"]
    changes: dict[str, list[float]] = {"cusps_per_km": [], "cusp_area_m2": []}
    cpu: dict[str, list[float]] = {"default": [], "scaled": []}
    for seed in seeds:
        base = _measure(size, [*MOTIONS["dynamic"], f"seed={seed}"])
        scaled = _measure(size, [*MOTIONS["dynamic"], *window_scaled(factor), f"seed={seed}"])
        cpu["default"].append(base["cpu_s"])
        cpu["scaled"].append(scaled["cpu_s"])
        for key, values in changes.items():
            values.append(100 * (scaled[key] / base[key] - 1))
        print(
            f"seed {seed}: window ×1 {base['cusps_per_km']:.0f} cusps/km, {base['cusp_area_m2']:.0f} m², "
            f"CPU {base['cpu_s']:.2f} s; ×{factor:g} {scaled['cusps_per_km']:.0f} cusps/km, "
            f"{scaled['cusp_area_m2']:.0f} m², CPU {scaled['cpu_s']:.2f} s",
            flush=True,
        )
    summary = ", ".join(
        f"{key} {float(np.mean(v)):+.1f} ± {float(np.std(v, ddof=1)) if len(v) > 1 else 0.0:.1f} %"
        for key, v in changes.items()
    )
    total = sum(cpu["scaled"]) / sum(cpu["default"]) - 1
    print(f"window ×{factor:g} against ×1 over seeds {seeds[0]}–{seeds[-1]} (mean ± sd): {summary}")
    print(f"  CPU {sum(cpu['default']):.1f} → {sum(cpu['scaled']):.1f} s ({100 * total:+.0f} %)")


def _paired_change(runs, refs, key: str, relative: bool = True) -> tuple[float, float]:
    """Mean ± standard error over the seeds of each run's change in `key` against its reference run: in %
    (`relative`) or, for a share, in percentage points."""
    if relative:
        change = [100 * (run[key] / ref[key] - 1) for run, ref in zip(runs, refs, strict=True)]
    else:
        change = [100 * (run[key] - ref[key]) for run, ref in zip(runs, refs, strict=True)]
    error = float(np.std(change, ddof=1) / np.sqrt(len(change))) if len(change) > 1 else 0.0
    return float(np.mean(change)), error


def window_sweep(windows: list[tuple[float, float, float]], seeds: tuple[int, ...]) -> None:
    """`dynamic` on the 385 m field at each window (ahead, behind, side) [m] for each seed; each window's
    paired change in cusps/km, cusp area and CPU against the last window, mean ± standard error."""
    size = ["field.length_m=385.0", "field.width_m=100.0"]
    keys = ("window_ahead_m", "window_behind_m", "window_side_m")
    rows: list[list[dict[str, float]]] = [[] for _ in windows]
    for seed in seeds:
        for k, window in enumerate(windows):
            overrides = [f"ice_motion.{key}={value!r}" for key, value in zip(keys, window, strict=True)]
            rows[k].append(_measure(size, [*MOTIONS["dynamic"], *overrides, f"seed={seed}"]))
            print(f"seed {seed}, window {window}: {rows[k][-1]['cusps_per_km']:.1f} cusps/km", flush=True)
    for window, runs in zip(windows, rows, strict=True):
        summary = []
        for key in ("cusps_per_km", "cusp_area_m2", "cpu_s"):
            mean_change, error = _paired_change(runs, rows[-1], key)
            summary.append(
                f"{key} {float(np.mean([r[key] for r in runs])):.1f} ({mean_change:+.2f} ± {error:.2f} %)"
            )
        print(f"window {window} against {windows[-1]}, seeds {seeds[0]}–{seeds[-1]}: {'; '.join(summary)}")


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


@contextmanager
def _judged_only_every(judged_at_m: float | None):
    """Within the block, a run's failure judgements (`floebreak.engine.loop._Run.judge`) leave every piece
    intact except at the searches on multiples of `judged_at_m` from the start (the hold forces are still
    refreshed at every search): the coarse step's judgement spacing without its force lag."""
    original = _Run.judge
    if judged_at_m is not None:

        def judge(self, pid, polygon_bf, contact):
            classification, outcome = original(self, pid, polygon_bf, contact)
            offset = (self.motion.bow_x - self.params.x_start_m) / judged_at_m
            return (
                (classification, outcome)
                if abs(offset - round(offset)) < 1e-6
                else (classification, intact("none"))
            )

        _Run.judge = judge
    try:
        yield
    finally:
        _Run.judge = original


def search_step_table(
    search_steps_m: tuple[float, ...],
    seeds: tuple[int, ...],
    motion: str,
    judged_at_m: float | None,
    extra: list[str],
) -> None:
    """`motion` (with the overrides `extra`) on the 385 m field at each contact-search step (`ship.step_m`)
    for each seed, and with `judged_at_m` the finest step once more with the failure judged only every
    `judged_at_m` (`_judged_only_every`); each row's mean cusps/km, cusp area and share of touched floes
    broken, with its paired change against the finest step, mean ± standard error over the seeds."""
    size = ["field.length_m=385.0", "field.width_m=100.0"]
    finest = search_steps_m[-1]
    variants = [(step, None) for step in search_steps_m]
    if judged_at_m is not None:
        variants.append((finest, judged_at_m))
    rows: dict[tuple, list[dict[str, float]]] = {variant: [] for variant in variants}
    for seed in seeds:
        for step, judged_at in variants:
            with _judged_only_every(judged_at):
                row = _measure(size, [*MOTIONS[motion], *extra, f"ship.step_m={step}", f"seed={seed}"])
            rows[(step, judged_at)].append(row)
            print(
                f"seed {seed}, {_variant_name((step, judged_at))}: {row['cusps_per_km']:.1f} cusps/km, "
                f"{row['cusp_area_m2']:.0f} m², {100 * row['broke_share']:.1f} % broke, "
                f"CPU {row['cpu_s']:.1f} s",
                flush=True,
            )
    for variant, runs in rows.items():
        summary = []
        for key, scale, unit in (
            ("cusps_per_km", 1, "%"),
            ("cusp_area_m2", 1, "%"),
            ("broke_share", 100, "pts"),
        ):
            mean = float(np.mean([run[key] for run in runs])) * scale
            mean_change, error = _paired_change(runs, rows[(finest, None)], key, relative=unit == "%")
            summary.append(f"{key} {mean:.1f} ({mean_change:+.1f} ± {error:.1f} {unit})")
        cpu = float(np.mean([run["cpu_s"] for run in runs]))
        print(f"{motion}, {_variant_name(variant)} against {finest} m: {'; '.join(summary)}; CPU {cpu:.1f} s")


def _variant_name(variant: tuple[float, float | None]) -> str:
    step, judged_at = variant
    return f"step {step} m" + ("" if judged_at is None else f", judged every {judged_at} m")


def _option(flag: str) -> str:
    return sys.argv[sys.argv.index(flag) + 1]


if __name__ == "__main__":
    compile_kernels()
    engine.compile_now()
    gc.freeze()
    first = int(sys.argv[sys.argv.index("--first-seed") + 1]) if "--first-seed" in sys.argv else 1
    seeds = (
        tuple(range(first, first + int(sys.argv[sys.argv.index("--seeds") + 1])))
        if "--seeds" in sys.argv
        else SEEDS
    )
    if "--windows" in sys.argv:
        text = sys.argv[sys.argv.index("--windows") + 1]
        window_sweep([tuple(float(v) for v in w.split("/")) for w in text.split(",")], seeds)
        sys.exit(0)
    window = float(sys.argv[sys.argv.index("--window") + 1]) if "--window" in sys.argv else None
    if window is not None and "--seeds" in sys.argv:
        window_table(window, seeds)
        sys.exit(0)
    if "--search-steps" in sys.argv:  # e.g. --search-steps 0.25,0.125,0.0625,0.03125 [--static]
        text = sys.argv[sys.argv.index("--search-steps") + 1]
        motion = "static" if "--static" in sys.argv else "dynamic"
        judged_at = float(_option("--judged-at")) if "--judged-at" in sys.argv else None
        if judged_at is not None and motion == "static":
            sys.exit("--judged-at: dynamic only (it reads the engine's bow position)")
        extra = [f"ice_motion.time_step_s={_option('--time-step')}"] if "--time-step" in sys.argv else []
        search_step_table(tuple(float(v) for v in text.split(",")), seeds, motion, judged_at, extra)
        sys.exit(0)
    if "--time-steps" in sys.argv:
        steps = (*TIME_STEPS_S, 0.0025) if "--fine" in sys.argv else TIME_STEPS_S
        if "--steps" in sys.argv:  # e.g. --steps 0.04,0.02: coarser steps than the default
            steps = tuple(float(v) for v in sys.argv[sys.argv.index("--steps") + 1].split(","))
        time_step_table(steps, seeds)
        sys.exit(0)
    repeats = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 3
    extra = (
        {}
        if window is None
        else {f"dynamic, window ×{window:g}": [*MOTIONS["dynamic"], *window_scaled(window)]}
    )
    # the first run in a process pays one-time costs (imports, caches): not measured
    _measure(["field.length_m=60.0", "field.width_m=100.0"], MOTIONS["dynamic"])
    print(f"load average {_load_average()} (1, 5, 15 min)")
    compare(385.0, 100.0, repeats, extra)
    if "--long" in sys.argv:
        compare(1000.0, 200.0, repeats, extra)
    print(f"load average {_load_average()} (1, 5, 15 min)")
