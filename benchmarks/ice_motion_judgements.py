"""The breaking judgements of static and dynamic ice motion (issue 29 item 4): how many, how many re-judge a
piece already judged, whether a cache could serve them, and their CPU time.

A judgement is one call of the stepping loop's per-piece failure judgement
(`floebreak.engine.loop._Run.judge`: classification and failure dispatch of a piece in contact). On the
reference transit (`default` profile, observation 2019-12-18T20:20, h = 1 m, `agulhas_ii`, 0.25 m searches;
1 km × 200 m, or 385 m × 100 m with `--short`), for `static` and for `dynamic` at each engine time step of
`--steps` (default 0.02; e.g. `--steps 0.02,0.04`):

- judgements, and re-judgements (of a piece judged before) with how many broke it;
- exact-cache hits: re-judgements whose inputs (the bow-frame outline's coordinates, thickness, crack count,
  and under `dynamic` the load share of `ice_motion.failure_force`) equal, bit for bit, those of the piece's
  last judgement or of any earlier judgement, and those within 1e-9 of the piece's last (coordinates in m,
  the contact's numbers relative);
- how far a re-judged piece moved since its last judgement: the Hausdorff distance of its outlines in the
  bow frame (what the judgement sees) and in the field;
- the CPU time inside the judgements (all, and of the re-judgements), of `simulate`, and under `dynamic` the
  engine steps and the process time per Chipmunk step (`pymunk.Space.step`).

The counts come from one run per motion with the judgement, the engine step and Chipmunk's step wrapped in
this script (nothing in `src` changes; the wrappers add their own time to `simulate`'s). Unless
`--repeat 0`, the motions are then run unwrapped, alternating, `--repeat` times (3): the medians, their ratio
to static, and the ratio if the dynamic re-judgements cost nothing (the bound of any judgement cache).
Run: `PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/ice_motion_judgements.py [--short] [--steps
0.02,0.04] [--repeat N] [--seed S]`.
"""

from __future__ import annotations

import gc
import os
import sys
import time
from contextlib import contextmanager

import numpy as np
import pymunk
import shapely
from shapely.affinity import translate

from floebreak.app.build import build_bow, build_field, build_model_for, ice_motion_params
from floebreak.config.scenario import Scenario
from floebreak.dynamics import engine
from floebreak.engine import loop as simulation
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.engine.motion.dynamic import DynamicIce as IceMotion
from floebreak.mechanics import compile_kernels

TOLERANCE = 1e-9
# where the time goes: process time inside each of these (inclusive: the engine step holds Chipmunk's, a
# body is built inside whichever call first needs it)
TIMED = (
    ("static loop (_evaluate_queue)", simulation._Run, "_evaluate_queue"),
    ("between searches (DynamicIce.advance_to)", IceMotion, "advance_to"),
    ("engine steps (IceMotionEngine.step)", engine.IceMotionEngine, "step"),
    ("bodies built (IceMotionEngine._materialize)", engine.IceMotionEngine, "_materialize"),
    ("moved outlines stored (DynamicIce.flush)", IceMotion, "flush"),
    ("skip check of moved pieces (_apart_after_moving)", simulation._Run, "_apart_after_moving"),
)


def _contact_numbers(contact) -> np.ndarray:
    """The numbers of a contact that a judgement reads (per zone: centre, normal, areas, forces, extent)."""
    values: list[float] = [contact.floe_area_m2 if contact.floe_area_m2 is not None else np.nan]
    for z in contact.zones:
        extent = z.floe_extent_m if z.floe_extent_m is not None else (np.nan, np.nan)
        values += [*z.centre_xy_m, *z.centre_normal, z.a_u_m2, z.a_l_m2, *z.force_on_ice_xy_n, *extent]
        values += [float(z.f_c_n.sum()), float(z.f_v_n.sum()), float(z.f_h_n.sum())]
    return np.array(values, dtype=float)


class _Tally:
    """Every judgement of one run: its inputs, its outcome, and the process time inside it."""

    def __init__(self) -> None:
        self.bow_x = 0.0
        self.pid: list[int] = []
        self.bow_x_m: list[float] = []
        self.polygon_bf: list = []
        self.key: list[bytes] = []
        self.contact: list[np.ndarray] = []
        self.cpu_ns: list[int] = []
        self.failed: list[bool] = []
        self.engine_steps = 0
        self.chipmunk_steps = 0
        self.chipmunk_ns = 0
        self.inclusive_ns = dict.fromkeys((name for name, _, _ in TIMED), 0)

    def record(self, run, pid: int, polygon_bf, contact, judged, cpu_ns: int) -> None:
        share = 1.0 if run.motion is None else run.motion.load_share.get(pid, 1.0)
        pieces = run.pieces
        scalars = np.array([pieces.thickness[pid], pieces.crack_count[pid], share], dtype=float)
        self.pid.append(pid)
        self.bow_x_m.append(self.bow_x)
        self.polygon_bf.append(polygon_bf)
        self.key.append(shapely.get_coordinates(polygon_bf).tobytes() + scalars.tobytes())
        self.contact.append(_contact_numbers(contact))
        self.cpu_ns.append(cpu_ns)
        self.failed.append(bool(judged[1].failed))


@contextmanager
def _wrapped(tally: _Tally):
    """The judgement, the piece evaluation (for its bow position), the engine step and Chipmunk's step
    wrapped to feed `tally`; the originals restored on exit."""
    run_cls, engine_cls = simulation._Run, engine.IceMotionEngine
    judge, evaluate, step, space_step = (
        run_cls.judge,
        run_cls._evaluate_piece,
        engine_cls.step,
        pymunk.Space.step,
    )

    def timed_judge(self, pid, polygon_bf, contact):
        start = time.process_time_ns()
        judged = judge(self, pid, polygon_bf, contact)
        cpu_ns = time.process_time_ns() - start
        tally.record(self, pid, polygon_bf, contact, judged, cpu_ns)
        return judged

    def located_evaluate(self, step_index, bow_x, pid, polygon_bf, contact):
        tally.bow_x = bow_x
        return evaluate(self, step_index, bow_x, pid, polygon_bf, contact)

    def counted_step(self, dt_s=None):
        tally.engine_steps += 1
        return step(self, dt_s)

    def timed_space_step(self, dt):
        start = time.process_time_ns()
        space_step(self, dt)
        tally.chipmunk_ns += time.process_time_ns() - start
        tally.chipmunk_steps += 1

    run_cls.judge, run_cls._evaluate_piece = timed_judge, located_evaluate
    engine_cls.step, pymunk.Space.step = counted_step, timed_space_step
    originals = [(owner, attr, getattr(owner, attr)) for _, owner, attr in TIMED]
    for (name, owner, attr), (_, _, original) in zip(TIMED, originals, strict=True):
        setattr(owner, attr, _timer(tally, name, original))
    try:
        yield
    finally:
        for owner, attr, original in reversed(originals):
            setattr(owner, attr, original)
        run_cls.judge, run_cls._evaluate_piece = judge, evaluate
        engine_cls.step, pymunk.Space.step = step, space_step


def _timer(tally: _Tally, name: str, function):
    def timed(*args, **kwargs):
        start = time.process_time_ns()
        try:
            return function(*args, **kwargs)
        finally:
            tally.inclusive_ns[name] += time.process_time_ns() - start

    return timed


def _run(size: list[str], motion: list[str]) -> float:
    """CPU time of `simulate` on the reference transit with the `motion` overrides."""
    scenario = Scenario.reference([*size, *motion]).resolved()
    field = build_field(scenario, np.random.default_rng(scenario.seed))
    bow, model = build_bow(scenario, field), build_model_for(scenario)
    params = SimulationParams(step_m=scenario.ship.step_m, **ice_motion_params(scenario))
    start = time.process_time()
    simulate(field, bow, model, params)
    return time.process_time() - start


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    if a.shape != b.shape:
        return False
    scale = np.maximum(np.abs(a), np.abs(b))
    return bool(np.all((a == b) | (np.abs(a - b) <= TOLERANCE * scale) | (np.isnan(a) & np.isnan(b))))


def _in_field(polygons_bf: np.ndarray, bow_x_m: np.ndarray) -> np.ndarray:
    shifted = [translate(p, xoff=x) for p, x in zip(polygons_bf, bow_x_m, strict=True)]
    return np.array(shifted, dtype=object)


def _summary(tally: _Tally) -> dict[str, float]:
    """Counts, cache hits, movements and CPU times of one run's judgements."""
    last: dict[int, int] = {}
    seen: set[bytes] = set()
    again, hit_last, hit_any, near = [], 0, 0, 0
    for i, pid in enumerate(tally.pid):
        j = last.get(pid)
        if j is not None:
            again.append((j, i))
            hit_last += tally.key[i] == tally.key[j]
            hit_any += tally.key[i] in seen
            a = shapely.get_coordinates(tally.polygon_bf[i])
            b = shapely.get_coordinates(tally.polygon_bf[j])
            same_shape = a.shape == b.shape and tally.key[i][-24:] == tally.key[j][-24:]
            near += (
                same_shape
                and bool(np.all(np.abs(a - b) <= TOLERANCE))
                and _close(tally.contact[i], tally.contact[j])
            )
        seen.add(tally.key[i])
        last[pid] = i
    before, after = (np.array([pair[k] for pair in again], dtype=np.int64) for k in (0, 1))
    polygons = np.array(tally.polygon_bf, dtype=object)
    bow_x = np.array(tally.bow_x_m)
    if len(after):
        bow_frame = shapely.hausdorff_distance(polygons[before], polygons[after])
        field_moved = shapely.hausdorff_distance(
            _in_field(polygons[before], bow_x[before]), _in_field(polygons[after], bow_x[after])
        )
    else:
        bow_frame = field_moved = np.zeros(0)
    cpu_s = np.array(tally.cpu_ns) * 1e-9
    return {
        "judgements": len(tally.pid),
        "rejudged": len(after),
        "rejudged_broke": int(np.count_nonzero(np.array(tally.failed)[after])) if len(after) else 0,
        "hit_last": hit_last,
        "hit_any": hit_any,
        "near": near,
        "bow_moved": bow_frame,
        "field_moved": field_moved,
        "judge_cpu_s": float(cpu_s.sum()),
        "rejudge_cpu_s": float(cpu_s[after].sum()) if len(after) else 0.0,
        "engine_steps": tally.engine_steps,
        "chipmunk_us": 1e6 * tally.chipmunk_ns * 1e-9 / max(tally.chipmunk_steps, 1),
        "chipmunk_s": tally.chipmunk_ns * 1e-9,
        "inclusive_s": {name: ns * 1e-9 for name, ns in tally.inclusive_ns.items() if ns},
    }


def _instrumented(size: list[str], motion: list[str]) -> dict[str, float]:
    tally = _Tally()
    with _wrapped(tally):
        cpu_s = _run(size, motion)
    return {**_summary(tally), "cpu_s": cpu_s}


def _distances(values: np.ndarray) -> str:
    if not len(values):
        return "none"
    p5, median, p95 = np.percentile(values, [5, 50, 95])
    return (
        f"min {values.min():.3f}, 5 % {p5:.3f}, median {median:.3f}, 95 % {p95:.3f} m; "
        f"{np.count_nonzero(values < 0.01)} below 0.01 m, {np.count_nonzero(values < 0.1)} below 0.1 m"
    )


def _report(name: str, row: dict[str, float]) -> None:
    judged, again = row["judgements"], row["rejudged"]
    print(
        f"{name}: {judged} judgements, {again} re-judgements ({row['rejudged_broke']} broke the piece); "
        f"exact-cache hits {row['hit_last']} (piece's last), {row['hit_any']} (any earlier), "
        f"{row['near']} within {TOLERANCE:g}"
    )
    print(f"  moved between judgements, bow frame: {_distances(row['bow_moved'])}")
    print(f"  moved between judgements, field: {_distances(row['field_moved'])}")
    per_call = 1e6 * row["judge_cpu_s"] / max(judged, 1)
    print(
        f"  CPU: simulate {row['cpu_s']:.2f} s (wrapped), judgements {row['judge_cpu_s']:.2f} s "
        f"({per_call:.0f} µs each), re-judgements {row['rejudge_cpu_s']:.2f} s"
    )
    if row["engine_steps"]:
        print(
            f"  engine steps {row['engine_steps']}, Chipmunk {row['chipmunk_us']:.0f} µs per step "
            f"({row['chipmunk_s']:.2f} s)"
        )
    print("  inclusive: " + ", ".join(f"{name} {t:.2f} s" for name, t in row["inclusive_s"].items()))


def _load_average() -> str:
    return " ".join(f"{v:.1f}" for v in os.getloadavg())


def main(argv: list[str]) -> None:
    size = (
        ["field.length_m=385.0", "field.width_m=100.0"]
        if "--short" in argv
        else ["field.length_m=1000.0", "field.width_m=200.0"]
    )
    steps = argv[argv.index("--steps") + 1].split(",") if "--steps" in argv else ["0.02"]
    repeats = int(argv[argv.index("--repeat") + 1]) if "--repeat" in argv else 3
    seed = [f"seed={argv[argv.index('--seed') + 1]}"] if "--seed" in argv else []
    motions = {"static": ["simulation.ice_motion=static", *seed]}
    for dt in steps:
        motions[f"dynamic {dt} s"] = ["simulation.ice_motion=dynamic", f"ice_motion.time_step_s={dt}", *seed]
    # the first run in a process pays one-time costs (imports, caches): not measured
    _run(["field.length_m=60.0", "field.width_m=100.0"], motions[f"dynamic {steps[0]} s"])
    print(f"{' × '.join(v.split('=')[1] for v in size)} m; load average {_load_average()} (1, 5, 15 min)")
    rows = {}
    for name, motion in motions.items():
        rows[name] = _instrumented(size, motion)
        _report(name, rows[name])
    if repeats <= 0:
        return
    times: dict[str, list[float]] = {name: [] for name in motions}
    for _ in range(repeats):
        for name, motion in motions.items():
            times[name].append(_run(size, motion))
    static = float(np.median(times["static"]))
    for name in motions:
        median = float(np.median(times[name]))
        line = f"unwrapped {name}: CPU {median:.2f} s (runs {', '.join(f'{t:.2f}' for t in times[name])})"
        if name != "static":
            free = (median - rows[name]["rejudge_cpu_s"]) / static
            line += f", ratio {median / static:.2f}, with free re-judgements {free:.2f}"
        print(line)
    print(f"load average {_load_average()} (1, 5, 15 min)")


if __name__ == "__main__":
    compile_kernels()
    engine.compile_now()
    gc.freeze()
    main(sys.argv[1:])
