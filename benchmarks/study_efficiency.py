"""Parallel efficiency of a local study (issue 20): the same runs serially and on a pool of 2 workers.

A study of 8 runs (reference scenario, 400 m × 50 m, each run its own field: `common_fields = false`, so
field generation runs in the workers too) is run into fresh directories by `floebreak.studies.runner
.run_study`, once with the serial executor and once with a local process pool of 2 workers (spawned
processes, each loading the kernels once). Efficiency = T_serial / (2 · T_pool); goal ≥ 85 %.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/study_efficiency.py [--runs 8] [--repeat 2]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from floebreak.mechanics import compile_kernels
from floebreak.studies.design import StudySpec, expand
from floebreak.studies.executors import ProcessPoolExecutor, SerialExecutor
from floebreak.studies.runner import run_study


def timed(spec: StudySpec, executor, folder: Path) -> float:
    runs, members = expand(spec)
    started = time.perf_counter()
    state = run_study(spec, runs, members, folder, executor)
    seconds = time.perf_counter() - started
    assert state.failed == 0, state.failures
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    compile_kernels()
    spec = StudySpec(name="efficiency", root_seed=1, n_fields=args.runs, common_fields=False, base=None)
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as temp:
            serial = timed(spec, SerialExecutor(), Path(temp) / "serial")
            pool = ProcessPoolExecutor(2)
            try:
                parallel = timed(spec, pool, Path(temp) / "pool")
            finally:
                pool.close()
        print(
            f"{args.runs} runs: serial {serial:.1f} s, 2 workers {parallel:.1f} s, "
            f"efficiency {serial / (2 * parallel):.0%}",
            flush=True,
        )


if __name__ == "__main__":
    main()
