"""Problems of the machine, not of the input: a full disk, no permission, a read-only or pseudo file system.

`StorageError` names the path and the operating system's error; the CLI exits with code 3 for it (README,
exit codes), never 1 ("please report this bug") nor 2 (bad input). `probe_directory` finds most such problems
before a run spends its time: it creates and removes a small file where the output will go.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path

# OS errors that say something about the machine or the path, not about floebreak
STORAGE_ERRNOS = frozenset(
    {errno.ENOSPC, errno.EDQUOT, errno.EACCES, errno.EPERM, errno.EROFS, errno.EIO, errno.ENOENT, errno.EFBIG}
)
# pyarrow's OSErrors often carry the OS error only in their text
_STORAGE_TEXTS = {
    "No space left on device": errno.ENOSPC,
    "Disk quota exceeded": errno.EDQUOT,
    "Permission denied": errno.EACCES,
    "Read-only file system": errno.EROFS,
}
PROBE_BYTES = 64 * 1024  # a full disk usually still takes a few bytes, rarely 64 kB


class StorageError(OSError):
    """Writing `path` failed for a reason of the machine (disk full, permission, read-only file system)."""

    def __init__(self, path: str | os.PathLike[str], error: OSError | str):
        reason = error if isinstance(error, str) else (error.strerror or str(error))
        code = getattr(error, "errno", None) or _errno_from_text(str(error))
        super().__init__(code, f"cannot write {str(path)!r}: {reason}")
        self.path = str(path)


def _errno_from_text(text: str) -> int | None:
    return next((code for part, code in _STORAGE_TEXTS.items() if part in text), None)


def as_storage_error(error: BaseException, path: str | os.PathLike[str]) -> StorageError | None:
    """`error` as a StorageError about `path` (its own file name if it has one), or None if it is not one."""
    if isinstance(error, StorageError):
        return error
    if not isinstance(error, OSError):
        return None
    code = error.errno if error.errno is not None else _errno_from_text(str(error))
    if code not in STORAGE_ERRNOS:
        return None
    if error.errno is None:  # pyarrow: the OS error is in the text
        error = OSError(code, os.strerror(code))
    return StorageError(getattr(error, "filename", None) or path, error)


def probe_directory(directory: str | os.PathLike[str], target: str | os.PathLike[str]) -> None:
    """Create, fill with `PROBE_BYTES` and remove a temporary file in `directory`, where `target` will be
    written; raise StorageError naming `target` if the machine refuses (full, read-only, pseudo file system,
    no permission)."""
    directory = Path(directory)
    try:
        handle, name = tempfile.mkstemp(prefix=".floebreak-probe-", dir=directory)
    except OSError as error:
        raise StorageError(target, error) from None
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(b"\0" * PROBE_BYTES)
            file.flush()
            os.fsync(file.fileno())
    except OSError as error:
        raise StorageError(target, error) from None
    finally:
        with contextlib.suppress(OSError):
            os.unlink(name)
