"""The console command's exit codes and its Ctrl-C line, shared by `floebreak.__main__` (before the command
line loads) and `floebreak.cli`. Standard library only: `__main__` imports it before anything heavy."""

EXIT_INPUT = 2  # an InputError: the user can fix the input
EXIT_STORAGE = 3  # disk full, permission denied, read-only or pseudo file system (README, exit codes)
EXIT_INTERRUPTED = 130  # Ctrl-C: 128 + SIGINT, the shells' convention
INTERRUPTED_MESSAGE = "interrupted (Ctrl-C); nothing half-written was kept"
