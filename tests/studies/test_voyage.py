"""Voyages (issue 18 §4): period → scenario, field rules, generator fallback, a tiny voyage end to end."""

from __future__ import annotations

import json
import math

import pyarrow.csv
import pytest

from floebreak.errors import InputError
from floebreak.io.voyage_log import parse_voyage_log
from floebreak.scenario import Scenario
from floebreak.studies.design import expand
from floebreak.studies.voyage import (
    DEFAULT_MAX_LENGTH_M,
    base_scenario,
    choose_generators,
    period_members,
    period_scenario,
    plan_voyage,
    prepare_voyage,
    run_voyage,
    voyage_spec,
)

AGULHAS_BEAM_M = 21.7  # physics-notes §6.1
HEADER = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d2m_percent,share_d4m_percent"


def test_period_plan_distance_length_and_width():
    log = parse_voyage_log(
        HEADER + ",speed_kn\n"
        "2020-01-01T00:00,2020-01-01T00:10,40,0.5,50,50,3.887689\n"  # 2 m/s for 10 min: 1200 m
        "2020-01-01T01:00,2020-01-01T01:02,30,0.8,100,0,1.943844\n",  # 1 m/s for 2 min: 120 m
        "log.csv",
    )
    first, second = plan_voyage(log, base_scenario())
    assert first.speed_source == "log" and first.speed_m_s == pytest.approx(2.0, rel=1e-6)
    assert first.distance_m == pytest.approx(1200.0, rel=1e-6)
    assert first.simulated_length_m == DEFAULT_MAX_LENGTH_M == 400.0  # capped
    assert second.simulated_length_m == pytest.approx(120.0, rel=1e-6)  # shorter than the cap: all of it
    # W = beam + 2 × largest floe diameter + 2 × 5 m
    assert first.field_width_m == pytest.approx(AGULHAS_BEAM_M + 2 * 4.0 + 10.0)
    assert second.field_width_m == pytest.approx(AGULHAS_BEAM_M + 2 * 2.0 + 10.0)  # 4 m class at 0 %


def test_speed_from_option_else_default():
    log = parse_voyage_log(HEADER + "\n2020-01-01T00:00,2020-01-01T00:30,40,0.5,50,50\n", "log.csv")
    (default,) = plan_voyage(log, base_scenario())  # ship.speed_m_s: 3 m/s (thesis Eq. 28)
    assert (default.speed_source, default.speed_m_s, default.distance_m) == ("scenario", 3.0, 5400.0)
    (scenario,) = plan_voyage(log, base_scenario(["ship.speed_m_s=2.0"]))
    assert (scenario.speed_source, scenario.distance_m) == ("scenario", 3600.0)
    (option,) = plan_voyage(log, base_scenario(["ship.hull=polarstern"]), speed_m_s=2.5, max_length_m=100.0)
    assert (option.speed_source, option.distance_m, option.simulated_length_m) == ("option", 4500.0, 100.0)
    assert option.field_width_m == pytest.approx(
        25.0 + 8.0 + 10.0
    )  # Polarstern B = 25 m (physics-notes §6.1)
    with pytest.raises(InputError, match="speed_m_s"):
        plan_voyage(log, base_scenario(), speed_m_s=0.0)


def test_period_scenario_is_the_logged_observation():
    log = parse_voyage_log(HEADER + "\n2020-01-01T00:00,2020-01-01T00:01,40,0.5,25,75\n", "log.csv")
    base = base_scenario(["failure.crack_criterion=line_load"])
    (plan,) = plan_voyage(log, base)
    scenario = Scenario.from_dict(period_scenario(base, plan, "voronoi")).resolved()
    assert scenario.field.source == "user_observation"
    assert scenario.field.concentration == 0.4
    assert scenario.field.diameter_classes_m == [2.0, 4.0] and scenario.field.percentages == [25.0, 75.0]
    assert scenario.field.length_m == pytest.approx(180.0)  # 3 m/s × 60 s
    assert scenario.field.generator == "voronoi"
    assert scenario.ice.thickness_m == 0.5
    assert scenario.ship.speed_m_s == 3.0  # the period's speed, for the runs' own rates
    assert scenario.failure.mode_tables()["cracking"]["criterion"] == "line_load"  # the --set is kept


@pytest.mark.parametrize("key", ["ice.thickness_m", "field.length_m", "field.observation", "seed"])
def test_keys_the_log_sets_cannot_be_overridden(key):
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        base_scenario([f"{key}=1"])


def test_study_design_has_one_point_per_period_and_n_fields_each():
    text = (
        HEADER
        + "\n"
        + "\n".join(f"2020-01-01T0{i}:00,2020-01-01T0{i}:10,{30 + 10 * i},0.5,50,50" for i in range(3))
    )
    log = parse_voyage_log(text, "log.csv")
    base = base_scenario()
    plans = plan_voyage(log, base)
    spec = voyage_spec("v", plans, base, n_fields=2, seed=5, generators=["circles"] * 3)
    runs, members = expand(spec)
    assert len(runs) == 6
    for plan, group in zip(plans, period_members(members, 3, 2), strict=True):
        assert [m.field_index for m in group] == [0, 1]
        assert {m.point["field.concentration"] for m in group} == {plan.period.concentration}


def test_generator_falls_back_to_voronoi_and_says_why(tmp_path):
    # 20 m floes at 50 % in a 60 m long field: whole circles cannot give 50 % (too coarse) → voronoi;
    # 2 m floes at 30 % are placed as circles
    log = parse_voyage_log(
        "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d2m_percent,share_d20m_percent,"
        "speed_m_s\n"
        "2020-01-01T00:00,2020-01-01T00:01,50,0.5,0,100,1\n"
        "2020-01-01T00:01,2020-01-01T00:02,30,0.5,100,0,1\n",
        "log.csv",
    )
    base = base_scenario()
    plans = plan_voyage(log, base)
    choices = choose_generators("v", plans, base, 1, 3, tmp_path / "fields")
    assert choices[0][0] == "voronoi" and choices[0][1].startswith("circles: ")
    assert choices[1] == ("circles", "")


TINY_LOG = (
    "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d3m_percent,share_d6m_percent,"
    "speed_m_s,propeller_pitch_percent\n"
    "2020-01-01T00:00,2020-01-01T00:02,40,0.6,50,50,0.25,0\n"  # 30 m sailed
    "2020-01-01T00:10,2020-01-01T00:12,30,0.9,100,0,0.5,90\n"  # 60 m sailed, simulated on 40 m
)


def test_tiny_voyage_end_to_end_and_resume(tmp_path):
    log = parse_voyage_log(TINY_LOG, "tiny.csv")
    setup = prepare_voyage(log, n_fields=1, seed=4, overrides=["ship.step_m=1.0"], max_length_m=40.0)
    out = tmp_path / "voyage"
    summary = run_voyage(setup, out)
    voyage = json.loads((out / "voyage.json").read_text(encoding="utf-8"))
    runs = [json.loads((out / "runs" / p["runs"][0] / "summary.json").read_text()) for p in voyage["periods"]]
    # independent: each simulated cusp counts D / (n L) times; n = 1 field
    expected = runs[0]["n_cusps"] * 30.0 / 30.0 + runs[1]["n_cusps"] * 60.0 / 40.0
    assert summary["cusps_voyage"] == pytest.approx(expected)
    hours = 4 / 60
    assert summary["cusps_per_hour"] == pytest.approx(expected / hours)
    per_propeller = expected / 2  # two propellers share the cusps (Agulhas II, thesis §6.1), all reach one
    for case in ("p0", "p95", "operated"):
        assert summary["cases"][case]["loads_per_hour"] == pytest.approx(per_propeller / hours)
        assert summary["cases"][case]["loads_per_km"] == pytest.approx(per_propeller / 0.09)
    periods = pyarrow.csv.read_csv(
        out / "results" / "periods.csv",
        parse_options=pyarrow.csv.ParseOptions(),
        read_options=_skip_comments(out),
    ).to_pydict()
    assert periods["distance_m"] == pytest.approx([30.0, 60.0])
    assert periods["simulated_length_m"] == pytest.approx([30.0, 40.0])
    assert periods["operated_pitch_percent"] == [0.0, 95.0]  # nearest FEM table to 0 % and 90 %
    assert periods["cusps_per_km"][1] == pytest.approx(runs[1]["n_cusps"] / 0.04)
    for name in ("force_spectrum", "torque_spectrum", "exceedance", "timeline"):
        assert (out / "results" / "figures" / f"{name}.png").stat().st_size > 0
    assert not any((out / "runs" / p["runs"][0] / "figures").exists() for p in voyage["periods"])
    _check_rule_form_and_report(summary, out, runs[0]["n_cusps"], runs[1]["n_cusps"])
    # resume: nothing re-runs, the same results
    again = run_voyage(setup, out)
    assert again["cusps_voyage"] == summary["cusps_voyage"] and again["failures"] == []
    # another voyage into the same directory is refused before anything is written
    other = prepare_voyage(log, n_fields=1, seed=5, overrides=["ship.step_m=1.0"], max_length_m=40.0)
    with pytest.raises(InputError, match="another voyage"):
        run_voyage(other, out)


def _skip_comments(out):
    lines = (out / "results" / "periods.csv").read_text(encoding="utf-8").splitlines()
    return pyarrow.csv.ReadOptions(skip_rows=sum(1 for line in lines if line.startswith("#")))


def _check_rule_form_and_report(summary, out, n_first, n_second):
    """The operated loads' rule-form fit is in summary.json, periods.md and report.html (propeller
    section with the time base and the rule-form figure)."""
    written = json.loads((out / "results" / "summary.json").read_text(encoding="utf-8"))
    torque = written["rule_form"]["torque_knm"]
    # weights: 30/30 and 60/40 cusps per simulated cusp, × 1/2 per propeller → 0.5 and 0.75
    n_eff = (0.5 * n_first + 0.75 * n_second) ** 2 / (0.25 * n_first + 0.5625 * n_second)
    assert torque["n_samples"] == n_first + n_second and torque["n_effective"] == pytest.approx(n_eff)
    per_hour = summary["cases"]["operated"]["loads_per_hour"]
    assert written["rule_form"]["n_ice_per_hour"] == torque["n_per_hour"] == pytest.approx(per_hour)
    x_max = torque["scale"] * math.log(per_hour) ** (1 / torque["k"])  # λ (ln N)^(1/k), notes §7.3
    assert torque["x_max_per_hour"] == pytest.approx(x_max)
    assert "Rule-form fit of the operated loads" in (out / "results" / "periods.md").read_text(
        encoding="utf-8"
    )
    report = (out / "results" / "report.html").read_text(encoding="utf-8")
    assert "<h2>Propeller loads</h2>" in report and "Time base:" in report
    assert "alt='rule_form.png'" in report and "report.html" in written["files"]
