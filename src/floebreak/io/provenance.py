"""Provenance that travels with every output file: package and library versions, parameters, seed.

`libraries["blas"]` names the BLAS kernels in use (OpenBLAS picks them for the CPU when it loads): scipy's
L-BFGS-B, which packs the generated floe fields, rounds differently with different kernels, so the same
scenario and seed can give a different field on another machine (docs/model.md §4, "Reproducibility").
"""

from __future__ import annotations

import functools
import platform
import sys
from importlib import metadata
from pathlib import Path
from typing import Any

_LIBRARIES = (
    "numpy",
    "scipy",
    "shapely",
    "numba",
    "pyarrow",
    "pydantic",
    "matplotlib",
    "opentorsion",  # shaft-line modes and response
    "rainflow",  # shaft fatigue cycle counting
    "pymunk",  # rigid-body contact of the floes
)


# Cached: each `metadata.version` call scans the installed distributions (≈ 3 ms), and a run directory asks
# about 60 times; versions do not change while the process runs.
@functools.cache
def floebreak_version() -> str:
    try:
        return metadata.version("floebreak")
    except metadata.PackageNotFoundError:  # running from a source tree that is not installed
        return "0+unknown"


def library_versions() -> dict[str, str]:
    """Versions of Python and the libraries results depend on, and the BLAS kernels loaded (`blas`)."""
    # a copy: callers may change theirs. BLAS libraries load with numpy and scipy.linalg, so the kernels
    # are looked up again (≈ 5 ms) only when one of those was imported since the last call
    loaded = tuple(name in sys.modules for name in ("numpy", "scipy.linalg"))
    return {**_library_versions(), "blas": _blas_kernels(loaded)}


@functools.cache
def _library_versions() -> dict[str, str]:
    versions = {"python": platform.python_version()}
    for name in _LIBRARIES:
        # an imported library's own `__version__` (the same string as its distribution's) costs nothing;
        # `metadata.version` parses the installed METADATA file (≈ 6 ms per library)
        version = getattr(sys.modules.get(name), "__version__", None)
        if isinstance(version, str):
            versions[name] = version
            continue
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "not installed"
    return versions


@functools.cache
def _blas_kernels(loaded: tuple[bool, ...]) -> str:
    """'openblas 0.3.30 SkylakeX (numpy.libs); …' for each BLAS library loaded, or 'none loaded'."""
    import threadpoolctl  # here, not at the top: `import floebreak` stays light

    del loaded  # only the cache key
    kernels = [
        f"{info.get('internal_api', '?')} {info.get('version', '?')} {info.get('architecture', '?')}"
        f" ({Path(info.get('filepath', '?')).parent.name})"  # the owning package's folder, not a path
        for info in threadpoolctl.threadpool_info()
        if info.get("user_api") == "blas"
    ]
    return "; ".join(sorted(kernels)) or "none loaded"


def provenance(**extra: Any) -> dict[str, Any]:
    """A provenance record: floebreak version, library versions, plus any extra keys given."""
    return {"floebreak_version": floebreak_version(), "libraries": library_versions(), **extra}
