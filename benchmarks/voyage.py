"""Voyage benchmark (issue 18 §4): thesis Table 1 as a log, end to end through the CLI, on 2 workers.

``floebreak voyage examples/agu1920_log.csv --out TMP --n-fields 4 --workers 2``: 10 periods of 10 min at
the default speed (3 m/s → 1.8 km each, simulated on 400 m fields), 40 runs. Goal: ≤ 5 min wall time on
2 cores. Wall time: ``time.perf_counter`` around the child process; CPU time (user + system of the CLI and
its worker processes, ``os.wait4``) is printed too: on a shared machine it is less sensitive to load.

Run: ``.venv/bin/python benchmarks/voyage.py [--n-fields 4] [--workers 2]`` (the CLI next to the running
Python is used). The voyage directory is a temporary one, removed afterwards (`--keep DIR`: kept in DIR).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
GOAL_SECONDS = 300.0


def _cli() -> str:
    path = Path(sys.executable).parent / "floebreak"
    if not path.exists():
        sys.exit(f"no floebreak entry point next to {sys.executable}; run with the project's venv Python")
    return str(path)


def measure(n_fields: int, workers: int, keep: Path | None = None) -> dict:
    with tempfile.TemporaryDirectory() as temp:
        out = keep if keep is not None else Path(temp) / "voyage"
        command = [
            _cli(),
            "voyage",
            str(REPO / "examples" / "agu1920_log.csv"),
            "--out",
            str(out),
            "--n-fields",
            str(n_fields),
            "--workers",
            str(workers),
        ]
        env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        log = Path(temp) / "output.txt"
        with open(log, "w", encoding="utf-8") as handle:  # a file: a full pipe would block the child
            started = time.perf_counter()
            child = subprocess.Popen(command, env=env, stdout=handle, stderr=subprocess.STDOUT)
            _, status, usage = os.wait4(child.pid, 0)
            wall = time.perf_counter() - started
        output = log.read_text(encoding="utf-8")
        if os.waitstatus_to_exitcode(status) != 0:
            sys.exit(f"voyage failed:\n{output}")
        summary = json.loads((out / "results" / "summary.json").read_text(encoding="utf-8"))
        engine = [
            json.loads(p.read_text(encoding="utf-8"))["wall_time_s"] for p in out.glob("runs/*/summary.json")
        ]
    return {
        "wall_s": wall,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "runs": len(engine),
        "engine_s_sum": sum(engine),
        "periods_simulated": summary["n_periods_simulated"],
        "cusps_per_hour": summary["cusps_per_hour"],
        "generators": [g for g, _ in summary["generators"].values()],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-fields", type=int, default=4)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="write the voyage here (a new directory) and keep it")
    args = parser.parse_args()
    if args.keep is not None and args.keep.exists():
        sys.exit(f"{args.keep} exists: the benchmark needs a new directory (an existing voyage would resume)")
    result = measure(args.n_fields, args.workers, args.keep)
    verdict = "met" if result["wall_s"] <= GOAL_SECONDS else "NOT met"
    print(
        f"voyage agu1920_log.csv, {args.n_fields} fields/period, {args.workers} workers: "
        f"wall {result['wall_s']:.1f} s, CPU {result['cpu_s']:.1f} s, {result['runs']} runs "
        f"(engine {result['engine_s_sum']:.1f} s summed), {result['periods_simulated']} periods, "
        f"{result['cusps_per_hour']:.0f} cusps/h; generators {result['generators']}; "
        f"goal ≤ {GOAL_SECONDS:.0f} s: {verdict}"
    )


if __name__ == "__main__":
    main()
