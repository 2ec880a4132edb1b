"""Atomic file and directory writes: write under a temporary name, rename when complete.

A failure (exception, Ctrl-C, even SIGKILL) never leaves a half-written file under the final name;
at most a temporary sibling named ``.<name>.<kind>-<pid>.<host>-<random>`` remains (kind ``tmp``, ``old`` or
``spool``; `pid` and `host`, a hash of the host name, of the process that made it), which nothing reads.
The next atomic directory or scratch directory made in the same folder removes those whose process is gone
(`remove_dead_temporaries`: same host, and ``os.kill(pid, 0)`` says no such process). Names without a pid
(older floebreak versions') cannot be told from live ones and are left for the user to remove.

A directory never replaces an existing one without `overwrite`: besides the check at the start, the final
step is ``os.rename``, which on POSIX refuses to replace a non-empty directory (and on Windows any existing
path), so of two runs writing to one path the second to finish gets an InputError (exit 2) and its result
is discarded. (``os.rename`` does replace an *empty* directory created in the instant between the check and
the rename: nothing is lost then.)
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import socket
import tempfile
from collections.abc import Iterator
from pathlib import Path

from floebreak.errors import InputError
from floebreak.io.output_lock import remove_stale_locks


def _check_parent_writable(path: Path, field: str) -> None:
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.exists():
        raise InputError(field, f"directory {str(parent)!r} does not exist", allowed="an existing directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(field, f"directory {str(parent)!r} is not writable", allowed="a writable directory")


_TEMPORARY = re.compile(
    r"^\.(?P<name>.+)\.(?:tmp|old|spool)-(?P<pid>\d+)\.(?P<host>[0-9a-f]{8})-[a-z0-9_]+(?:\.[^.]+)?$"
)


def _host_tag() -> str:
    """8 hex digits naming this host in temporary names (a shared file system may be written by several)."""
    return hashlib.sha256(socket.gethostname().encode()).hexdigest()[:8]


def _temporary_prefix(final: Path, kind: str) -> str:
    return f".{final.name}.{kind}-{os.getpid()}.{_host_tag()}-"


def _process_alive(pid: int) -> bool:
    """Whether process `pid` exists on this host (signal 0 only checks; Windows' os.kill would kill it, so
    there every process counts as alive)."""
    if os.name == "nt":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's live process
        return True
    return True


def remove_dead_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files and directories in `folder` (module docstring) whose process on this
    host has died (SIGKILL, power loss, a killed worker); return them. Those of live processes and of other
    hosts are kept."""
    removed: list[Path] = remove_stale_locks(folder)
    host = _host_tag()
    with contextlib.suppress(OSError), os.scandir(folder) as entries:
        for entry in entries:
            match = _TEMPORARY.match(entry.name) if entry.name.startswith(".") else None
            if match is None or match["host"] != host or _process_alive(int(match["pid"])):
                continue
            path = Path(entry.path)
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(path, ignore_errors=True)
            else:
                path.unlink(missing_ok=True)
            removed.append(path)
    return removed


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
    handle, temp_name = tempfile.mkstemp(
        prefix=_temporary_prefix(final, "tmp"), suffix=suffix, dir=final.parent
    )
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
    """Yield a fresh temporary directory next to `path`; on success it becomes `path`.

    Without `overwrite` an existing `path` is refused (InputError) before anything is written, and again at
    the end if another process created it meanwhile (the no-replace rename of the module docstring); the
    temporary directory is then removed. With `overwrite` the result replaces what is there.
    """
    final = Path(path)
    if final.exists() and not overwrite:
        raise InputError(
            field, f"{str(final)!r} exists", allowed="a new path, or overwrite=True (--overwrite)"
        )
    _check_parent_writable(final, field)
    remove_dead_temporaries(final.parent)
    temp = Path(tempfile.mkdtemp(prefix=_temporary_prefix(final, "tmp"), dir=final.parent))
    try:
        yield temp
        temp.chmod(0o777 & ~_umask())  # mkdtemp directories are private (0700)
        if overwrite and final.exists():
            trash = Path(tempfile.mkdtemp(prefix=_temporary_prefix(final, "old"), dir=final.parent))
            os.replace(final, trash / final.name)
            os.replace(temp, final)
            shutil.rmtree(trash, ignore_errors=True)
        else:
            _rename_no_replace(temp, final, field)
    except BaseException:
        shutil.rmtree(temp, ignore_errors=True)
        raise


def _rename_no_replace(temp: Path, final: Path, field: str) -> None:
    """Rename `temp` to `final` unless `final` appeared meanwhile (another run on the same path)."""
    taken = InputError(
        field,
        f"{str(final)!r} was created by another process while this one was writing; its result is kept and "
        "this one's discarded",
        allowed="one run per output path, or overwrite=True (--overwrite)",
    )
    if final.exists() or final.is_symlink():
        raise taken
    try:
        os.rename(temp, final)
    except OSError as error:
        if error.errno in (errno.EEXIST, errno.ENOTEMPTY, errno.ENOTDIR, errno.EISDIR):
            raise taken from None
        raise


@contextlib.contextmanager
def scratch_directory(near: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a fresh temporary directory next to `near` (its file system, not /tmp's), deleted on exit
    whatever happens; named ``.<name>.spool-<pid>.<host>-<random>``, which nothing reads. Spool directories
    of dead processes in that folder are removed first (`remove_dead_temporaries`)."""
    near = Path(near)
    remove_dead_temporaries(near.parent)
    temp = Path(tempfile.mkdtemp(prefix=_temporary_prefix(near, "spool"), dir=near.parent))
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
