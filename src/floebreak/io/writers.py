"""The one writer of each kind: CSV tables, CF-1.8 NetCDF datasets and JSON documents.

Every file goes through `floebreak.io.atomic.atomic_path` (a unique temporary name, then a rename), so a
reader never sees half a file and two processes writing the same folder never share a temporary name.

- CSV (`write_csv`): ``#`` comment lines, a header, one row per index of the equally long columns. One
  format for every table floebreak writes: floats (as float64) in Arrow's shortest round-trip text
  (``pyarrow.compute.cast`` to string, the text ``pyarrow.csv`` writes: ``0.1``, ``1`` for 1.0, ``-0``,
  ``0.00001``, ``1e-7``, ``1e+15``; parsed as float64 it gives back the same value, bit for bit),
  non-finite floats and None as empty cells, booleans as ``true``/``false``, integers as digits, other
  values as text, quoted only where the CSV dialect needs it (comma, quote or line break: Python's ``csv``
  module). A table of numbers and booleans only is written by ``pyarrow.csv`` (its rows need no quoting).
  Read float columns as floats: a type-guessing reader (pandas, ``pyarrow.csv``) takes a column of whole
  numbers (``1``, ``-0``) for integers.
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
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.io.atomic import atomic_path
from floebreak.io.jsonable import jsonable

CF_CONVENTIONS = "CF-1.8"


def _float_text(values: Any) -> list[str]:
    """Float cells in the module's format: Arrow's shortest round-trip text, non-finite ones empty."""
    import pyarrow as pa
    import pyarrow.compute as pc

    array = np.asarray(values, dtype=np.float64)
    text = pc.cast(pa.array(array, mask=~np.isfinite(array)), pa.string())
    return pc.fill_null(text, "").to_pylist()


def _cell(value: Any) -> str:
    """A cell that is not a float (`_column_text` formats those together)."""
    if value is None:
        return ""
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    if isinstance(value, np.integer):
        return str(int(value))
    return str(value)


def _column_text(values: Any) -> list[str]:
    """The cells of one column as text (the module's format); its float cells in one call of Arrow."""
    array = np.asarray(values)
    if array.dtype.kind == "f":
        return _float_text(array)
    if array.dtype.kind in "iu":
        return list(map(str, array.tolist()))
    if array.dtype.kind == "b":
        return ["true" if v else "false" for v in array.tolist()]
    items = values if isinstance(values, list) else array.tolist()
    cells = [_cell(v) for v in items]
    floats = [i for i, v in enumerate(items) if isinstance(v, float | np.floating)]
    for i, text in zip(floats, _float_text([items[i] for i in floats]), strict=True):
        cells[i] = text
    return cells


def _numeric_array(values: Any) -> np.ndarray | None:
    """`values` as an array of numbers or booleans (float64 for floats), None if it holds anything else."""
    array = np.asarray(values)
    if array.ndim != 1 or array.dtype.kind not in "fiub":
        return None
    return array.astype(np.float64, copy=False) if array.dtype.kind == "f" else array


def _numeric_rows(arrays: list[np.ndarray]) -> bytes:
    """The rows of equally long numeric or boolean columns, as `pyarrow.csv` writes them (no header; the
    float text as `_float_text`'s: Arrow formats both)."""
    import pyarrow as pa
    import pyarrow.csv as pa_csv

    columns = [pa.array(a, mask=~np.isfinite(a)) if a.dtype.kind == "f" else pa.array(a) for a in arrays]
    table = pa.table(columns, names=[f"c{i}" for i in range(len(columns))])
    buffer = io.BytesIO()
    pa_csv.write_csv(table, buffer, pa_csv.WriteOptions(include_header=False))
    return buffer.getvalue()


def _csv_parts(columns: Mapping[str, Any], comments: Iterable[str]) -> list[bytes]:
    """The UTF-8 text `write_csv` writes, in parts (the rows of a long numeric table are not copied)."""
    names = list(columns)
    lengths = {name: len(columns[name]) for name in names}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"columns of unequal length: {lengths}")
    buffer = io.StringIO()
    for line in comments:
        buffer.write(f"# {line}\n")
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(names)
    arrays = [_numeric_array(columns[name]) for name in names]
    if len(names) > 1 and all(a is not None for a in arrays):
        # no cell to quote (and no lone empty field, which the csv module quotes): Arrow writes the rows
        return [buffer.getvalue().encode("utf-8"), _numeric_rows(arrays)]
    writer.writerows(zip(*(_column_text(columns[name]) for name in names), strict=True))
    return [buffer.getvalue().encode("utf-8")]


def csv_text(columns: Mapping[str, Any], comments: Iterable[str] = ()) -> str:
    """The text `write_csv` writes (for a caller that needs it in memory)."""
    return b"".join(_csv_parts(columns, comments)).decode("utf-8")


def rows_to_columns(rows: list[Mapping[str, Any]]) -> dict[str, list]:
    """Equally keyed rows (the first row's keys, in its order) as columns for `write_csv`."""
    names = list(rows[0]) if rows else []
    return {name: [row[name] for row in rows] for name in names}


def write_csv(path: str | os.PathLike[str], columns: Mapping[str, Any], comments: Iterable[str] = ()) -> Path:
    """Write `columns` (name → equally long sequence) as a CSV with `comments` first; returns `path`."""
    parts = _csv_parts(columns, comments)
    with atomic_path(path) as temp, temp.open("wb") as file:
        file.writelines(parts)
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
