"""Limits and keys shared by both fuzz generators (`fuzz`, `fuzz.adversarial`)."""

MAX_PIECES = 5_000
MAX_WALL_S = 100.0  # simulation.max_wall_s of every drawn scenario: a runaway is stopped (exit 2) in time
FILES = "_files"  # the drawn record's key for the files a scenario names (not a scenario key)
