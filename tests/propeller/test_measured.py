"""Measured shaft-torque CSV (thesis §6.2) and its density spectrum."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.app.inputs import read_torque_csv, synthetic_torque_path
from floebreak.errors import InputError
from floebreak.propeller.measured import parse_torque_csv
from floebreak.propeller.spectra import bin_edges, density, envelope, ranges_above


def test_synthetic_series_is_labelled_and_reads():
    path = synthetic_torque_path()
    assert "SYNTHETIC" in path.read_text().splitlines()[0]
    series = read_torque_csv(path)
    assert series.time_s.size == 2400 and np.all(np.diff(series.time_s) > 0)
    assert -150e3 < series.torque_nm.min() < 0.0 < 300e3 < series.torque_nm.max() < 450e3
    flipped = read_torque_csv(path, flip_sign=True)
    assert np.array_equal(flipped.torque_nm, -series.torque_nm)


def test_units_from_header_or_option():
    text = "# c\ntime [ms],torque (MN m)\n0,0.1\n10,0.2\n"
    series = parse_torque_csv(text, "x")
    assert series.time_s.tolist() == pytest.approx([0.0, 0.01])
    assert series.torque_nm.tolist() == pytest.approx([1e5, 2e5])
    plain = parse_torque_csv("time,torque\n0,5\n1,6\n", "x", torque_unit="kNm")
    assert plain.torque_nm.tolist() == pytest.approx([5e3, 6e3])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("time_s,torque_kNm\n", "no numeric rows"),
        ("# only comments\n", "no header"),
        ("time_s,torque_kNm\n0,1\n2,1\n1,1\n", r"data row 3, column 'time_s'.*does not increase"),
        ("time_s,torque_kNm\n0,1\n0,1\n", "does not increase"),
        ("time_s,torque_kNm\n0,abc\n", r"data row 1, column 'torque_kNm'"),
        ("time_s,torque_kNm\n0,nan\n", r"column 'torque_kNm'"),
        ("time_s,force_kN\n0,1\n", "no torque column"),
        ("time_s,torque\n0,1\n", "no unit"),
    ],
)
def test_bad_torque_csv(text, match):
    with pytest.raises(InputError, match=match) as info:
        parse_torque_csv(text, "m.csv")
    assert info.value.field == "torque_csv"


def test_density_and_threshold_ranges():
    values = np.r_[np.full(90, 15.0), np.full(10, 35.0)]
    edges = bin_edges(values, 10.0)
    assert edges.tolist() == [0.0, 10.0, 20.0, 30.0, 40.0]
    dens = density(values, edges)
    assert np.sum(dens * np.diff(edges)) == pytest.approx(1.0)
    assert dens.tolist() == pytest.approx([0.0, 0.09, 0.0, 0.01])
    intervals = ranges_above(edges, dens, 0.005)
    assert intervals == [(10.0, 20.0), (30.0, 40.0)] and envelope(intervals) == (10.0, 40.0)
    assert bin_edges([-15.0, 5.0], 10.0)[0] == -20.0
