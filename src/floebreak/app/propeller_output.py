"""The output directory of ``floebreak propeller``: the propeller analysis and, with a shaft line, the shaft
analysis in ``shaft/``, written into one temporary directory that becomes the output at once — a full disk
or an interruption leaves either the complete directory or nothing (never the propeller files without
``shaft/``)."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any

from floebreak.app.propeller import write_propeller
from floebreak.io.atomic import atomic_directory
from floebreak.io.output_lock import output_lock
from floebreak.io.storage import StorageError

# below this much free space the HDF5 library (the shaft's netCDF files) may crash instead of reporting
# ENOSPC; a propeller directory with its shaft analysis is a few MB
MIN_FREE_BYTES = 32 * 1024 * 1024

Stage = Callable[[str], AbstractContextManager[Any]]


def require_free_space(directory: Path, target: Path, needed: int | None = None) -> None:
    """StorageError (exit 3) naming `target` when `directory`'s file system has less than `needed` bytes
    (default `MIN_FREE_BYTES`) free."""
    needed = MIN_FREE_BYTES if needed is None else needed
    free = shutil.disk_usage(directory).free
    if free < needed:
        raise StorageError(
            target, f"No space left on device ({free / 1e6:.3g} MB free, {needed / 1e6:.3g} MB needed)"
        )


def write_propeller_directory(
    result, record: dict, shaft, out: Path, *, overwrite: bool, stage: Stage, workers=(None, None)
) -> Path:
    """Write the propeller `result` (provenance `record`) and the prepared `shaft` analysis (or None) to
    `out` as one atomic directory; `stage(label)` gives a progress context for each part; of the two figure
    `workers` the first draws the propeller's figures, the second the shaft's."""
    out = Path(out)
    parent = out.parent if str(out.parent) else Path(".")
    if parent.is_dir():
        require_free_space(parent, out)
    mine, theirs = workers
    with output_lock(out), atomic_directory(out, overwrite=overwrite, field="out") as temp:
        with stage("writing") as progress:
            # replaces the empty temporary directory (so that the propeller files are complete in it)
            write_propeller(
                result, temp, overwrite=True, record=record, progress=progress, figure_worker=mine
            )
        if shaft is not None:
            with stage("writing the shaft analysis") as progress:
                shaft.write(temp / "shaft", progress=progress, figure_worker=theirs)
    return out
