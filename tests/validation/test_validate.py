"""`floebreak validate thesis|sensitivity|convergence`: designs, options, errors, an end-to-end run."""

from __future__ import annotations

import csv
import math

import pytest
from typer.testing import CliRunner

from floebreak.cli import app
from floebreak.errors import InputError
from floebreak.studies.design import expand
from floebreak.studies.field_size import thesis_scenario
from floebreak.validation.scoreboard import TABLE_OUTPUTS
from floebreak.validation.sensitivity import (
    CONTINUOUS_INPUTS,
    converged_from,
    elasticity,
    sensitivity_points,
)
from floebreak.validation.validate import (
    POINTS,
    make_configs,
    parse_variant,
    single_floe_spec,
    split_group,
    thesis_validation_spec,
)


def test_parse_variant():
    name, keys = parse_variant(
        "wide:failure.wedge_angle_deg=10.0,ice.thickness_range_m=[0.75, 1.25],ship.hull=x"
    )
    assert name == "wide"
    assert keys == {"failure.wedge_angle_deg": 10.0, "ice.thickness_range_m": [0.75, 1.25], "ship.hull": "x"}


@pytest.mark.parametrize("text", ["noseparator", "bad name:a.b=1", ":a.b=1", "x:", "x:a.b", "x:a.b=1,=2"])
def test_bad_variant_syntax(text):
    with pytest.raises(InputError, match=r"variant|set"):
        parse_variant(text)


def test_configs():
    configs = make_configs("both", ["w:failure.wedge_angle_deg=10.0"])
    assert [c.name for c in configs] == ["default", "thesis", "default+w", "thesis+w"]
    assert configs[3].profile == "thesis" and configs[3].overrides == {"failure.wedge_angle_deg": 10.0}
    with pytest.raises(InputError, match="profile"):
        make_configs("literal", [])
    with pytest.raises(InputError, match="repeated"):
        make_configs("default", ["w:ship.step_m=0.5", "w:ship.step_m=0.125"])


def test_design_runs_every_point_of_every_configuration_on_common_fields():
    base = thesis_scenario(["ship.step_m=0.5"], 100.0)
    configs = make_configs("both", [])
    runs, members = expand(thesis_validation_spec(configs, base, n_fields=1, seed=3))
    assert len(members) == 2 * len(POINTS)
    assert len(runs) == len(members)  # every point differs from the reference
    by_group = {}
    for m, run in zip(members, runs, strict=True):
        by_group.setdefault(split_group(m.group), []).append(run)
    assert set(by_group) == {(c.name, p) for c in configs for p in POINTS}
    seeds = {tuple(r.seed for r in group) for group in by_group.values()}
    assert len(seeds) == 1  # the same field at every point of every configuration
    reference = by_group[("thesis", "reference")][0].scenario
    assert reference["profile"] == "thesis" and reference["field"]["length_m"] == 100.0
    assert reference["ship"]["step_m"] == 0.5
    assert by_group[("default", "line_load")][0].scenario["failure"]["cracking"]["criterion"] == "line_load"
    random = by_group[("default", "h_random")][0].scenario["ice"]
    assert "thickness_m" not in random and random["thickness_range_m"] == [0.75, 1.25]


def test_single_floe_design():
    runs, members = expand(single_floe_spec(make_configs("default", []), thesis_scenario(length_m=385.0)))
    assert len(runs) == 10  # Figs. 15 (d 10 m, h 0.8 m) and 16 (d 20 m, h 1 m) × positions a–e
    floes = {m.group: r.scenario["field"]["floes"][0] for m, r in zip(members, runs, strict=True)}
    a, c = floes["default | single d20 h1 a"], floes["default | single d20 h1 c"]
    assert a["x_m"] == c["x_m"] == 11.0 and a["y_m"] == -c["y_m"] > 0  # mirror images, 1 m ahead of the stem


def test_sensitivity_points_move_every_input_by_delta():
    points = sensitivity_points(thesis_scenario(length_m=100.0), 0.1)
    assert points["h-"] == {"ice.thickness_m": pytest.approx(0.9)}
    assert points["K_Ic+"] == {"ice.fracture_toughness_pa_sqrt_m": pytest.approx(1.1 * 145.7e3)}
    assert points["φ-"] == {"failure.bending.wedge_angle_deg": pytest.approx(4.5)}  # thesis §4.1.2: φ = 5°
    # thesis §4.2.3: α = 30°
    assert points["α_nextcrack+"] == {"failure.cracking.next_crack_angle_deg": pytest.approx(33.0)}
    # the dispatch's shoulder region starts half-way from the stem to the shoulder (docs/model.md §10)
    assert points["shoulder start-"] == {"failure.shoulder_region_start": pytest.approx(0.45)}
    assert len(points) == 1 + 2 * len(CONTINUOUS_INPUTS) + 5


def test_elasticity_of_a_power_law():
    # y = x² per field at x = 0.9 and 1.1: the central difference of ln y / ln x is exactly 2
    minus = {0: 0.9**2 * 3.0, 1: 0.9**2 * 5.0}
    plus = {0: 1.1**2 * 3.0, 1: 1.1**2 * 5.0}
    mean, se, n = elasticity(minus, plus, 0.1)
    assert (mean, n) == (pytest.approx(2.0), 2) and se == pytest.approx(0.0, abs=1e-12)


def test_converged_from():
    def entry(d):
        return dict.fromkeys(TABLE_OUTPUTS, d)

    table = {0.0625: entry(0.0), 0.125: entry(0.01), 0.25: entry(-0.019), 0.5: entry(0.05)}
    assert converged_from(table) == 0.25
    assert converged_from({0.0625: entry(0.0), 0.125: entry(0.03)}) is None
    assert converged_from({2.5: entry(0.0), 5.0: entry(math.nan), 10.0: entry(0.1)}) == 5.0


runner = CliRunner()


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["thesis", "--profile", "literal"], "--profile"),
        (["thesis", "--n-fields", "0"], "--n-fields"),
        (["thesis", "--holdout", "--holdout-n-fields", "0"], "--holdout-n-fields"),
        (["thesis", "--variant", "broken"], "--variant"),
        (["thesis", "--variant", "x:failure.crack_criterion=nonsense"], "crack_criterion"),
        (["thesis", "--set", "ice.thickness_m=-1.0"], "thickness_m"),
        (["sensitivity", "--delta", "1.5"], "--delta"),
        (["convergence", "--profile", "both"], "--profile"),
        (["convergence", "--length-m", "0"], "--length-m"),
    ],
)
def test_bad_options_are_input_errors_and_write_nothing(tmp_path, args, field):
    out = tmp_path / "out"
    result = runner.invoke(app, ["validate", *args, "--out", str(out)])
    assert isinstance(result.exception, InputError), result.output
    assert field in str(result.exception)
    assert not out.exists()


def test_out_must_be_a_validate_directory(tmp_path):
    (tmp_path / "somefile.txt").write_text("x")
    result = runner.invoke(app, ["validate", "thesis", "--out", str(tmp_path)])
    assert isinstance(result.exception, InputError) and "--out" in str(result.exception)


@pytest.mark.slow
def test_validate_thesis_end_to_end_and_resume(tmp_path):
    out = tmp_path / "v"
    args = [
        "validate",
        "thesis",
        "--out",
        str(out),
        "--profile",
        "default",
        "--n-fields",
        "1",
        "--length-m",
        "40",
    ]
    args += ["--workers", "1", "--set", "ship.step_m=0.5", "--variant", "wide:failure.wedge_angle_deg=10.0"]
    args += ["--holdout", "--holdout-n-fields", "1"]
    first = runner.invoke(app, args)
    assert first.exit_code == 0, first.output
    with (out / "scoreboard.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == len({r["id"] for r in rows}) > 50
    assert {
        "default_verdict",
        "default+wide_verdict",
        "default@holdout_status",
        "default+wide@holdout_inert",
    } <= set(rows[0])
    assert {r["default_verdict"] for r in rows} <= {"pass", "fail", "info", "missing"}
    by_id = {r["id"]: r for r in rows}
    assert by_id["T8.BZ1.dV"]["default@holdout_status"] == "inert"  # the same run as BZ: a change of 0
    assert float(by_id["T8.BZ1.dV"]["default@holdout_ours"]) == 0.0
    assert (out / "holdout" / "runs").is_dir()
    markdown = (out / "scoreboard.md").read_text()
    assert "floebreak validate thesis --out" in markdown and "per 100 m" in markdown
    assert "`default@holdout`: " in markdown and "## Inert rows" in markdown
    assert (out / "figures" / "fig13_bending_forces.png").exists()
    second = runner.invoke(app, args)
    assert second.exit_code == 0 and "resumed" in second.output
