"""The application layer: the only place that combines reading, computing and writing (docs/architecture.md).

- `run`: a scenario → field, bow and model → `simulate` → `Result` → run directory;
- `propeller`: a run's or study's cusps → `analyse_propeller` → spectra, tables and figures;
- `shaft`: a run's cusps → `shaft_response` → shaft-torque files and figures.

Below it, the computing packages take arrays and dataclasses, `io` reads and writes, `plotting` draws;
above it, `floebreak.api` (the curated public functions) and the command line call it.
"""
