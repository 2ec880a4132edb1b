"""`floebreak validate thesis` says its sample size and which committed tally it compares with."""

from __future__ import annotations

from pathlib import Path

from floebreak.validation.validate import parse_samples, sample_lines

REGISTRY = parse_samples((Path(__file__).parents[2] / "validation" / "samples.toml").read_text("utf-8"))


def test_the_default_call_is_not_the_16_field_sample_and_says_so():
    lines = sample_lines(4, 2023, "2019-12-18T20:20", 385.0, 100.0, REGISTRY)
    assert lines[0] == (
        "sample: 4 field(s) per design point, root seed 2023, observation 2019-12-18T20:20, "
        "field 385 m × 100 m"
    )
    assert "'choice' with 16 fields" in lines[1] and "n_fields 4 (its 16)" in lines[1]
    assert "not comparable" in lines[1] and "--sample choice" in lines[1]


def test_a_registered_sample_is_named():
    lines = sample_lines(16, 31, "2020-01-03T13:40", 385.0, 100.0, REGISTRY)
    assert lines[1] == "this is the registered sample 'holdout': compare with its committed tally"


def test_without_a_registry_the_size_alone():
    assert len(sample_lines(4, 1, "2019-12-18T20:20", 100.0, 50.0, {})) == 1
