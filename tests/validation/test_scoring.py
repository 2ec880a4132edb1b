"""Scoreboard metrics and scoring on hand-made numbers."""

from __future__ import annotations

import csv
import io
import math
from dataclasses import replace

import numpy as np
import pytest

from floebreak.validation.scoreboard import (
    bending_force_metrics,
    bending_forces_kn,
    cusp_volume_metrics,
    evaluate,
    must_hold_counts,
    scoreboard_csv,
    scoreboard_markdown_table,
    scoreboard_rows,
    single_floe_metrics,
    summary_metrics,
    tally_text,
)
from floebreak.validation.statements import STATEMENTS, Recorded
from floebreak.validation.validation_report import explained_and_inert_lines


def test_summary_metrics_ratios():
    m = summary_metrics({"n_cusps": 150, "n_flipped": 50, "cusp_area_m2": 1000.0, "flipped_area_m2": 2500.0})
    assert m["affected_area_m2"] == 3500.0
    assert m["cusp_flip_count_ratio"] == 3.0 and m["flip_cusp_area_ratio"] == 2.5
    assert math.isnan(summary_metrics({"n_cusps": 3, "n_flipped": 0})["cusp_flip_count_ratio"])


def test_bending_forces_are_summed_per_evaluation_of_bending_failures():
    contacts = {  # two panels of one bending evaluation, one bending evaluation, one cracking evaluation
        "step": np.array([1, 1, 2, 3]),
        "piece_id": np.array([7, 7, 7, 9]),
        "zone": np.array([0, 0, 0, 0]),
        "f_c_n": np.array([300e3, 200e3, 1.0e6, 5.0e6]),
        "outcome": np.array(["bending", "bending", "bending", "cracking"], dtype=object),
    }
    assert sorted(bending_forces_kn(contacts)) == pytest.approx([500.0, 1000.0])
    m = bending_force_metrics(np.array([100.0, 500.0, 1000.0, 3000.0]))
    assert m["bending_force_median_kn"] == 750.0 and m["bending_force_mean_kn"] == 1150.0
    assert m["bending_force_share_le_2500kn"] == 0.75 and m["bending_force_share_le_3000kn"] == 1.0


def test_cusp_volume_metrics():
    m = cusp_volume_metrics(np.array([1.0, 4.0, 8.0, 12.0]))
    assert m == {"max_cusp_volume_m3": 12.0, "share_cusps_le_4m3": 0.5, "share_cusps_gt_11m3": 0.25}


def test_single_floe_metrics_by_hand():
    def case(n_cusps, cusp, flipped, area=100.0):
        return {
            "n_cusps": n_cusps,
            "cusp_area_m2": cusp,
            "flipped_area_m2": flipped,
            "initial_ice_area_m2": area,
        }

    cases = {
        (10.0, 1.0, "a"): case(1, 20.0, 60.0),
        (10.0, 1.0, "c"): case(1, 20.0, 60.0),
        (10.0, 1.0, "b"): case(2, 50.0, 0.0),
        (10.0, 1.0, "d"): case(2, 49.0, 0.0),
        (10.0, 1.0, "e"): case(3, 90.0, 10.0),
        (20.0, 1.0, "e"): case(0, 0.0, 0.0, 300.0),
    }
    m = single_floe_metrics(cases)
    assert m["single_floe_midship_cusp_share"] == 0.5
    # of the broken ice the shoulders flip 60/80 = 75 %, the one midship floe that broke 10/100 = 10 % (the
    # one that did not break is left out; the 20 m² the shoulder floes leave in the field do not count)
    assert m["single_floe_shoulder_flip_excess"] == pytest.approx(0.65)
    assert m["single_floe_mirror_difference"] == pytest.approx(0.01)  # b/d: 1 m² of 100 m²


def _data(reference: list[float], **points: list[float]) -> dict:
    """Per-point, per-field metrics with one metric, the mean cusp volume."""
    out = {"reference": {i: {"mean_cusp_volume_m3": v} for i, v in enumerate(reference)}}
    for name, values in points.items():
        out[name] = {i: {"mean_cusp_volume_m3": v} for i, v in enumerate(values)}
    return out


def test_evaluate_level_and_paired_change():
    by_id = {st.id: st for st in STATEMENTS}
    data = _data([8.0, 9.0], K230=[8.4, 9.0])
    mean, se, n = evaluate(by_id["T5.V"], data)
    assert (mean, n) == (8.5, 2) and se == pytest.approx(0.5)  # std 0.7071 / √2
    mean, se, n = evaluate(by_id["T5.K230.dV"], data)  # +5 % and 0 %
    assert (mean, n) == (pytest.approx(0.025), 2) and se == pytest.approx(0.025)


def test_scoreboard_rows_csv_and_must_hold_counts():
    statements = tuple(st for st in STATEMENTS if st.id in ("T5.V", "T5.K230.dV"))
    data = {"default": _data([8.0, 9.0], K230=[8.4, 9.0]), "thesis": _data([4.0, 4.0], K230=[5.0, 5.0])}
    rows = scoreboard_rows(data, {"default": "default", "thesis": "thesis"}, statements)
    assert [r["default"]["verdict"] for r in rows] == ["pass", "pass"]  # 8.5 within 15 % of 8.14; 2.5 % ≤ 5 %
    assert [r["thesis"]["verdict"] for r in rows] == ["fail", "fail"]  # 4.0 vs 8.14; +25 %
    assert must_hold_counts(rows, "default") == (("T5.K230.dV",), (), (), ())  # T5.V: thesis profile only
    thesis = must_hold_counts(rows, "thesis")
    assert thesis == ((), (), ("T5.V", "T5.K230.dV"), ())
    assert tally_text(thesis) == (
        "0 pass, 0 fail (explained), 2 fail, 0 inert (of 2 must-hold rows); fail: T5.V, T5.K230.dV"
    )
    assert tally_text(must_hold_counts(rows, "default")) == (
        "1 pass, 0 fail (explained), 0 fail, 0 inert (of 1 must-hold rows)"
    )
    table = list(csv.DictReader(io.StringIO(scoreboard_csv(rows, ["default", "thesis"]))))
    assert [r["id"] for r in table] == ["T5.V", "T5.K230.dV"]
    assert table[0]["thesis_value"] == "8.14" and table[0]["thesis_verdict"] == "fail"
    assert table[0]["thesis_must_hold"] == "yes" and table[0]["default_must_hold"] == "no"
    markdown = "\n".join(scoreboard_markdown_table(rows, ["default", "thesis"]))
    assert "**FAIL**" in markdown and "8.5 ± 0.5 pass" in markdown


def _explained_statement():
    """T6.line_load.dA_aff with a made-up explanation band in `default`: recorded −10.0 % on the choice sample
    and −14.0 % on the holdout, to 0.1 % → −10.0 ± (4.0 + 0.1) %, i.e. −14.1 … −5.9 %."""
    by_id = {st.id: st for st in STATEMENTS}
    recorded = (Recorded("default", -0.100, -0.140, 0.001, "made up"),)
    return replace(by_id["T6.line_load.dA_aff"], explained="made-up mechanism", recorded=recorded)


def _line_load_data(change: float) -> dict:
    return {"default": {
        "reference": {0: {"affected_area_m2": 100.0, "mean_cusp_volume_m3": 8.0}},
        "line_load": {0: {"affected_area_m2": 100.0 * (1.0 + change)}},
        "BZ1": {0: {"mean_cusp_volume_m3": 8.0}},
        "K230": {0: {"mean_cusp_volume_m3": 8.8}},  # +10 %: beyond the 5 % of a small effect, unexplained
    }}  # fmt: skip


def test_the_explanation_band_is_the_choice_value_with_its_spread_to_the_holdout():
    low, high = _explained_statement().explained_band("default")
    assert (low, high) == (pytest.approx(-0.141), pytest.approx(-0.059))
    assert _explained_statement().explained_band("thesis") is None  # no value recorded for that profile


@pytest.mark.parametrize(
    ("change", "status"),
    [
        (-0.10, "fail (explained)"),  # the recorded failure: inside the band
        (-0.14, "fail (explained)"),  # the holdout's value: inside
        (-0.06, "fail (explained)"),  # −6.0 % lies within −14.1 … −5.9 %
        (-0.05, "fail"),  # fails (beyond the 1 % of "nearly constant") but outside the band: a plain failure
        (-0.20, "fail"),  # fails by more than the explanation was recorded for
        (+0.10, "fail"),  # the other sign
        (-0.005, "pass"),  # passes: the explanation is not needed
    ],
)
def test_an_explained_row_fails_explained_only_within_its_band(change, status):
    rows = scoreboard_rows(_line_load_data(change), {"default": "default"}, (_explained_statement(),))
    assert rows[0]["default"]["status"] == status
    tally = must_hold_counts(rows, "default")
    row_id = ("T6.line_load.dA_aff",)
    expected = {"pass": (row_id, (), ()), "fail (explained)": ((), row_id, ()), "fail": ((), (), row_id)}
    assert tuple(tally[:3]) == expected[status]
    lines = "\n".join(explained_and_inert_lines(rows, ["default"]))
    expected_text = {
        "pass": "pass: explanation not needed",
        "fail": "FAIL outside the explained band (-14.1 … -5.9 %)",
        "fail (explained)": "fail (explained; band -14.1 … -5.9 %)",
    }[status]
    assert expected_text in lines


def test_an_explained_failure_is_not_a_pass_and_an_inert_row_is_not_counted():
    """A must-hold row that fails for a documented reason (within its band) counts as
    "fail (explained)"; a row that cannot fail (flagged inert) is left out of the count, whatever its
    verdict."""
    from floebreak.validation.inert import Inert

    by_id = {st.id: st for st in STATEMENTS}
    statements = (_explained_statement(), by_id["T8.BZ1.dV"], by_id["T5.K230.dV"])
    assert statements[0].must_hold == {"default", "thesis"}
    inert = {"default": {"T8.BZ1.dV": Inert("identity", "same run", 0.0)}}
    rows = scoreboard_rows(_line_load_data(-0.10), {"default": "default"}, statements, inert=inert)
    assert [r["default"]["status"] for r in rows] == ["fail (explained)", "inert", "fail"]
    tally = must_hold_counts(rows, "default")
    assert tally == ((), ("T6.line_load.dA_aff",), ("T5.K230.dV",), ("T8.BZ1.dV",)) and tally.counted == 2
    assert tally_text(tally).startswith("0 pass, 1 fail (explained), 1 fail, 1 inert (of 3 must-hold rows)")
    markdown = "\n".join(scoreboard_markdown_table(rows, ["default"]))
    assert "FAIL (explained)" in markdown and " inert |" in markdown and "**FAIL**" in markdown
    table = list(csv.DictReader(io.StringIO(scoreboard_csv(rows, ["default"]))))
    assert [r["default_status"] for r in table] == ["fail (explained)", "inert", "fail"]
    assert table[1]["default_inert"] == "same run"
    assert table[0]["default_explained_band"] == "-0.141 … -0.059"


def test_an_inert_flag_whose_reason_the_value_contradicts_does_not_hide_a_failure():
    """Audit gap 7: a row flagged inert whose measured value is not what the reason predicts (the same run:
    exactly 0; the cap: the cap's change within 1 %) is scored as any other row."""
    from floebreak.validation.inert import Inert

    by_id = {st.id: st for st in STATEMENTS}
    statements = (by_id["T8.BZ1.dV"], by_id["S533.h1.2.dV_max"])
    data = {"default": {
        "reference": {0: {"mean_cusp_volume_m3": 8.0, "max_cusp_volume_m3": 10.0}},
        "BZ1": {0: {"mean_cusp_volume_m3": 8.8}},  # +10 %: not 0, and beyond the 5 % of a small effect
        "h1.2": {0: {"max_cusp_volume_m3": 13.0}},  # +30 %, not the cap's +37.6 %: the direction still passes
    }}  # fmt: skip
    inert = {"default": {"T8.BZ1.dV": Inert("identity", "same run", 0.0),
                         "S533.h1.2.dV_max": Inert("cap", "cap", 1.2**1.75 - 1.0)}}  # fmt: skip
    rows = scoreboard_rows(data, {"default": "default"}, statements, inert=inert)
    assert [r["default"]["status"] for r in rows] == ["fail", "pass"]
    assert [r["default"]["inert"] for r in rows] == [None, None]
    lines = "\n".join(explained_and_inert_lines(rows, ["default"]))
    assert "**T8.BZ1.dV** (`default`): flagged inert (same run), but the measured value contradicts" in lines
    assert must_hold_counts(rows, "default") == (("S533.h1.2.dV_max",), (), ("T8.BZ1.dV",), ())
    data["default"]["BZ1"][0]["mean_cusp_volume_m3"] = 8.0  # exactly 0 and the cap's change: inert again
    data["default"]["h1.2"][0]["max_cusp_volume_m3"] = 10.0 * 1.2**1.75
    rows = scoreboard_rows(data, {"default": "default"}, statements, inert=inert)
    assert [r["default"]["status"] for r in rows] == ["inert", "inert"]
