"""Atomic file and directory writes: write under a temporary name, rename when complete.

A failure (exception, Ctrl-C, even SIGKILL) never leaves a half-written file under the final name;
at most a temporary sibling named ``.<name>.tmp-<random>`` remains, which nothing reads.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from floebreak.errors import InputError


def _check_parent_writable(path: Path, field: str) -> None:
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.exists():
        raise InputError(field, f"directory {str(parent)!r} does not exist", allowed="an existing directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(field, f"directory {str(parent)!r} is not writable", allowed="a writable directory")


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


@contextlib.contextmanager
def atomic_path(
    path: str | os.PathLike[str], field: str = "output", keep_suffix: bool = False
) -> Iterator[Path]:
    """Yield a temporary path next to `path`; on success rename it onto `path`, else delete it.

    `keep_suffix`: the temporary name ends with `path`'s suffix (for writers that choose the format by it,
    such as Pillow and ffmpeg)."""
    final = Path(path)
    _check_parent_writable(final, field)
    suffix = final.suffix if keep_suffix else ""
    handle, temp_name = tempfile.mkstemp(prefix=f".{final.name}.tmp-", suffix=suffix, dir=final.parent or ".")
    os.close(handle)
    temp = Path(temp_name)
    try:
        yield temp
        if temp.is_file():  # mkstemp files are private (0600): give the result the usual umask mode
            temp.chmod(0o666 & ~_umask())
        os.replace(temp, final)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            temp.unlink()
        raise


@contextlib.contextmanager
def atomic_directory(
    path: str | os.PathLike[str], *, overwrite: bool = False, field: str = "out"
) -> Iterator[Path]:
    """Yield a fresh temporary directory next to `path`; on success it replaces `path`.

    Without `overwrite` an existing `path` is refused (InputError) before anything is written.
    """
    final = Path(path)
    if final.exists() and not overwrite:
        raise InputError(field, f"{str(final)!r} exists", allowed="a new path, or pass --overwrite")
    _check_parent_writable(final, field)
    temp = Path(tempfile.mkdtemp(prefix=f".{final.name}.tmp-", dir=final.parent or "."))
    try:
        yield temp
        temp.chmod(0o777 & ~_umask())  # mkdtemp directories are private (0700)
        if final.exists():
            trash = Path(tempfile.mkdtemp(prefix=f".{final.name}.old-", dir=final.parent or "."))
            os.replace(final, trash / final.name)
            os.replace(temp, final)
            shutil.rmtree(trash, ignore_errors=True)
        else:
            os.replace(temp, final)
    except BaseException:
        shutil.rmtree(temp, ignore_errors=True)
        raise


@contextlib.contextmanager
def scratch_directory(near: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a fresh temporary directory next to `near` (its file system, not /tmp's), deleted on exit
    whatever happens; named ``.<name>.spool-<random>``, which nothing reads."""
    near = Path(near)
    temp = Path(tempfile.mkdtemp(prefix=f".{near.name}.spool-", dir=near.parent or "."))
    try:
        yield temp
    finally:
        shutil.rmtree(temp, ignore_errors=True)


def write_text_atomic(path: str | os.PathLike[str], text: str, field: str = "output") -> Path:
    """Write `text` (UTF-8) to `path` through `atomic_path`: a unique temporary name, so two processes
    writing the same folder never share one, then a rename. Returns `path`."""
    with atomic_path(path, field) as temp:
        temp.write_text(text, encoding="utf-8")
    return Path(path)
