"""What the command line says about an exception nothing else handled: a problem of the machine (a full disk,
a read-only file system: exit 3), Ctrl-C surfacing inside a library (reported as the interruption), or a bug
(its traceback, then one closing ``internal error: … — please report this bug`` line, exit 1)."""

from __future__ import annotations

import traceback

from rich.markup import escape

from floebreak.exit_codes import EXIT_STORAGE
from floebreak.io.storage import as_storage_error

EXIT_BUG = 1


def interrupted(error: BaseException | None) -> bool:
    """Whether `error` is, or was raised while handling, a KeyboardInterrupt (Ctrl-C inside a numba kernel
    surfaces as ``SystemError: … returned a result with an exception set``)."""
    seen: set[int] = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


def report_unexpected(error: Exception, console) -> int | None:
    """Print what `error` means on the rich `console` (standard error) and return the exit code; None if it
    is an interruption, which the caller reports with its own line and code."""
    if interrupted(error):
        return None
    storage = as_storage_error(error, getattr(error, "filename", None) or "the output")
    if storage is not None:
        console.print(f"[bold red]error:[/] {escape(storage.strerror)}", soft_wrap=True, highlight=False)
        return EXIT_STORAGE
    text = "".join(traceback.format_exception(type(error), error, error.__traceback__))
    console.print(escape(text.rstrip()), soft_wrap=True, highlight=False, markup=True)
    console.print(
        f"[bold red]internal error:[/] {escape(f'{type(error).__name__}: {error}')} — please report this bug",
        soft_wrap=True,
        highlight=False,
    )
    return EXIT_BUG
