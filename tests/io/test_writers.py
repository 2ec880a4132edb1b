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
        {"x": values, "n": np.arange(6), "ok": [True, False, True, False, True, None], "s": list("ab,d\"f")},
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
    assert (tmp_path / "t.csv").read_text() == "a\n2.0\n"
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


def test_csv_numeric_table_as_the_csv_module_writes_it():
    # long numeric tables are joined without the csv module (issue 33): the same text, cell by cell as
    # Python's repr / str and the csv module's dialect would give it
    rng = np.random.default_rng(7)
    bits = rng.integers(0, 2**62, 3000, dtype=np.int64).view(np.float64)  # any exponent, denormals included
    x = np.concatenate([bits, [0.0, -0.0, 1.0, 1e-5, 1e16, 1e15, np.nan, np.inf, -np.inf, 105.0]])
    n = np.arange(x.size) - 5
    ok = rng.uniform(size=x.size) < 0.5
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["x", "n", "ok", "y"])
    for a, b, c, d in zip(x.tolist(), n.tolist(), ok.tolist(), x[::-1].tolist(), strict=True):
        text = [repr(v) if math.isfinite(v) else "" for v in (a, d)]
        writer.writerow([text[0], str(b), "true" if c else "false", text[1]])
    expected = "# c\n" + buffer.getvalue()
    assert csv_text({"x": x, "n": n, "ok": ok, "y": x[::-1]}, ["c"]) == expected
    assert "1e-05" in expected and "1e+16" in expected and "\n1.0," in expected  # the forms kept
    # one column: a lone empty cell is quoted by the csv module, and still is
    assert csv_text({"x": np.array([1.0, np.nan])}) == 'x\n1.0\n""\n'
