"""The run directory's writers: each writes its file(s) of a finished run (`RunRecord`) into the directory
being built, in the order listed. The built-in writers are listed in `BUILTIN`; an installed package adds one
through the entry point group ``floebreak.writers`` (``name = "my_pkg.files:write_mine"``, a function
``write(record, folder)``), written after the built-ins. The figures (drawn alongside by a figure worker),
the report (drawn from the files written) and the files' checksums in ``summary.json`` come after
(`floebreak.output.run_directory.write_run_directory`; docs/architecture.md, "Extension points")."""

from __future__ import annotations

import functools
import importlib
from pathlib import Path
from typing import Protocol

from floebreak.output.record import RunRecord

ENTRY_POINT_GROUP = "floebreak.writers"
# name → "module:function", in writing order (a list here, not entry points: a source checkout on the path has
# no installed entry points)
BUILTIN = {
    "field": "floebreak.output.run_directory:write_field_file",  # field.parquet
    "fates": "floebreak.output.run_directory:write_fate_files",  # cusps, flipped, remaining .parquet
    "contacts": "floebreak.output.run_directory:write_contacts_file",  # contacts.parquet
    "pieces": "floebreak.output.run_directory:write_pieces_file",  # pieces.parquet
    "surge": "floebreak.output.surge_file:write_surge_file",  # surge.csv, only with ship.propulsion
    "poses": "floebreak.output.pose_file:write_poses_file",  # poses.parquet, only with recorded poses
    "summary": "floebreak.output.run_directory:write_summary_file",  # summary.json (checksums added last)
    "scenario": "floebreak.output.run_directory:write_scenario_file",  # scenario.resolved.toml
}


class RunWriter(Protocol):
    """Writes its file(s) of `record` into `folder` (the run directory being built)."""

    def __call__(self, record: RunRecord, folder: Path) -> None: ...


@functools.cache
def _entry_points() -> dict[str, str]:
    from importlib.metadata import entry_points

    return {point.name: point.value for point in entry_points(group=ENTRY_POINT_GROUP)}


def _load(target: str) -> RunWriter:
    module, _, attribute = target.partition(":")
    return getattr(importlib.import_module(module), attribute)


def run_writers() -> tuple[tuple[str, RunWriter], ...]:
    """(name, writer) of every writer in writing order: the built-ins, then those of installed packages."""
    plugins = {name: target for name, target in _entry_points().items() if name not in BUILTIN}
    return tuple((name, _load(target)) for name, target in {**BUILTIN, **plugins}.items())
