"""Measured shaft torque time series (thesis §6.2, Fig. 35, Appendix A.2–A.3).

CSV: ``#`` comment lines, a header with a time column (name starting with "time") and a torque column
(name starting with "torque"), units in the names (``time_s``, ``torque_kNm``, ``torque [kN m]``) or given
as `torque_unit`; then numeric rows. Time must increase strictly. `flip_sign` multiplies the torque by −1.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.io.delimiters import check_comma_separated
from floebreak.propeller.loads.fem import _UNITS as _FEM_UNITS
from floebreak.propeller.loads.fem import split_name_unit, unit_factor

_TIME_UNITS = {"time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}}
# a measured series is compared as a whole in memory: at most a million rows (≈ 17 min at 1 kHz, ≈ 200 MB
# while parsed); longer records are cut into pieces (or resampled) by the user
MAX_TORQUE_ROWS = 1_000_000
# the largest physical shaft torque: 100 MN·m, ≈ 30 × the rated torque of the largest ice-going ships'
# shafts (Agulhas II ≈ 0.4 MN·m per shaft); beyond it a value is a unit or typing error
MAX_TORQUE_NM = 1.0e8
_TORQUE_UNITS = {"torque": _FEM_UNITS["torque"]}  # the same torque units as FEM tables


@dataclass(frozen=True)
class TorqueSeries:
    time_s: np.ndarray
    torque_nm: np.ndarray
    source: str

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0])


def parse_torque_csv(
    text: str,
    source: str,
    torque_unit: str | None = None,
    time_unit: str | None = None,
    flip_sign: bool = False,
    field: str = "torque_csv",
) -> TorqueSeries:
    lines = [line for line in text.splitlines() if line.strip() and not line.strip().startswith("#")]
    if not lines:
        raise InputError(field, f"{source}: no header line", allowed="a header with time and torque columns")
    if len(lines) - 1 > MAX_TORQUE_ROWS:
        raise InputError(
            field,
            f"{source}: data row {MAX_TORQUE_ROWS + 1:,}: more than {MAX_TORQUE_ROWS:,} rows",
            value=len(lines) - 1,
            allowed=f"at most {MAX_TORQUE_ROWS:,} rows (cut a longer record into pieces, or resample it)",
        )
    rows = csv.reader(lines)
    header = next(rows)
    check_comma_separated(f"{field}: {source}, header", header, lines[0])
    t_col = q_col = None
    t_unit = q_unit = None
    for i, name in enumerate(header):
        base, unit = split_name_unit(name)
        if base.startswith("time") and t_col is None:
            t_col, t_unit = i, unit
        elif base.startswith("torque") and q_col is None:
            q_col, q_unit = i, unit
    if t_col is None or q_col is None:
        missing = "time" if t_col is None else "torque"
        raise InputError(
            field,
            f"{source}: no {missing} column in header {header}",
            value=header,
            allowed="columns named time_<unit> and torque_<unit>",
        )
    q_unit = torque_unit.strip().lower() if torque_unit else q_unit
    t_unit = time_unit.strip().lower() if time_unit else (t_unit or "s")
    q_factor = unit_factor("torque", q_unit, header[q_col], field, _TORQUE_UNITS, source)
    t_factor = unit_factor("time", t_unit, header[t_col], field, _TIME_UNITS, source)
    time, torque = [], []
    for r, row in enumerate(rows, start=1):
        cells = []
        for col in (t_col, q_col):
            cell = row[col].strip() if col < len(row) else ""
            try:
                number = float(cell)
            except ValueError:
                raise InputError(
                    field,
                    f"{source}: data row {r}, column {header[col]!r}: {cell!r} is not a number",
                    value=cell,
                ) from None
            if not math.isfinite(number):
                raise InputError(
                    field,
                    f"{source}: data row {r}, column {header[col]!r} is {cell!r}",
                    value=cell,
                    allowed="finite numbers",
                )
            cells.append(number)
        time.append(cells[0] * t_factor)
        torque.append(cells[1] * q_factor)
    if not time:
        raise InputError(field, f"{source}: no numeric rows", allowed="at least one row of time, torque")
    t = np.asarray(time)
    steps = np.flatnonzero(np.diff(t) <= 0.0)
    if steps.size:
        raise InputError(
            field,
            f"{source}: data row {steps[0] + 2}, column {header[t_col]!r}: time does not increase",
            value=float(t[steps[0] + 1]) / t_factor,
            allowed="strictly increasing time",
        )
    q = np.asarray(torque) * (-1.0 if flip_sign else 1.0)
    _check_series(t, q, source, field, header[q_col], q_factor)
    return TorqueSeries(t, q, source)


def _check_series(t: np.ndarray, q: np.ndarray, source: str, field: str, column: str, factor: float) -> None:
    """InputError for a series that cannot be compared: fewer than 2 samples (no duration), or a torque
    beyond `MAX_TORQUE_NM` (naming the data row)."""
    if t.size < 2:
        raise InputError(
            field,
            f"{source}: {t.size} sample, a series of zero duration",
            value=int(t.size),
            allowed="at least 2 samples over a positive duration",
        )
    big = np.flatnonzero(np.abs(q) > MAX_TORQUE_NM)
    if big.size:
        raise InputError(
            field,
            f"{source}: data row {big[0] + 1}, column {column!r}: {q[big[0]] / factor:g} is beyond any "
            f"shaft's torque (|Q| ≤ {MAX_TORQUE_NM / 1e3:g} kN·m; a unit or typing error?)",
            value=float(q[big[0]] / factor),
            allowed=f"|torque| ≤ {MAX_TORQUE_NM / 1e3:g} kN·m",
        )
