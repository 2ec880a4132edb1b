"""One field per seed on every CPU: a short reference run repeated with OpenBLAS' kernels for other CPUs
(OPENBLAS_CORETYPE) and with numpy's CPU-specific loops switched off (NPY_DISABLE_CPU_FEATURES) writes the
same field and the same results. Only the provenance's record of the BLAS kernel may differ.

Each variant runs in its own process (both variables are read when the libraries load). Core types this
CPU cannot execute are left out; the kernels of the others differ in their summation order (Prescott,
Sandybridge and Haswell/Zen differ from each other on any x86-64 CPU with AVX2, SkylakeX on AVX-512).
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

ROOT = Path(__file__).resolve().parents[2]
# OpenBLAS core types and the CPU flags (/proc/cpuinfo names) their kernels need
CORE_TYPES = {
    "Prescott": {"pni"},
    "Sandybridge": {"avx"},
    "Haswell": {"avx2", "fma"},
    "Zen": {"avx2", "fma"},
    "SkylakeX": {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"},
}
# summary keys that describe the process, not the result
NOT_RESULTS = ("wall_time_s", "summary_sha256", "files", "provenance")


def _cpu_flags() -> set[str]:
    try:
        text = Path("/proc/cpuinfo").read_text(encoding="utf-8")
    except OSError:
        return set()
    return {flag for line in text.splitlines() if line.startswith("flags") for flag in line.split()[2:]}


def _variants() -> dict[str, dict[str, str]]:
    """Environment overrides per variant: every core type this CPU runs, and numpy at its baseline."""
    flags = _cpu_flags()
    variants = {
        f"OPENBLAS_CORETYPE={name}": {"OPENBLAS_CORETYPE": name}
        for name, needs in CORE_TYPES.items()
        if needs <= flags
    }
    dispatched = np.show_config(mode="dicts")["SIMD Extensions"].get("found", [])
    if dispatched:
        variants["NPY_DISABLE_CPU_FEATURES"] = {"NPY_DISABLE_CPU_FEATURES": " ".join(dispatched)}
    return variants


def _start(out: Path, overrides: dict[str, str]) -> subprocess.Popen:
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES")}
    env.update(overrides, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    command = [sys.executable, "-m", "floebreak", "run", str(ROOT / "examples" / "reference.toml")]
    command += ["--out", str(out), "--quiet", "--set", "field.length_m=30", "--set", "seed=3"]
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def _field(run: Path) -> tuple[bytes, dict]:
    """The field file's columns (Arrow IPC bytes: NaN compares equal to itself) and its metadata without
    the record of the BLAS kernel."""
    table = pq.read_table(run / "field.parquet")
    metadata = {key: value for key, value in table.schema.metadata.items() if key != b"floebreak"}
    provenance = json.loads(table.schema.metadata[b"floebreak"])
    provenance["libraries"].pop("blas")
    sink = pa.BufferOutputStream()
    with pa.ipc.new_stream(sink, table.schema.remove_metadata()) as writer:
        writer.write_table(table.replace_schema_metadata(None))
    return sink.getvalue().to_pybytes(), {**metadata, b"floebreak": provenance}


def _results(run: Path) -> dict:
    summary = json.loads((run / "summary.json").read_text(encoding="utf-8"))
    return {key: value for key, value in summary.items() if key not in NOT_RESULTS}


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="OpenBLAS x86-64 core types")
def test_the_same_seed_gives_the_same_field_and_results_with_every_kernel(tmp_path):
    variants = _variants()
    if len(variants) < 2:
        pytest.skip("this CPU runs fewer than two OpenBLAS core types")
    runs = {name: (tmp_path / f"run{k}", overrides) for k, (name, overrides) in enumerate(variants.items())}
    started = {name: _start(out, overrides) for name, (out, overrides) in runs.items()}
    for name, process in started.items():
        output, _ = process.communicate(timeout=300)
        assert process.returncode == 0, f"{name}: {output}"
    (first, (reference_run, _)), *others = runs.items()
    data, metadata = _field(reference_run)
    results = _results(reference_run)
    assert results["n_cusps"] > 0 and results["n_floes_initial"] > 5
    for name, (run, _) in others:
        other_data, other_metadata = _field(run)
        assert other_data == data, f"field data: {name} differs from {first}"
        assert other_metadata == metadata, f"field metadata: {name} differs from {first}"
        assert _results(run) == results, f"summary.json: {name} differs from {first}"
