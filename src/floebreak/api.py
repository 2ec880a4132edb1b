"""The curated public functions of a run (docs/api.md), as thin names for the application layer's
`floebreak.app.run`, where a scenario is built, run and written (module docstring there: the run
directory's files)."""

from floebreak.app.run import (
    CONTACTS_FILE,
    FIGURE_WINDOW_M,
    FIGURES,
    PIECE_FILES,
    PIECES_FILE,
    Result,
    as_scenario,
    build_bow,
    build_field,
    build_model_for,
    check_output_directory,
    field_key,
    file_checksums,
    plot_field_figure,
    run,
    waterline_rule,
    write_run_directory,
)

__all__ = [
    "CONTACTS_FILE",
    "FIGURES",
    "FIGURE_WINDOW_M",
    "PIECES_FILE",
    "PIECE_FILES",
    "Result",
    "as_scenario",
    "build_bow",
    "build_field",
    "build_model_for",
    "check_output_directory",
    "field_key",
    "file_checksums",
    "plot_field_figure",
    "run",
    "waterline_rule",
    "write_run_directory",
]
