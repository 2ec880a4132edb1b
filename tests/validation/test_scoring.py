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
from floebreak.validation.statements import STATEMENTS, null_verdict
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
    # "≤ 5 %" passes a change of 0 too: the pass of T5.K230.dV is weak; T5.V: thesis profile only
    assert [r["default"]["status"] for r in rows] == ["pass", "weak-pass"]
    assert must_hold_counts(rows, "default") == ((), ("T5.K230.dV",), (), ())
    thesis = must_hold_counts(rows, "thesis")
    assert thesis == ((), (), ("T5.V", "T5.K230.dV"), ())  # a weak row that fails is a failure
    assert tally_text(thesis) == "0 of 2 must-hold rows pass; 0 weak; 0 inert; fail: T5.V, T5.K230.dV"
    assert tally_text(must_hold_counts(rows, "default")) == "0 of 0 must-hold rows pass; 1 weak; 0 inert"
    table = list(csv.DictReader(io.StringIO(scoreboard_csv(rows, ["default", "thesis"]))))
    assert [r["id"] for r in table] == ["T5.V", "T5.K230.dV"]
    assert table[0]["thesis_value"] == "8.14" and table[0]["thesis_verdict"] == "fail"
    assert table[0]["thesis_must_hold"] == "yes" and table[0]["default_must_hold"] == "no"
    assert [(r["null_verdict"], r["weak"]) for r in table] == [("", "no"), ("pass", "yes")]
    assert table[1]["default_status"] == "weak-pass"
    markdown = "\n".join(scoreboard_markdown_table(rows, ["default", "thesis"]))
    assert "**FAIL**" in markdown and "8.5 ± 0.5 pass" in markdown and "weak pass" in markdown


def test_the_weak_rows_are_the_changes_a_change_of_zero_passes():
    """The null variant (no change between the two points) passes exactly the changes whose tolerance admits
    0: the "small" and "nearly constant" effects (|ours| ≤ a bound); it fails a direction, a rough size, and
    levels have no null variant."""
    weak = {st.id for st in STATEMENTS if st.weak and st.must_hold}
    assert weak == {
        "T5.K120.dV", "T5.K230.dV", "T5.K120.dA_aff", "T5.K230.dA_aff",  # K_Ic: ≤ 5 %, ≤ 1 %
        "T6.point_load.dA_aff", "T6.line_load.dA_aff", "T6.flexural_stress.dA_aff",  # criteria: ≤ 1 %
        "S535.flex.dA_cusp",  # < 4 %
        "S533.random.dV",  # random h: ≤ 10 %
        "T8.BZ1.dV", "T8.BZ2.dV", "T8.BZ1.dA_aff", "T8.BZ2.dA_aff",  # size-effect laws: ≤ 5 %, ≤ 1 %
    }  # fmt: skip
    by_id = {st.id: st for st in STATEMENTS}
    assert null_verdict(by_id["S532.line.dn_cusp"]) == "fail"  # a direction: 0 has no sign
    assert null_verdict(by_id["T7.h1.2.dA_size"]) == "fail"  # a rough size
    assert null_verdict(by_id["T5.V"]) is None and not by_id["T5.V"].weak  # a level


def _explained_statement():
    """T6.line_load.dA_aff with a made-up explanation."""
    by_id = {st.id: st for st in STATEMENTS}
    return replace(by_id["T6.line_load.dA_aff"], explained="made-up mechanism")


def _line_load_data(change: float) -> dict:
    return {"default": {
        "reference": {0: {"affected_area_m2": 100.0, "mean_cusp_volume_m3": 8.0}},
        "line_load": {0: {"affected_area_m2": 100.0 * (1.0 + change)}},
        "BZ1": {0: {"mean_cusp_volume_m3": 8.0}},
        "K230": {0: {"mean_cusp_volume_m3": 8.8}},  # +10 %: beyond the 5 % of a small effect
        "h1.2": {0: {"mean_cusp_volume_m3": 10.0}},  # +25 %: the thesis' direction
    }}  # fmt: skip


@pytest.mark.parametrize(
    ("change", "status"),
    [
        (-0.10, "fail"),  # fails by the documented mechanism: still a failure
        (+0.10, "fail"),
        (-0.005, "weak-pass"),  # within "nearly constant": a change of 0 would pass too
    ],
)
def test_an_explained_row_fails_like_any_other_and_its_explanation_is_a_note(change, status):
    rows = scoreboard_rows(_line_load_data(change), {"default": "default"}, (_explained_statement(),))
    assert rows[0]["default"]["status"] == status
    tally = must_hold_counts(rows, "default")
    row_id = ("T6.line_load.dA_aff",)
    assert tuple(tally[:3]) == {"weak-pass": ((), row_id, ()), "fail": ((), (), row_id)}[status]
    lines = "\n".join(explained_and_inert_lines(rows, ["default"]))
    note = {"fail": "FAIL", "weak-pass": "weak pass"}[status]
    assert f"- **T6.line_load.dA_aff** (`default` {note}): made-up mechanism" in lines
    table = list(csv.DictReader(io.StringIO(scoreboard_csv(rows, ["default"]))))
    assert table[0]["note"] == "made-up mechanism" and table[0]["default_status"] == status


def test_an_explained_failure_is_a_failure_and_an_inert_row_is_not_counted():
    """A must-hold row that fails for a documented reason counts as a failure; a row that cannot fail
    (flagged inert) is left out of the count, whatever its verdict; a pass that the null variant shares is
    counted apart."""
    from floebreak.validation.inert import Inert

    by_id = {st.id: st for st in STATEMENTS}
    ids = ("T8.BZ1.dV", "T5.K230.dV", "S535.h1.2.dV", "T5.K120.dV")
    statements = (_explained_statement(), *(by_id[i] for i in ids))
    assert statements[0].must_hold == {"default", "thesis"}
    data = _line_load_data(-0.10)
    data["default"]["K120"] = {0: {"mean_cusp_volume_m3": 8.1}}  # −1.25 %: small, as the thesis says
    inert = {"default": {"T8.BZ1.dV": Inert("identity", "same run", 0.0)}}
    rows = scoreboard_rows(data, {"default": "default"}, statements, inert=inert)
    assert [r["default"]["status"] for r in rows] == ["fail", "inert", "fail", "pass", "weak-pass"]
    tally = must_hold_counts(rows, "default")
    assert tally == (
        ("S535.h1.2.dV",),
        ("T5.K120.dV",),
        ("T6.line_load.dA_aff", "T5.K230.dV"),
        ("T8.BZ1.dV",),
    )
    assert tally.counted == 3
    assert tally_text(tally) == (
        "1 of 3 must-hold rows pass; 1 weak; 1 inert; fail: T6.line_load.dA_aff, T5.K230.dV"
    )
    markdown = "\n".join(scoreboard_markdown_table(rows, ["default"]))
    assert "(explained" not in markdown and " inert |" in markdown and markdown.count("**FAIL**") == 2
    table = list(csv.DictReader(io.StringIO(scoreboard_csv(rows, ["default"]))))
    assert [r["default_status"] for r in table] == ["fail", "inert", "fail", "pass", "weak-pass"]
    assert table[1]["default_inert"] == "same run"


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
