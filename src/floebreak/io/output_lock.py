"""One writer per output path: a command holds an exclusive lock (``fcntl.flock``) on a small file
``.<name>.floebreak-lock`` next to its output from its first check to its last write, so that a second
command on the same ``--out`` (with or without ``--overwrite``) is refused at once instead of both printing
"written" and one result silently replacing the other. The lock file is removed when the lock is released;
a killed process' lock is released by the operating system, and its file removed by the next command
writing to that folder (`remove_stale_locks`, called by `floebreak.io.atomic.remove_dead_temporaries`)."""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from floebreak.errors import InputError
from floebreak.io.storage import as_storage_error

LOCK_SUFFIX = ".floebreak-lock"


def lock_path(out: str | os.PathLike[str]) -> Path:
    out = Path(out)
    return out.parent / f".{out.name}{LOCK_SUFFIX}"


def _open_locked(path: Path, out: Path, field: str) -> int:
    """An open descriptor of `path` holding its exclusive lock; InputError if another process holds it."""
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as error:
            storage = as_storage_error(error, out)
            if storage is None:
                raise
            raise storage from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise InputError(
                field,
                f"{str(out)!r} is being written by another floebreak process (lock {path.name!r} held)",
                allowed="one command per output path at a time",
            ) from None
        # the holder before us may have removed the file after we opened it: lock the file that is there
        try:
            if os.fstat(fd).st_ino == os.stat(path).st_ino:
                return fd
        except FileNotFoundError:
            pass
        os.close(fd)


@contextlib.contextmanager
def output_lock(out: str | os.PathLike[str], field: str = "out") -> Iterator[None]:
    """Hold the output lock of `out` for the block (see the module docstring)."""
    out = Path(out)
    if not out.parent.is_dir():  # the command's own check names the missing parent
        yield
        return
    path = lock_path(out)
    fd = _open_locked(path, out, field)
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)
        os.close(fd)


def remove_stale_locks(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the lock files in `folder` that no process holds (their process was killed); return them."""
    removed = []
    with contextlib.suppress(OSError), os.scandir(folder) as entries:
        for entry in entries:
            if not (entry.name.startswith(".") and entry.name.endswith(LOCK_SUFFIX)):
                continue
            try:
                fd = os.open(entry.path, os.O_RDWR)
            except OSError:
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                os.unlink(entry.path)  # held by us: a waiting opener sees the file gone and re-creates it
                removed.append(Path(entry.path))
            except OSError:
                pass  # held by a live process
            finally:
                os.close(fd)
    return removed
