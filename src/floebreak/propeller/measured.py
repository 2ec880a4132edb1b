"""Measured shaft torque time series (thesis §6.2, Fig. 35, Appendix A.2–A.3).

CSV: ``#`` comment lines, a header with a time column (name starting with "time") and a torque column
(name starting with "torque"), units in the names (``time_s``, ``torque_kNm``, ``torque [kN m]``) or given
as `torque_unit`; then numeric rows. Time must increase strictly. `flip_sign` multiplies the torque by −1.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.io.delimiters import check_comma_separated
from floebreak.propeller.loads.fem import _UNITS as _FEM_UNITS
from floebreak.propeller.loads.fem import split_name_unit, unit_factor

_TIME_UNITS = {"time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}}
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
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = rows[0]
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
    for r, row in enumerate(rows[1:], start=1):
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
    return TorqueSeries(t, q, source)
