"""Voyages: period → scenario, field rules, generator fallback, a tiny voyage end to end."""

from __future__ import annotations

import json
import math

import numpy as np
import pyarrow.csv
import pytest

from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.propeller.spec import PropellerSpec
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
from floebreak.studies.voyage_log import parse_voyage_log
from floebreak.studies.voyage_results import VoyageAnalysis, write_voyage_results

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


def _reaching(run_dirs, speeds, settings=None, n_propellers=2):
    """Cusps of each run that reach a propeller: the flow transport on its cusps.parquet (`n_propellers`
    discs), each run at its speed's controlled operating point, its Generator seeded with (0, its rank among
    the runs' names), as the pooled propeller analysis of the default profile does."""
    import pyarrow.parquet as pq

    from floebreak.propeller.flow_transport import flow_transport_cusps
    from floebreak.propeller.load_models import drive_rated_torque_n_m
    from floebreak.propeller.operating import controlled_point
    from floebreak.propeller.transport import TransportSettings

    settings, spec = settings or TransportSettings(), PropellerSpec()
    names = sorted(d.name for d in run_dirs)
    out = []
    for run_dir, speed in zip(run_dirs, speeds, strict=True):
        columns = [c.to_numpy() for c in _columns(pq.read_table(run_dir / "cusps.parquet"))[1]]
        order = np.argsort(columns[0], kind="stable")  # the analysis follows a run's cusps by bow position
        point = controlled_point(spec, speed, drive_rated_torque_n_m(spec))
        moved = flow_transport_cusps(
            *(c[order] for c in columns),
            speed_m_s=speed,
            induced_velocity_m_s=point.point.induced_velocity_m_s,
            wake_fraction=point.wake_fraction,
            rng=np.random.default_rng([0, names.index(run_dir.name)]),
            hull=settings.hull,
            arrangement=settings.arrangement(n_propellers, spec.radius_m),
            params=settings.params,
        )
        out.append(int(np.sum(moved.propeller_index >= 0)))
    return out


def _columns(table):
    names = ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")
    return names, [table.column(n) for n in names]


def test_tiny_voyage_end_to_end_and_resume(tmp_path, cli):
    log = parse_voyage_log(TINY_LOG, "tiny.csv")
    setup = prepare_voyage(log, n_fields=1, seed=4, overrides=["ship.step_m=1.0"], max_length_m=40.0)
    out = tmp_path / "voyage"
    summary = run_voyage(setup, out)
    voyage = json.loads((out / "voyage.json").read_text(encoding="utf-8"))
    run_dirs = [out / "runs" / p["runs"][0] for p in voyage["periods"]]
    runs = [json.loads((d / "summary.json").read_text()) for d in run_dirs]
    # independent: each simulated cusp counts D / (n L) times; n = 1 field
    weights = (30.0 / 30.0, 60.0 / 40.0)
    expected = runs[0]["n_cusps"] * weights[0] + runs[1]["n_cusps"] * weights[1]
    assert summary["cusps_voyage"] == pytest.approx(expected)
    hours = 4 / 60
    assert summary["cusps_per_hour"] == pytest.approx(expected / hours)
    # default profile: the milling model and the flow transport, as `floebreak propeller`
    assert summary["load_model"]["load_model"] == "milling" and summary["transport"]["rule"] == "flow"
    reaching = _reaching(run_dirs, (0.25, 0.5))
    assert 0 < sum(reaching) < runs[0]["n_cusps"] + runs[1]["n_cusps"]
    per_propeller = (reaching[0] * weights[0] + reaching[1] * weights[1]) / 2  # two shafts, one load each
    for case in summary["cases"]:
        assert summary["cases"][case]["loads_per_hour"] == pytest.approx(per_propeller / hours)
        assert summary["cases"][case]["loads_per_km"] == pytest.approx(per_propeller / 0.09)
    assert sorted(summary["cases"]) == ["operated", "p0", f"p{PropellerSpec().pitch_percent:g}"]
    periods = pyarrow.csv.read_csv(
        out / "results" / "periods.csv",
        parse_options=pyarrow.csv.ParseOptions(),
        read_options=_skip_comments(out),
    ).to_pydict()
    assert periods["distance_m"] == pytest.approx([30.0, 60.0])
    assert periods["simulated_length_m"] == pytest.approx([30.0, 40.0])
    # nearest milling pitch (0 % or the propeller's 95.9 %) to the logged 0 % and 90 %
    assert periods["operated_pitch_percent"] == [0.0, PropellerSpec().pitch_percent]
    assert periods["cusps_per_km"][1] == pytest.approx(runs[1]["n_cusps"] / 0.04)
    assert periods["fraction_reaching"][1] == pytest.approx(reaching[1] / runs[1]["n_cusps"])
    for name in ("force_spectrum", "torque_spectrum", "exceedance", "timeline"):
        assert (out / "results" / "figures" / f"{name}.png").stat().st_size > 0
    assert not any((out / "runs" / p["runs"][0] / "figures").exists() for p in voyage["periods"])
    _check_rule_form_and_report(summary, out, reaching, weights)
    _check_analysis_options(out, summary, runs, reaching, weights, run_dirs)
    _check_thesis_profile(tmp_path, out, expected / 2 / hours)
    _check_cli_options(tmp_path, out, cli)
    # resume: nothing re-runs, the same results
    again = run_voyage(setup, out)
    assert again["cusps_voyage"] == summary["cusps_voyage"] and again["failures"] == []
    # another voyage into the same directory is refused before anything is written
    other = prepare_voyage(log, n_fields=1, seed=5, overrides=["ship.step_m=1.0"], max_length_m=40.0)
    with pytest.raises(InputError, match="another voyage"):
        run_voyage(other, out)


def _check_analysis_options(out, default, runs, reaching, weights, run_dirs):
    """Each propeller option of `floebreak voyage` re-writes the results from the same runs."""
    from floebreak.propeller.iceclass import ur_i3_loads
    from floebreak.propeller.transport import transport_settings

    hours = 4 / 60
    # --fraction-reaching 0.5 --propellers 1: every cusp loads the one propeller with weight 0.5
    override = write_voyage_results(out, None, VoyageAnalysis(fraction_reaching=0.5, n_propellers=1))
    every = runs[0]["n_cusps"] * weights[0] + runs[1]["n_cusps"] * weights[1]
    assert override["cases"]["operated"]["loads_per_hour"] == pytest.approx(0.5 * every / hours)
    assert override["transport"]["rule"] == "override" and override["propeller"]["count"] == 1
    assert any("is an override" in w for w in override["warnings"])
    # --propellers 1 alone: the transport still decides, one propeller takes every cusp that reaches
    one = write_voyage_results(out, None, VoyageAnalysis(n_propellers=1))
    alone = _reaching(run_dirs, (0.25, 0.5), n_propellers=1)
    assert one["transport"]["rule"] == "flow" and one["transport"]["n_reaching"] == sum(alone)
    assert one["cases"]["operated"]["loads_per_hour"] == pytest.approx(
        (alone[0] * weights[0] + alone[1] * weights[1]) / hours
    )
    # --polar-class PC5: the rule's Q_max, F_b and N_ice in the summary and the rule-form entries
    rule = ur_i3_loads(PropellerSpec(), "PC5")
    pc5 = write_voyage_results(out, None, VoyageAnalysis(polar_class="PC5"))
    assert pc5["ice_class"]["torque_knm"] == pytest.approx(rule.max_torque_nm / 1e3)
    assert pc5["rule_form"]["torque_knm"].get("rule_maximum", rule.max_torque_nm / 1e3) == pytest.approx(
        rule.max_torque_nm / 1e3
    )
    assert pc5["rule_form"]["rule_n_ice"] > 0 and default["ice_class"] is None
    # --transport-parameter shoulder_cusps_submerge=true: shoulder cusps go under the hull too
    values = {"shoulder_cusps_submerge": "true", "slip_factor": "0.8"}
    moved = write_voyage_results(out, None, VoyageAnalysis(transport=values))
    now = _reaching(run_dirs, (0.25, 0.5), transport_settings(values))
    assert moved["transport"]["n_reaching"] == sum(now)
    assert moved["transport"]["settings"]["slip_factor"] == 0.8
    # --shaft-line: the shaft analysis of each period's runs, pooled by time
    shaft = write_voyage_results(out, None, VoyageAnalysis(shaft_line="agulhas_ii"))["shaft"]
    per_period = shaft["periods"]
    assert [p["runs"] for p in per_period] == [1, 1] and shaft["hours"] == pytest.approx(hours)
    assert shaft["max_shaft_torque_knm"] == max(p["max_shaft_torque_knm"] for p in per_period)
    assert shaft["exceedance"]["time_share_above"][0] == pytest.approx(1.0)  # the lowest level: always
    assert (out / "results" / "shaft" / "shaft_exceedance.csv").is_file()


def _check_thesis_profile(tmp_path, out, all_per_hour):
    """Runs of the thesis profile: FEM tables and every cusp reaches (the profile recorded in each run's
    scenario.resolved.toml picks the model, as for `floebreak propeller`; edited on a copy here so that
    the voyage need not be simulated twice)."""
    import shutil

    copy = tmp_path / "thesis"
    shutil.copytree(out, copy)
    for path in (copy / "runs").glob("*/scenario.resolved.toml"):
        text = path.read_text(encoding="utf-8")
        assert 'profile = "default"' in text
        path.write_text(text.replace('profile = "default"', 'profile = "thesis"'), encoding="utf-8")
    thesis = write_voyage_results(copy, None, VoyageAnalysis())
    assert thesis["load_model"]["load_model"] == "fem" and thesis["transport"]["rule"] == "all"
    assert thesis["cases"]["p95"]["loads_per_hour"] == pytest.approx(all_per_hour)


def _check_cli_options(tmp_path, out, cli):
    """`floebreak voyage` with the propeller options on the finished voyage: the runs resume, the results
    are re-written and the terminal states the load model, the fraction reaching, the rule and the shaft."""
    (tmp_path / "tiny.csv").write_text(TINY_LOG, encoding="utf-8")
    code, stdout, err = cli(
        *("voyage", tmp_path / "tiny.csv", "--out", out, "--n-fields", "1", "--seed", "4"),
        *("--set", "ship.step_m=1.0", "--max-length-m", "40", "--workers", "1", "--polar-class", "PC5"),
        *("--fraction-reaching", "0.5", "--propellers", "1", "--shaft-line", "agulhas_ii"),
        *("--transport-parameter", "slip_factor=0.8"),
    )
    assert code == 0, err
    text = " ".join(stdout.split())
    assert "per-cusp loads: milling model" in text and "0.5 (override)" in text and "PC5 Q_max" in text
    assert "milling model (tip placement (no cusp geometry at the disc" in text  # the override: no geometry
    assert "shaft line agulhas_ii" in text and "is an override" in text
    written = json.loads((out / "results" / "summary.json").read_text(encoding="utf-8"))
    assert written["analysis"]["polar_class"] == "PC5" and written["analysis"]["n_propellers"] == 1
    assert written["analysis"]["transport"] == {"slip_factor": "0.8"}
    assert written["load_model"]["placement"].startswith("tip placement")


def _skip_comments(out):
    lines = (out / "results" / "periods.csv").read_text(encoding="utf-8").splitlines()
    return pyarrow.csv.ReadOptions(skip_rows=sum(1 for line in lines if line.startswith("#")))


def _check_rule_form_and_report(summary, out, reaching, weights):
    """The operated loads' rule-form fit is in summary.json, periods.md and report.html (propeller
    section with the time base and the rule-form figure)."""
    written = json.loads((out / "results" / "summary.json").read_text(encoding="utf-8"))
    torque = written["rule_form"]["torque_knm"]
    if "k" not in torque:  # the fit needs 10 loads, not all equal (`fit_rule_form`): the tiny voyage's
        # few loads of one thickness (0.9 m: period 0's cusps reach no propeller) are all the same
        assert f"{sum(reaching)} positive amplitudes, 1 distinct" in torque["reason"]
    else:  # weights of the cusps that reach: 30/30 and 60/40 cusps per simulated cusp, × 1/2 per propeller
        w = [0.5 * weights[0], 0.5 * weights[1]]
        n_eff = (w[0] * reaching[0] + w[1] * reaching[1]) ** 2 / (
            w[0] ** 2 * reaching[0] + w[1] ** 2 * reaching[1]
        )
        assert torque["n_samples"] == sum(reaching) and torque["n_effective"] == pytest.approx(n_eff)
        per_hour = summary["cases"]["operated"]["loads_per_hour"]
        assert written["rule_form"]["n_ice_per_hour"] == torque["n_per_hour"] == pytest.approx(per_hour)
        x_max = torque["scale"] * math.log(per_hour) ** (1 / torque["k"])  # λ (ln N)^(1/k), notes §7.3
        assert torque["x_max_per_hour"] == pytest.approx(x_max)
    assert "Rule-form fit of the operated loads" in (out / "results" / "periods.md").read_text(
        encoding="utf-8"
    )
    report = (out / "results" / "report.html").read_text(encoding="utf-8")
    assert "<h2>Propeller loads</h2>" in report and "Time base:" in report
    assert "per-cusp loads: milling model (engaged interval from the transport)" in report
    assert "alt='rule_form.png'" in report and "report.html" in written["files"]
