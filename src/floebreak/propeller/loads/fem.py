"""FEM force/torque tables per cusp volume (thesis Tables 10 and 11, §6.1.2; notes erratum 24).

A table CSV has `#` comment lines, then a header with the six columns volume, length, width, height,
force, torque, each with its unit in the name (``volume_m3``, ``force_kN``, ``torque [kN m]`` …), then one
numeric row per exemplary cusp. An optional ``# pitch_percent: X`` comment names the pitch the table
belongs to. A leading row at volume 0 must have zero force and torque (the thesis' boundary condition);
the interpolation always passes through (0, 0) whether or not the row is present.

A table over more than one dimension names them in a ``# dimensions: volume, thickness`` comment (any two
or more of volume, length, width, height/thickness; length = the cusp's longer side, width = its shorter,
height = thickness); it needs those columns plus force and torque, one row per FEM cusp, all coordinates
> 0, no point twice. It is interpolated linearly: on a full grid by scipy's RegularGridInterpolator, else
by LinearNDInterpolator (`floebreak.propeller.interpolation.table_interpolant`). Without the comment a
table is the thesis' 1-D table in volume.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.cusps import cusp_geometry
from floebreak.propeller.interpolation import check_options, table_interpolant
from floebreak.propeller.spectra import pitch_label

SHIPPED_TABLES = {0.0: "fem_pitch0.csv", 95.0: "fem_pitch95.csv"}

_UNITS = {
    "volume": {"m3": 1.0, "m^3": 1.0, "m³": 1.0},
    "length": {"m": 1.0},
    "width": {"m": 1.0},
    "height": {"m": 1.0},
    "thickness": {"m": 1.0},
    "force": {"n": 1.0, "kn": 1e3, "mn": 1e6},
    "torque": {
        "nm": 1.0,
        "n_m": 1.0,
        "n m": 1.0,
        "n·m": 1.0,
        "knm": 1e3,
        "kn_m": 1e3,
        "kn m": 1e3,
        "kn·m": 1e3,
        "mnm": 1e6,
        "mn_m": 1e6,
        "mn m": 1e6,
        "mn·m": 1e6,
    },
}
COLUMNS = ("volume", "length", "width", "height", "force", "torque")
# the physical range of a FEM table's cells (SI): the thesis' cusps are 0.1–10 m³ with loads of 0.1–3 MN and
# MN·m; values many orders beyond are typing or unit errors, and extreme ones (1e-300 m³, 1e300 kN) overflow
# the interpolation's slopes. Volume 0 is the origin row only.
CELL_RANGES = {
    "volume": (1e-6, 1e4, "m³"),
    "length": (0.0, 1e3, "m"),
    "width": (0.0, 1e3, "m"),
    "height": (0.0, 1e3, "m"),
    "force": (-1e9, 1e9, "N"),
    "torque": (-1e9, 1e9, "N·m"),
}
DIMENSIONS = ("volume", "length", "width", "height")  # "thickness" is read as height


@dataclass(frozen=True)
class FemTable:
    """One FEM table in SI: points sorted by volume, without the origin row.

    volume_m3, force_n, torque_nm (signed as in the FEM output), length_m, width_m, height_m: (k,) arrays.
    """

    pitch_percent: float
    volume_m3: np.ndarray
    length_m: np.ndarray
    width_m: np.ndarray
    height_m: np.ndarray
    force_n: np.ndarray
    torque_nm: np.ndarray
    source: str
    dimensions: tuple[str, ...] = ("volume",)

    @property
    def max_volume_m3(self) -> float:
        """The largest FEM cusp's volume (NaN if an N-D table gives neither volume nor l, w, h)."""
        v = (
            self.volume_m3
            if np.isfinite(self.volume_m3).all()
            else self.length_m * self.width_m * self.height_m
        )
        return float(np.max(v)) if np.isfinite(v).all() else float("nan")

    def coordinate(self, name: str) -> np.ndarray:
        """The table's values of dimension `name` (volume, length, width, height)."""
        return {"volume": self.volume_m3, "length": self.length_m, "width": self.width_m}.get(
            name, self.height_m
        )


def split_name_unit(name: str) -> tuple[str, str | None]:
    """'force_kN' / 'force [kN]' / 'force (kN)' → ('force', 'kn'); 'force' → ('force', None)."""
    text = name.strip()
    match = re.fullmatch(r"\s*([A-Za-z]+)\s*[\[(]\s*([^\])]*)\s*[\])]\s*", text)
    if match:
        return match.group(1).lower(), match.group(2).strip().lower()
    base, _, unit = text.partition("_")
    return base.lower(), (unit.strip().lower() or None)


def unit_factor(
    quantity: str, unit: str | None, column: str, field: str, units=None, source: str = ""
) -> float:
    """Factor to SI for `unit` of `quantity`; InputError naming file and column if unknown or missing."""
    table = (units or _UNITS)[quantity]
    where = f"{source}: " if source else ""
    if unit is None:
        raise InputError(
            field,
            f"{where}column {column!r} has no unit in its name",
            value=column,
            allowed=f"{quantity}_<unit> with unit one of {', '.join(sorted(table))}",
        )
    if unit not in table:
        raise InputError(
            field,
            f"{where}column {column!r}: unknown unit {unit!r}",
            value=column,
            allowed=", ".join(sorted(table)),
        )
    return table[unit]


def parse_fem_table(
    text: str,
    source: str,
    default_pitch_percent: float | None = None,
    field: str = "fem_table",
    fallback_pitch_percent: float | None = None,
) -> FemTable:
    """Parse and validate a FEM table CSV text (see module docstring)."""
    pitch = default_pitch_percent
    dimensions = ("volume",)
    lines = []
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            dims = re.match(r"#\s*dimensions\s*:\s*(.+)", stripped)
            if dims:
                dimensions = _parse_dimensions(dims.group(1), source, field)
            match = re.match(r"#\s*pitch_percent\s*:\s*(\S+)", stripped)
            if match:
                pitch = _comment_pitch(match.group(1), default_pitch_percent, source, field)
            continue
        if stripped:
            lines.append(line)
    pitch = fallback_pitch_percent if pitch is None else pitch
    if not lines:
        raise InputError(field, f"{source}: no header line", allowed="a CSV header " + ",".join(COLUMNS))
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = rows[0]
    index: dict[str, tuple[int, float]] = {}
    for i, name in enumerate(header):
        base, unit = split_name_unit(name)
        base = "height" if base == "thickness" else base
        if base in _UNITS:
            if base in index:
                raise InputError(field, f"{source}: column {base!r} appears twice", value=name)
            index[base] = (i, unit_factor(base, unit, name, field, source=source))
    required = COLUMNS if dimensions == ("volume",) else (*dimensions, "force", "torque")
    missing = [c for c in required if c not in index]
    if missing:
        raise InputError(
            field,
            f"{source}: missing column(s) {', '.join(missing)}",
            value=header,
            allowed="volume, length, width, height, force, torque, each with its unit",
        )
    values = {c: [] for c in index}
    for r, row in enumerate(rows[1:], start=1):
        for c in index:
            i, factor = index[c]
            cell = row[i].strip() if i < len(row) else ""
            try:
                number = float(cell)
            except ValueError:
                raise InputError(
                    field, f"{source}: row {r}, column {header[i]!r}: {cell!r} is not a number", value=cell
                ) from None
            if not math.isfinite(number):
                raise InputError(
                    field,
                    f"{source}: row {r}, column {header[i]!r} is {cell!r}",
                    value=cell,
                    allowed="finite numbers",
                )
            values[c].append(number * factor)
    arrays = {c: np.asarray(v, dtype=float) for c, v in values.items()}
    if dimensions != ("volume",):
        return grid_table_from_arrays(arrays, dimensions, pitch, source, field, header, index)
    return fem_table_from_arrays(arrays, pitch, source, field, header=header, index=index)


def _comment_pitch(text: str, given: float | None, source: str, field: str) -> float:
    """The ``# pitch_percent:`` value; InputError if not a number or if it contradicts the given pitch."""
    try:
        pitch = float(text)
    except ValueError:
        raise InputError(field, f"{source}: pitch_percent {text!r} is not a number", value=text) from None
    if not math.isfinite(pitch) or not 0.0 <= pitch <= 100.0:
        raise InputError(field, f"{source}: pitch_percent {text!r}", value=text, allowed="[0, 100] %")
    if given is not None and float(given) != pitch:
        raise InputError(
            field,
            f"{source}: the file says pitch_percent {pitch:g}, given {float(given):g}",
            allowed="the same pitch, or a file without a '# pitch_percent:' line",
        )
    return pitch


def _parse_dimensions(text: str, source: str, field: str) -> tuple[str, ...]:
    names = []
    for part in text.replace(";", ",").split(","):
        base, _ = split_name_unit(part)
        base = "height" if base == "thickness" else base
        if base not in DIMENSIONS or base in names:
            raise InputError(
                field,
                f"{source}: '# dimensions:' lists {part.strip()!r}",
                value=text,
                allowed="distinct names among volume, length, width, height (or thickness)",
            )
        names.append(base)
    return tuple(names)


def check_cell_ranges(arrays, source: str, field: str, name) -> None:
    """InputError naming the file, row and column of the first cell outside `CELL_RANGES` (volume 0 allowed:
    the origin row, checked by the caller); `name(c)` is column c's header."""
    for c, (low, high, unit) in CELL_RANGES.items():
        if c not in arrays:
            continue
        a = np.asarray(arrays[c], dtype=float)
        outside = (a < low) | (a > high)
        if c == "volume":
            outside &= a > 0.0  # 0 (the origin row) and negative volumes: the callers' own checks
        bad = np.flatnonzero(outside & np.isfinite(a))
        if bad.size:
            raise InputError(
                field,
                f"{source}: row {bad[0] + 1}, column {name(c)!r}: {a[bad[0]]:g} {unit} (SI) is outside the "
                "physical range of a FEM cusp table",
                value=float(a[bad[0]]),
                allowed=f"[{low:g}, {high:g}] {unit}"
                + (" (or 0 at the origin row)" if c == "volume" else ""),
            )


def grid_table_from_arrays(arrays, dimensions, pitch_percent, source, field, header, index) -> FemTable:
    """Validate an N-D table (see module docstring): finite cells, coordinates > 0, distinct points,
    at least dimensions + 1 points; columns not given become NaN."""
    n = arrays["force"].size
    for c, a in arrays.items():
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise InputError(
                field, f"{source}: row {bad[0] + 1}, column {header[index[c][0]]!r} is not finite"
            )
    check_cell_ranges(arrays, source, field, lambda c: header[index[c][0]])
    for c in dimensions:
        bad = np.flatnonzero(arrays[c] <= 0.0)
        if bad.size:
            raise InputError(
                field,
                f"{source}: row {bad[0] + 1}, column {header[index[c][0]]!r} must be > 0",
                allowed="> 0",
            )
    points = np.column_stack([arrays[c] for c in dimensions])
    if np.unique(points, axis=0).shape[0] < n:
        raise InputError(field, f"{source}: a point appears twice", allowed="distinct points")
    if n < len(dimensions) + 1:
        raise InputError(field, f"{source}: {n} points", allowed=f"at least {len(dimensions) + 1}")
    if pitch_percent is None:
        raise InputError(field, f"{source}: pitch unknown", allowed="a '# pitch_percent: X' line or a pitch")
    full = {c: arrays.get(c, np.full(n, np.nan)) for c in COLUMNS}
    for a in full.values():
        a.setflags(write=False)
    return FemTable(
        float(pitch_percent),
        full["volume"],
        full["length"],
        full["width"],
        full["height"],
        full["force"],
        full["torque"],
        source,
        tuple(dimensions),
    )


def fem_table_from_arrays(
    arrays, pitch_percent, source, field="fem_table", header=None, index=None
) -> FemTable:
    """Validate SI arrays (keys volume, length, width, height, force, torque) and build a FemTable."""

    def name(c):
        return header[index[c][0]] if header is not None else c

    volume = np.asarray(arrays["volume"], dtype=float)
    for c in COLUMNS:
        bad = np.flatnonzero(~np.isfinite(np.asarray(arrays[c], dtype=float)))
        if bad.size:
            raise InputError(
                field,
                f"{source}: row {bad[0] + 1}, column {name(c)!r} is not finite",
                allowed="finite numbers",
            )
    check_cell_ranges(arrays, source, field, name)
    keep = np.ones(volume.size, dtype=bool)
    if volume.size and volume[0] == 0.0:
        if arrays["force"][0] != 0.0 or arrays["torque"][0] != 0.0:
            raise InputError(
                field,
                f"{source}: row 1 has volume 0 but non-zero force or torque",
                allowed="force = torque = 0 at volume 0 (the interpolation passes through 0)",
            )
        keep[0] = False
    negative = np.flatnonzero(volume[keep] <= 0.0)
    if negative.size:
        row = np.flatnonzero(keep)[negative[0]] + 1
        raise InputError(
            field,
            f"{source}: row {row}, column {name('volume')!r}: volume must be > 0",
            value=float(volume[row - 1]),
        )
    if int(keep.sum()) < 2:
        raise InputError(
            field, f"{source}: {int(keep.sum())} table point(s) with volume > 0", allowed="at least 2 points"
        )
    steps = np.flatnonzero(np.diff(volume[keep]) <= 0.0)
    if steps.size:
        row = np.flatnonzero(keep)[steps[0] + 1] + 1
        raise InputError(
            field,
            f"{source}: row {row}, column {name('volume')!r}: volumes must increase strictly",
            value=float(volume[row - 1]),
        )
    if pitch_percent is None:
        raise InputError(
            field,
            f"{source}: pitch unknown",
            allowed="a '# pitch_percent: X' comment line or an explicit pitch",
        )
    out = {c: np.asarray(arrays[c], dtype=float)[keep] for c in COLUMNS}
    for a in out.values():
        a.setflags(write=False)
    return FemTable(
        pitch_percent=float(pitch_percent),
        volume_m3=out["volume"],
        length_m=out["length"],
        width_m=out["width"],
        height_m=out["height"],
        force_n=out["force"],
        torque_nm=out["torque"],
        source=source,
    )


def fem_table_dict(tables) -> dict[float, FemTable]:
    """`tables` (FemTables, or a mapping whose values are FemTables) → {pitch_percent: table}, sorted by
    pitch; anything but a FemTable (e.g. a path: read it with `read_fem_table` or
    `floebreak.app.inputs.resolve_fem_tables`) and two tables of one pitch are InputErrors."""
    if isinstance(tables, FemTable):
        tables = [tables]
    items = list(tables.values()) if isinstance(tables, dict) else list(tables)
    out: dict[float, FemTable] = {}
    for table in items:
        if not isinstance(table, FemTable):
            raise InputError(
                "fem_table",
                f"{type(table).__name__} is not a FemTable",
                value=str(table),
                allowed="FemTable objects (a file: floebreak.app.inputs.resolve_fem_tables)",
            )
        if table.pitch_percent in out:
            raise InputError(
                "fem_table",
                f"two tables for pitch {table.pitch_percent:g} %",
                value=table.source,
                allowed="one table per pitch",
            )
        out[table.pitch_percent] = table
    if not out:
        raise InputError("fem_table", "no table given", allowed="one or more FemTables")
    return dict(sorted(out.items()))


VOLUME_BASES = ("box", "actual")
# The cusp's own volume (area × thickness) enters the FEM interpolation (thesis §6.1.3: the loads "are
# interpolated with respect to the cusp volume"). Evidence from §6.2: at h = 0.4 m the neutral-pitch torques
# end at 210 kN·m, which the quartic reaches at 2.59 m³ — the actual volume of the largest unbreakable cusp,
# A_rotate(0.4 m) × 0.4 m = 6.79 m² × 0.4 m = 2.72 m³ (215 kN·m); its bounding box is larger (box/actual
# 1.3–2 for broken pieces), and box volumes would end at 250–300 kN·m. "box" (Alg. 1's class volume) stays.
DEFAULT_VOLUME_BASIS = "actual"


def propeller_loads(
    columns: dict[str, np.ndarray],
    tables: dict[float, FemTable],
    *,
    interpolation: str = "newton",
    beyond: str = "power_law",
    volume_basis: str = DEFAULT_VOLUME_BASIS,
    cusp_speed_m_s: float = 3.0,
) -> dict[str, np.ndarray]:
    """Per-cusp table (pure): box dimensions, class, kinetic energy, and per pitch force [N], torque [N·m]
    and whether the cusp lies beyond the FEM table. `columns` as returned by `cusp_columns`."""
    check_options(interpolation, beyond)
    if volume_basis not in VOLUME_BASES:
        raise InputError(
            "volume_basis",
            f"unknown value {volume_basis!r}",
            value=volume_basis,
            allowed=", ".join(VOLUME_BASES),
        )
    out = cusp_geometry(columns, cusp_speed_m_s)
    longer, shorter = out["bbox_longer_m"], out["bbox_shorter_m"]
    volume = out["box_volume_m3"] if volume_basis == "box" else columns["volume_m3"]
    coordinates = {"volume": volume, "thickness": columns["thickness_m"], "length": longer, "width": shorter}
    coordinates["height"] = columns["thickness_m"]
    for pitch, table in tables.items():
        label = pitch_label(pitch)
        f = table_interpolant(table, "force", interpolation, beyond)
        q = table_interpolant(table, "torque", interpolation, beyond)
        out[f"force_n_{label}"], beyond_f = f(coordinates)
        out[f"torque_nm_{label}"], _ = q(coordinates)
        out[f"beyond_table_{label}"] = beyond_f
    return out


class FemLoads:
    """The FEM tables' load model: per cusp and table pitch, force and torque interpolated over the cusp
    (`propeller_loads`; thesis §6.1.3)."""

    name = "fem"
    label = "FEM"
    description = "FEM tables (thesis Tables 10/11 or given), interpolated over the cusp volume"
    rpm_text = "FEM loads at 140 rpm, thesis §6.1.2"
    needs_tables = True
    places_on_blade = False

    def pitches(self, propeller, tables) -> tuple[float, ...]:
        return tuple(tables)

    def cusp_loads(
        self, columns, tables, options, propeller, speed_m_s, engaged=None
    ) -> dict[str, np.ndarray]:
        return propeller_loads(
            columns,
            tables,
            interpolation=options["interpolation"],
            beyond=options["beyond"],
            volume_basis=options["volume_basis"],
            cusp_speed_m_s=options["cusp_speed_m_s"],
        )


MODEL = FemLoads()
