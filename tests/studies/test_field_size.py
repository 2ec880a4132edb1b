"""The thesis' field length inferred from its affected area."""

from __future__ import annotations

import pytest

from floebreak.errors import InputError
from floebreak.studies.field_size import (
    THESIS_FIELD_WIDTH_M,
    affected_strip_width_m,
    infer_field_length_m,
    thesis_field_length_m,
    thesis_scenario,
)


def test_affected_strip_of_a_wide_field_is_beam_plus_area_weighted_diameter():
    # Table 1, 2019-12-18 20:20: 20/40/40 % of the floes at 2.5/7.5/15 m
    # Σ p d² = 0.2·6.25 + 0.4·56.25 + 0.4·225 = 113.75
    # Σ p d³ = 0.2·15.625 + 0.4·421.875 + 0.4·3375 = 1521.875
    strip = affected_strip_width_m(21.7, (2.5, 7.5, 15.0), (20, 40, 40))
    assert strip == pytest.approx(21.7 + 1521.875 / 113.75)


def test_thesis_field_length_by_hand():
    # wide field: 3446.38 m² / (0.44 · 0.25/0.5 · (21.7 m + 13.379 m)) = 3446.38 / 7.7174 = 446.6 m
    wide = 3446.38 / (0.22 * (21.7 + 1521.875 / 113.75))
    assert wide == pytest.approx(446.6, abs=0.1)
    assert thesis_field_length_m(None) == round(wide) == 447
    # 100 m wide: the centres of class d spread over 100 − d m, so per metre the bow affects
    # (B + d)·100/(100 − d): 24.2·100/97.5 = 24.821, 29.2·100/92.5 = 31.568, 36.7·100/85 = 43.176 m,
    # weighted by p d² (1.25, 22.5, 90 of 113.75): 40.678 m → L = 3446.38 / (0.22 · 40.678) = 385.1 m
    strip = (1.25 * 24.2 / 0.975 + 22.5 * 29.2 / 0.925 + 90.0 * 36.7 / 0.85) / 113.75
    assert strip == pytest.approx(40.678, abs=1e-3)
    assert THESIS_FIELD_WIDTH_M == 100.0
    assert thesis_field_length_m() == round(3446.38 / (0.22 * strip)) == 385


def test_thesis_scenario_is_the_reference_on_the_thesis_field_and_follows_a_width_override():
    base = thesis_scenario()
    assert (base["field"]["length_m"], base["field"]["width_m"]) == (385.0, 100.0)
    assert base["field"]["observation"] == "2019-12-18T20:20"
    wide = thesis_scenario(["field.width_m=1000.0", "ship.step_m=0.5"])
    # w_d = (B + d)·1000/(1000 − d), weighted by p d² as in the 100 m case: 35.57 m → 3446.38 / (0.22 · 35.57)
    strip = (1.25 * 24.2 / 0.9975 + 22.5 * 29.2 / 0.9925 + 90.0 * 36.7 / 0.985) / 113.75
    assert wide["field"]["length_m"] == round(3446.38 / (0.22 * strip)) == 440
    assert wide["ship"]["step_m"] == 0.5
    assert thesis_scenario(length_m=120.0)["field"]["length_m"] == 120.0


def test_the_reference_scenario_field_is_the_inferred_thesis_field():
    from floebreak.constants import REFERENCE_FIELD_LENGTH_M, REFERENCE_FIELD_WIDTH_M

    assert REFERENCE_FIELD_LENGTH_M == thesis_field_length_m()
    assert REFERENCE_FIELD_WIDTH_M == THESIS_FIELD_WIDTH_M
    assert REFERENCE_FIELD_WIDTH_M > 21.7 + 2 * 15.0  # beam + 2 d_max: no floe class forced into the path


def test_a_narrow_field_puts_every_floe_of_a_class_in_the_bow_path():
    # W = 50 m: the 15 m floes' centres spread over 35 m < B + d = 36.7 m: all are touched, strip = W
    only_large = affected_strip_width_m(21.7, (15.0,), (100,), field_width_m=50.0)
    assert only_large == 50.0
    with pytest.raises(InputError, match="field_width_m"):
        affected_strip_width_m(21.7, (15.0,), (100,), field_width_m=15.0)


def test_bounds_of_the_inference():
    args = (3446.38, 0.44, 21.7, (2.5, 7.5, 15.0), (20, 40, 40))
    # only the swept strip affected (κ = 0): 3446.38 / (0.22 · 21.7) = 721.9 m
    assert infer_field_length_m(*args, straddle_fraction=0.0) == pytest.approx(3446.38 / (0.22 * 21.7))
    # circles counted with their true area (π d²/4): the cover is the nominal 44 %, half the length
    assert infer_field_length_m(*args, floe_area_factor=0.25) == pytest.approx(
        infer_field_length_m(*args) / 2
    )


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"affected_area_m2": 0.0}, "affected_area_m2"),
        ({"concentration": 1.5}, "concentration"),
        ({"beam_m": -1.0}, "beam_m"),
        ({"straddle_fraction": 2.0}, "straddle_fraction"),
    ],
)
def test_bad_inputs_name_the_field(kwargs, field):
    args = {"affected_area_m2": 3446.38, "concentration": 0.44, "beam_m": 21.7,
            "diameters_m": (2.5,), "percentages": (100.0,)}  # fmt: skip
    with pytest.raises(InputError, match=field):
        infer_field_length_m(**{**args, **kwargs})
