"""Measured torque files: at most `MAX_TORQUE_ROWS` rows, at least two samples over a positive duration,
and no torque beyond any shaft's (|Q| ≤ 1e5 kN·m) — otherwise an input error naming the file and row."""

from __future__ import annotations

import pytest

from floebreak.errors import InputError
from floebreak.propeller.measured import MAX_TORQUE_NM, MAX_TORQUE_ROWS, parse_torque_csv

HEADER = "time_s,torque_kNm\n"


def test_a_single_sample_is_refused():
    with pytest.raises(InputError, match=r"m\.csv: 1 sample, a series of zero duration") as info:
        parse_torque_csv(HEADER + "0.0,300\n", "m.csv")
    assert info.value.field == "torque_csv"


@pytest.mark.parametrize(("value", "row"), [("1e300", 2), ("-2e5", 2)])
def test_a_torque_beyond_any_shaft_is_refused_naming_the_row(value, row):
    with pytest.raises(InputError, match=rf"m.csv: data row {row}, column 'torque_kNm': .* beyond any shaft"):
        parse_torque_csv(HEADER + f"0.0,300\n0.001,{value}\n0.002,310\n", "m.csv")


def test_the_bound_itself_is_accepted():
    series = parse_torque_csv(HEADER + f"0.0,{MAX_TORQUE_NM / 1e3:g}\n0.001,0\n", "m.csv")
    assert series.duration_s == pytest.approx(0.001)


def test_more_rows_than_the_bound_are_refused_before_parsing():
    rows = "".join(f"{i * 1e-3:.3f},300\n" for i in range(MAX_TORQUE_ROWS + 1))
    with pytest.raises(InputError, match=f"more than {MAX_TORQUE_ROWS:,} rows") as info:
        parse_torque_csv(HEADER + rows, "long.csv")
    assert f"long.csv: data row {MAX_TORQUE_ROWS + 1:,}" in str(info.value)
