"""FEM tables: thesis Tables 10/11 as shipped, and validation of user tables."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.app.inputs import read_fem_table, resolve_fem_tables, shipped_fem_tables
from floebreak.errors import InputError
from floebreak.propeller.loads.fem import fem_table_dict, parse_fem_table

GOOD = """# pitch_percent: 50
volume_m3,length_m,width_m,height_m,force_kN,torque [kN m]
1.0,1.0,1.0,1.0,100,-90
2.0,2.0,1.0,1.0,150,-140
"""


def test_shipped_tables_are_thesis_tables_10_and_11():
    tables = shipped_fem_tables()
    assert sorted(tables) == [0.0, 95.0]
    t0, t95 = tables[0.0], tables[95.0]
    assert t0.volume_m3 == pytest.approx([3.7073, 6.5232, 9.4535, 12.5043])
    assert t0.force_n == pytest.approx([240.55e3, 263.11e3, 291.05e3, 362.60e3])
    assert t0.torque_nm == pytest.approx([-244.58e3, -267.17e3, -282.97e3, -347.22e3])
    assert t95.force_n == pytest.approx([763.09e3, 1058.27e3, 1434.74e3, 1686.20e3])
    assert t95.torque_nm == pytest.approx([-841.47e3, -1092.60e3, -1384.67e3, -1658.78e3])
    # the cuboids' volumes are length × width × height to the table's rounding
    assert t0.length_m * t0.width_m * t0.height_m == pytest.approx(t0.volume_m3, rel=2e-4)


def test_user_table_units_and_pitch():
    table = parse_fem_table(GOOD, "good.csv")
    assert table.pitch_percent == 50.0
    assert table.force_n == pytest.approx([1e5, 1.5e5])
    assert table.torque_nm == pytest.approx([-9e4, -1.4e5])
    no_pitch = GOOD.replace("# pitch_percent: 50\n", "")
    assert parse_fem_table(no_pitch, "x", default_pitch_percent=12.0).pitch_percent == 12.0


def test_resolve_from_path_and_mapping(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text(GOOD)
    assert list(resolve_fem_tables(path)) == [50.0]
    assert list(resolve_fem_tables({50: path})) == [50.0]
    with pytest.raises(InputError, match="says pitch_percent 50, given 30"):
        resolve_fem_tables({30: path})
    with pytest.raises(InputError, match="two tables"):
        resolve_fem_tables([path, path])
    # a table without a '# pitch_percent:' line needs a pitch: never a silent default
    bare = tmp_path / "bare.csv"
    bare.write_text(GOOD.replace("# pitch_percent: 50\n", ""))
    with pytest.raises(InputError, match="pitch unknown"):
        resolve_fem_tables(bare)
    assert list(resolve_fem_tables([(0.0, bare), (95.0, bare)])) == [0.0, 95.0]
    # a caller may state a fallback for files without the line; the line still wins where present
    assert list(resolve_fem_tables([bare, path], 20.0)) == [20.0, 50.0]
    with pytest.raises(InputError, match="does not exist"):
        read_fem_table(tmp_path / "missing.csv")


def test_the_pure_side_takes_tables_only(tmp_path):
    # the analyses' own check (fem_table_dict): FemTables in, sorted by pitch; a path is not read there
    table = parse_fem_table(GOOD, "good.csv")
    shipped = shipped_fem_tables()
    assert list(fem_table_dict([table, shipped[95.0], shipped[0.0]])) == [0.0, 50.0, 95.0]
    assert list(fem_table_dict({"any key": table})) == [50.0]
    assert list(fem_table_dict(table)) == [50.0]
    with pytest.raises(InputError, match="PosixPath is not a FemTable"):
        fem_table_dict([tmp_path / "t.csv"])
    with pytest.raises(InputError, match="two tables for pitch 50"):
        fem_table_dict([table, table])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (GOOD.replace("2.0,2.0,1.0", "0.5,2.0,1.0"), r"row 2, column 'volume_m3'.*increase"),
        (GOOD.replace("2.0,2.0,1.0", "1.0,2.0,1.0"), "increase"),
        (
            "# pitch_percent: 5\nvolume_m3,length_m,width_m,height_m,force_kN,torque_kNm\n1,1,1,1,1,1\n",
            "at least 2 points",
        ),
        (GOOD.replace(",width_m", ",breadth_m"), "missing column.*width"),
        (GOOD.replace("150", "nan"), r"row 2, column 'force_kN'"),
        (GOOD.replace("150", "abc"), r"row 2, column 'force_kN'.*not a number"),
        (GOOD.replace("force_kN", "force"), "no unit"),
        (GOOD.replace("force_kN", "force_lbf"), "unknown unit"),
        (GOOD.replace("1.0,1.0,1.0,1.0,100", "0.0,1.0,1.0,1.0,100"), "volume 0"),
        (GOOD.replace("1.0,1.0,1.0,1.0,100", "-1.0,1.0,1.0,1.0,100"), "> 0"),
        (GOOD.replace("# pitch_percent: 50\n", ""), "pitch unknown"),
    ],
)
def test_bad_tables_are_refused_naming_column_and_row(text, match):
    with pytest.raises(InputError, match=match) as info:
        parse_fem_table(text, "user.csv")
    assert info.value.field == "fem_table"
    assert "user.csv" in str(info.value)


def test_origin_row_is_optional():
    with_origin = GOOD.replace("torque [kN m]\n", "torque [kN m]\n0,0,0,0,0,0\n")
    a, b = parse_fem_table(with_origin, "a"), parse_fem_table(GOOD, "b")
    assert np.array_equal(a.volume_m3, b.volume_m3)
