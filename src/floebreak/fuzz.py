"""Fuzz campaign: random valid scenarios over the options and the edges of the ranges, each run checked.

``python -m floebreak.fuzz --n 5000 --seed 1 --jobs 2 --out fuzz-report`` (or ``make fuzz N=5000 SEED=1``)
draws `n` whole scenarios with hypothesis (`scenario_dicts`), runs each through `floebreak.run` in worker
processes and checks: no internal error (an `InputError` is a refusal, allowed), the area balance
(≤ `AREA_TOLERANCE`), every output polygon valid (`shapely.is_valid`), and each run's peak resident memory
(≤ `--max-rss-mb`). Each run's record is appended to ``records.jsonl`` in ``--out`` as it completes
(``--resume`` continues a stopped campaign, ``--summarize`` rebuilds ``summary.json`` from the records);
each violation's scenario is saved there as TOML with its traceback. The test suite runs a small fixed
sample (tests/test_fuzz.py); the campaign is the documented command (benchmarks/README.md, fuzz).

Ranges are those of `floebreak.scenario` (one place). To keep a run to at most about a second of CPU
(5 000 runs in well under an hour on 2 shared cores), a run's cost is capped where it grows without
exercising another code path: fields are at most 100 m × 100 m (a bow is 20–25 m wide), the thinnest ice
(< 0.1 m, which breaks into thousands of pieces: ≈ 8 ms each) gets 10 m of transit, a run at most
`MAX_STEPS` steps (short steps a short transit: 0.5 m at 1 mm) and a budget of `MAX_PIECES` pieces (a run
that reaches it is a refusal, exit 2, as for a user). The caps leave the options and range edges drawn as
they were. Drawn: the profile, the field (observation, user observation or inline floes; generator,
cover, clustering), every [ice] number, the ship (hull, step, waterlines, initial contact, speed), the flat
[failure] keys and, from the failure-mode registry, any setting of every mode's ``[failure.<mode>]`` table
(numbers within their `Bounds`, choices among their `Literal` values). Not drawn: the ``sqp`` generator (a
slow reference for small fields), bow CSV files and hull parameters, field files, the propeller section
(not used by `floebreak.run`'s breaking) and the dispatch policy lists.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import sys
import time
import traceback
import typing
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any, Literal

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

from floebreak import scenario as sc

AREA_TOLERANCE = 1e-9  # the engine's own (`floebreak.simulation.AREA_BALANCE_TOLERANCE`)
MAX_PIECES = 5_000
MAX_STEPS = 500
OBSERVATIONS = (
    "2019-12-18T20:20",
    "2019-12-18T22:30",
    "2019-12-19T04:40",
    "2019-12-30T07:10",
    "2019-12-30T13:10",
    "2019-12-30T16:10",
    "2020-01-02T15:20",
    "2020-01-02T17:50",
    "2020-01-03T13:40",
    "2020-01-03T17:40",
)


def _edge_or_inside(low: float, high: float, log: bool = False) -> st.SearchStrategy[float]:
    """The range's edges, or a value inside it (log-uniform for ranges over decades)."""
    if log:
        inside = st.floats(math.log10(low), math.log10(high)).map(
            lambda e: float(min(max(10.0**e, low), high))
        )
    else:
        inside = st.floats(low, high, allow_nan=False, allow_infinity=False)
    return st.one_of(st.sampled_from([low, high]), inside, inside)


def _ice() -> st.SearchStrategy[dict[str, Any]]:
    thickness = _edge_or_inside(*sc.THICKNESS_M, log=True)
    return st.fixed_dictionaries(
        {},
        optional={
            "thickness_m": thickness,
            "fracture_toughness_pa_sqrt_m": _edge_or_inside(1.0e3, 1.0e7, log=True),
            "flexural_strength_pa": _edge_or_inside(1.0e3, 1.0e8, log=True),
            "crushing_strength_pa": _edge_or_inside(1.0e3, 1.0e8, log=True),
            "contact_coefficient": _edge_or_inside(1e-3, 10.0, log=True),
            "friction_coefficient": _edge_or_inside(0.0, 2.0),
            "youngs_modulus_pa": _edge_or_inside(1.0e6, 1.0e11, log=True),
            "poisson_ratio": _edge_or_inside(0.01, 0.49),
        },
    )


@st.composite
def _field(draw) -> dict[str, Any]:
    source = draw(st.sampled_from(["observation", "observation", "user_observation", "floes"]))
    if source == "floes":
        n = draw(st.integers(1, 6))
        floes, x = [], 5.0
        for _ in range(n):  # placed along x without overlap
            d = draw(_edge_or_inside(1.0, 40.0))
            y = draw(st.floats(-20.0, 20.0))
            floes.append({"x_m": x + d / 2, "y_m": y, "diameter_m": d})
            x += d + draw(st.floats(0.01, 10.0))
        return {"floes": floes}
    field: dict[str, Any] = {
        "length_m": draw(_edge_or_inside(20.0, 100.0)),
        "width_m": draw(_edge_or_inside(20.0, 100.0)),
        "generator": draw(st.sampled_from(["circles", "voronoi"])),
    }
    if source == "observation":
        field["observation"] = draw(st.sampled_from(OBSERVATIONS))
    else:
        k = draw(st.integers(1, 3))
        field["diameter_classes_m"] = sorted(
            draw(st.lists(_edge_or_inside(1.0, 30.0), min_size=k, max_size=k, unique=True))
        )
        shares = draw(st.lists(st.integers(1, 10), min_size=k, max_size=k))
        field["percentages"] = [100.0 * s / sum(shares) for s in shares]
        field["concentration"] = draw(_edge_or_inside(0.05, 0.9))
    if draw(st.booleans()):
        field["concentration"] = draw(_edge_or_inside(0.05, 1.0))
    if draw(st.booleans()):
        field["clustering"] = draw(_edge_or_inside(0.0, 10.0))
    return field


def _within(bounds) -> st.SearchStrategy[float]:
    """A value of a `floebreak.errors.Bounds` interval: its edges (nudged inside where open) or inside it."""
    low = bounds.low if bounds.low_inclusive else math.nextafter(bounds.low, math.inf)
    high = bounds.high if bounds.high_inclusive else math.nextafter(bounds.high, -math.inf)
    return _edge_or_inside(low, high, log=low > 0 and high / low >= 100.0)


@st.composite
def _mode_tables(draw, drawn_flat: set[tuple[str, str]]) -> dict[str, dict[str, Any]]:
    """``[failure.<mode>]`` tables: some settings of every registered mode, each number within its `Bounds`
    and each choice among its `Literal` values (settings given by a flat [failure] key are left out)."""
    from floebreak.errors import field_bounds
    from floebreak.failure import get_mode, mode_names

    tables: dict[str, dict[str, Any]] = {}
    for name in mode_names():
        spec = get_mode(name)
        if spec.settings is None:
            continue
        bounds = field_bounds(spec.settings)
        hints = typing.get_type_hints(spec.settings)
        for key in spec.table_keys():
            if (name, key) in drawn_flat or not draw(st.booleans()):
                continue
            choices = typing.get_args(hints[key]) if typing.get_origin(hints[key]) is Literal else ()
            if key in bounds:
                tables.setdefault(name, {})[key] = draw(_within(bounds[key]))
            elif choices:
                tables.setdefault(name, {})[key] = draw(st.sampled_from(choices))
            elif hints[key] is bool:
                tables.setdefault(name, {})[key] = draw(st.booleans())
    return tables


def _ship(draw) -> dict[str, Any]:
    ship = {
        "hull": draw(st.sampled_from(["agulhas_ii", "polarstern"])),
        "step_m": draw(st.one_of(st.sampled_from([sc.STEP_M[0], sc.STEP_M[1]]), _edge_or_inside(0.05, 3.0))),
        "initial_contact": draw(st.sampled_from(["shift_field", "shift_floes"])),
    }
    if draw(st.booleans()):
        ship["waterlines"] = draw(st.sampled_from(["follow_thickness", "fixed"]))
        ship["waterline_ice_thickness_m"] = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    if draw(st.booleans()):
        ship["speed_m_s"] = draw(_edge_or_inside(0.01, sc.SPEED_M_S[1]))
    return ship


@st.composite
def scenario_dicts(draw) -> dict[str, Any]:
    """A whole valid scenario (a dict as read from TOML)."""
    data: dict[str, Any] = {
        "profile": draw(st.sampled_from(["default", "thesis"])),
        "seed": draw(st.integers(0, 2**31)),
        "field": draw(_field()),
        "ice": draw(_ice()),
        "ship": _ship(draw),
        "failure": {
            "crack_criterion": draw(
                st.sampled_from(["point_load", "line_load", "tensile_stress", "flexural_stress"])
            ),
            "size_effect_law": draw(st.sampled_from(["BZ", "BZ1", "BZ2"])),
            "stress_mode": draw(st.sampled_from(["thesis", "strength", "sif"])),
            "wedge_angle_deg": draw(_edge_or_inside(0.5, 60.0)),
            "next_crack_angle_deg": draw(_edge_or_inside(0.0, 90.0)),
            "shoulder_region_start": draw(_edge_or_inside(0.0, 1.0)),
            "flip_uncracked_at_shoulder": draw(st.booleans()),
        },
        "simulation": {"max_pieces": MAX_PIECES},
    }
    flat = {sc.FLAT_FAILURE_KEYS[key] for key in data["failure"] if key in sc.FLAT_FAILURE_KEYS}
    data["failure"].update(draw(_mode_tables(flat)))
    if "thickness_m" not in data["ice"] and draw(st.booleans()):
        low = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
        data["ice"]["thickness_range_m"] = [low, draw(_edge_or_inside(low, sc.THICKNESS_M[1], log=True))]
    elif "observation" not in data["field"] and "thickness_m" not in data["ice"]:  # no observed thickness
        data["ice"]["thickness_m"] = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    thickness = data["ice"].get("thickness_m") or (data["ice"].get("thickness_range_m") or [1.0])[0]
    transit_m = min(10.0 if thickness < 0.1 else math.inf, MAX_STEPS * data["ship"]["step_m"])
    if transit_m < 150.0:  # else the default: the hull passes the field
        data["ship"]["x_end_m"] = transit_m
    return data


def draw_scenarios(n: int, campaign_seed: int) -> list[dict[str, Any]]:
    """`n` scenarios drawn by hypothesis from `campaign_seed` (same seed → same scenarios)."""
    drawn: list[dict[str, Any]] = []

    @seed(campaign_seed)
    @settings(
        max_examples=n,
        phases=[Phase.generate],
        database=None,
        deadline=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(scenario_dicts())
    def collect(data):
        drawn.append(data)

    collect()
    return drawn[:n]


def _peak_rss_reset() -> bool:
    """Reset this process's peak resident memory (Linux ``/proc/self/clear_refs``); False if unsupported."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        return False
    return True


def _peak_rss_mb(reset: bool) -> float:
    """Peak resident memory in MB: of this run (``VmHWM`` after a reset), else of the process so far."""
    if reset:
        try:
            for line in Path("/proc/self/status").read_text().splitlines():
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
        except OSError:
            pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def check_one(data: dict[str, Any]) -> dict[str, Any]:
    """Run one scenario and check it; returns a JSON-able record (runs in a worker process)."""
    import numpy as np
    import shapely

    import floebreak
    from floebreak.errors import InputError

    reset = _peak_rss_reset()
    started, cpu = time.perf_counter(), time.process_time()
    record: dict[str, Any] = {"scenario": data, "status": "ok", "problems": []}
    try:
        result = floebreak.run(data)
    except InputError as error:
        record.update(status="refused", message=str(error))
    except Exception as error:  # everything else is what the campaign looks for
        record.update(status="crash", message="".join(traceback.format_exception(error)))
    else:
        balance = result.summary["area_balance_rel_error"]
        record["area_balance_rel_error"] = balance
        if not balance <= AREA_TOLERANCE:
            record["problems"].append(f"area balance {balance:.3e}")
        for name in ("cusps", "flipped", "remaining", "pieces"):
            geometry = np.asarray(getattr(result, name)["geometry"], dtype=object)
            invalid = int((~shapely.is_valid(geometry)).sum()) if geometry.size else 0
            if invalid:
                record["problems"].append(f"{invalid} invalid polygons in {name}")
    record["seconds"] = time.perf_counter() - started
    record["cpu_seconds"] = time.process_time() - cpu  # the run's own cost, whatever the host's load
    record["peak_rss_mb"] = _peak_rss_mb(reset)
    return record


WORKER_SCENARIOS = 100  # scenarios per fresh worker process (bounds what a leak could accumulate)


def _indexed(check: Callable[[dict[str, Any]], dict[str, Any]], index: int, data: dict[str, Any]):
    return {"index": index, **check(data)}


def _records(todo: list[tuple[int, dict[str, Any]]], jobs: int, check=check_one):
    """The `check` records of `todo` (index, scenario) in completion order, each with its ``index``: in this
    process (jobs = 0, the test suite's sample), else in `jobs` one-worker pools, each replaced by a fresh
    one after `WORKER_SCENARIOS` (not ``max_tasks_per_child``: Python 3.11's executor hangs when a worker
    retires). One task per worker at a time, so a slow scenario holds only its own worker."""
    if not jobs:
        yield from (_indexed(check, i, data) for i, data in todo)
        return
    pending = iter(todo)
    slots: dict[Future, tuple[ProcessPoolExecutor, int]] = {}

    def submit(pool: ProcessPoolExecutor | None, done: int) -> None:
        task = next(pending, None)
        if pool is not None and (task is None or done >= WORKER_SCENARIOS):
            pool.shutdown()
            pool, done = None, 0
        if task is not None:
            pool = pool or ProcessPoolExecutor(max_workers=1)
            slots[pool.submit(_indexed, check, *task)] = (pool, done + 1)

    try:
        for _ in range(jobs):
            submit(None, 0)
        while slots:
            finished, _ = wait(slots, return_when=FIRST_COMPLETED)
            for future in finished:
                pool, done = slots.pop(future)
                yield future.result()
                submit(pool, done)
    finally:
        for pool, _ in slots.values():
            pool.shutdown(wait=False, cancel_futures=True)


def _percentile(values: list[float], q: float) -> float:
    """The nearest-rank percentile (the smallest value with at least `q` of the values at or below it)."""
    ordered = sorted(values)
    return ordered[max(0, math.ceil(q * len(ordered)) - 1)] if ordered else 0.0


def _distribution(values: list[float]) -> dict[str, float]:
    return {
        "total": sum(values),
        "p50": _percentile(values, 0.5),
        "p90": _percentile(values, 0.9),
        "max": max(values, default=0.0),
    }


def _flagged(record: dict[str, Any], max_rss_mb: float) -> bool:
    return record["status"] == "crash" or bool(record["problems"]) or record["peak_rss_mb"] > max_rss_mb


def summarize(records: list[dict[str, Any]], n: int, campaign_seed: int, max_rss_mb: float) -> dict[str, Any]:
    """The campaign's summary from its records (so it can be rebuilt from ``records.jsonl``): counts, the
    worst area balance and peak memory, the time distribution and the 10 slowest scenarios."""
    counts = {"runs": len(records), "ok": 0, "refused": 0, "crash": 0, "violations": 0, "over_memory": 0}
    for record in records:
        counts[record["status"]] += 1
        counts["violations"] += bool(record["problems"])
        counts["over_memory"] += record["peak_rss_mb"] > max_rss_mb
    slowest = sorted(records, key=lambda record: -record["seconds"])[:10]
    return {
        "n": n,
        "seed": campaign_seed,
        **counts,
        "max_rss_mb": max_rss_mb,
        "worst": {
            "area_balance_rel_error": max(
                (r.get("area_balance_rel_error") or 0.0 for r in records), default=0
            ),
            "peak_rss_mb": max((r["peak_rss_mb"] for r in records), default=0.0),
        },
        **{key: _distribution([r.get(key, 0.0) for r in records]) for key in ("seconds", "cpu_seconds")},
        "slowest": [
            {key: r.get(key) for key in ("index", "status", "seconds", "cpu_seconds", "scenario")}
            for r in slowest
        ],
    }


def read_records(out: Path, n: int, campaign_seed: int) -> list[dict[str, Any]]:
    """The records already in ``out/records.jsonl`` (none if absent); refuses those of another campaign.
    A line cut by a stopped campaign (the last, unterminated) is dropped: that scenario is run again."""
    path = out / "records.jsonl"
    if not path.exists():
        return []
    records = []
    for line in path.read_text(encoding="utf-8").splitlines(keepends=True):
        if not line.endswith("\n"):
            break
        record = json.loads(line)
        if (record["n"], record["seed"]) != (n, campaign_seed):
            raise SystemExit(
                f"{path} holds the campaign n={record['n']} seed={record['seed']}, "
                f"not n={n} seed={campaign_seed}"
            )
        records.append(record)
    return records


def _write_case(out: Path, record: dict[str, Any]) -> None:
    import tomli_w

    text = "".join(f"# {line}\n" for line in json.dumps(record, default=str, indent=1).splitlines())
    (out / f"case-{record['index']:05d}.toml").write_text(text + tomli_w.dumps(record["scenario"]), "utf-8")


def run_campaign(
    n: int,
    campaign_seed: int,
    jobs: int,
    out: Path,
    max_rss_mb: float,
    resume: bool = False,
    check: Callable[[dict[str, Any]], dict[str, Any]] = check_one,
) -> dict[str, Any]:
    """Draw and `check` `n` scenarios. Each record is appended to ``out/records.jsonl`` as it completes (with
    `resume`, the indices already recorded there are skipped; without it an existing campaign is refused),
    each violation saved as ``case-NNNNN.toml``; writes ``summary.json`` and returns the summary."""
    out.mkdir(parents=True, exist_ok=True)
    records = read_records(out, n, campaign_seed)
    if records and not resume:
        raise SystemExit(f"{out / 'records.jsonl'} exists: pass --resume to continue it, or another --out")
    done = {record["index"] for record in records}
    scenarios = draw_scenarios(n, campaign_seed)
    todo = [(i, data) for i, data in enumerate(scenarios) if i not in done]
    path = out / "records.jsonl"
    if path.exists():  # drop a line cut by a stopped campaign
        os.truncate(path, path.read_bytes().rfind(b"\n") + 1)
    with path.open("a", encoding="utf-8") as log:
        for record in _records(todo, jobs, check):
            record.update(n=n, seed=campaign_seed)
            log.write(json.dumps(record, default=str) + "\n")
            log.flush()
            records.append(record)
            if _flagged(record, max_rss_mb):
                _write_case(out, record)
            if len(records) % 25 == 0:
                print(f"{len(records)} of {n}: {_brief(records, max_rss_mb)}", file=sys.stderr, flush=True)
    summary = summarize(records, n, campaign_seed, max_rss_mb)
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


def _brief(records: list[dict[str, Any]], max_rss_mb: float) -> dict[str, int]:
    summary = summarize(records, 0, 0, max_rss_mb)
    return {key: summary[key] for key in ("ok", "refused", "crash", "violations", "over_memory")}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m floebreak.fuzz", description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=200, help="number of scenarios")
    parser.add_argument("--seed", type=int, default=1, help="campaign seed (same seed → same scenarios)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--out", type=Path, default=Path("fuzz-report"), help="records, violations")
    parser.add_argument("--max-rss-mb", type=float, default=1024.0, help="peak memory allowed per run")
    parser.add_argument("--resume", action="store_true", help="continue the campaign recorded in --out")
    parser.add_argument(
        "--summarize", action="store_true", help="only rebuild summary.json from --out/records.jsonl"
    )
    args = parser.parse_args(argv)
    started = time.perf_counter()
    if args.summarize:
        summary = summarize(read_records(args.out, args.n, args.seed), args.n, args.seed, args.max_rss_mb)
        (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    else:
        summary = run_campaign(args.n, args.seed, args.jobs, args.out, args.max_rss_mb, args.resume)
    print(json.dumps(summary, indent=2), f"\n{time.perf_counter() - started:.0f} s")
    return 1 if summary["crash"] or summary["violations"] or summary["over_memory"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
