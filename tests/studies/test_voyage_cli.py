"""`floebreak voyage`: bad logs and options exit with code 2, name file, row and column, and
write nothing."""

from __future__ import annotations

import pytest

HEADER = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d5m_percent,share_d20m_percent"
ROW1 = "2020-01-01T00:00,2020-01-01T00:10,50,0.5,60,40"
ROW2 = "2020-01-01T01:00,2020-01-01T01:30,30,1.0,100,0"


BAD_LOGS = [
    # (log lines, texts the message must hold)
    (
        [HEADER.replace("mean_thickness_m", "mean_thickness_mm"), ROW1],
        ["header (line 1)", "'mean_thickness_mm'"],
    ),
    ([HEADER.replace(",mean_thickness_m", ""), ROW1], ["header (line 1)", "'mean_thickness_m'", "missing"]),
    ([HEADER, ROW1, ROW2.replace(",1.0,", ",NaN,")], ["row 2 (line 3)", "'mean_thickness_m'"]),
    ([HEADER, ROW1.replace(",50,", ",fifty,")], ["row 1 (line 2)", "'concentration_percent'"]),
    ([HEADER, ROW2, ROW1], ["row 2 (line 3)", "'start_utc'", "time order"]),
    ([HEADER, ROW1, ROW1.replace("T00:00", "T00:09").replace("T00:10", "T00:30")], ["row 2", "overlaps"]),
    ([HEADER, ROW1.replace("60,40", "60,41")], ["row 1 (line 2)", "share_d5m_percent", "100 ± 0.5 %"]),
    ([HEADER + ",speed_m_s", ROW1 + ",0"], ["row 1 (line 2)", "'speed_m_s'"]),
    ([HEADER + ",speed_m_s", ROW1 + ",-2"], ["row 1 (line 2)", "'speed_m_s'"]),
]


@pytest.mark.parametrize(("lines", "expected"), BAD_LOGS)
def test_bad_log_exit_code_2_names_file_row_column_and_writes_nothing(tmp_path, lines, expected, cli):
    log = tmp_path / "season.csv"
    log.write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = tmp_path / "voyage"
    code, _, err = cli("voyage", str(log), "--out", str(out), "--workers", "1")
    assert code == 2, err
    message = " ".join(err.split())  # rich may wrap the line
    assert "season.csv" in message
    for part in expected:
        assert part in message, message
    assert sorted(p.name for p in tmp_path.iterdir()) == ["season.csv"]


@pytest.mark.parametrize(
    ("args", "key"),
    [
        (["--speed-m-s", "0"], "speed_m_s"),
        (["--max-length-m", "-5"], "max_length_m"),
        (["--n-fields", "0"], "n_fields"),
        (["--set", "ice.thickness_m=0.5"], "--set"),
        (["--set", "ship.hull=titanic"], "ship.hull"),
        (["--workers", "0"], "workers"),
        (["--years", "20"], "--years"),
        (["--hours-in-ice-per-year", "9000", "--years", "20"], "hours_in_ice_per_year"),
    ],
)
def test_bad_options_exit_code_2_and_write_nothing(tmp_path, args, key, cli):
    log = tmp_path / "season.csv"
    log.write_text(f"{HEADER}\n{ROW1}\n", encoding="utf-8")
    code, _, err = cli("voyage", str(log), "--out", str(tmp_path / "voyage"), *args)
    assert code == 2 and key in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["season.csv"]


def test_an_existing_directory_that_is_not_a_voyage_is_refused(tmp_path, cli):
    log = tmp_path / "season.csv"
    log.write_text(f"{HEADER}\n{ROW1}\n", encoding="utf-8")
    out = tmp_path / "voyage"
    out.mkdir()
    (out / "mine.txt").write_text("keep", encoding="utf-8")
    code, _, err = cli("voyage", str(log), "--out", str(out), "--workers", "1")
    assert code == 2 and "out" in err
    assert [p.name for p in out.iterdir()] == ["mine.txt"]
