"""The thesis statements as data: completeness, thesis values, verdicts, paired statistics."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from floebreak.validation.chain_statements import PC5_METRICS, shaft_range_measures
from floebreak.validation.scoreboard import (
    bending_force_metrics,
    cusp_volume_metrics,
    single_floe_metrics,
    summary_metrics,
)
from floebreak.validation.statements import (
    STATEMENTS,
    Tolerance,
    mean_se,
    paired_relative_change,
    verdict,
)
from floebreak.validation.validate import POINTS

BY_ID = {st.id: st for st in STATEMENTS}


def test_every_statement_has_source_quote_value_and_tolerance():
    assert len(BY_ID) == len(STATEMENTS)  # unique ids
    for st in STATEMENTS:
        assert st.source.startswith(("§", "IACS UR I3")) and st.quote and st.quantity, st.id
        assert st.tolerance.kind in (
            "rel",
            "abs",
            "direction",
            "rough",
            "max_abs",
            "at_least",
            "range",
            "info",
        )
        if st.tolerance.kind in ("rel", "direction", "rough"):  # these compare with the thesis' number
            assert math.isfinite(st.thesis_value) and st.thesis_value != 0.0, st.id
        if st.tolerance.kind not in ("info", "direction"):
            assert math.isfinite(st.tolerance.value), st.id
        assert st.must_hold <= {"default", "thesis"}, st.id
        assert st.point in POINTS or st.point == "single_floe", st.id
        assert st.statistic == "level" or st.against in POINTS, st.id


def test_every_metric_is_one_the_scoreboard_computes():
    summary = {"mean_cusp_volume_m3": 1.0, "mean_cusp_area_m2": 1.0, "n_cusps": 2, "n_flipped": 1,
               "cusp_area_m2": 2.0, "flipped_area_m2": 1.0, "remaining_ice_area_m2": 0.0,
               "initial_ice_area_m2": 3.0}  # fmt: skip
    keys = (
        set(summary_metrics(summary))
        | set(cusp_volume_metrics(np.ones(3)))
        | set(bending_force_metrics([1.0]))
    )
    keys |= {"torque_max_knm_p0", "torque_max_knm_p95", "torque_min_knm_p0", "torque_min_knm_p95"}
    case = {"n_cusps": 1, "cusp_area_m2": 1.0, "flipped_area_m2": 0.0, "initial_ice_area_m2": 1.0}
    keys |= set(single_floe_metrics({(10.0, 1.0, "e"): case, (10.0, 1.0, "a"): case, (10.0, 1.0, "c"): case}))
    keys |= set(shaft_range_measures([0.0])) | set(PC5_METRICS)  # the chain rows (chain_statements)
    assert {st.metric for st in STATEMENTS} <= keys


@pytest.mark.parametrize(
    ("statement", "expected"),
    [
        # thesis Table 5 reference row
        ("T5.V", 8.14),
        ("T5.n_ratio", 125 / 83),
        ("T5.A_ratio", 2426.90 / 1019.48),
        # §5.3.2: "19 % more cusps ... for the linear crack face loading" (Table 6: 149 vs 125)
        ("S532.line.dn_cusp", 0.192),
        # "7 % fewer floes fail by direct rotation" (78 vs 83)
        ("S532.line.dn_flip", -0.060),
        # §5.3.3: "around 29 % more ice cusps" at 0.8 m (161 vs 125), "around 5 % less" at 1.2 m (119)
        ("S533.h0.8.dn_cusp", 0.288),
        ("S533.h1.2.dn_cusp", -0.048),
        # §5.3.5: "varying h by 20 %, the cusp volume changes accordingly by around 35 %"
        # (Table 7: 5.50 and 11.21 vs 8.14 m³)
        ("S535.h0.8.dV", -0.324),
        ("S535.h1.2.dV", 0.377),
        # §5.3.5: point load vs line load cusp area "a decrease of around 20 %" (983.52 vs 1233.53)
        ("S535.point_vs_line.dA_cusp", -0.203),
        # §5.3.4: BZ1 "0.6 % larger cusps", BZ2 "about 1.2 % larger"
        ("T8.BZ1.dV", 0.006),
        ("T8.BZ2.dV", 0.012),
        # §5.3.3: A_tot 3361.58 m² at 0.8 m "2.5 % lower" than 3446.38 m²
        ("S533.h0.8.dA_aff", -0.0246),
    ],
)
def test_thesis_values_are_the_thesis_numbers(statement, expected):
    assert BY_ID[statement].thesis_value == pytest.approx(expected, abs=6e-4)


def test_must_hold_rows_cover_the_issue_targets():
    # thesis profile — V̄, Ā within ±15 %, ratios within ±35 %, K_Ic and SEL effects ≤ 5 %
    for key in ("T5.V", "T5.A"):
        assert BY_ID[key].tolerance == Tolerance("rel", 0.15) and "thesis" in BY_ID[key].must_hold
    for key in ("T5.n_ratio", "T5.A_ratio"):
        assert BY_ID[key].tolerance == Tolerance("rel", 0.35) and "thesis" in BY_ID[key].must_hold
    for key in ("T5.K120.dV", "T5.K230.dV", "T8.BZ1.dV", "T8.BZ2.dV"):
        assert BY_ID[key].tolerance == Tolerance("max_abs", 0.05) and BY_ID[key].must_hold == {
            "default",
            "thesis",
        }
    # §3: the large trends (thickness, criteria) hold in direction in every profile
    for key in ("S533.h0.8.dn_cusp", "S533.h1.2.dn_cusp", "S535.h1.2.dV", "T7.h1.2.dA", "S532.line.dn_cusp"):
        assert BY_ID[key].tolerance.kind == "direction" and BY_ID[key].must_hold == {"default", "thesis"}


@pytest.mark.parametrize(
    ("value", "thesis", "tolerance", "expected"),
    [
        (9.0, 8.0, Tolerance("rel", 0.15), "pass"),  # +12.5 %
        (9.3, 8.0, Tolerance("rel", 0.15), "fail"),  # +16.25 %
        (6.9, 8.0, Tolerance("rel", 0.15), "pass"),  # −13.75 %
        (10.0, 8.0, Tolerance("abs", 2.0), "pass"),
        (10.5, 8.0, Tolerance("abs", 2.0), "fail"),
        (0.03, 0.19, Tolerance("direction"), "pass"),
        (-0.03, 0.19, Tolerance("direction"), "fail"),
        (0.0, 0.19, Tolerance("direction"), "fail"),
        (0.10, 0.19, Tolerance("rough", 2.0), "pass"),  # ratio 0.53
        (0.09, 0.19, Tolerance("rough", 2.0), "fail"),  # ratio 0.47
        (0.39, 0.19, Tolerance("rough", 2.0), "fail"),  # ratio 2.05
        (-0.2, 0.19, Tolerance("rough", 2.0), "fail"),
        (-0.049, 0.01, Tolerance("max_abs", 0.05), "pass"),
        (0.051, 0.01, Tolerance("max_abs", 0.05), "fail"),
        (0.5, 0.5, Tolerance("at_least", 0.5), "pass"),
        (0.49, 0.5, Tolerance("at_least", 0.5), "fail"),
        (200.0, math.nan, Tolerance("range", 200.0, 2500.0), "pass"),
        (2501.0, math.nan, Tolerance("range", 200.0, 2500.0), "fail"),
        (1.0, 2.0, Tolerance("info"), "info"),
        (math.nan, 2.0, Tolerance("rel", 0.1), "missing"),
    ],
)
def test_verdict(value, thesis, tolerance, expected):
    assert verdict(value, thesis, tolerance) == expected


def test_paired_relative_change_against_numpy():
    rng = np.random.default_rng(5)
    reference = rng.uniform(5.0, 10.0, 6)
    values = reference * rng.uniform(0.9, 1.3, 6)
    r = values / reference - 1.0
    mean, se, n = paired_relative_change(dict(enumerate(values)), dict(enumerate(reference)))
    assert n == 6
    assert mean == pytest.approx(r.mean(), rel=1e-12)
    assert se == pytest.approx(r.std(ddof=1) / np.sqrt(6), rel=1e-12)


def test_paired_change_uses_only_common_fields_and_removes_the_field_spread():
    # fields 0–2 differ wildly in level but every field changes by exactly +10 %: s.e. 0
    reference = {0: 1.0, 1: 100.0, 2: 10.0, 3: 5.0}
    values = {0: 1.1, 1: 110.0, 2: 11.0, 7: 3.0}
    mean, se, n = paired_relative_change(values, reference)
    assert (mean, n) == (pytest.approx(0.1), 3) and se == pytest.approx(0.0, abs=1e-15)


def test_mean_se_by_hand():
    # values 2, 4, 9: mean 5, sample variance ((−3)² + (−1)² + 4²)/2 = 13, s.e. = √(13/3)
    mean, se, n = mean_se([2.0, 4.0, None, math.nan, 9.0])
    assert (mean, n) == (5.0, 3) and se == pytest.approx(math.sqrt(13 / 3))
    assert mean_se([3.0]) == (3.0, 0.0, 1)
    assert math.isnan(mean_se([])[0])


def test_an_explained_deviation_names_its_test_and_the_demoted_rows_must_hold_again():
    """An explained statement points at the docs/model.md section and the test that shows the mechanism; the
    explanation does not take a row out of the must-hold rows (the three affected-area rows over the crack
    criteria, once demoted, must hold in both profiles)."""
    import pathlib

    root = pathlib.Path(__file__).parents[2]
    explained = [st for st in STATEMENTS if st.explained]
    demoted = {"T6.line_load.dA_aff", "T6.point_load.dA_aff", "T6.flexural_stress.dA_aff"}
    # the flexural criterion's row passes on every sample, so it carries no explanation
    assert {st.id for st in explained} >= demoted - {"T6.flexural_stress.dA_aff"} | {"S533.h1.2.dA_aff"}
    for key in demoted:
        assert BY_ID[key].must_hold == {"default", "thesis"}, key
    for st in explained:
        tests = re.findall(r"(tests/[\w/]+\.py)::(\w+)", st.explained)
        assert tests, st.id
        for test_file, test_name in tests:
            assert f"def {test_name}(" in (root / test_file).read_text(encoding="utf-8"), (st.id, test_name)
        assert re.search(r"docs/(explanation/)?(model|shaft|propeller)\.md §", st.explained), st.id


def test_the_thickness_trends_of_the_cusp_area_have_rough_size_rows():
    """docs/validation.md: the rough sizes (×2) of the 0.8 m / 1.2 m trends must hold in the thesis profile —
    Ā's too (Table 7: 6.87 / 8.14 / 9.34 m², −15.6 % and +14.7 %)."""
    assert BY_ID["T7.h0.8.dA_size"].thesis_value == pytest.approx(6.87 / 8.14 - 1)
    assert BY_ID["T7.h1.2.dA_size"].thesis_value == pytest.approx(9.34 / 8.14 - 1)
    for key in ("T7.h0.8.dA_size", "T7.h1.2.dA_size"):
        assert BY_ID[key].tolerance == Tolerance("rough", 2.0) and BY_ID[key].must_hold == {"thesis"}
