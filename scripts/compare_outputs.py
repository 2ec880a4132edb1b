"""Compare two output trees (run directories, propeller and shaft analyses, studies) file by file, ignoring
what is expected to differ between two runs of the same physics: provenance (JSON ``provenance`` entries,
Parquet schema metadata's ``provenance``, NetCDF ``provenance*``/``history`` attributes, PNG text chunks),
measured wall times, and the checksums that cover them (``summary.json``'s ``files`` and
``summary_sha256``). Everything else must be equal: table columns and values, array values, pixels, text.

    python scripts/compare_outputs.py OLD_TREE NEW_TREE

Prints one line per differing or missing file and exits 1 if there is any, else prints the file count and
exits 0.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path
from typing import Any

IGNORED_KEYS = {"provenance", "wall_time_s", "summary_sha256", "files"}
# in report.html: the wall-time row, and the summary.json it shows (escaped JSON)
WALL_TIME_ROW = re.compile(r"(<td>wall time</td><td class='num'>)[^<]*(</td>)")
SHOWN_KEYS = r"&quot;(?:report\.html|summary_sha256|wall_time_s)&quot;: "
SHOWN_JSON = re.compile(rf"({SHOWN_KEYS})(&quot;[0-9a-f]+&quot;|[-+.\de]+)")


def _strip(value: Any) -> Any:
    """A JSON value without the ignored keys, at any depth."""
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k not in IGNORED_KEYS}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _json_text(text: str | bytes | None) -> Any:
    if text is None:
        return None
    try:
        return _strip(json.loads(text))
    except ValueError:
        return text


def _same_json(old: Path, new: Path) -> bool:
    return _json_text(old.read_bytes()) == _json_text(new.read_bytes())


def _same_parquet(old: Path, new: Path) -> bool:
    import pyarrow.parquet as pq

    a, b = pq.read_table(old), pq.read_table(new)
    if not a.equals(b):  # columns, types and values (schema metadata aside)
        return False
    meta_a, meta_b = a.schema.metadata or {}, b.schema.metadata or {}
    return {k: _json_text(v) for k, v in meta_a.items()} == {k: _json_text(v) for k, v in meta_b.items()}


def _attrs(attrs: dict) -> dict:
    return {
        k: _json_text(v) if isinstance(v, str) else repr(v)
        for k, v in attrs.items()
        if not k.startswith("provenance") and k != "history"
    }


def _same_netcdf(old: Path, new: Path) -> bool:
    import numpy as np
    import xarray as xr

    with xr.open_dataset(old, engine="h5netcdf") as a, xr.open_dataset(new, engine="h5netcdf") as b:
        if _attrs(a.attrs) != _attrs(b.attrs) or set(a.variables) != set(b.variables):
            return False
        for name in a.variables:
            va, vb = a[name], b[name]
            if va.dims != vb.dims or _attrs(va.attrs) != _attrs(vb.attrs):
                return False
            if not np.array_equal(va.values, vb.values, equal_nan=va.dtype.kind in "fc"):
                return False
    return True


def _same_png(old: Path, new: Path) -> bool:
    from PIL import Image

    with Image.open(old) as a, Image.open(new) as b:
        return a.mode == b.mode and a.size == b.size and a.tobytes() == b.tobytes()


def _same_html(old: Path, new: Path) -> bool:
    def normal(path: Path) -> str:
        text = WALL_TIME_ROW.sub(r"\1…\2", path.read_text(encoding="utf-8"))
        return SHOWN_JSON.sub(r"\1…", text)

    return normal(old) == normal(new)


COMPARERS = {
    ".json": _same_json,
    ".parquet": _same_parquet,
    ".nc": _same_netcdf,
    ".png": _same_png,
    ".html": _same_html,
}


def compare(old_root: Path, new_root: Path) -> tuple[int, list[str]]:
    """(files compared, differences) of the two trees."""
    old_files = {p.relative_to(old_root) for p in old_root.rglob("*") if p.is_file()}
    new_files = {p.relative_to(new_root) for p in new_root.rglob("*") if p.is_file()}
    problems = [f"only in {old_root}: {p}" for p in sorted(old_files - new_files)]
    problems += [f"only in {new_root}: {p}" for p in sorted(new_files - old_files)]
    for relative in sorted(old_files & new_files):
        old, new = old_root / relative, new_root / relative
        if old.read_bytes() == new.read_bytes():
            continue
        same = COMPARERS.get(relative.suffix)
        if same is None or not same(old, new):
            problems.append(f"differs: {relative}")
    return len(old_files & new_files), problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    args = parser.parse_args(argv)
    count, problems = compare(args.old, args.new)
    for line in problems:
        print(line)
    if not problems:
        print(f"{count} files compared: identical apart from provenance and wall times")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
