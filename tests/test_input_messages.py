"""Messages that misled: each names the parameter or file and the fix, in the user's units,
and its numbers agree with each other. The reproducers are rebuilt from the issue's descriptions."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.ice.generation import CONCENTRATION_TOLERANCE, ConcentrationError, floe_counts, generate_field
from floebreak.ice.observations import Observation, get_observation
from floebreak.ship.hulls import agulhas_ii, polarstern
from floebreak.studies.design import load_study


# (a) "0.318 not reached … highest reached 73.07 % (allowed: at most about 0.731)" with floe_area_factor = 0.1
def test_an_unreached_concentration_with_another_floe_area_factor_is_stated_in_the_users_units():
    factor, target = 0.1, 0.318
    obs = Observation(target, 1.0, (5.0, 10.0), (50.0, 50.0))
    with pytest.raises(ConcentrationError) as info:
        generate_field(obs, 60.0, 40.0, np.random.default_rng(0), floe_area_factor=factor)
    error, message = info.value, str(info.value)
    # the circles (0.25·π d² each) must cover target · 0.25 / factor of the field: 79.5 %
    assert f"{100 * target * 0.25 / factor:.1f} %" in message
    assert "floe_area_factor = 0.1" in message
    # the concentration reached, in the user's units, is below the target, and is what the message allows
    assert error.reached == pytest.approx(error.cover * factor / 0.25)
    assert error.reached < target < error.cover
    allowed = re.search(r"field\.concentration ≤ about ([0-9.]+)", message)
    assert allowed and float(allowed.group(1)) == pytest.approx(error.reached, rel=1e-2)
    assert float(allowed.group(1)) < target  # not "at most about 0.731" for a target of 0.318
    factor_needed = re.search(r"field\.floe_area_factor ≥ about ([0-9.]+)", message)
    assert factor_needed and float(factor_needed.group(1)) > factor


def test_a_concentration_whose_circles_would_cover_more_than_the_field_is_refused_before_placing():
    obs = Observation(0.5, 1.0, (5.0, 10.0), (50.0, 50.0))  # 0.5 · 0.25 / 0.1: circles covering 125 %
    with pytest.raises(InputError) as info:
        generate_field(obs, 60.0, 40.0, np.random.default_rng(0), floe_area_factor=0.1)
    message = str(info.value)
    assert "125 %" in message and "floe_area_factor = 0.1" in message
    densest = math.pi / math.sqrt(12.0)
    assert f"field.concentration < {densest * 0.1 / 0.25:.3g}" in message


# (b) documented-valid shoulder_frame_angle_deg = 89.999: "node 0: the waterline … intersects itself"
def test_a_shoulder_flare_that_folds_the_lower_waterline_names_the_parameter_and_its_range():
    with pytest.raises(InputError) as info:
        agulhas_ii(1.0, shoulder_frame_angle_deg=89.999)
    assert info.value.field == "shoulder_frame_angle_deg"
    limit = math.degrees(math.atan(21.7 / (2 * 1.0)))  # Agulhas II: B = 21.7 m; Δz = h = 1 m
    assert f"[0, {limit:.4g})°" in str(info.value)
    agulhas_ii(1.0, shoulder_frame_angle_deg=limit - 0.01)  # just inside the range: a bow


def test_the_scenario_names_the_hull_parameter():
    scenario = Scenario.from_dict({"ship": {"hull_parameters": {"shoulder_frame_angle_deg": 89.999}}})
    from floebreak.api import build_bow

    with pytest.raises(InputError) as info:
        build_bow(scenario.resolved())
    assert str(info.value).startswith("ship.hull_parameters.shoulder_frame_angle_deg: 89.999°")


def test_a_fully_collapsed_lower_waterline_stays_a_bow():
    bow = polarstern(stem_angle_deg=5.0, shoulder_frame_angle_deg=89.999, midbody_frame_angle_deg=89.999)
    assert bow.hull_lower.area == 0.0


# (c) a field called "too small" where "whole floes give 46.4 % for a target of 44 %"
def test_whole_floes_that_miss_the_target_are_explained_with_sizes_that_fit():
    obs = get_observation("2019-12-18T20:20")  # 44 %: 2.5, 7.5, 15 m at 20, 40, 40 %
    with pytest.raises(InputError) as info:
        generate_field(obs, 60.0, 40.0, np.random.default_rng(0))
    message = str(info.value)
    assert "too small" not in message
    # 12 floes: 2 × 2.5 m, 5 × 7.5 m, 5 × 15 m cover π/4 (2·2.5² + 5·7.5² + 5·15²) / 2400 = 46.4 %
    cover = math.pi / 4 * (2 * 2.5**2 + 5 * 7.5**2 + 5 * 15.0**2) / (60 * 40)
    assert f"{100 * cover:.1f} %" in message and "12 floes" in message
    length = float(re.search(r"length_m = ([0-9.]+)", message).group(1))
    width = float(re.search(r"width_m = ([0-9.]+)", message).group(1))
    for size in ((length, 40.0), (60.0, width)):  # the sizes it proposes do give the target
        assert abs(floe_counts(obs, size[0] * size[1]).circle_concentration - 0.44) <= CONCENTRATION_TOLERANCE
        field = generate_field(obs, *size, np.random.default_rng(0))
        assert abs(field.concentration - 0.44) <= CONCENTRATION_TOLERANCE


# (d) a UTF-8 BOM in a TOML gave "Invalid statement (line 1, column 1)"
def test_a_toml_file_with_a_utf8_bom_is_read(tmp_path):
    text = "[field]\nlength_m = 30.0\n[ice]\nthickness_m = 0.8\n"
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + text.encode())
    (tmp_path / "plain.toml").write_text(text, encoding="utf-8")
    assert (
        Scenario.from_toml(tmp_path / "bom.toml").hash() == Scenario.from_toml(tmp_path / "plain.toml").hash()
    )
    study = 'name = "s"\nn_fields = 1\nbase = "plain.toml"\n'
    (tmp_path / "study.toml").write_bytes(b"\xef\xbb\xbf" + study.encode())
    assert load_study(tmp_path / "study.toml")[0].name == "s"
