"""A bug in any command ends with one closing "internal error" line (exit 1); a machine's storage error is
exit 3; FEM tables with extreme finite cells and TOML files nested thousands of levels deep are input errors
(exit 2) naming the file, before any drawing or parsing recursion."""

from __future__ import annotations

import errno

import pytest

import floebreak.config.scenario
from floebreak.errors import InputError
from floebreak.io.toml_text import MAX_TOML_DEPTH, loads_toml
from floebreak.propeller.loads.fem import parse_fem_table

HEADER = "# pitch_percent: 95\nvolume_m3,length_m,width_m,height_m,force_kN,torque_kNm\n0,0,0,0,0,0\n"


def test_a_bug_in_any_command_ends_with_the_internal_error_line(cli, monkeypatch):
    def broken():
        raise ValueError("`dydx` must contain only finite values.")

    monkeypatch.setattr(floebreak.config.scenario, "json_schema", broken)
    code, _, err = cli("schema")
    assert code == 1
    last = err.strip().splitlines()[-1]
    assert last.startswith("internal error: ValueError: `dydx` must contain only finite values.")
    assert "please report this bug" in last
    assert "Traceback" in err  # the traceback, for the bug report, comes before it


def test_a_storage_error_in_any_command_is_exit_3(cli, monkeypatch):
    def full():
        raise OSError(errno.ENOSPC, "No space left on device", "x.parquet")

    monkeypatch.setattr(floebreak.config.scenario, "json_schema", full)
    code, _, err = cli("schema")
    assert code == 3
    assert "No space left on device" in err and "x.parquet" in err
    assert "internal error" not in err and "Traceback" not in err


@pytest.mark.parametrize(
    ("rows", "where"),
    [
        ("1e-300,1,1,1,1e300,-1e300\n2e-300,1,1,1,2e300,-2e300\n", "row 2, column 'volume_m3'"),
        ("1,1,1,1,1e300,-5\n2,1,1,1,2,-6\n", "row 2, column 'force_kN'"),
        ("1,1,1,1,5,-5\n2,1e9,1,1,2,-6\n", "row 3, column 'length_m'"),
        ("1,1,1,1,5,-5\n2e30,1,1,1,2,-6\n", "row 3, column 'volume_m3'"),
        ("1,1,1,1,5,-5\n2,1,1,1,2,-1e12\n", "row 3, column 'torque_kNm'"),
    ],
)
def test_extreme_finite_fem_cells_are_refused_naming_row_and_column(rows, where):
    with pytest.raises(InputError, match="physical range") as info:
        parse_fem_table(HEADER + rows, "t.csv")
    assert f"t.csv: {where}" in str(info.value)


def test_extreme_fem_table_on_the_command_line_is_exit_2(cli, tmp_path, small_run_dir):
    table = tmp_path / "t.csv"
    table.write_text(HEADER + "1e-300,1,1,1,1e300,-1e300\n2e-300,1,1,1,2e300,-2e300\n")
    code, _, err = cli("propeller", small_run_dir, "--out", tmp_path / "p", "--fem-table", table)
    assert code == 2, err
    assert "t.csv: row 2, column 'volume_m3'" in err
    assert "Traceback" not in err
    assert not (tmp_path / "p").exists()


@pytest.mark.parametrize("depth", [MAX_TOML_DEPTH + 1, 5000])
def test_deeply_nested_toml_is_refused_naming_the_file(cli, tmp_path, depth):
    path = tmp_path / "s.toml"
    path.write_text("a = " + "[" * depth + "]" * depth + "\n")
    code, _, err = cli("run", path, "--out", tmp_path / "out")
    assert code == 2
    assert "s.toml" in err and f"{MAX_TOML_DEPTH} levels" in err
    assert "Traceback" not in err and "RecursionError" not in err
    assert not (tmp_path / "out").exists()


def test_nesting_within_the_bound_parses():
    depth = MAX_TOML_DEPTH
    assert loads_toml("a = " + "[" * depth + "]" * depth, "scenario")["a"] is not None
    with pytest.raises(InputError, match="--set"):
        loads_toml("v = " + "[" * 3000 + "]" * 3000, "--set")
