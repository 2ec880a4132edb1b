"""The analyses' input files, read and resolved before anything is computed: FEM tables, a measured torque
series and a shaft line given as paths (or built-in names), the shipped tables by default. The pure analyses
(`floebreak.propeller.pipeline`, `floebreak.shaft.analysis`) take the resulting `FemTable`s, `TorqueSeries`
and `ShaftLine`s only (docs/architecture.md)."""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

from floebreak.errors import InputError, require_range
from floebreak.io.text_files import package_data_path, read_package_data, read_text_file
from floebreak.io.toml_text import loads_toml
from floebreak.propeller.loads.fem import SHIPPED_TABLES, FemTable, fem_table_dict, parse_fem_table
from floebreak.propeller.measured import TorqueSeries, parse_torque_csv
from floebreak.shaft.line import (
    BUILTIN_LINES,
    ShaftLine,
    builtin_shaft_line,
    merge_base,
    shaft_line_from_dict,
)


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


def read_fem_table(
    path: str | os.PathLike[str],
    pitch_percent: float | None = None,
    field: str = "fem_table",
    fallback_pitch_percent: float | None = None,
) -> FemTable:
    """Read a user FEM table CSV; the pitch comes from `pitch_percent` or ``# pitch_percent:`` (which must
    agree when both are given), else `fallback_pitch_percent`."""
    text = read_text_file(path, field)
    return parse_fem_table(text, str(Path(path)), pitch_percent, field, fallback_pitch_percent)


def shipped_fem_tables() -> dict[float, FemTable]:
    """Thesis Table 10 (pitch 0 %) and Table 11 (pitch 95 %) as shipped in floebreak/data."""
    tables = {}
    for pitch, name in SHIPPED_TABLES.items():
        tables[pitch] = parse_fem_table(read_package_data(name), f"floebreak/data/{name}", pitch)
    return tables


def read_torque_csv(
    path: str | os.PathLike[str],
    torque_unit: str | None = None,
    time_unit: str | None = None,
    flip_sign: bool = False,
    field: str = "torque_csv",
) -> TorqueSeries:
    text = read_text_file(path, field)
    return parse_torque_csv(text, str(Path(path)), torque_unit, time_unit, flip_sign, field)


def read_open_water_table(path: str | os.PathLike[str], field: str = "open_water_table"):
    """The open-water curves of a CSV file (`floebreak.propeller.open_water.parse_open_water_table`)."""
    from floebreak.propeller.open_water import parse_open_water_table

    return parse_open_water_table(read_text_file(path, field), str(Path(path)), field)


def synthetic_torque_path() -> Path:
    """Path of the shipped SYNTHETIC example series (not measured data)."""
    return package_data_path("synthetic_shaft_torque.csv")


def load_shaft_line(spec: str | os.PathLike[str]) -> ShaftLine:
    """A built-in name (``agulhas_ii``) or a TOML file with a ``[shaft_line]`` table. The table may start
    from a built-in line (``base = "agulhas_ii"``) and override its keys and, in
    ``[shaft_line.element_overrides.NAME]``, keys of its elements."""
    if str(spec) in BUILTIN_LINES:
        return shaft_line_from_dict(builtin_shaft_line(str(spec)), source=f"built-in {spec}")
    path = Path(spec)
    if path.suffix.lower() != ".toml" or not path.is_file():
        raise InputError(
            "shaft_line",
            f"{str(spec)!r} is neither a built-in line nor a TOML file",
            value=str(spec),
            allowed=", ".join(BUILTIN_LINES) + ", or FILE.toml",
        )
    text = read_text_file(path, "shaft_line", encoding="utf-8-sig")
    try:
        data = loads_toml(text, "shaft_line", str(path))
    except tomllib.TOMLDecodeError as error:
        raise InputError("shaft_line", f"cannot read {str(path)!r}: {error}", value=str(path)) from None
    table = data.get("shaft_line")
    if not isinstance(table, dict):
        raise InputError("shaft_line", f"{str(path)!r} has no [shaft_line] table", value=str(path))
    table = dict(table)
    base = table.pop("base", None)
    if base is not None:
        table = merge_base(builtin_shaft_line(str(base)), table, "shaft_line")
    elif "element_overrides" in table:
        raise InputError("shaft_line.element_overrides", "needs base = a built-in line")
    return shaft_line_from_dict(table, source=str(path))
