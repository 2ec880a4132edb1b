"""What a run and an analysis write: the run directory's writers (`run_directory`, one per file), the report,
the propeller and shaft analyses' files, and the figure worker (docs/architecture.md)."""
