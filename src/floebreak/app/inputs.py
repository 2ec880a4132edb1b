"""The analyses' input files, resolved before anything is computed: FEM tables and a measured torque series
given as paths, the shipped tables by default. The pure analyses (`floebreak.propeller.pipeline`,
`floebreak.shaft.analysis`) take the resulting `FemTable`s and `TorqueSeries` only (docs/architecture.md).
"""

from __future__ import annotations

import os

from floebreak.errors import InputError, require_range
from floebreak.propeller.fem import FemTable, fem_table_dict, read_fem_table, shipped_fem_tables
from floebreak.propeller.measured import TorqueSeries, read_torque_csv


def resolve_fem_tables(fem_table, fallback_pitch_percent: float | None = None) -> dict[float, FemTable]:
    """None → the shipped tables; a path or FemTable → one table; a mapping {pitch_percent: path or
    FemTable}; a list of paths/FemTables or of (pitch_percent or None, path) pairs. A path given without a
    pitch needs a ``# pitch_percent:`` line, else `fallback_pitch_percent` if the caller states one (the
    propeller analysis and CLI do not: no silent default); pitches must be distinct."""
    if fem_table is None:
        return shipped_fem_tables()
    if isinstance(fem_table, FemTable | str | os.PathLike):
        items = [(None, fem_table)]
    elif isinstance(fem_table, dict):
        items = list(fem_table.items())
    else:  # paths / FemTables, or (pitch or None, path) pairs
        items = [t if isinstance(t, tuple) else (None, t) for t in fem_table]
    tables = []
    for pitch, item in items:
        if isinstance(item, FemTable):
            tables.append(item)
            continue
        given = (
            None
            if pitch is None
            else require_range("fem_table pitch", pitch, low=0.0, high=100.0, low_inclusive=True, unit="%")
        )
        tables.append(read_fem_table(item, given, fallback_pitch_percent=fallback_pitch_percent))
    if not tables:
        raise InputError("fem_table", "no table given", allowed="a CSV path or a mapping pitch → path")
    return fem_table_dict(tables)


def measured_series(
    torque_csv, torque_unit: str | None = None, flip_sign: bool = False
) -> TorqueSeries | None:
    """A measured torque series: None → None; a `TorqueSeries` as it is (sign flipped if asked); a path →
    `read_torque_csv` (with `torque_unit`, `flip_sign`)."""
    if torque_csv is None:
        return None
    if isinstance(torque_csv, TorqueSeries):
        s = torque_csv
        return TorqueSeries(s.time_s, -s.torque_nm, s.source) if flip_sign else s
    return read_torque_csv(torque_csv, torque_unit=torque_unit, flip_sign=flip_sign)
