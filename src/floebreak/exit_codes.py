"""The console command's exit codes and its Ctrl-C line, shared by `floebreak.__main__` (before the command
line loads) and `floebreak.cli`. Standard library only: `__main__` imports it before anything heavy."""

EXIT_INPUT = 2  # an InputError: the user can fix the input
EXIT_STORAGE = 3  # disk full, permission denied, read-only or pseudo file system (README, exit codes)
EXIT_INTERRUPTED = 130  # Ctrl-C: 128 + SIGINT, the shells' convention
INTERRUPTED_MESSAGE = "interrupted (Ctrl-C); nothing half-written was kept"
EXIT_TERMINATED = 143  # SIGTERM: 128 + 15
TERMINATED_MESSAGE = "terminated (SIGTERM); nothing half-written was kept"


class Terminated(KeyboardInterrupt):
    """SIGTERM during a command: raised like Ctrl-C, so that the same clean-up runs."""


# the signals that interrupted the command: signals are process-wide, and so is this record
_received: list[int] = []


def record_signal(signum: int) -> None:
    _received.append(signum)


def interruption() -> tuple[str, int]:
    """(message, exit code) of the interruption being reported: SIGTERM's if one came, else Ctrl-C's.
    Reporting consumes the record, so that a later interruption in the same process (a notebook, a test
    session) is judged on its own signal."""
    import signal

    terminated = bool(_received) and _received[-1] == signal.SIGTERM
    _received.clear()
    if terminated:
        return TERMINATED_MESSAGE, EXIT_TERMINATED
    return INTERRUPTED_MESSAGE, EXIT_INTERRUPTED
