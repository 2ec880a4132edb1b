"""Parallel efficiency of a local study (issue 20): the same runs serially and on a pool of 2 workers.

A study of `--runs` runs (reference scenario: 385 m × 100 m since 2026-12-02; each run its own field:
`common_fields = false`, so field generation runs in the workers too) is run into fresh directories by
`floebreak.studies.runner.run_study`, once with the serial executor and once with a local process pool of 2
workers (spawned processes). Efficiency = T_serial / (2 · T_pool); goal ≥ 85 %.

Two figures per repeat, because a pool pays a one-off start that a long study does not notice:
- **steady state**: both paths warm — the serial process has done one run before the clock starts, the
  pool's workers have started, imported floebreak and loaded the numba kernels (each has answered a task);
- **cold**: the pool timed from its creation (each worker's imports and kernels inside the clock), against
  the warm serial path — the figure of a short study started from a running program.
The start (pool creation → both workers warm) is printed too.

`--cli N` adds the figure a user sees: `floebreak study thesis --n-fields N` (the thesis §5.3 study, 11
design points on N common fields of the thesis' inferred size, 385 m × 100 m, which the parent generates
as the runs are handed out) through the installed command, `--workers 1` against `--workers 2`, wall time
from the command's start to its end (interpreter start, imports, common fields, runs, aggregated tables and
figures).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/study_efficiency.py [--runs 8] [--repeat 3] [--cli 4]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from floebreak.mechanics import compile_kernels
from floebreak.studies.design import StudySpec, expand
from floebreak.studies.executors import ProcessPoolExecutor, SerialExecutor
from floebreak.studies.runner import execute_run, run_study


def timed(spec: StudySpec, executor, folder: Path) -> float:
    runs, members = expand(spec)
    started = time.perf_counter()
    state = run_study(spec, runs, members, folder, executor)
    seconds = time.perf_counter() - started
    assert state.failed == 0, state.failures
    return seconds


def worker_pid(_: int) -> int:
    """The worker's process id, after a short wait that lets another ready worker take the next task."""
    time.sleep(0.05)
    return os.getpid()


def wait_for_workers(pool: ProcessPoolExecutor, workers: int) -> set[int]:
    """Until each of the pool's workers has answered: each prepares itself (imports, kernels) when it starts
    (`floebreak.studies.executors.prepare_worker`), so then all are warm."""
    pids: set[int] = set()
    while len(pids) < workers:
        pids |= {pid for _, pid, _ in pool.run(worker_pid, range(workers))}
    return pids


def cli_seconds(n_fields: int, workers: int, folder: Path) -> float:
    """Wall time of `floebreak study thesis --n-fields N --workers W` in a fresh process."""
    command = shutil.which("floebreak", path=str(Path(sys.executable).parent)) or "floebreak"
    started = time.perf_counter()
    arguments = ["study", "thesis", "--n-fields", str(n_fields), "--workers", str(workers), "--out", folder]
    subprocess.run([command, *map(str, arguments)], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - started


def cli_figures(n_fields: int, repeat: int) -> None:
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as temp:
            serial = cli_seconds(n_fields, 1, Path(temp) / "serial")
            pool = cli_seconds(n_fields, 2, Path(temp) / "pool")
        print(
            f"floebreak study thesis --n-fields {n_fields}: --workers 1 {serial:.1f} s, --workers 2 "
            f"{pool:.1f} s (efficiency {serial / (2 * pool):.0%})",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cli", type=int, default=0, metavar="N", help="also the CLI figure on N fields")
    args = parser.parse_args()
    if args.cli:
        cli_figures(args.cli, args.repeat)
    compile_kernels()
    spec = StudySpec(name="efficiency", root_seed=1, n_fields=args.runs, common_fields=False, base=None)
    warm_up = expand(StudySpec(name="warm", root_seed=99, n_fields=1, common_fields=False, base=None))[0][0]
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as temp:
            execute_run({"scenario": warm_up.scenario, "run_dir": str(Path(temp) / "warm"), "index": 0})
            serial = timed(spec, SerialExecutor(), Path(temp) / "serial")
            pool = ProcessPoolExecutor(2)
            try:
                cold = timed(spec, pool, Path(temp) / "cold")
            finally:
                pool.close()
            started = time.perf_counter()
            pool = ProcessPoolExecutor(2)
            try:
                pids = wait_for_workers(pool, 2)
                start_s = time.perf_counter() - started
                warm = timed(spec, pool, Path(temp) / "warm-pool")
            finally:
                pool.close()
        print(
            f"{args.runs} runs: serial {serial:.1f} s; 2 workers warm {warm:.1f} s "
            f"(steady-state efficiency {serial / (2 * warm):.0%}), cold {cold:.1f} s "
            f"(efficiency {serial / (2 * cold):.0%}); pool start {start_s:.1f} s on {len(pids)} workers",
            flush=True,
        )


if __name__ == "__main__":
    main()
