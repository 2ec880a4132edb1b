"""Scenario files: validation, defaults, --set overrides, resolution and the JSON schema."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from floebreak.config.scenario import REFERENCE_TOML, Scenario, json_schema, parse_override
from floebreak.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_reference_example_is_the_issue_scenario():
    assert (EXAMPLES / "reference.toml").read_text(encoding="utf-8") == REFERENCE_TOML
    s = Scenario.reference()
    # the values of the issue's TOML
    assert (s.profile, s.seed) == ("default", 1)
    assert s.field.observation == "2019-12-18T20:20"
    # the thesis' field (docs/validation.md): 100 m wide, above B + 2 d_max = 21.7 + 2 × 15 = 51.7 m, and the
    # length inferred for that width (tests/studies/test_field_size.py checks 385 m by hand)
    assert (s.field.length_m, s.field.width_m, s.field.generator) == (385.0, 100.0, "circles")
    assert s.field.width_m > 21.7 + 2 * 15.0
    assert s.ice.thickness_m == 1.0 and s.ice.fracture_toughness_pa_sqrt_m == 145.7e3
    assert (s.ship.hull, s.ship.step_m) == ("agulhas_ii", 0.25)
    # the flat keys of the issue's TOML stand for the cracking mode's table
    assert s.failure.mode_tables() == {"cracking": {"criterion": "tensile_stress", "size_effect_law": "BZ"}}


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_every_example_validates_and_resolves(path):
    scenario = Scenario.from_toml(path).resolved()
    again = Scenario.from_toml_text(scenario.to_toml())
    assert again.hash() == scenario.hash()  # the resolved TOML reproduces the scenario exactly


def test_examples_cover_the_documented_sources():
    names = {p.name for p in EXAMPLES.glob("*.toml")}
    assert names >= {
        "reference.toml",
        "thesis_profile.toml",
        "polarstern.toml",
        "random_thickness.toml",
        "single_floe.toml",
    }
    assert Scenario.from_toml(EXAMPLES / "single_floe.toml").field.source == "floes"
    assert Scenario.from_toml(EXAMPLES / "random_thickness.toml").ice.thickness_range_m == (0.75, 1.25)


def test_resolution_fills_profile_and_observation_defaults():
    # thesis profile: floe area factor 1/2 (erratum 1) and p_h = 1180 (erratum 6), from physics-notes §5
    thesis = Scenario.from_dict({"profile": "thesis"}).resolved()
    assert thesis.field.floe_area_factor == 0.5 and thesis.ice.thickness_summands == 1180
    default = Scenario.from_dict({"field": {"observation": "2019-12-19T04:40"}}).resolved()
    assert default.field.floe_area_factor == 0.25 and default.ice.thickness_summands == 12
    # no thickness given: the observation's mean thickness (thesis Table 1: 1.12 m for 2019-12-19 04:40)
    assert default.ice.thickness_m == pytest.approx(1.12)
    # no size given: the thesis' field, 385 m × 100 m (docs/validation.md, "The thesis' field size")
    assert (default.field.length_m, default.field.width_m, default.ship.hull) == (385.0, 100.0, "agulhas_ii")
    assert "thickness_m = 1.12" in default.to_toml()


def test_empty_scenario_is_the_reference_observation():
    s = Scenario.from_dict({}).resolved()
    assert s.field.observation == "2019-12-18T20:20"


def test_hash_changes_with_any_value():
    base = Scenario.reference().resolved()
    assert base.hash() == Scenario.reference().resolved().hash()
    assert Scenario.reference(["seed=2"]).resolved().hash() != base.hash()
    assert Scenario.reference(["ice.thickness_m=0.8"]).resolved().hash() != base.hash()


@pytest.mark.parametrize(
    ("expression", "path", "value"),
    [
        ("ice.thickness_m=0.8", ["ice", "thickness_m"], 0.8),
        ("seed=3", ["seed"], 3),
        ("ship.hull=polarstern", ["ship", "hull"], "polarstern"),
        ('ship.hull="polarstern"', ["ship", "hull"], "polarstern"),
        ("field.observation=2019-12-30T07:10", ["field", "observation"], "2019-12-30T07:10"),
        ("ice.thickness_range_m=[0.75, 1.25]", ["ice", "thickness_range_m"], [0.75, 1.25]),
        ("failure.flip_uncracked_at_shoulder=false", ["failure", "flip_uncracked_at_shoulder"], False),
    ],
)
def test_override_parsing(expression, path, value):
    assert parse_override(expression) == (path, value)


def test_overrides_are_validated_like_the_file():
    s = Scenario.reference(["ice.thickness_m=0.8", "ship.hull=polarstern", "seed=5"])
    assert (s.ice.thickness_m, s.ship.hull, s.seed) == (0.8, "polarstern", 5)
    with pytest.raises(InputError, match=r"ice\.thickness_m"):
        Scenario.reference(["ice.thickness_m=-0.8"])


def test_a_field_source_override_replaces_the_files_source(tmp_path):
    # the reference scenario generates its field (observation, length, width); `--set field.file=...` runs
    # a given field instead: the observation and the generation-only keys go, the rest stays
    s = Scenario.from_toml_text(REFERENCE_TOML, base_dir=tmp_path, overrides=['field.file="f.parquet"'])
    assert s.field.source == "file" and s.field.file == tmp_path / "f.parquet"
    assert (s.field.observation, s.field.length_m, s.field.width_m) == (None, None, None)
    assert s.ice.thickness_m == 1.0 and s.failure.mode_tables()["cracking"]["criterion"] == "tensile_stress"
    # and back: a file scenario given an observation generates again
    from_file = "[field]\nfile = 'f.parquet'\n"
    s = Scenario.from_toml_text(
        from_file, overrides=["field.observation=2019-12-30T07:10", "field.length_m=90"]
    )
    assert (s.field.source, s.field.file, s.field.length_m) == ("observation", None, 90.0)
    # a user observation replaces the named one
    s = Scenario.reference(
        ["field.diameter_classes_m=[5.0]", "field.percentages=[100.0]", "field.concentration=0.5"]
    )
    assert (s.field.source, s.field.observation, s.field.length_m) == ("user_observation", None, 385.0)
    # and back to a named observation: the user observation's concentration goes with it
    user = "[field]\ndiameter_classes_m = [5.0]\npercentages = [100.0]\nconcentration = 0.5\n"
    s = Scenario.from_toml_text(user, overrides=["field.observation=2019-12-30T07:10"])
    assert (s.field.source, s.field.concentration, s.field.diameter_classes_m) == ("observation", None, None)


def test_overrides_switch_between_other_alternatives(tmp_path):
    # the reference scenario fixes h = 1 m and the Agulhas II hull; a range or a bow file replaces them
    s = Scenario.reference(["ice.thickness_range_m=[0.75, 1.25]"])
    assert (s.ice.thickness_m, s.ice.thickness_range_m) == (None, (0.75, 1.25))
    s = Scenario.from_toml_text(REFERENCE_TOML, base_dir=tmp_path, overrides=['ship.file="bow.csv"'])
    assert (s.ship.hull, s.ship.file, s.ship.hull_parameters) == (None, tmp_path / "bow.csv", {})
    ranged = "[ice]\nthickness_range_m = [0.5, 0.7]\n[ship]\nfile = 'bow.csv'\n"
    s = Scenario.from_toml_text(ranged, overrides=["ice.thickness_m=0.9", "ship.hull=polarstern"])
    assert (s.ice.thickness_m, s.ice.thickness_range_m, s.ship.hull, s.ship.file) == (
        0.9,
        None,
        "polarstern",
        None,
    )
    with pytest.raises(InputError, match="not both"):  # both alternatives as overrides: still refused
        Scenario.reference(["ice.thickness_m=0.9", "ice.thickness_range_m=[0.5, 0.7]"])


def test_two_field_sources_in_overrides_still_conflict():
    with pytest.raises(InputError, match="only one field source"):
        Scenario.reference(['field.file="f.parquet"', "field.observation=2019-12-30T07:10"])
    # a generation key next to a given field is still refused
    with pytest.raises(InputError, match="only for generated fields") as info:
        Scenario.reference(['field.file="f.parquet"', "field.length_m=100"])
    assert info.value.field == "field.length_m"


@pytest.mark.parametrize(
    ("expression", "field"),
    [
        ("ice.thickness_m", "--set"),  # no '='
        ("=1", "--set"),
        ("ice..x=1", "--set"),
        ("ice.thickness_m=", "--set"),
        ("ice.thickness_m=[1,", "--set"),
        ("ice.thickness_m.x=1", "--set"),  # not a table
        ("ice.thickness_mm=1.0", "ice.thickness_mm"),  # unknown key
    ],
)
def test_bad_set_expression(expression, field):
    with pytest.raises(InputError) as info:
        Scenario.reference([expression])
    assert info.value.field == field


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    return path


# (TOML text, key named in the error, a word of the allowed values/range that must be in the message)
BAD_FILES = [
    ("seed = 1\n[field\n", "scenario", "TOML"),  # malformed
    ("colour = 'red'\n", "colour", "profile"),  # unknown top-level key, allowed keys listed
    ("[ice]\nthickness = 1.0\n", "ice.thickness", "thickness_m"),  # unknown key in a section
    ("[ship]\nbow = 'x'\n", "ship.bow", "hull"),
    ("[ice]\nthickness_m = '1.0'\n", "ice.thickness_m", "number"),  # wrong type: string
    ("seed = 1.5\n", "seed", "integer"),
    ("[failure]\nflip_uncracked_at_shoulder = 1\n", "failure.flip_uncracked_at_shoulder", "bool"),
    ("[ice]\nthickness_m = 0.0\n", "ice.thickness_m", "greater than or equal to 0.01"),
    ("[ice]\nthickness_m = -1.0\n", "ice.thickness_m", "greater than or equal to 0.01"),
    ("[ice]\nthickness_m = 11.0\n", "ice.thickness_m", "less than or equal to 10"),
    ("[ice]\nthickness_m = nan\n", "ice.thickness_m", "finite"),
    ("[ice]\nyoungs_modulus_pa = inf\n", "ice.youngs_modulus_pa", "finite"),
    ("[ice]\ncrushing_strength_pa = inf\n", "ice.crushing_strength_pa", "finite"),
    ("[ice]\nfracture_toughness_pa_sqrt_m = inf\n", "ice.fracture_toughness_pa_sqrt_m", "finite"),
    ("[ice]\nthickness_range_m = [1e-9, 1e9]\n", "ice.thickness_range_m[0]", "0.01"),
    ("[ship]\nx_start_m = nan\n", "ship.x_start_m", "finite"),
    ("[ship]\nstep_m = inf\n", "ship.step_m", "finite"),
    ("[ship]\nhull_parameters = {beam_m = inf}\n", "ship.hull_parameters.beam_m", "finite"),
    ("[field]\nlength_m = inf\n", "field.length_m", "finite"),
    ("[field]\nfloes = [{x_m = nan, y_m = 0.0, diameter_m = 5.0}]\n", "field.floes[0].x_m", "finite"),
    ("[simulation]\nmax_pieces = 0\n", "simulation.max_pieces", "greater than or equal to 1"),
    ("[ship]\nstep_m = 0.0\n", "ship.step_m", "greater than or equal to 0.001"),
    ("[ship]\nstep_m = -0.25\n", "ship.step_m", "greater than or equal to 0.001"),
    ("[field]\nconcentration = 1.2\n", "field.concentration", "less than or equal to 1"),
    ("[field]\nconcentration = 0.0\n", "field.concentration", "greater than 0"),
    (
        "[ice]\nfracture_toughness_pa_sqrt_m = -145.7e3\n",
        "ice.fracture_toughness_pa_sqrt_m",
        "greater than or equal to 1000",
    ),
    ("[ship]\nhull = 'titanic'\n", "ship.hull", "agulhas_ii, polarstern"),
    ("[failure]\ncrack_criterion = 'shear'\n", "failure.crack_criterion", "tensile_stress"),
    ("[failure]\nsize_effect_law = 'BZ3'\n", "failure.size_effect_law", "BZ1"),
    ("profile = 'fast'\n", "profile", "thesis"),
    ("[field]\nobservation = '2019-01-01T00:00'\n", "field.observation", "2019-12-18T20:20"),
    ("[field]\ngenerator = 'hexagons'\n", "field.generator", "voronoi"),
    ("[ice]\nthickness_range_m = [1.25, 0.75]\n", "ice.thickness_range_m", "h_min"),
    ("[ice]\nthickness_m = 1.0\nthickness_range_m = [0.75, 1.25]\n", "ice.thickness_range_m", "not both"),
    ("[field]\nobservation = '2019-12-18T20:20'\nfile = 'f.parquet'\n", "field.file", "only one"),
    ("[field]\nfloes = [{x_m = 1.0, y_m = 0.0, diameter_m = 0.0}]\n", "field.floes[0].diameter_m", "greater"),
    ("[field]\nfloes = [{x_m = 1.0, y_m = 0.0}]\n", "field.floes[0].diameter_m", "required"),
    (
        "[field]\nfloes = [{x_m = 1.0, y_m = 0.0, diameter_m = 5.0}]\nlength_m = 60.0\n",
        "field.length_m",
        "only",
    ),
    (
        "[field]\ndiameter_classes_m = [5.0, 10.0]\npercentages = [50.0, 50.0]\n",
        "field.diameter_classes_m",
        "conc",
    ),
    ("[ship]\nhull = 'polarstern'\nfile = 'bow.csv'\n", "ship.file", "not both"),
]


@pytest.mark.parametrize(("text", "field", "word"), BAD_FILES, ids=[b[1] for b in BAD_FILES])
def test_bad_scenario_names_the_key(tmp_path, text, field, word):
    with pytest.raises(InputError) as info:
        Scenario.from_toml(_write(tmp_path, text))
    assert info.value.field == field
    assert word.lower() in str(info.value).lower()
    assert str(info.value).startswith(f"{field}:")


def test_missing_scenario_file(tmp_path):
    with pytest.raises(InputError) as info:
        Scenario.from_toml(tmp_path / "nope.toml")
    assert info.value.field == "scenario"


def test_relative_file_paths_are_relative_to_the_scenario(tmp_path):
    (tmp_path / "sub").mkdir()
    path = tmp_path / "sub" / "s.toml"
    path.write_text("[field]\nfile = 'field.parquet'\n[ship]\nfile = '../bow.csv'\n", encoding="utf-8")
    s = Scenario.from_toml(path)
    assert s.field.file == tmp_path / "sub" / "field.parquet"
    assert s.ship.file.resolve() == (tmp_path / "bow.csv").resolve()


def test_schema_has_units_and_forbids_extra_keys():
    schema = json_schema()
    ice = schema["$defs"]["IceSection"]
    assert ice["additionalProperties"] is False
    assert "[m]" in ice["properties"]["thickness_m"]["description"]
    assert "Pa·√m" in ice["properties"]["fracture_toughness_pa_sqrt_m"]["description"]
    assert "[m]" in schema["$defs"]["ShipSection"]["properties"]["step_m"]["description"]
    assert set(schema["properties"]) >= {"profile", "seed", "field", "ice", "ship", "failure"}


def test_resolved_toml_is_valid_toml_without_nulls():
    data = tomllib.loads(Scenario.reference().resolved().to_toml())
    assert data["ice"]["thickness_summands"] == 12
    assert "x_end_m" not in data["ship"]  # unset optional keys are omitted, not written as null


@pytest.mark.parametrize("text", ["", "\n\n", "# only a comment\n", "\ufeff"])
def test_an_empty_scenario_file_is_refused_naming_it(tmp_path, text):
    path = tmp_path / "empty.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as caught:
        Scenario.from_toml(path)
    message = str(caught.value)
    assert "empty.toml" in message and "empty scenario" in message and "examples/reference.toml" in message


def test_the_cli_refuses_an_empty_scenario_with_exit_2(tmp_path):
    import subprocess
    import sys

    (tmp_path / "empty.toml").write_text("", encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", "run", "empty.toml", "--out", "out"],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert done.returncode == 2 and "empty.toml" in done.stderr and not (tmp_path / "out").exists()
