"""Arrow columns built from buffers: the same arrays as ``pa.array``, without importing pandas."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from floebreak.io.geoparquet import arrow_array

COLUMNS = [
    np.arange(7, dtype=np.int64),
    np.array([0.5, np.nan, -0.0, np.inf, 1e300]),
    np.arange(10, dtype=np.int32)[::3],  # not contiguous
    np.array([True, False, True, True, False, False, False, False, True, True]),
    np.zeros(0),
    np.zeros(0, dtype=bool),
    np.array(["cusp", "flipped", "", "bending>cracking", "ü"], dtype=object),
    ["remaining", "cusp"],
    [],  # pa.array([]) is of type null
    np.array([], dtype=object),
    ["a", None],  # nulls: left to pa.array
    [1, 2],  # not str: left to pa.array
]


@pytest.mark.parametrize("values", COLUMNS, ids=range(len(COLUMNS)))
def test_arrow_array_is_what_pa_array_gives(values):
    built, expected = arrow_array(values), pa.array(values)
    assert built.type == expected.type
    assert built.null_count == expected.null_count
    assert repr(built.to_pylist()) == repr(expected.to_pylist())  # repr: NaN == NaN, -0.0 kept


@pytest.mark.parametrize("values", [[b"\x01\x03", b"", b"wkb"], []])
def test_arrow_array_binary(values):
    assert arrow_array(values, binary=True).equals(pa.array(values, type=pa.binary()))


def test_writing_a_geoparquet_file_does_not_import_pandas(tmp_path, imported_by):
    code = (
        "import sys, numpy as np, shapely\n"
        "from floebreak.io.geoparquet import write_geoparquet\n"
        "write_geoparquet(sys.argv[1], np.array([shapely.box(0, 0, 1, 1)]),"
        " {'area_m2': np.ones(1), 'fate': ['cusp'], 'ok': np.ones(1, bool)}, {'seed': 1})\n"
    )
    assert imported_by(code, ("pandas",), tmp_path / "t.parquet") == set()


def test_reading_a_geoparquet_file_does_not_import_the_dataset_layer(tmp_path, imported_by):
    code = (
        "import sys, numpy as np, shapely\n"
        "from floebreak.io.geoparquet import read_geoparquet, write_geoparquet\n"
        "write_geoparquet(sys.argv[1], np.array([shapely.box(0, 0, 1, 2)]),"
        " {'area_m2': np.full(1, 2.0), 'fate': ['cusp']}, {'seed': 1})\n"
        "geometry, columns, meta = read_geoparquet(sys.argv[1])\n"
        "assert geometry[0].area == 2.0 and columns['fate'].tolist() == ['cusp'] and meta['seed'] == 1\n"
    )
    assert imported_by(code, ("pyarrow.dataset",), tmp_path / "t.parquet") == set()


def test_big_endian_numbers_are_left_to_pa_array():
    with pytest.raises(pa.ArrowNotImplementedError):  # as pa.array: "Byte-swapped arrays not supported"
        arrow_array(np.arange(4.0).astype(">f8"))
