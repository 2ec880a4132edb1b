"""The ice-class rule's torque excitation beside the simulation (`--excitation rule`): the sequence, the
pulses' peaks, the resonance sweep's set speeds and the CLI's output, against numbers computed here."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from floebreak.app.inputs import load_shaft_line
from floebreak.errors import InputError
from floebreak.propeller.spec import PropellerSpec
from floebreak.shaft.line import modal_analysis
from floebreak.shaft.rule_excitation import (
    case_peaks,
    rule_excitation,
    rule_resonance_sweep,
    rule_response,
    sweep_rpms,
)

from .test_cli_shaft import make_run

# PC5 (H_ice 2 m, S_qice 1.15) for the default Agulhas II spec: D = 4.3 m > 1.8 H_ice, so
# Q_max = 202 (1 − d/D) S_qice H^1.1 (P_0.7/D)^0.16 (t_0.7/D)^0.6 (nD)^0.17 D^1.9 [kN·m] (notes §7.2)
D, H, ND = 4.3, 2.0, 140 / 60 * 4.3
Q_MAX = 202 * 0.7 * 1.15 * H**1.1 * (0.7 * 5.15 / D) ** 0.16 * (0.105 / D) ** 0.6 * ND**0.17 * D**1.9 * 1e3
MEAN = 250e3


@pytest.fixture(scope="module")
def line():
    return load_shaft_line("agulhas_ii")


def test_the_rule_sequence_of_pc5():
    e = rule_excitation(PropellerSpec(), "pc5")
    assert e.q_max_n_m == pytest.approx(Q_MAX, rel=1e-12)
    assert e.revolutions == 4.0  # N_Q = 2 H_ice
    assert e.n_impacts == 16  # Z · N_Q, Z = 4


@pytest.mark.parametrize(("case", "c_q"), [(1, 0.75), (3, 0.5), (4, 0.5)])
def test_linear_load_peak_is_the_mean_plus_one_pulse(line, case, c_q):
    # cases 1, 3 and 4: pulses (90°, 2 × 45° half a passage apart, 45°) do not overlap at Z = 4 (90° apart),
    # so the load's peak is Q_mean + C_q Q_max, sampled at the pulse's crest
    e = rule_excitation(PropellerSpec(), "PC5")
    result = rule_response(e, line, model="linear", mean_torque_n_m=MEAN, speed_m_s=3.0, cases=(case,))
    assert case_peaks(result)[case]["load_peak_knm"] == pytest.approx((MEAN + c_q * Q_MAX) / 1e3, rel=1e-9)
    ice = result.load_torque_n_m[0] - MEAN
    dt = result.time_s[1] - result.time_s[0]
    pulse_s = {1: 90.0, 3: 45.0, 4: 45.0}[case] / 360.0 * 60.0 / 140.0
    blocks = 2 if case == 3 else 1
    # area of 16 half sines (× blocks): 16 blocks C_q Q_max (2/π) pulse length (sampled: within 0.3 %)
    expected = 16 * blocks * c_q * Q_MAX * 2.0 / math.pi * pulse_s
    assert np.sum(ice) * dt == pytest.approx(expected, rel=5e-3)


def test_case_2_pulses_overlap(line):
    # 135° pulses 90° apart: two neighbours sum to at most max_φ sin(πφ/135°) + sin(π(φ−90°)/135°)
    e = rule_excitation(PropellerSpec(), "PC5")
    result = rule_response(e, line, model="linear", mean_torque_n_m=MEAN, speed_m_s=3.0, cases=(2,))
    phi = np.linspace(90.0, 135.0, 20001)
    both = np.max(np.sin(np.pi * phi / 135.0) + np.sin(np.pi * (phi - 90.0) / 135.0))
    assert case_peaks(result)[2]["load_peak_knm"] == pytest.approx((MEAN + both * Q_MAX) / 1e3, rel=2e-3)


def test_drive_model_mills_the_whole_sequence_when_it_does_not_stop(line):
    e = rule_excitation(PropellerSpec(), "PC5")
    result = rule_response(e, line, model="drive", mean_torque_n_m=MEAN, speed_m_s=3.0, cases=(3,))
    summary = result.drive_summaries[0]
    assert not summary["stalled"] and summary["impacts"] == 16
    with pytest.raises(InputError, match="shaft_model"):
        rule_response(e, line, model="rigid", mean_torque_n_m=MEAN, speed_m_s=3.0)


def test_sweep_passes_every_crossing_in_range(line):
    rpms = sweep_rpms(line, 4)
    low, high = 0.3 * line.rpm, 1.1 * line.rpm
    assert rpms.min() >= low and rpms.max() <= high and line.rpm in rpms
    # order k·Z crosses mode j at 60 f_j / (k Z)
    f = modal_analysis(line).frequency_hz
    crossings = [60.0 * fj / (k * 4) for fj in f for k in (1, 2, 3)]
    inside = [c for c in crossings if low <= c <= high]
    assert inside  # the Agulhas II line has crossings below its 140 rpm
    for c in inside:
        assert np.min(np.abs(rpms - c)) < 1e-3
        assert np.any(np.abs(rpms - 0.9 * c) < 1e-3) or 0.9 * c < low


def test_resonance_sweep_peaks_near_a_crossing(line):
    e = rule_excitation(PropellerSpec(), "PC5")
    sweep = rule_resonance_sweep(e, line, model="linear", mean_torque_n_m=MEAN, speed_m_s=3.0, cases=(4,))
    points = sweep["points"]
    top = max(points, key=lambda p: p["cases"][4]["q_peak_knm"])
    near = [abs(top["rpm"] / c["rpm"] - 1.0) <= 0.1 + 1e-9 for c in sweep["crossings"]]
    assert any(near)
    # the mean follows the propeller law: Q_mean (n/140)²
    for p in points:
        assert p["mean_torque_knm"] == pytest.approx(MEAN / 1e3 * (p["rpm"] / 140.0) ** 2)


def test_cli_rule_excitation_beside_the_simulation(tmp_path, cli):
    run = make_run(tmp_path / "run", speed_m_s=3.0, profile="default")
    out = tmp_path / "out"
    args = [
        "--shaft-line",
        "agulhas_ii",
        "--speed-m-s",
        "3",
        "--excitation",
        "rule",
        "--excitation-cases",
        "1,3",
    ]
    code, stdout, err = cli("propeller", run, "--out", out, *args)
    assert code == 0, err
    summary = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))
    rule = summary["rule_excitation"]
    assert rule["excitation"]["polar_class"] == "PC5"  # the built-in line's class
    assert rule["excitation"]["q_max_knm"] == pytest.approx(Q_MAX / 1e3, rel=1e-9)
    assert set(rule["cases"]) == {"1", "3"}
    mean = summary["propeller_operating_point"]["mean_torque_knm"]
    assert rule["mean_torque_knm"] == pytest.approx(mean)  # the open-water mean, not a typed-in one
    for case, entry in rule["cases"].items():
        assert entry["simulation_q_peak_knm"] == pytest.approx(summary["q_peak_knm"][case]["q_peak_knm"])
    assert rule["resonance_sweep"]["points"]
    assert "rule excitation (PC5" in stdout and "case 3: Q_peak rule" in stdout
    assert (out / "shaft" / "shaft_series.csv").is_file()


def test_cli_rule_excitation_needs_a_class_for_another_line_and_a_known_choice(tmp_path, cli):
    run = make_run(tmp_path / "run", speed_m_s=3.0, profile="default")
    out = tmp_path / "out"
    code, _, err = cli("propeller", run, "--out", out, "--shaft-line", "agulhas_ii", "--excitation", "fem")
    assert code == 2 and "excitation" in err and not out.exists()
    code, _, err = cli("propeller", run, "--out", out, "--excitation", "rule")
    assert code == 2 and "--excitation" in err and not out.exists()
