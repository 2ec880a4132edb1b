"""``contacts.parquet``: the contact records of a run (`floebreak.engine.records.CONTACT_COLUMNS`), one row
per
floe–panel pair of each contact evaluation, written at once or streamed in row groups while the run goes on.

Both ways give the same table: the columns in the recorder's order and types, each unit as Arrow field
metadata (`geoparquet.with_units`), provenance as JSON under the schema metadata key ``floebreak``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from floebreak.io.geoparquet import (
    FLOEBREAK_METADATA_KEY,
    arrow_array,
    as_schema,
    row_groups,
    with_units,
    write_row_groups,
)
from floebreak.io.jsonable import to_json


def contacts_table(columns: Mapping[str, np.ndarray], metadata: Mapping[str, Any]) -> pa.Table:
    """The Arrow table of contact-record columns (text columns as strings even when empty)."""
    arrays = {k: arrow_array(v) for k, v in columns.items()}
    arrays = {k: (v.cast(pa.string()) if pa.types.is_null(v.type) else v) for k, v in arrays.items()}
    table = pa.table(arrays).replace_schema_metadata(
        {FLOEBREAK_METADATA_KEY: to_json(dict(metadata)).encode()}
    )
    return with_units(table)


def write_contacts(
    path: str | os.PathLike[str], columns: Mapping[str, np.ndarray], metadata: Mapping[str, Any]
) -> None:
    """Write contact-record columns held in memory (row groups of `geoparquet.ROW_GROUP_ROWS`)."""
    n_rows = len(next(iter(columns.values())))
    parts = ({k: v[rows] for k, v in columns.items()} for rows in row_groups(n_rows))
    write_row_groups(path, (contacts_table(part, metadata) for part in parts))


class ContactFile:
    """A ``contacts.parquet`` written chunk by chunk while a run goes on
    (`floebreak.engine.records.ContactRecorder`
    with a spool): each chunk of records becomes a row group and leaves memory.

    `empty`: the columns of a run without contact (their types make the file's schema when no chunk comes).
    """

    def __init__(
        self, path: str | os.PathLike[str], metadata: Mapping[str, Any], empty: Mapping[str, np.ndarray]
    ):
        self.path = Path(path)
        self._metadata = dict(metadata)
        self._empty = dict(empty)
        self._writer: pq.ParquetWriter | None = None

    def write(self, columns: Mapping[str, np.ndarray]) -> None:
        table = contacts_table(columns, self._metadata)
        if self._writer is None:
            self._writer = pq.ParquetWriter(self.path, table.schema)
        self._writer.write_table(as_schema(table, self._writer.schema))

    def close(self) -> None:
        """Finish the file (a run without contact: an empty table)."""
        if self._writer is None:
            self.write(self._empty)
        self._writer.close()

    def discard(self) -> None:
        """Close and delete a file the run did not finish."""
        if self._writer is not None:
            self._writer.close()
        self.path.unlink(missing_ok=True)


def read_contacts(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """The contact records of a ``contacts.parquet`` as numpy columns (text as object arrays of str)."""
    table = pq.read_table(path)
    return {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names}
