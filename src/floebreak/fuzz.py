"""Fuzz campaign: random valid scenarios over every option and the edges of every range, each run checked.

``python -m floebreak.fuzz --n 5000 --seed 1 --jobs 2 --out fuzz-report`` (or ``make fuzz N=5000 SEED=1``)
draws `n` whole scenarios with hypothesis (`scenario_dicts`), runs each through `floebreak.run` in worker
processes and checks: no internal error (an `InputError` is a refusal, allowed), the area balance
(≤ `AREA_TOLERANCE`), every output polygon valid (`shapely.is_valid`), and the workers' peak resident memory
(≤ `--max-rss-mb`). Each violation's scenario is saved as TOML in ``--out`` with its traceback; the summary
counts runs, refusals, crashes and violations. The test suite runs a small fixed sample
(tests/test_fuzz.py); the campaign is the documented command (benchmarks/README.md, fuzz).

Ranges are those of `floebreak.scenario` (one place). To keep a run to seconds, fields are at most 250 m ×
150 m, the thinnest ice (< 0.1 m) gets at most 80 m of transit, the shortest steps a 5 m transit, and every
run a budget of `MAX_PIECES` pieces (a run that reaches it is a refusal, exit 2, as for a user). The
``sqp`` generator (a slow reference for small fields) is not drawn.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
import traceback
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

from floebreak import scenario as sc

AREA_TOLERANCE = 1e-9  # the engine's own (`floebreak.simulation.AREA_BALANCE_TOLERANCE`)
MAX_PIECES = 20_000
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
        import math

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
        "length_m": draw(_edge_or_inside(20.0, 250.0)),
        "width_m": draw(_edge_or_inside(20.0, 150.0)),
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


@st.composite
def scenario_dicts(draw) -> dict[str, Any]:
    """A whole valid scenario (a dict as read from TOML)."""
    data: dict[str, Any] = {
        "profile": draw(st.sampled_from(["default", "thesis"])),
        "seed": draw(st.integers(0, 2**31)),
        "field": draw(_field()),
        "ice": draw(_ice()),
        "ship": {
            "hull": draw(st.sampled_from(["agulhas_ii", "polarstern"])),
            "step_m": draw(
                st.one_of(st.sampled_from([sc.STEP_M[0], sc.STEP_M[1]]), _edge_or_inside(0.05, 3.0))
            ),
        },
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
    if "thickness_m" not in data["ice"] and draw(st.booleans()):
        low = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
        data["ice"]["thickness_range_m"] = [low, draw(_edge_or_inside(low, sc.THICKNESS_M[1], log=True))]
    elif "floes" in data["field"] and "thickness_m" not in data["ice"]:
        data["ice"]["thickness_m"] = draw(_edge_or_inside(*sc.THICKNESS_M, log=True))
    thickness = data["ice"].get("thickness_m") or (data["ice"].get("thickness_range_m") or [1.0])[0]
    if thickness < 0.1:  # thin ice breaks into many pieces: a short transit
        data["ship"]["x_end_m"] = 80.0
    if data["ship"]["step_m"] < 0.05:
        data["ship"]["x_end_m"] = 5.0
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


def check_one(data: dict[str, Any]) -> dict[str, Any]:
    """Run one scenario and check it; returns a JSON-able record (runs in a worker process)."""
    import numpy as np
    import shapely

    import floebreak
    from floebreak.errors import InputError

    started = time.perf_counter()
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
    record["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # the worker's so far
    return record


WORKER_SCENARIOS = 100  # scenarios per pool of fresh workers (a worker's peak memory covers few runs)


def _records(scenarios: list[dict[str, Any]], jobs: int):
    """The check records in order: in this process (jobs = 0, the test suite's sample), else in pools of
    `jobs` fresh workers, one pool per `WORKER_SCENARIOS` (not ``max_tasks_per_child``: Python 3.11's
    executor hangs when a worker retires)."""
    if not jobs:
        yield from map(check_one, scenarios)
        return
    for start in range(0, len(scenarios), WORKER_SCENARIOS):
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            yield from pool.map(check_one, scenarios[start : start + WORKER_SCENARIOS])


def run_campaign(n: int, campaign_seed: int, jobs: int, out: Path, max_rss_mb: float) -> dict[str, Any]:
    """Draw and check `n` scenarios; write violations and ``summary.json`` into `out`; return the summary."""
    import tomli_w

    out.mkdir(parents=True, exist_ok=True)
    scenarios = draw_scenarios(n, campaign_seed)
    counts = {"runs": 0, "ok": 0, "refused": 0, "crash": 0, "violations": 0, "over_memory": 0}
    worst = {"area_balance_rel_error": 0.0, "peak_rss_mb": 0.0, "seconds": 0.0}
    for i, record in enumerate(_records(scenarios, jobs)):
        counts["runs"] += 1
        counts[record["status"]] += 1
        counts["violations"] += bool(record["problems"])
        over = record["peak_rss_mb"] > max_rss_mb
        counts["over_memory"] += over
        for key in worst:
            worst[key] = max(worst[key], record.get(key) or 0.0)
        if (i + 1) % 25 == 0:
            print(f"{i + 1} of {n}: {counts}", file=sys.stderr, flush=True)
        if record["status"] == "crash" or record["problems"] or over:
            text = "".join(f"# {line}\n" for line in json.dumps(record, default=str, indent=1).splitlines())
            (out / f"case-{i:05d}.toml").write_text(
                text + tomli_w.dumps(record["scenario"]), encoding="utf-8"
            )
    summary = {"n": n, "seed": campaign_seed, **counts, "worst": worst, "max_rss_mb": max_rss_mb}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m floebreak.fuzz", description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=200, help="number of scenarios")
    parser.add_argument("--seed", type=int, default=1, help="campaign seed (same seed → same scenarios)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--out", type=Path, default=Path("fuzz-report"), help="folder for violations")
    parser.add_argument("--max-rss-mb", type=float, default=1024.0, help="peak memory allowed per worker")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    summary = run_campaign(args.n, args.seed, args.jobs, args.out, args.max_rss_mb)
    print(json.dumps(summary, indent=2), f"\n{time.perf_counter() - started:.0f} s")
    return 1 if summary["crash"] or summary["violations"] or summary["over_memory"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
