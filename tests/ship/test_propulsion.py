"""Propulsion in ice (floebreak.ship.propulsion) and the scenario key ship.propulsion: published forms, the
balance speed, and bad input naming its key."""

from __future__ import annotations

import math

import pytest

from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.ship.propulsion import (
    Propulsion,
    balance_speed_m_s,
    bollard_pull_estimate_n,
    juva_riska_net_thrust_n,
    net_thrust_n,
)

AGULHAS_MASS_KG = 13.687e6  # displacement 13 687 t (public ship data, docs/model.md "Ship surge")


def test_juva_riska_net_thrust_at_rest_half_and_full_open_water_speed():
    # T_net = T_B (1 − u/3 − 2u²/3): u = 0 → T_B; u = ½ → T_B (1 − 1/6 − 1/6) = ⅔ T_B; u = 1 → 0
    assert juva_riska_net_thrust_n(0.0, 1.2e6, 8.0) == pytest.approx(1.2e6)
    assert juva_riska_net_thrust_n(4.0, 1.2e6, 8.0) == pytest.approx(0.8e6)
    assert juva_riska_net_thrust_n(8.0, 1.2e6, 8.0) == pytest.approx(0.0, abs=1e-6)


def test_fsicr_bollard_pull_of_agulhas_ii_like_machinery():
    # K_e = 0.98 (two CP propellers), P = 9 000 kW, D_P = 4.3 m: (9000·4.3)^(2/3) = 38 700^(2/3) = 1144.1
    assert bollard_pull_estimate_n(9.0e6, 4.3, 2) == pytest.approx(0.98 * 1144.13e3, rel=1e-4)
    with pytest.raises(InputError, match="power_w"):
        bollard_pull_estimate_n(0.0, 4.3)


def test_power_form_balances_at_the_open_water_speed_and_is_bollard_limited_at_rest():
    p = Propulsion(
        "power",
        AGULHAS_MASS_KG,
        bollard_pull_n=1.1e6,
        open_water_speed_m_s=8.0,
        delivered_power_w=9.0e6,
        propulsive_efficiency=0.5,
    )
    # at rest: T = T_B, R_ow = 0
    assert net_thrust_n(p, 0.0) == pytest.approx(1.1e6)
    # at 4 m/s: T = min(1.1e6, 0.5·9e6/4 = 1.125e6) = 1.1e6; R_ow = (0.5·9e6/8)·(4/8)² = 140 625 N
    assert net_thrust_n(p, 4.0) == pytest.approx(1.1e6 - 140_625.0)
    assert balance_speed_m_s(p) == pytest.approx(8.0, rel=1e-9)


def test_table_form_interpolates_and_its_balance_speed_is_the_zero_crossing():
    p = Propulsion("table", AGULHAS_MASS_KG, speeds_m_s=(0.0, 4.0, 10.0), net_thrust_n=(1e6, 6e5, -3e5))
    assert net_thrust_n(p, 2.0) == pytest.approx(8e5)
    # between (4, 6e5) and (10, −3e5): zero at 4 + 6·(6/9) = 8 m/s
    assert balance_speed_m_s(p) == pytest.approx(8.0)
    # a constant ice force of 6e5 N leaves 4 m/s
    assert balance_speed_m_s(p, 6e5) == pytest.approx(4.0)
    assert balance_speed_m_s(p, 2e6) == 0.0


def test_effective_mass_includes_the_surge_added_mass():
    p = Propulsion("bollard_pull", 1.0e7, 0.08, bollard_pull_n=1e6, open_water_speed_m_s=8.0)
    assert p.effective_mass_kg == pytest.approx(1.08e7)


def _scenario(**propulsion):
    return Scenario.from_dict({"ship": {"propulsion": {"displacement_kg": AGULHAS_MASS_KG, **propulsion}}})


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ({"model": "bollard_pull", "bollard_pull_n": 0.0, "open_water_speed_m_s": 8.0}, "bollard_pull_n"),
        ({"model": "bollard_pull", "bollard_pull_n": -1e6, "open_water_speed_m_s": 8.0}, "bollard_pull_n"),
        ({"model": "bollard_pull", "bollard_pull_n": 1e6}, "open_water_speed_m_s"),
        (
            {
                "model": "power",
                "bollard_pull_n": 1e6,
                "open_water_speed_m_s": 8.0,
                "delivered_power_w": 0.0,
                "propulsive_efficiency": 0.5,
            },
            "delivered_power_w",
        ),
        (
            {
                "model": "power",
                "bollard_pull_n": 1e6,
                "open_water_speed_m_s": 8.0,
                "delivered_power_w": 9e6,
                "propulsive_efficiency": 1.5,
            },
            "propulsive_efficiency",
        ),
        ({"model": "table", "speeds_m_s": [0.0, 5.0, 4.0], "net_thrust_n": [1e6, 5e5, -1e5]}, "speeds_m_s"),
        ({"model": "table", "speeds_m_s": [1.0, 5.0], "net_thrust_n": [1e6, -1e5]}, "speeds_m_s"),
        (
            {"model": "table", "speeds_m_s": [0.0, 4.0, 8.0], "net_thrust_n": [1e6, 1.2e6, -1e5]},
            "net_thrust_n",
        ),
        ({"model": "table", "speeds_m_s": [0.0, 4.0], "net_thrust_n": [0.0, -1e5]}, "net_thrust_n"),
        ({"model": "table", "speeds_m_s": [0.0, 4.0], "net_thrust_n": [1e6, 1e5]}, "net_thrust_n"),
        ({"model": "table", "speeds_m_s": [0.0, 4.0], "net_thrust_n": [1e6]}, "net_thrust_n"),
        (
            {"model": "table", "speeds_m_s": [0.0, 4.0], "net_thrust_n": [1e6, -1e5], "bollard_pull_n": 1e6},
            "bollard_pull_n",
        ),
        ({"model": "thrust", "bollard_pull_n": 1e6, "open_water_speed_m_s": 8.0}, "model"),
    ],
)
def test_bad_propulsion_names_its_key(table, key):
    with pytest.raises(InputError) as caught:
        _scenario(**table)
    assert caught.value.field == f"ship.propulsion.{key}"


def test_no_displacement_is_refused():
    with pytest.raises(InputError) as caught:
        Scenario.from_dict(
            {
                "ship": {
                    "propulsion": {
                        "model": "bollard_pull",
                        "bollard_pull_n": 1e6,
                        "open_water_speed_m_s": 8.0,
                    }
                }
            }
        )
    assert caught.value.field == "ship.propulsion.displacement_kg"


def test_a_valid_table_resolves_and_round_trips_through_toml():
    s = _scenario(model="table", speeds_m_s=[0.0, 4.0, 9.0], net_thrust_n=[1.1e6, 7e5, -2e5]).resolved()
    again = Scenario.from_toml_text(s.to_toml())
    assert again.ship.propulsion == s.ship.propulsion
    assert math.isclose(again.ship.propulsion.to_propulsion().bollard_thrust_n, 1.1e6)


def test_bad_propulsion_on_the_command_line_exits_2_and_writes_nothing(tmp_path, cli):
    scenario = tmp_path / "s.toml"
    scenario.write_text(
        '[field]\nlength_m = 60.0\n[ship.propulsion]\nmodel = "table"\ndisplacement_kg = 1.3687e7\n'
        "speeds_m_s = [0.0, 4.0, 8.0]\nnet_thrust_n = [1e6, 1.2e6, -1e5]\n",
        encoding="utf-8",
    )
    code, out, err = cli("run", str(scenario), "--out", str(tmp_path / "out"), "-q")
    assert code == 2
    assert "ship.propulsion.net_thrust_n" in "".join((out + err).split())
    assert not (tmp_path / "out").exists()
