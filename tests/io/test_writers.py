"""The one CSV, NetCDF and JSON writer (floebreak.io.writers): one float format, CF coordinates without
_FillValue, unique temporary names."""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest

from floebreak.io import atomic
from floebreak.io.writers import csv_text, write_csv, write_json, write_netcdf


def test_csv_one_format_reads_back_exactly():
    values = np.array([0.1, 1.0 / 3.0, 1e-7, 2.5e20, np.nan, -np.inf])
    text = csv_text(
        {"x": values, "n": np.arange(6), "ok": [True, False, True, False, True, None], "s": list('ab,d"f')},
        ["a comment"],
    )
    lines = text.splitlines()
    assert lines[0] == "# a comment" and lines[1] == "x,n,ok,s"  # the header unquoted
    rows = list(csv.DictReader(io.StringIO("\n".join(lines[1:]))))
    parsed = [float(r["x"]) if r["x"] else math.nan for r in rows]
    assert parsed[:4] == values[:4].tolist()  # shortest round-trip text: exact
    assert [r["x"] for r in rows[4:]] == ["", ""]  # non-finite: empty cells
    assert [r["n"] for r in rows] == ["0", "1", "2", "3", "4", "5"]
    assert [r["ok"] for r in rows] == ["true", "false", "true", "false", "true", ""]
    assert [r["s"] for r in rows] == ["a", "b", ",", "d", '"', "f"]  # quoted only where needed
    # a list of Python floats is formatted as the array of them
    assert csv_text({"x": values.tolist()}) == csv_text({"x": values})
    with pytest.raises(ValueError, match="unequal"):
        csv_text({"a": [1.0], "b": [1.0, 2.0]})


def test_every_write_uses_its_own_temporary_name(tmp_path, monkeypatch):
    seen = []
    real = atomic.tempfile.mkstemp

    def spy(*args, **kwargs):
        handle, name = real(*args, **kwargs)
        seen.append(name)
        return handle, name

    monkeypatch.setattr(atomic.tempfile, "mkstemp", spy)
    write_csv(tmp_path / "t.csv", {"a": [1.0]})
    write_csv(tmp_path / "t.csv", {"a": [2.0]})
    write_json(tmp_path / "s.json", {"b": np.float64(np.nan), "a": np.arange(2)})
    assert len(set(seen)) == 3 and all(".tmp-" in name for name in seen)
    assert (tmp_path / "t.csv").read_text() == "a\n2\n"
    assert json.loads((tmp_path / "s.json").read_text()) == {"a": [0, 1], "b": None}
    assert (tmp_path / "s.json").read_text().startswith('{\n  "a"')  # keys sorted, indented by 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json", "t.csv"]  # no temporary left


def test_netcdf_cf_coordinates_without_fill_value(tmp_path):
    xr = pytest.importorskip("xarray")
    ds = xr.Dataset(
        {"density": ("bin", np.array([0.5, np.nan]), {"units": "1/(kN m)"})},
        coords={
            "torque": ("bin", np.array([5.0, 15.0]), {"units": "kN m"}),
            "torque_bin_lower": ("bin", np.array([0.0, 10.0])),
            "torque_bin_upper": ("bin", np.array([10.0, 20.0])),
        },
    )
    write_netcdf(ds, tmp_path / "s.nc")
    with xr.open_dataset(tmp_path / "s.nc", mask_and_scale=False) as back:
        assert back.attrs["Conventions"] == "CF-1.8"
        for name in ("torque", "torque_bin_lower", "torque_bin_upper"):
            assert "_FillValue" not in back[name].attrs, name
        assert "_FillValue" in back["density"].attrs  # data variables keep their missing-value marker
    assert "Conventions" not in ds.attrs  # the caller's dataset is not changed


def _any_floats(rng: np.random.Generator) -> np.ndarray:
    """Random bit patterns (any exponent, subnormals included) and the edge cases of the format."""
    bits = rng.integers(0, 2**63, 3000, dtype=np.int64).view(np.float64)
    signs = np.where(rng.uniform(size=bits.size) < 0.5, -1.0, 1.0)
    edges = [0.0, -0.0, 1.0, 1e-5, 1e-7, 1e15, 1e16, 2.0**53, 2.0**53 + 2, 5e-324, 2.2250738585072014e-308]
    edges += [1.7976931348623157e308, 105.0, 0.1, 1 / 3, -123456789.0, 12345678901234567890.0]
    return np.concatenate([bits * signs, edges, [np.nan, np.inf, -np.inf]])


def _same_bits(parsed, expected) -> bool:
    parsed, expected = np.asarray(parsed, dtype=np.float64), np.asarray(expected, dtype=np.float64)
    finite = np.isfinite(expected)
    return bool(np.all(parsed[finite].view(np.int64) == expected[finite].view(np.int64)))


def test_csv_floats_read_back_bit_for_bit(tmp_path):
    # one float format for every CSV, read back exactly by the usual readers
    x = _any_floats(np.random.default_rng(7))
    path = write_csv(tmp_path / "t.csv", {"x": x, "n": np.arange(x.size) - 5, "y": x[::-1]}, ["c"])
    finite = np.isfinite(x)
    # numpy: empty (non-finite) cells as nan
    back = np.genfromtxt(path, delimiter=",", skip_header=2, dtype=np.float64)
    assert _same_bits(back[:, 0], x) and np.isnan(back[~finite, 0]).all()
    assert _same_bits(back[:, 2], x[::-1])
    # the csv module and float()
    with path.open() as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    assert _same_bits([float(r["x"]) if r["x"] else math.nan for r in rows], x)
    assert [r["x"] for r in rows if not r["x"]] == [""] * 3
    assert [int(r["n"]) for r in rows] == list(range(-5, x.size - 5))
    # pandas, told the column is float (a guessing reader takes whole numbers for integers)
    pd = pytest.importorskip("pandas")
    frame = pd.read_csv(path, comment="#", dtype={"x": "float64", "y": "float64"})
    assert _same_bits(frame["x"].to_numpy(), x)
    assert frame["x"].isna().to_numpy().tolist() == (~finite).tolist()


def test_csv_float_text_forms():
    # Arrow's shortest round-trip text (the documented examples), in a table of numbers (written by
    # pyarrow.csv) and in a column alone or beside text (written cell by cell): the same text
    x = np.array([1.0, -0.0, 1e-5, 1e-7, 1e15, 0.1, 105.5, np.nan])
    expected = ["1", "-0", "0.00001", "1e-7", "1e+15", "0.1", "105.5", ""]
    numeric = csv_text({"x": x, "ok": x > 1}).splitlines()[1:]
    assert [line.split(",")[0] for line in numeric] == expected
    assert [line.split(",")[1] for line in numeric] == ["false"] * 4 + ["true", "false", "true", "false"]
    assert csv_text({"x": x, "s": list("abcdefgh")}).splitlines()[1:] == [
        f"{e},{s}" for e, s in zip(expected, "abcdefgh", strict=True)
    ]
    # a list mixing floats with None and text formats its floats the same way
    assert csv_text({"v": [1e-7, None, "a,b", np.float32(0.5)]}) == 'v\n1e-7\n""\n"a,b"\n0.5\n'
    # one column: a lone empty cell is quoted by the csv module
    assert csv_text({"x": np.array([1.0, np.nan])}) == 'x\n1\n""\n'
    # float32 is written as its float64 value (which reads back as that float64)
    assert csv_text({"x": np.array([0.1], dtype=np.float32)}) == f"x\n{float(np.float32(0.1))!r}\n"
