"""Provenance records: the library versions are those of the installed distributions."""

from __future__ import annotations

import platform
import subprocess
import sys
from importlib import metadata

import matplotlib  # noqa: F401  (imported: its version comes from the module)
import pytest

from floebreak.io import provenance


def test_library_versions_are_the_installed_distributions():
    versions = provenance.library_versions()
    assert set(versions) == {"python", *provenance._LIBRARIES, "blas"}
    for name in provenance._LIBRARIES:
        assert versions[name] == metadata.version(name), name


def test_provenance_carries_versions_and_extra_keys():
    record = provenance.provenance(seed=3)
    assert record["floebreak_version"] == provenance.floebreak_version()
    assert record["libraries"] == provenance.library_versions()
    assert record["seed"] == 3
    record["libraries"]["numpy"] = "changed"  # a copy: the cache is not affected
    assert provenance.library_versions()["numpy"] == metadata.version("numpy")


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="OpenBLAS core names are x86's")
def test_blas_entry_names_the_kernels_openblas_was_told_to_use():
    # OPENBLAS_CORETYPE overrides OpenBLAS' choice of kernels for the CPU; Nehalem (SSE4.2) runs on any
    # x86-64 numpy supports. The entry must report what was chosen, for numpy's and scipy's copies alike.
    code = (
        "import numpy, scipy.linalg\n"
        "from floebreak.io.provenance import library_versions\n"
        "print(library_versions()['blas'])"
    )
    env_run = subprocess.run(
        [sys.executable, "-c", code],
        env={"OPENBLAS_CORETYPE": "Nehalem", "PATH": ""},
        capture_output=True,
        text=True,
        check=True,
    )
    kernels = env_run.stdout.strip().split("; ")
    assert sorted(k.rsplit("(", 1)[1] for k in kernels) == ["numpy.libs)", "scipy.libs)"], kernels
    assert all(" Nehalem (" in k for k in kernels), kernels


def test_blas_entry_follows_imports():
    # numpy (and with it one BLAS) is imported here; the entry is not stale after more libraries load
    assert provenance.library_versions()["blas"] != "none loaded"
