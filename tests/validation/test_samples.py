"""The samples registry (validation/samples.toml): its entries parse, the samples fixed in code are the
registered ones, and a malformed entry is refused naming the sample and the key."""

from __future__ import annotations

import datetime
from pathlib import Path

import pytest

from floebreak.errors import InputError
from floebreak.validation.validate import CHOICE_SAMPLE, HOLDOUT_SAMPLE, parse_samples

REGISTRY = Path(__file__).parents[2] / "validation" / "samples.toml"
ENTRY = """[[sample]]
name = "tiny"
seed = 1
observation = "2019-12-18T20:20"
n_fields = 1
length_m = 60.0
width_m = 40.0
profiles = ["default"]
registered = 2026-12-07
"""


def test_the_samples_fixed_in_code_are_the_registered_ones():
    samples = parse_samples(REGISTRY.read_text(encoding="utf-8"))
    for fixed in (CHOICE_SAMPLE, HOLDOUT_SAMPLE):
        registered = samples[fixed.name]
        assert (registered.seed, registered.observation, registered.n_fields) == (
            fixed.seed,
            fixed.observation,
            fixed.n_fields,
        )
        assert (registered.length_m, registered.width_m) == (385.0, 100.0)  # the thesis' inferred field
    assert samples["clean-chain"].seed == 4242 and samples["clean-chain"].observation == "2020-01-03T17:40"
    # the samples scored before this registry existed say so
    assert all(samples[name].run_before_registration for name in ("choice", "holdout", "clean-chain"))


def test_a_registered_sample_parses_with_its_types():
    (sample,) = parse_samples(ENTRY).values()
    assert sample.registered == datetime.date(2026, 12, 7) and sample.profiles == ("default",)
    assert sample.length_m == 60.0 and not sample.run_before_registration and sample.note == ""


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("seed = 1", 'seed = "one"'), "sample 'tiny'.seed"),
        (("n_fields = 1", "n_fields = 0"), "n_fields ≥ 1"),
        (('observation = "2019-12-18T20:20"', 'observation = "2019-12-18T20:21"'), "Table 1"),
        (('profiles = ["default"]', 'profiles = ["fast"]'), "sample 'tiny'.profiles"),
        (("width_m = 40.0", "width_m = -40.0"), "sample 'tiny'.width_m"),
        (
            ("registered = 2026-12-07", 'colour = "red"'),
            "unknown keys ['colour'], missing keys ['registered']",
        ),
    ],
)
def test_a_malformed_sample_is_refused_naming_it(change, message):
    with pytest.raises(InputError) as caught:
        parse_samples(ENTRY.replace(*change))
    assert message in str(caught.value)
    with pytest.raises(InputError, match="registered twice"):
        parse_samples(ENTRY + ENTRY)


def test_a_sample_may_name_its_field_generator_and_its_fields_are_made_by_it(tmp_path):
    from floebreak.cli.validate import _thesis_inputs

    assert parse_samples(ENTRY)["tiny"].generator == "circles"  # without the key: the default generator
    path = tmp_path / "samples.toml"
    path.write_text(ENTRY + 'generator = "voronoi"\n', encoding="utf-8")
    assert parse_samples(path.read_text(encoding="utf-8"))["tiny"].generator == "voronoi"
    *_, sets, _ = _thesis_inputs("tiny", path, None, None, None, None, [], False, None)
    assert 'field.generator="voronoi"' in sets
    *_, sets, _ = _thesis_inputs("fresh-0710", REGISTRY, None, None, None, None, [], False, None)
    assert not any(s.startswith("field.generator") for s in sets)  # a circles sample sets nothing
    with pytest.raises(InputError, match=r"sample 'tiny'\.generator"):
        parse_samples(ENTRY + 'generator = "squares"\n')
