"""One writer per output path: a command holds an exclusive lock (``fcntl.flock``) on a small file
``.<name>.lock`` next to its output from its first check to its last write, so that a second command on the
same ``--out`` (with or without ``--overwrite``) is refused at once instead of both printing "written" and
one result silently replacing the other. The lock file is removed when the lock is released; a crashed
process' lock is released by the operating system."""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from floebreak.errors import InputError
from floebreak.io.storage import as_storage_error


def lock_path(out: str | os.PathLike[str]) -> Path:
    out = Path(out)
    return out.parent / f".{out.name}.lock"


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
