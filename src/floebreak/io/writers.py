"""The one writer of each kind: CSV tables, CF-1.8 NetCDF datasets and JSON documents.

Every file goes through `floebreak.io.atomic.atomic_path` (a unique temporary name, then a rename), so a
reader never sees half a file and two processes writing the same folder never share a temporary name.

- CSV (`write_csv`): ``#`` comment lines, a header, one row per index of the equally long columns. One
  format for every table floebreak writes: floats as their shortest round-trip text (Python's ``repr``:
  ``0.1``, ``1.0``, ``1e-07``), non-finite floats and None as empty cells, booleans as ``true``/``false``,
  integers as digits, other values as text, quoted only where the CSV dialect needs it (comma, quote or
  line break: Python's ``csv`` module).
- NetCDF (`write_netcdf`): ``xarray.Dataset.to_netcdf`` (public API), NetCDF4 through h5netcdf when it is
  installed, else NetCDF3 through scipy; ``Conventions = "CF-1.8"``; coordinates and bin bounds
  (``*_bounds``, ``*_bin_lower``/``*_bin_upper``) get no ``_FillValue`` (CF: coordinate values are never
  missing).
- JSON (`write_json`): `floebreak.io.jsonable.jsonable` (numpy as Python numbers, non-finite as null),
  indented by 2, keys sorted, a final line break.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.io.atomic import atomic_path
from floebreak.io.jsonable import jsonable

CF_CONVENTIONS = "CF-1.8"


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    if isinstance(value, float | np.floating):
        return repr(float(value)) if math.isfinite(value) else ""
    if isinstance(value, np.integer):
        return str(int(value))
    return str(value)


def _column_text(values: Any) -> tuple[list[str], bool]:
    """The cells of one column as text (the module's format) and whether they are numbers or booleans
    (no cell then needs quoting). Float arrays in one pass: ``repr`` mapped over the values in C (long
    series), the non-finite ones emptied afterwards."""
    array = np.asarray(values)
    if array.dtype.kind == "f":
        cells = list(map(repr, array.tolist()))
        for i in np.flatnonzero(~np.isfinite(array)).tolist():
            cells[i] = ""
        return cells, True
    if array.dtype.kind in "iu":
        return list(map(str, array.tolist())), True
    if array.dtype.kind == "b":
        return ["true" if v else "false" for v in array.tolist()], True
    return [_cell(v) for v in (values if isinstance(values, list) else array.tolist())], False


def csv_text(columns: Mapping[str, Any], comments: Iterable[str] = ()) -> str:
    """The text `write_csv` writes (for a caller that needs it in memory)."""
    names = list(columns)
    texts = [_column_text(columns[name]) for name in names]
    cells = [c for c, _ in texts]
    lengths = {len(c) for c in cells}
    if len(lengths) > 1:
        raise ValueError(f"columns of unequal length: {dict(zip(names, map(len, cells), strict=True))}")
    buffer = io.StringIO()
    for line in comments:
        buffer.write(f"# {line}\n")
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(names)
    if len(names) > 1 and all(numeric for _, numeric in texts):
        # no cell to quote (and no lone empty field, which csv quotes): rows joined directly, the same text
        buffer.writelines(f"{row}\n" for row in map(",".join, zip(*cells, strict=True)))
    else:
        writer.writerows(zip(*cells, strict=True))
    return buffer.getvalue()


def rows_to_columns(rows: list[Mapping[str, Any]]) -> dict[str, list]:
    """Equally keyed rows (the first row's keys, in its order) as columns for `write_csv`."""
    names = list(rows[0]) if rows else []
    return {name: [row[name] for row in rows] for name in names}


def write_csv(path: str | os.PathLike[str], columns: Mapping[str, Any], comments: Iterable[str] = ()) -> Path:
    """Write `columns` (name → equally long sequence) as a CSV with `comments` first; returns `path`."""
    text = csv_text(columns, comments)
    with atomic_path(path) as temp:
        temp.write_text(text, encoding="utf-8")
    return Path(path)


def netcdf_engine() -> str:
    """ "h5netcdf" (NetCDF4) when installed, else "scipy" (NetCDF3)."""
    import importlib.util

    return "h5netcdf" if importlib.util.find_spec("h5netcdf") is not None else "scipy"


def _is_coordinate_like(ds, name: str) -> bool:
    return name in ds.coords or name.endswith(("_bounds", "_bin_lower", "_bin_upper"))


def write_netcdf(ds, path: str | os.PathLike[str]) -> str:
    """Write the xarray Dataset `ds` as CF-1.8 NetCDF (module docstring); returns the engine used."""
    engine = netcdf_engine()
    ds = ds.copy()
    ds.attrs.setdefault("Conventions", CF_CONVENTIONS)
    encoding = {
        name: {"_FillValue": None}
        for name in ds.variables
        if _is_coordinate_like(ds, name) and ds[name].dtype.kind == "f"
    }
    with atomic_path(path) as temp:
        ds.to_netcdf(temp, engine=engine, encoding=encoding)
    return engine


def write_json(path: str | os.PathLike[str], document: Any) -> Path:
    """Write `document` as JSON (module docstring); returns `path`."""
    text = json.dumps(jsonable(document), indent=2, sort_keys=True) + "\n"
    with atomic_path(path) as temp:
        temp.write_text(text, encoding="utf-8")
    return Path(path)
