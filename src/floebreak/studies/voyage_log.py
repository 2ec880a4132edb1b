"""Voyage logs: a ship's ice observation log, one row per observation period.

A CSV file (UTF-8, comma-separated with decimal points, lines starting with ``#`` are comments), read
row by row (`iter_voyage_log`). Units are part of every column
name; docs/studies.md ("Voyages") is the user's reference:

=============================  ==========================================================================
column                         meaning
=============================  ==========================================================================
``start_utc``, ``end_utc``     start and end of the period, ISO 8601 (``2019-12-18T20:20``, ``…Z`` or
                               ``…+02:00``; without an offset the time is UTC)
``concentration_percent``      ice concentration in (0, 100] % — or ``concentration_fraction`` in (0, 1]
``mean_thickness_m``           mean ice thickness [m], in (0, 10]
``share_d<D>m_percent``        share of the floe *count* in the equivalent-diameter class D [m], e.g.
                               ``share_d2.5m_percent`` (thesis Table 1 classes: 2.5, 7.5, 15, 60, 300 m);
                               one column per class, shares in [0, 100] %, summing to 100 ± 0.5 % per row
``speed_m_s`` / ``speed_kn``   optional: ship speed [m/s] or [kn], in (0, 20] m/s (38.8 kn)
``propeller_rpm``              optional: propeller speed [1/min], in (0, 1000]
``propeller_pitch_percent``    optional: pitch P_0.7 relative to the maximum pitch [%], in [0, 100]
``label``                      optional: free text
=============================  ==========================================================================

Every error is an `InputError` whose key names the file, the row (data rows counted from 1, and the line
of the file) and the column: wrong or missing units in a header, unknown, duplicate or missing columns,
empty, non-numeric or NaN cells, values out of range, shares not summing to 100 %, a period that does not
end after it starts, periods not in time order or overlapping. Gaps between periods are allowed (no ice
observed, or open water): they are not part of the voyage's hours in ice.
"""

from __future__ import annotations

import csv
import datetime as dt
import io
import itertools
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from floebreak.config.scenario import SPEED_M_S, THICKNESS_M
from floebreak.errors import InputError, csv_where
from floebreak.ice.observations import PERCENT_SUM_TOLERANCE
from floebreak.io.delimiters import check_comma_separated
from floebreak.propeller.spec import MAX_PROPELLER_RPM

KNOT_M_S = 1852.0 / 3600.0  # international knot
SHARE_COLUMN = re.compile(r"^share_d(?P<diameter>[0-9]+(\.[0-9]+)?)m_percent$")
SHARE_FORM = "share_d<D>m_percent with D in m, e.g. share_d2.5m_percent"
TIME_COLUMNS = ("start_utc", "end_utc")
# quantity stem → the columns that give it (one of them); used to name a wrong unit in a header
QUANTITIES: dict[str, tuple[str, ...]] = {
    "start": ("start_utc",),
    "end": ("end_utc",),
    "concentration": ("concentration_percent", "concentration_fraction"),
    "mean_thickness": ("mean_thickness_m",),
    "thickness": ("mean_thickness_m",),
    "speed": ("speed_m_s", "speed_kn"),
    "propeller_rpm": ("propeller_rpm",),
    "rpm": ("propeller_rpm",),
    "propeller_pitch": ("propeller_pitch_percent",),
    "pitch": ("propeller_pitch_percent",),
}
REQUIRED = ("start_utc", "end_utc", "mean_thickness_m")
OPTIONAL = ("speed_m_s", "speed_kn", "propeller_rpm", "propeller_pitch_percent", "label")
KNOWN = (*REQUIRED, "concentration_percent", "concentration_fraction", *OPTIONAL)


@dataclass(frozen=True, slots=True)
class LogPeriod:
    """One period of a log (SI; times in UTC). `row`: data row counted from 1; `line`: line of the file."""

    row: int
    line: int
    start_utc: dt.datetime
    end_utc: dt.datetime
    concentration: float  # fraction in (0, 1]
    mean_thickness_m: float
    diameter_classes_m: tuple[float, ...]
    percentages: tuple[float, ...]  # share of the floe count per class [%]
    speed_m_s: float | None = None
    propeller_rpm: float | None = None
    propeller_pitch_percent: float | None = None
    label: str = ""

    @property
    def duration_h(self) -> float:
        return (self.end_utc - self.start_utc).total_seconds() / 3600.0


@dataclass(frozen=True)
class VoyageLog:
    """A validated voyage log: its source (file name) and periods in time order."""

    source: str
    periods: tuple[LogPeriod, ...]
    columns: tuple[str, ...]

    @property
    def hours(self) -> float:
        return sum(p.duration_h for p in self.periods)


def _check_header(source: str, header: list[str], line: int) -> None:
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise InputError(
                csv_where(source, name, line=line), "duplicate column", allowed="each column once"
            )
        seen.add(name)
        if name in KNOWN or SHARE_COLUMN.match(name):
            continue
        if name.startswith("share_d") or name.startswith("share"):
            raise InputError(
                csv_where(source, name, line=line), "not a diameter-class column", allowed=SHARE_FORM
            )
        stem = next((s for s in sorted(QUANTITIES, key=len, reverse=True) if name.startswith(s)), None)
        if stem is not None:
            unit = name[len(stem) :].lstrip("_") or "none"
            raise InputError(
                csv_where(source, name, line=line),
                f"unit {unit!r} not accepted",
                allowed=" or ".join(QUANTITIES[stem]),
            )
        raise InputError(
            csv_where(source, name, line=line),
            "unknown column",
            allowed=", ".join((*KNOWN, SHARE_FORM)),
        )
    missing = [c for c in REQUIRED if c not in seen]
    if missing:
        raise InputError(
            csv_where(source, missing[0], line=line), "missing column", allowed=", ".join(REQUIRED)
        )
    given = [c for c in ("concentration_percent", "concentration_fraction") if c in seen]
    if len(given) != 1:
        raise InputError(
            csv_where(source, given[1] if given else "concentration_percent", line=line),
            "missing column" if not given else "give the concentration once",
            allowed="one of concentration_percent, concentration_fraction",
        )
    if "speed_m_s" in seen and "speed_kn" in seen:
        raise InputError(
            csv_where(source, "speed_kn", line=line), "give the speed once", allowed="speed_m_s or speed_kn"
        )
    if not any(SHARE_COLUMN.match(name) for name in header):
        raise InputError(
            csv_where(source, "share_d<D>m_percent", line=line),
            "no diameter-class column",
            allowed=SHARE_FORM,
        )


DECIMAL_COMMA = re.compile(r"^[+-]?[0-9]*,[0-9]+$")
PROGRESS_ROWS = 10_000  # rows between two progress reports


def _number(
    text: str, where: Callable[[], str], low: float, high: float | None, low_inclusive: bool, unit: str
) -> float:
    """`text` as a number in the interval; `where()` builds the error key (only on an error: a log may have
    millions of rows)."""
    try:
        value = float(text)
    except ValueError:
        text = text.strip()
        if not text:
            raise InputError(where(), "empty cell", allowed="a number") from None
        if DECIMAL_COMMA.match(text):
            raise InputError(
                where(),
                f"{text!r} has a decimal comma",
                value=text,
                allowed=f"a decimal point, {text.replace(',', '.')!r} (the log is comma-separated)",
            ) from None
        raise InputError(where(), f"{text!r} is not a number", value=text, allowed="a number") from None
    if not math.isfinite(value):
        raise InputError(
            where(), f"{text.strip()!r} is not a finite number", value=text, allowed="a finite number"
        )
    if (value < low if low_inclusive else value <= low) or (high is not None and value > high):
        left = "[" if low_inclusive else "("
        interval = f"{left}{low:g}, {'inf)' if high is None else f'{high:g}]'}" + (f" {unit}" if unit else "")
        raise InputError(where(), f"{value:g} is outside {interval}", value=value, allowed=interval)
    return value


def _time(text: str, where: Callable[[], str]) -> dt.datetime:
    try:
        value = dt.datetime.fromisoformat(text.strip())
    except ValueError:
        raise InputError(
            where(),
            f"{text.strip()!r} is not an ISO 8601 date and time",
            value=text,
            allowed="e.g. 2019-12-18T20:20, 2019-12-18T20:20Z or 2019-12-18T22:20+02:00",
        ) from None
    if value.tzinfo is None:
        return value.replace(tzinfo=dt.UTC)
    return value.astimezone(dt.UTC)


class _Row:
    """Error keys of one data row, built only when an error is raised."""

    __slots__ = ("line", "row", "source")

    def __init__(self, source: str, row: int, line: int):
        self.source, self.row, self.line = source, row, line

    def at(self, column: str) -> Callable[[], str]:
        return lambda: csv_where(self.source, column, self.row, self.line)


def _period(source: str, row: int, line: int, cells: dict[str, str], shares: list[tuple[str, float]]):
    here = _Row(source, row, line)
    start = _time(cells["start_utc"], here.at("start_utc"))
    end = _time(cells["end_utc"], here.at("end_utc"))
    if not end > start:
        raise InputError(
            here.at("end_utc")(),
            f"{end.isoformat()} is not after the start {start.isoformat()}",
            allowed="end > start",
        )
    if "concentration_percent" in cells:
        c = _number(cells["concentration_percent"], here.at("concentration_percent"), 0.0, 100.0, False, "%")
        concentration = c / 100.0
    else:
        concentration = _number(
            cells["concentration_fraction"], here.at("concentration_fraction"), 0.0, 1.0, False, ""
        )
    thickness = _number(
        cells["mean_thickness_m"], here.at("mean_thickness_m"), 0.0, THICKNESS_M[1], False, "m"
    )
    percentages = [_number(cells[name], here.at(name), 0.0, 100.0, True, "%") for name, _ in shares]
    total = sum(percentages)
    if abs(total - 100.0) > PERCENT_SUM_TOLERANCE:
        raise InputError(
            here.at(", ".join(name for name, _ in shares))(),
            f"shares sum to {total:g} %",
            value=total,
            allowed=f"100 ± {PERCENT_SUM_TOLERANCE:g} %",
        )
    speed = None
    if "speed_m_s" in cells:
        speed = _number(cells["speed_m_s"], here.at("speed_m_s"), 0.0, SPEED_M_S[1], False, "m/s")
    elif "speed_kn" in cells:
        top_kn = math.floor(10.0 * SPEED_M_S[1] / KNOT_M_S) / 10.0  # 38.8 kn: not above 20 m/s
        speed = _number(cells["speed_kn"], here.at("speed_kn"), 0.0, top_kn, False, "kn") * KNOT_M_S
    rpm = pitch = None
    if "propeller_rpm" in cells:
        rpm = _number(
            cells["propeller_rpm"], here.at("propeller_rpm"), 0.0, MAX_PROPELLER_RPM, False, "1/min"
        )
    if "propeller_pitch_percent" in cells:
        pitch = _number(
            cells["propeller_pitch_percent"], here.at("propeller_pitch_percent"), 0.0, 100.0, True, "%"
        )
    kept = [(d, p) for (_, d), p in zip(shares, percentages, strict=True) if p > 0.0]
    return LogPeriod(
        row=row,
        line=line,
        start_utc=start,
        end_utc=end,
        concentration=concentration,
        mean_thickness_m=thickness,
        diameter_classes_m=tuple(d for d, _ in kept),
        percentages=tuple(p for _, p in kept),
        speed_m_s=speed,
        propeller_rpm=rpm,
        propeller_pitch_percent=pitch,
        label=cells.get("label", "").strip(),
    )


def _check_order(source: str, before: LogPeriod, period: LogPeriod) -> None:
    if period.start_utc >= before.end_utc:
        return
    where = csv_where(source, "start_utc", period.row, period.line)
    if period.start_utc < before.start_utc:
        raise InputError(
            where,
            f"{period.start_utc.isoformat()} is before the previous period's start "
            f"{before.start_utc.isoformat()} (row {before.row})",
            allowed="periods in increasing time order",
        )
    if period.start_utc < before.end_utc:
        raise InputError(
            where,
            f"{period.start_utc.isoformat()} overlaps the previous period (row {before.row}), which ends "
            f"{before.end_utc.isoformat()}",
            allowed=f"a start ≥ {before.end_utc.isoformat()}",
        )


def _shares(source: str, header: list[str], line: int) -> list[tuple[str, float]]:
    shares = sorted(
        ((name, float(SHARE_COLUMN.match(name)["diameter"])) for name in header if SHARE_COLUMN.match(name)),
        key=lambda item: item[1],
    )
    for (name, diameter), (_, other) in itertools.pairwise(shares):
        if diameter <= 0.0 or diameter == other:
            raise InputError(
                csv_where(source, name, line=line),
                "diameter must be > 0 and distinct from the other classes",
                allowed=SHARE_FORM,
            )
    if shares[0][1] <= 0.0:
        raise InputError(
            csv_where(source, shares[0][0], line=line), "diameter must be > 0", allowed=SHARE_FORM
        )
    return shares


def _cell_count(source: str, row: int, line: int, cells: list[str], header: list[str]) -> InputError:
    hint = ""
    if len(cells) > len(header) and any(
        a.strip().lstrip("+-").isdigit() and b.strip().isdigit() for a, b in itertools.pairwise(cells)
    ):
        hint = " (a decimal comma? numbers take a decimal point, 0.5, not 0,5)"
    return InputError(
        csv_where(source, None, row, line),
        f"{len(cells)} cells for {len(header)} columns{hint}",
        allowed="one cell per column",
    )


def _data_lines(lines: Iterable[str], position: list[int]) -> Iterator[str]:
    """The lines that are neither blank nor comments; `position[0]` is the file line of the last one given."""
    for number, line in enumerate(lines, start=1):
        if line.strip() and not line.lstrip().startswith("#"):
            position[0] = number
            yield line


def iter_voyage_log(
    lines: Iterable[str], source: str = "log", progress: Callable[[int], None] | None = None
) -> tuple[tuple[str, ...], Iterator[LogPeriod]]:
    """(columns, periods) of a voyage log given line by line: the header is validated at once, the periods
    one at a time as the iterator is consumed (memory independent of the number of rows); `progress(rows)`
    every `PROGRESS_ROWS` rows and at the end."""
    position = [0]
    reader = csv.reader(_data_lines(lines, position))
    first = next(reader, None)
    if first is None:
        raise InputError(source, "no header", allowed="a CSV header and one row per observation period")
    header = [name.strip() for name in first]
    header_line = position[0]
    check_comma_separated(csv_where(source, line=header_line), header, ",".join(first))
    _check_header(source, header, header_line)
    shares = _shares(source, header, header_line)
    classes: dict[tuple, tuple] = {}  # one tuple object per distinct set of classes, shared by the periods

    def periods() -> Iterator[LogPeriod]:
        before = None
        row = 0
        for row, cells in enumerate(reader, start=1):
            line = position[0]
            if len(cells) != len(header):
                raise _cell_count(source, row, line, cells, header)
            period = _period(source, row, line, dict(zip(header, cells, strict=True)), shares)
            key = period.diameter_classes_m
            object.__setattr__(period, "diameter_classes_m", classes.setdefault(key, key))
            if before is not None:
                _check_order(source, before, period)
            before = period
            if progress is not None and row % PROGRESS_ROWS == 0:
                progress(row)
            yield period
        if before is None:
            raise InputError(source, "no observation period", allowed="at least one row after the header")
        if progress is not None:
            progress(row)

    return tuple(header), periods()


def parse_voyage_log(text: str, source: str = "log") -> VoyageLog:
    """Validate the text of a voyage log (see the module docstring); `source` names it in errors."""
    columns, periods = iter_voyage_log(io.StringIO(text), source)
    return VoyageLog(source=source, periods=tuple(periods), columns=columns)


def read_voyage_log(path: str | Path, progress: Callable[[int], None] | None = None) -> VoyageLog:
    """Read and validate a voyage log CSV file, streaming it (the file's text is never held whole);
    `progress(rows)` as in `iter_voyage_log`; errors name the file, row and column."""
    path = Path(path)
    try:
        with path.open(encoding="utf-8-sig", newline="") as stream:
            columns, periods = iter_voyage_log(stream, str(path), progress)
            return VoyageLog(source=str(path), periods=tuple(periods), columns=columns)
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(
            str(path), f"cannot read the log: {error}", allowed="a readable UTF-8 CSV file"
        ) from None
