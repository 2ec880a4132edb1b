"""The output directory of a study (``floebreak study --out``), checked and created as a run's is: a file
or another tool's directory is an input error (exit 2), a directory the machine will not let us create or
write (read-only, full, no permission) a StorageError (exit 3), both before any run starts."""

from __future__ import annotations

from pathlib import Path

from floebreak.errors import InputError
from floebreak.io.storage import as_storage_error, probe_directory


def prepare_study_directory(out: Path, marker: str = "study.json") -> Path:
    """Check `out` (new, empty, or a study directory holding `marker`: resumed), create it, and probe that it
    can be written; return it."""
    if out.exists() and not out.is_dir():
        raise InputError("out", f"{str(out)!r} is a file", value=str(out), allowed="a new or study directory")
    if out.exists() and not (out / marker).exists() and any(out.iterdir()):
        raise InputError(
            "out", f"{str(out)!r} exists and is not a study directory", allowed="a new or study directory"
        )
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        if isinstance(error, NotADirectoryError | FileExistsError):
            raise InputError(
                "out", f"{str(out)!r}: a parent is a file", value=str(out), allowed="a directory path"
            ) from None
        storage = as_storage_error(error, out)
        if storage is None:
            raise
        raise storage from None
    probe_directory(out, out)
    return out
