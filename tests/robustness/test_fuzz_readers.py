"""The readers meet the fuzz campaign's hostile texts (`fuzz.adversarial`, tools/fuzz): TOML nested thousands
deep, FEM tables with extreme finite cells, measured torque files from no sample to past the row bound. Each
text is read or refused with an InputError naming the file — never another exception."""

from __future__ import annotations

import json

import numpy as np
import pytest

import floebreak.propeller.measured as measured
from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.propeller.loads.fem import parse_fem_table
from fuzz.adversarial import deep_toml_text, fem_table_texts, field_recipes, torque_csv_texts

SEEDS = range(40)


@pytest.mark.parametrize("seed", SEEDS)
def test_deep_toml_is_refused_naming_the_file(seed):
    with pytest.raises(InputError, match=r"s\.toml: arrays or tables nested more than"):
        Scenario.from_toml_text(deep_toml_text(np.random.default_rng(seed)), source="s.toml")


@pytest.mark.parametrize("seed", SEEDS)
def test_extreme_fem_tables_are_read_and_interpolate_finitely_or_are_refused(seed):
    text = fem_table_texts(np.random.default_rng(seed))
    try:
        table = parse_fem_table(text, "t.csv")
    except InputError as error:
        assert "t.csv" in str(error)
        return
    assert np.isfinite(table.torque_nm).all()


def test_the_fem_generator_draws_both_outcomes():
    outcomes = set()
    for seed in SEEDS:
        try:
            parse_fem_table(fem_table_texts(np.random.default_rng(seed)), "t.csv")
            outcomes.add("read")
        except InputError:
            outcomes.add("refused")
    assert outcomes == {"read", "refused"}


@pytest.mark.parametrize("seed", SEEDS)
def test_measured_files_are_read_or_refused_naming_the_file(seed, monkeypatch):
    monkeypatch.setattr(measured, "MAX_TORQUE_ROWS", 50)  # the bound's logic, not its size
    text = torque_csv_texts(np.random.default_rng(seed), 50)
    try:
        series = measured.parse_torque_csv(text, "m.csv")
    except InputError as error:
        assert "m.csv" in str(error)
        return
    assert series.time_s.size >= 2 and np.abs(series.torque_nm).max() <= measured.MAX_TORQUE_NM


def test_the_field_generator_draws_huge_and_far_floes():
    traits = {field_recipes(np.random.default_rng(seed))["trait"] for seed in range(200)}
    assert {"huge", "far"} <= traits


def test_the_readers_campaign_counts_and_keeps_violations(tmp_path):
    from fuzz import readers

    assert readers.main(["--n", "3", "--seed", "7", "--out", str(tmp_path)]) == 0
    counts = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert set(counts) == {"scenario", "fem_table", "torque_csv"}
    assert all(sum(c.values()) == 3 for c in counts.values()) and counts["scenario"]["refused"] == 3
    assert (tmp_path / "violations.jsonl").read_text(encoding="utf-8") == ""
    # a reader that breaks is a violation, not a crash of the campaign
    readers.READERS["broken"] = (lambda rng: "x", lambda text: 1 / 0)
    readers.SOURCES["broken"] = "b.txt"
    try:
        assert readers.check_text("broken", 1)["outcome"] == "violation"
    finally:
        del readers.READERS["broken"], readers.SOURCES["broken"]
