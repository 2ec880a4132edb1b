"""Reading a run directory's (or a study's run directories') files for the analyses: the cusp tables, the
Parquet files' floebreak metadata and the resolved scenario. Readers only: what the numbers mean is
`floebreak.propeller` and `floebreak.shaft`, and `floebreak.app` combines them."""

from __future__ import annotations

import json
import os
import tomllib
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from floebreak.errors import InputError
from floebreak.io.toml_text import loads_toml
from floebreak.propeller.cusps import OPTIONAL_COLUMNS as OPTIONAL_CUSP_COLUMNS
from floebreak.propeller.cusps import REQUIRED_COLUMNS as CUSP_COLUMNS

CUSPS_FILE = "cusps.parquet"
RESOLVED_SCENARIO_FILE = "scenario.resolved.toml"


def load_cusps(run_or_study_dir: str | os.PathLike[str]) -> pa.Table:
    """Cusp columns of one run directory, or of every run directory below a study directory.

    A directory holding ``cusps.parquet`` is a run; otherwise every ``cusps.parquet`` below it (hidden
    folders skipped) is read. The geometry column is ignored; a ``run_id`` column holds the run folder's
    name (its path relative to the study folder if names repeat).
    """
    field = "run_or_study_dir"
    tables = []
    for run_id, path in cusp_files(run_or_study_dir).items():
        try:
            table = pq.ParquetFile(path).read()  # one file: no dataset layer (pyarrow.dataset)
        except (OSError, pa.ArrowInvalid) as error:
            raise InputError(field, f"cannot read {str(path)!r}: {error}", value=str(path)) from None
        missing = [c for c in CUSP_COLUMNS if c not in table.column_names]
        if missing:
            raise InputError(
                field,
                f"{str(path)!r} lacks column(s) {', '.join(missing)}",
                value=str(path),
                allowed=", ".join(CUSP_COLUMNS),
            )
        present = [c for c in (*CUSP_COLUMNS, *OPTIONAL_CUSP_COLUMNS) if c in table.column_names]
        columns = {c: table.column(c).cast(pa.float64()) for c in present}
        for c in OPTIONAL_CUSP_COLUMNS:
            if c not in columns:
                columns[c] = pa.array(np.full(table.num_rows, np.nan), type=pa.float64())
        columns["run_id"] = pa.array([run_id] * table.num_rows, type=pa.string())
        tables.append(pa.table(columns))
    return pa.concat_tables(tables)


def cusp_files(run_or_study_dir: str | os.PathLike[str]) -> dict[str, Path]:
    """run_id → ``cusps.parquet`` of the run directory, or of every run below a study directory (hidden
    folders skipped); run_id is the run folder's name, or its path below the study folder if names repeat."""
    root = Path(run_or_study_dir)
    field = "run_or_study_dir"
    if not root.is_dir():
        raise InputError(field, f"{str(root)!r} is not a directory", value=str(root))
    if (root / CUSPS_FILE).is_file():
        return {root.name: root / CUSPS_FILE}
    files = sorted(
        p
        for p in root.rglob(CUSPS_FILE)
        if not any(part.startswith(".") for part in p.relative_to(root).parts)
    )
    if not files:
        raise InputError(
            field,
            f"no {CUSPS_FILE} in or below {str(root)!r}",
            value=str(root),
            allowed="a run directory or a study directory containing run directories",
        )
    names = [f.parent.name for f in files]
    if len(set(names)) < len(names):
        names = [f.parent.relative_to(root).as_posix() for f in files]
    return dict(zip(names, files, strict=True))


def read_run_cusps(run_dir: str | os.PathLike[str], columns: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The float `columns` of one run directory's ``cusps.parquet`` (InputError naming the run directory
    if it has none, or lacks a column)."""
    path = Path(run_dir) / CUSPS_FILE
    if not path.is_file():
        raise InputError(
            "run_dir",
            f"no {CUSPS_FILE} in {str(run_dir)!r}",
            value=str(run_dir),
            allowed="a run directory (the shaft analysis needs one run's transit order)",
        )
    try:
        parquet = pq.ParquetFile(path)
        missing = [c for c in columns if c not in parquet.schema_arrow.names]
        table = None if missing else parquet.read(columns=list(columns))
    except (OSError, pa.ArrowInvalid) as error:
        raise InputError("run_dir", f"cannot read {str(path)!r}: {error}", value=str(path)) from None
    if missing:
        raise InputError("run_dir", f"{str(path)!r} lacks column(s) {', '.join(missing)}", value=str(path))
    return {c: table.column(c).to_numpy().astype(float) for c in columns}


def parquet_metadata(path: Path) -> dict:
    """The ``floebreak`` key of a Parquet file's metadata as a dict; {} if the file or the key is absent."""
    try:
        meta = pq.read_metadata(path).metadata or {}
        return json.loads(meta.get(b"floebreak", b"{}"))
    except (OSError, pa.ArrowInvalid, json.JSONDecodeError):
        return {}


def read_resolved_scenario(run_dir: str | os.PathLike[str], *, strict: bool = True) -> dict | None:
    """The run's resolved scenario (``scenario.resolved.toml``, every default written out) as a dict, None
    if the run directory has none. An unreadable file: InputError naming it (`strict`), else None."""
    path = Path(run_dir) / RESOLVED_SCENARIO_FILE
    if not path.is_file():
        return None
    try:
        return loads_toml(path.read_text(encoding="utf-8-sig"), "run_or_study_dir", str(path))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
        if not strict:
            return None
        raise InputError("run_or_study_dir", f"cannot read {str(path)!r}: {error}", value=str(path)) from None
