"""Profiles (`floebreak.config.profiles`) and how a scenario's failure section becomes the model.

The thesis profile's values are those of physics-notes §5 (errata 1, 6, 9, 12, 17, 19) where the thesis' own
results allow the literal reading, and the results-supported readings of docs/model.md §11 where they do not
(errata 11, 13, 15, 16, 19: bending capacity over the fan, maximum-stress breaking distance, generalised BZ2,
correct Tada labels, K_I from the load); the defaults are the corrected physics of physics-notes.
"""

from __future__ import annotations

from contextlib import nullcontext

import pytest

from floebreak.api import build_model_for
from floebreak.config.profiles import build_model, field_switches
from floebreak.config.scenario import REFERENCE_TOML, Scenario
from floebreak.errors import InputError

THESIS_BENDING = {
    "capacity_model": "nevel_narrow",  # not erratum 13's literal per-wedge capacity: §5.1 forces
    "breaking_length_mode": "max_stress",  # not erratum 11's max-moment distance: floes bend (§5.2–5.3)
    "loading_radius_model": "sector_area_clipped",  # notes §1.7
    "capacity_lookup": "thesis_a4",  # erratum 12: App. A.4's table lookup, Table 7's count trends
}
THESIS_CRACKING = {
    "bz2_mode": "generalised",  # not erratum 15's literal law: Table 8 BZ2 ≈ BZ
    "tada_labels": "correct",  # not erratum 16's swap of Alg. 7: Table 6's flexural-vs-tensile direction
    "point_load_capacity": "tensile_Pt",  # erratum 20: §4.2.1's P_t, Table 6's point-load directions
    "line_load_divide_by_thickness": False,  # erratum 17
    "line_load_crack_length": "indentation",  # erratum 19
    "stress_mode": "sif",  # not erratum 19's load-independent form: §3.2, §5.3.1, Table 5's K_Ic effects
}
CORRECTED_BENDING = {
    "capacity_model": "nevel_narrow",
    "breaking_length_mode": "max_stress",
    "loading_radius_model": "sector_area",
    "capacity_lookup": "direct",
}
CORRECTED_CRACKING = {
    "bz2_mode": "generalised",
    "tada_labels": "correct",
    "point_load_capacity": "tensile_Pt",
    "line_load_divide_by_thickness": True,
    "line_load_crack_length": "strip_critical",
    "stress_mode": "sif",
}


def values(settings, keys) -> dict:
    return {key: getattr(settings, key) for key in keys}


@pytest.mark.parametrize(
    ("profile", "contact", "bending", "cracking"),
    [
        ("default", ("per_panel", "consistent"), CORRECTED_BENDING, CORRECTED_CRACKING),
        ("thesis", ("single_psi", "thesis_alg3"), THESIS_BENDING, THESIS_CRACKING),
    ],
)
def test_each_profile_has_its_switches(profile, contact, bending, cracking):
    model = build_model(profile)
    assert (model.contact.area_model, model.contact.force_signs) == contact
    modes = model.failure.modes
    assert values(modes["bending"].settings, bending) == bending
    # local cracking and cracking's capacity use the same bending settings (thesis §4.3.1)
    assert modes["local_cracking"].settings == modes["bending"].settings == modes["cracking"].bending
    assert values(modes["cracking"].settings, cracking) == cracking


def test_thesis_profile_rotates_floes_that_cannot_bend_at_the_stem():
    """A bending-class floe wholly within its breaking radius: passed on to cracking (default) or rotated
    whole (thesis profile, docs/model.md §11); the shoulder and the other classes keep the default policy."""
    default, thesis = build_model("default").failure.policy, build_model("thesis").failure.policy
    assert default["bending"]["stem"] == ("bending", "cracking")
    assert thesis["bending"]["stem"] == ("bending", "rotation")
    assert thesis["bending"]["shoulder"] == default["bending"]["shoulder"]
    assert thesis["cracking"] == default["cracking"]
    stated = build_model("thesis", failure={"policy": {"bending": ["bending", "cracking"]}}).failure.policy
    assert stated["bending"] == {"stem": ("bending", "cracking"), "shoulder": ("bending", "cracking")}


def test_field_switches_of_the_profiles():
    # erratum 1: floe area π d²/4 (default) or π d²/2 (thesis); erratum 6: p_h = 12 or 1180 summed from 0
    default, thesis = field_switches("default"), field_switches("thesis")
    assert (default.floe_area_factor, default.thickness_summands, default.thickness_sum_from_zero) == (
        0.25,
        12,
        False,
    )
    assert (thesis.floe_area_factor, thesis.thickness_summands, thesis.thickness_sum_from_zero) == (
        0.5,
        1180,
        True,
    )


def test_overrides_are_applied_after_the_profile():
    model = build_model(
        "thesis",
        contact={"area_model": "per_panel"},
        modes={"bending": {"capacity_model": "thesis_per_wedge"}, "cracking": {"criterion": "line_load"}},
    )
    assert model.contact.area_model == "per_panel" and model.contact.force_signs == "thesis_alg3"
    bending = model.failure.modes["bending"].settings
    assert bending.capacity_model == "thesis_per_wedge"
    assert bending.loading_radius_model == "sector_area_clipped"  # the profile's, kept
    cracking = model.failure.modes["cracking"].settings
    assert cracking.criterion == "line_load" and cracking.line_load_crack_length == "indentation"


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"profile": "fast"}, "profile"),
        ({"modes": {"crushing": {}}}, "failure.crushing"),
        ({"modes": {"bending": {"wedge_deg": 5.0}}}, "failure.bending.wedge_deg"),
        ({"modes": {"local_cracking": {"wedge_angle_deg": 5.0}}}, "failure.local_cracking"),
        ({"failure": {"policy": {"bending": ["crushing"]}}}, "failure.policy.bending"),
    ],
)
def test_unknown_names_are_input_errors(kwargs, key):
    with pytest.raises(InputError) as info:
        build_model(**kwargs)
    assert info.value.field == key


def model_of(text: str, overrides=()):
    return build_model_for(Scenario.from_toml_text(text, overrides=overrides).resolved())


def test_mode_tables_and_ice_material_reach_the_modes():
    text = """
[ice]
flexural_strength_pa = 6.0e5
fracture_toughness_pa_sqrt_m = 2.0e5
[failure.bending]
wedge_angle_deg = 6.0
capacity_model = "kashtelyan"
[failure.cracking]
criterion = "line_load"
next_crack_angle_deg = 20.0
"""
    modes = model_of(text).failure.modes
    bending = modes["bending"].settings
    assert (bending.wedge_angle_deg, bending.capacity_model, bending.flexural_strength_pa) == (
        6.0,
        "kashtelyan",
        6.0e5,
    )
    assert modes["local_cracking"].settings == bending == modes["cracking"].bending
    cracking = modes["cracking"].settings
    assert (cracking.criterion, cracking.next_crack_angle_deg, cracking.fracture_toughness_pa_sqrt_m) == (
        "line_load",
        20.0,
        2.0e5,
    )


def test_flat_keys_are_the_same_as_the_tables():
    flat = "[failure]\ncrack_criterion = 'line_load'\nsize_effect_law = 'BZ2'\nwedge_angle_deg = 4.0\n"
    table = (
        "[failure.cracking]\ncriterion = 'line_load'\nsize_effect_law = 'BZ2'\n"
        "[failure.bending]\nwedge_angle_deg = 4.0\n"
    )
    with pytest.warns(FutureWarning, match="is deprecated") as caught:
        from_flat = Scenario.from_toml_text(flat)
    messages = sorted(str(warning.message) for warning in caught)  # one per flat key, naming its table key
    assert [message.split(" ", 1)[0] for message in messages] == [
        "failure.crack_criterion",
        "failure.size_effect_law",
        "failure.wedge_angle_deg",
    ]
    assert messages[0].endswith("[failure.cracking] (failure.cracking.criterion)")
    assert from_flat.hash() == Scenario.from_toml_text(table).hash()
    resolved = from_flat.resolved()
    assert "[failure.cracking]" in resolved.to_toml() and "crack_criterion" not in resolved.to_toml()
    again = Scenario.from_toml_text(resolved.to_toml())
    assert again.hash() == resolved.hash()
    cracking = build_model_for(again).failure.modes["cracking"].settings
    assert (cracking.criterion, cracking.size_effect_law) == ("line_load", "BZ2")


def test_a_flat_override_replaces_the_table_key_and_back():
    # `--set failure.crack_criterion=...` on a resolved scenario (table form), and the table key on a file
    # with the flat key
    resolved = Scenario.reference().resolved().to_toml()
    with pytest.warns(FutureWarning, match="failure.crack_criterion is deprecated"):
        flat = Scenario.from_toml_text(resolved, overrides=["failure.crack_criterion=point_load"])
    assert flat.failure.mode_tables()["cracking"]["criterion"] == "point_load"
    flat_file = REFERENCE_TOML.replace("[failure.cracking]\ncriterion", "[failure]\ncrack_criterion")
    flat_file = flat_file.replace("size_effect_law", "# size_effect_law")
    table = Scenario.from_toml_text(flat_file, overrides=["failure.cracking.criterion=flexural_stress"])
    assert table.failure.mode_tables()["cracking"]["criterion"] == "flexural_stress"
    both = resolved.replace("[failure]\n", "[failure]\ncrack_criterion = 'line_load'\n")
    with pytest.raises(InputError) as info:
        Scenario.from_toml_text(both)  # in a file, both spellings at once are ambiguous
    assert info.value.field == "failure.crack_criterion" and "not both" in str(info.value)


def test_a_stated_policy_replaces_the_default_for_its_classes_and_regions():
    text = (
        "[failure]\nflip_uncracked_at_shoulder = false\n"
        "[failure.policy]\nbending = {shoulder = ['bending']}\n"
    )
    policy = model_of(text).failure.policy
    assert policy["bending"] == {"stem": ("bending", "cracking"), "shoulder": ("bending",)}
    # not stated: the default, without the rotation of uncracked floes at the shoulder (thesis §4.4)
    assert policy["cracking"] == {"stem": ("cracking",), "shoulder": ("cracking",)}
    assert policy["unbreakable"]["shoulder"] == ("rotation",)
    assert set(model_of(text).failure.modes) == {"bending", "cracking", "rotation"}


@pytest.mark.parametrize(
    ("section", "key", "word"),
    [
        ("[failure.policy]\nbending = ['crushing']\n", "failure.policy.bending", "local_cracking"),
        ("[failure.policy]\nbending = []\n", "failure.policy.bending", "no mode"),
        ("[failure.policy]\ncrushing = ['rotation']\n", "failure.policy.crushing", "unbreakable"),
        ("[failure.policy]\ncracking = {bow = ['rotation']}\n", "failure.policy.cracking.bow", "shoulder"),
        ("[failure.policy]\ncracking = 'cracking'\n", "failure.policy.cracking", "list"),
        ("[failure.crushing]\nx = 1\n", "failure.crushing", "cracking"),
        ("[failure.local_cracking]\nwedge_angle_deg = 5.0\n", "failure.local_cracking", "bending"),
        ("[failure.bending]\nwedge_angle = 5.0\n", "failure.bending.wedge_angle", "wedge_angle_deg"),
        ("[failure.bending]\nwedge_angle_deg = 75.0\n", "failure.bending.wedge_angle_deg", "60"),
        ("[failure.bending]\nyoungs_modulus_pa = 1e9\n", "failure.bending.youngs_modulus_pa", "ice"),
        ("[failure]\nwedge_angle_deg = 0.0\n", "failure.wedge_angle_deg", "60"),
        ("[failure.cracking]\ncriterion = 'shear'\n", "failure.cracking.criterion", "line_load"),
        ("[failure]\nbending = 5.0\n", "failure.bending", "table"),
    ],
)
def test_bad_failure_sections_name_the_key(section, key, word):
    flat = key == "failure.wedge_angle_deg"  # the earlier spelling: read, with its deprecation message
    warns = pytest.warns(FutureWarning, match="wedge_angle_deg is deprecated") if flat else nullcontext()
    with pytest.raises(InputError) as info, warns:
        Scenario.from_toml_text(section)
    assert info.value.field == key
    assert word in str(info.value)


def test_the_schema_lists_each_modes_table_with_its_docstrings():
    from floebreak.config.scenario import json_schema

    failure = json_schema()["$defs"]["FailureSection"]
    assert failure["additionalProperties"] is False
    criterion = failure["properties"]["cracking"]["properties"]["criterion"]
    assert set(criterion["enum"]) == {"point_load", "line_load", "tensile_stress", "flexural_stress"}
    wedge = failure["properties"]["bending"]["properties"]["wedge_angle_deg"]
    assert "[deg]" in wedge["description"] and wedge["default"] == 5.0  # thesis §4.1.2: φ = 5°
    assert "flexural_strength_pa" not in failure["properties"]["bending"]["properties"]  # from [ice]
    assert "cracking.criterion" in failure["properties"]["crack_criterion"]["description"]
