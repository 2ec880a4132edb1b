"""Voyage logs: the column scheme, and every bad input named by file, row and column."""

from __future__ import annotations

import datetime as dt
import itertools
import tracemalloc
from pathlib import Path

import pytest

from floebreak.errors import InputError
from floebreak.studies.voyage_log import iter_voyage_log, parse_voyage_log, read_voyage_log

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "agu1920_log.csv"

HEADER = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d5m_percent,share_d20m_percent"
ROW1 = "2020-01-01T00:00,2020-01-01T00:10,50,0.5,60,40"
ROW2 = "2020-01-01T01:00,2020-01-01T01:30,30,1.0,100,0"


def test_thesis_table1_example_log():
    log = read_voyage_log(EXAMPLE)
    assert len(log.periods) == 10
    third = log.periods[2]  # thesis Table 1, 19/12/2019 04:40–04:50: 79 %, 1.12 m, 15/60/300 m at 20/60/20 %
    assert third.start_utc == dt.datetime(2019, 12, 19, 4, 40, tzinfo=dt.UTC)
    assert third.duration_h == pytest.approx(10 / 60)
    assert third.concentration == pytest.approx(0.79)
    assert third.mean_thickness_m == 1.12
    assert third.diameter_classes_m == (15.0, 60.0, 300.0)  # the 0 % classes are dropped
    assert third.percentages == (20.0, 60.0, 20.0)
    assert third.speed_m_s is None and third.propeller_pitch_percent is None
    assert log.hours == pytest.approx(10 * 10 / 60)


def test_units_offsets_and_optional_columns():
    text = (
        "# a comment line\n"
        "start_utc,end_utc,concentration_fraction,mean_thickness_m,share_d10m_percent,speed_kn,"
        "propeller_rpm,propeller_pitch_percent,label\n"
        "2020-01-01T02:00+02:00,2020-01-01T02:30+02:00,0.4,0.7,100,5.832,140,80,first\n"
        "2020-01-01T00:45Z,2020-01-01T01:00Z,0.5,0.7,100,1,120,0,second\n"
    )
    log = parse_voyage_log(text, "log.csv")
    first, second = log.periods
    assert first.start_utc == dt.datetime(2020, 1, 1, 0, 0, tzinfo=dt.UTC)  # 02:00 at +02:00
    assert first.duration_h == 0.5
    assert first.concentration == 0.4
    assert first.speed_m_s == pytest.approx(5.832 * 1852 / 3600)  # international knot: 1852 m per hour
    assert (first.propeller_rpm, first.propeller_pitch_percent, first.label) == (140.0, 80.0, "first")
    assert first.line == 3 and second.row == 2 and second.line == 4
    assert second.start_utc == dt.datetime(2020, 1, 1, 0, 45, tzinfo=dt.UTC)


def _log(*lines: str) -> str:
    return "\n".join(lines) + "\n"


BAD = [
    # (log text, text the message must hold: the row or header, the column, the problem)
    (
        _log(HEADER.replace("mean_thickness_m", "mean_thickness_cm"), ROW1),
        ["header", "mean_thickness_cm", "unit"],
    ),
    (_log(HEADER.replace("concentration_percent", "concentration_pct"), ROW1), ["concentration_pct", "unit"]),
    (_log(HEADER.replace("share_d5m", "share_d5cm"), ROW1), ["share_d5cm_percent", "share_d<D>m_percent"]),
    (_log(HEADER + ",speed_mph", ROW1 + ",3"), ["speed_mph", "speed_m_s or speed_kn"]),
    (_log(HEADER + ",colour", ROW1 + ",red"), ["'colour'", "unknown column"]),
    (_log(HEADER + ",mean_thickness_m", ROW1 + ",0.5"), ["'mean_thickness_m'", "duplicate"]),
    (
        _log(HEADER.replace(",mean_thickness_m", ""), "2020-01-01T00:00,2020-01-01T00:10,50,60,40"),
        ["mean_thickness_m", "missing"],
    ),
    (
        _log(HEADER.replace(",concentration_percent", ""), "2020-01-01T00:00,2020-01-01T00:10,0.5,60,40"),
        ["concentration_percent", "missing"],
    ),
    (
        _log(
            "start_utc,end_utc,concentration_percent,mean_thickness_m",
            "2020-01-01T00:00,2020-01-01T00:10,50,1",
        ),
        ["share_d<D>m_percent"],
    ),
    (
        _log(HEADER, ROW1.replace(",0.5,", ",thick,")),
        ["row 1 (line 2)", "'mean_thickness_m'", "not a number"],
    ),
    (_log(HEADER, ROW1, ROW2.replace(",1.0,", ",nan,")), ["row 2 (line 3)", "'mean_thickness_m'", "finite"]),
    (_log(HEADER, ROW1.replace(",50,", ",,")), ["row 1", "'concentration_percent'", "empty cell"]),
    (_log(HEADER, ROW1.replace(",50,", ",120,")), ["row 1", "'concentration_percent'", "(0, 100] %"]),
    (_log(HEADER, ROW1.replace(",0.5,", ",0,")), ["row 1", "'mean_thickness_m'", "(0, 10] m"]),
    (_log(HEADER, ROW1.replace(",0.5,", ",11,")), ["row 1", "'mean_thickness_m'", "(0, 10] m"]),
    (
        _log(HEADER, ROW1.replace("60,40", "60,30")),
        ["row 1", "share_d5m_percent, share_d20m_percent", "sum to 90"],
    ),
    (_log(HEADER, ROW1.replace("60,40", "-10,110")), ["row 1", "'share_d5m_percent'", "[0, 100] %"]),
    (_log(HEADER, ROW1.replace("T00:10", "T00:00")), ["row 1", "'end_utc'", "not after the start"]),
    (
        _log(HEADER, ROW1.replace("2020-01-01T00:00", "01/01/2020 00:00")),
        ["row 1", "'start_utc'", "ISO 8601"],
    ),
    (_log(HEADER, ROW2, ROW1), ["row 2 (line 3)", "'start_utc'", "before the previous period's start"]),
    (
        _log(HEADER, ROW1, ROW1.replace("T00:00", "T00:05").replace("T00:10", "T00:20")),
        ["row 2", "'start_utc'", "overlaps"],
    ),
    (_log(HEADER + ",speed_m_s", ROW1 + ",0"), ["row 1", "'speed_m_s'", "(0, 20] m/s"]),
    # 38.8 kn × 1852 m / 3600 s = 19.96 m/s: the last tenth of a knot within 20 m/s
    (_log(HEADER + ",speed_kn", ROW1 + ",-4"), ["row 1", "'speed_kn'", "(0, 38.8] kn"]),
    (_log(HEADER + ",speed_kn", ROW1 + ",40"), ["row 1", "'speed_kn'", "(0, 38.8] kn"]),
    (_log(HEADER + ",propeller_rpm", ROW1 + ",5000"), ["row 1", "'propeller_rpm'", "(0, 1000] 1/min"]),
    (
        _log(HEADER + ",propeller_pitch_percent", ROW1 + ",101"),
        ["row 1", "'propeller_pitch_percent'", "[0, 100] %"],
    ),
    (_log(HEADER + ",propeller_rpm", ROW1 + ",0"), ["row 1", "'propeller_rpm'"]),
    (_log(HEADER, ROW1 + ",7"), ["row 1 (line 2)", "7 cells for 6 columns"]),
    (_log(HEADER), ["no observation period"]),
]


@pytest.mark.parametrize(("text", "expected"), BAD)
def test_bad_logs_name_file_row_and_column(text, expected):
    with pytest.raises(InputError) as info:
        parse_voyage_log(text, "season.csv")
    message = str(info.value)
    assert message.startswith("season.csv")
    for part in expected:
        assert part in message, message


def test_unreadable_file_names_it(tmp_path):
    with pytest.raises(InputError, match=r"missing\.csv"):
        read_voyage_log(tmp_path / "missing.csv")


# --- streaming, progress, and the separator named -------------------------------------------


def _rows(n: int):
    start = dt.datetime(2020, 1, 1)
    for i in range(n):
        a, b = start + dt.timedelta(minutes=10 * i), start + dt.timedelta(minutes=10 * i + 10)
        yield f"{a:%Y-%m-%dT%H:%M},{b:%Y-%m-%dT%H:%M},50,0.5,60,40\n"


def test_a_log_is_validated_row_by_row_as_it_is_read():
    # an endless log: the first periods come out without the rest being read
    def endless():
        yield HEADER + "\n"
        yield from _rows(10**12)

    columns, periods = iter_voyage_log(endless(), "endless.csv")
    first = list(itertools.islice(periods, 3))
    assert columns[0] == "start_utc" and [p.row for p in first] == [1, 2, 3]


def test_reading_a_long_log_reports_progress_and_holds_only_its_periods(tmp_path):
    # a 10⁶-row log gave no progress for 120 s and reached 1.8 GB (its text, its lines and its
    # cells held at once next to the periods)
    path = tmp_path / "long.csv"
    with path.open("w", encoding="utf-8") as stream:
        stream.write(HEADER + "\n")
        stream.writelines(_rows(25_000))
    reports = []
    tracemalloc.start()
    try:
        log = read_voyage_log(path, progress=reports.append)
        kept, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(log.periods) == 25_000 and reports == [10_000, 20_000, 25_000]
    assert peak < 1.2 * kept  # what the reading needs beyond the periods themselves is small


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            HEADER.replace(",", ";") + "\n" + ROW1.replace(",", ";").replace("0.5", "0,5"),
            "separated by semicolons",
        ),
        (HEADER.replace(",", "\t") + "\n" + ROW1.replace(",", "\t"), "separated by tabs"),
    ],
    ids=["semicolon", "tab"],
)
def test_a_log_separated_by_semicolons_or_tabs_names_the_separator(tmp_path, text, expected):
    # a semicolon or decimal-comma log blamed a "unit"
    path = tmp_path / "log.csv"
    path.write_text(text + "\n", encoding="utf-8")
    with pytest.raises(InputError) as info:
        read_voyage_log(path)
    message = str(info.value)
    assert message.startswith(f"{path}, header (line 1): the columns are {expected}, not by commas")
    assert "unit" not in message and "decimal" in message


def test_a_decimal_comma_in_a_comma_separated_log_is_named(tmp_path):
    unquoted = parse_error(HEADER + "\n" + ROW1.replace("0.5", "0,5"))
    assert "7 cells for 6 columns (a decimal comma? numbers take a decimal point" in unquoted
    quoted = parse_error(HEADER + "\n" + ROW1.replace("0.5", '"0,5"'))
    assert quoted.startswith("log.csv, row 1 (line 2), column 'mean_thickness_m': '0,5' has a decimal comma")
    assert "'0.5'" in quoted


def parse_error(text: str) -> str:
    with pytest.raises(InputError) as info:
        parse_voyage_log(text, "log.csv")
    return str(info.value)
