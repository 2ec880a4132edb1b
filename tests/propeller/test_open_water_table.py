"""Open-water curves from a table (`--open-water-table`): interpolation, the operating point on it, and
malformed tables refused by the command line (exit 2, the key named, nothing written)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from tests.shaft.test_cli_shaft import make_run

from floebreak.errors import InputError
from floebreak.propeller.open_water import (
    TabulatedPropeller,
    operating_point,
    parse_open_water_table,
    zero_thrust_advance_ratio,
)

# two straight curves: K_T = a − 0.4 J, K_Q = b − 0.02 J, with (a, b) = (0.5, 0.05) at P/D 1.0 and
# (0.6, 0.07) at P/D 1.2, tabulated at J = 0, 0.2, …, 1.2
J = np.round(np.arange(0.0, 1.21, 0.2), 10)


def _csv(rows=None, header="pitch_ratio,J,K_T,K_Q") -> str:
    if rows is None:
        rows = [(1.0, j, 0.5 - 0.4 * j, 0.05 - 0.02 * j) for j in J]
        rows += [(1.2, j, 0.6 - 0.4 * j, 0.07 - 0.02 * j) for j in J]
    return "# a test table\n" + header + "\n" + "\n".join(",".join(f"{v:.10g}" for v in r) for r in rows)


def test_interpolation_in_j_and_pitch_by_hand():
    table = parse_open_water_table(_csv(), "t.csv")
    kt, kq = table.coefficients(0.3, 1.1)  # halfway between the pitches, between two J points
    assert float(kt) == pytest.approx(0.55 - 0.4 * 0.3)
    assert float(kq) == pytest.approx(0.06 - 0.02 * 0.3)
    # zero thrust of the mean curve at J = 0.55/0.4 = 1.375 lies beyond the table: its end, 1.2
    assert zero_thrust_advance_ratio(TabulatedPropeller(4.3, 1.1, table)) == pytest.approx(1.2)
    # at P/D 1.0 zero thrust is at 1.25: beyond 1.2 too; a table to J = 1.4 finds it
    with pytest.raises(InputError) as info:
        table.coefficients(1.3, 1.1)
    assert info.value.field == "propeller.advance_ratio"
    with pytest.raises(InputError) as info:
        TabulatedPropeller(4.3, 1.3, table)
    assert info.value.field == "propeller.pitch_ratio"


def test_10kq_column_and_operating_point_by_hand():
    rows = [
        (p, j, a - 0.4 * j, 10 * (b - 0.02 * j))
        for p, a, b in ((1.0, 0.5, 0.05), (1.2, 0.6, 0.07))
        for j in J
    ]
    table = parse_open_water_table(_csv(rows, "pitch_ratio,J,K_T,10K_Q"))
    # 3 m/s, w = 0.2, 140 rpm, D = 4.3 m: J = 2.4/(2.333 · 4.3) = 0.2392; at P/D 1.1 K_Q = 0.06 − 0.02 J
    point = operating_point(TabulatedPropeller(4.3, 1.1, table), 3.0, 0.2, 140.0)
    j = 2.4 / (140 / 60 * 4.3)
    assert point.advance_ratio == pytest.approx(j)
    assert point.torque_n_m == pytest.approx((0.06 - 0.02 * j) * 1025.0 * (140 / 60) ** 2 * 4.3**5)
    assert point.thrust_n == pytest.approx((0.55 - 0.4 * j) * 1025.0 * (140 / 60) ** 2 * 4.3**4)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("pitch_ratio,J,K_T\n1.0,0.1,0.4\n1.0,0.2,0.3", "no column K_Q"),
        ("pitch_ratio,J,K_T,K_Q\n1.0,0.1,0.4,x\n1.0,0.2,0.3,0.04", "line 2, K_Q"),
        ("pitch_ratio,J,K_T,K_Q\n", "no header and data rows"),
        ("pitch_ratio,J,K_T,K_Q\n1.0,0.1,0.4,0.05\n1.2,0.1,0.5,0.06", "1 point(s)"),
        ("pitch_ratio,J,K_T,K_Q\n1.0,0.1,0.4,0.05\n1.0,0.1,0.3,0.04", "repeated J"),
        ("pitch_ratio,J,K_T,K_Q\n1.0,-0.1,0.4,0.05\n1.0,0.1,0.3,0.04", "advance ratio < 0"),
        ("pitch_ratio,J,K_T,K_Q\n1.0,0.1,0.4,0.05\n1.0,0.2,0.3", "has 3 fields"),
    ],
)
def test_malformed_tables_are_named(text, words):
    with pytest.raises(InputError) as info:
        parse_open_water_table(text, "t.csv")
    assert info.value.field == "open_water_table" and words in str(info.value)


def test_cli_malformed_table_exits_2_and_writes_nothing(tmp_path, cli):
    run = make_run(tmp_path / "run", speed_m_s=3.0, profile="default")
    bad = tmp_path / "bad.csv"
    bad.write_text("pitch_ratio,J,K_T\n1.0,0.1,0.4\n", encoding="utf-8")
    out = tmp_path / "out"
    code, _, err = cli(
        "propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--open-water-table", bad
    )
    assert code == 2 and "--open-water-table" in err and "K_Q" in err
    assert not out.exists()
    code, _, err = cli("propeller", run, "--out", out, "--open-water-table", tmp_path / "missing.csv")
    assert code == 2 and "--open-water-table" in err and not out.exists()


def test_cli_table_sets_the_shaft_operating_point(tmp_path, cli):
    # curves over P/D 0.5–1.4 (K_Q = 0.01 + 0.05 (P/D − 0.5) − 0.02 J): at 3 m/s the table's point is used
    rows = []
    for p in (0.5, 0.8, 1.1, 1.4):
        rows += [(p, j, 0.1 + 0.5 * (p - 0.5) - 0.3 * j, 0.01 + 0.05 * (p - 0.5) - 0.02 * j) for j in J]
    path = tmp_path / "ow.csv"
    path.write_text(_csv(rows), encoding="utf-8")
    run = make_run(tmp_path / "run", speed_m_s=3.0, profile="default")
    out = tmp_path / "out"
    args = [
        "--shaft-line",
        "agulhas_ii",
        "--speed-m-s",
        "3",
        "--wake-fraction",
        "0.2",
        "--open-water-table",
        path,
    ]
    code, _, err = cli("propeller", run, "--out", out, *args)
    assert code == 0, err
    point = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))[
        "propeller_operating_point"
    ]
    n, d = 140 / 60, 4.3
    j = 3.0 * 0.8 / (n * d)
    pd = point["pitch_ratio"]
    kq = 0.01 + 0.05 * (pd - 0.5) - 0.02 * j
    assert point["mean_torque_knm"] == pytest.approx(kq * 1025.0 * n**2 * d**5 / 1e3, rel=1e-9)
    # P/D 4.9365/4.3 = 1.148 gives K_Q = 0.0424 − 0.02 J → 0.0376 × ρ n² D⁵ = 308 kN·m > the rated 307:
    # the controller lowers the pitch until the torque is the rated one
    rated = 4.5e6 / (2 * math.pi * n) / 1e3
    assert point["torque_limited"] and point["mean_torque_knm"] == pytest.approx(rated, rel=1e-6)
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["propeller"]["open_water_curves"].startswith("table ")
