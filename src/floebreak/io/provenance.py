"""Provenance that travels with every output file: package and library versions, parameters, seed."""

from __future__ import annotations

import functools
import platform
import sys
from importlib import metadata
from typing import Any

_LIBRARIES = ("numpy", "scipy", "shapely", "pyarrow", "pydantic", "matplotlib")


# Cached: each `metadata.version` call scans the installed distributions (≈ 3 ms), and a run directory asks
# about 60 times; versions do not change while the process runs.
@functools.cache
def floebreak_version() -> str:
    try:
        return metadata.version("floebreak")
    except metadata.PackageNotFoundError:  # running from a source tree that is not installed
        return "0+unknown"


def library_versions() -> dict[str, str]:
    return dict(_library_versions())  # a copy: callers may change theirs


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


def provenance(**extra: Any) -> dict[str, Any]:
    """A provenance record: floebreak version, library versions, plus any extra keys given."""
    return {"floebreak_version": floebreak_version(), "libraries": library_versions(), **extra}
