"""The cusp transport's settings from the command line (`--transport-parameter KEY=VALUE` of
`floebreak propeller` and `floebreak voyage`): parsed, checked, and passed to the transport."""

from __future__ import annotations

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from floebreak.errors import InputError
from floebreak.propeller.pipeline import analyse_cusp_loads
from floebreak.propeller.transport import TRANSPORT_KEYS, TransportSettings, transport_settings


def _cusps():
    """Two 2 m × 2 m × 1 m stem cusps: on the port shaft line (y = 5.5 m: reaches, see test_load_models)
    and at y = 9 m. With the default bilge radius 2.5 m the flat bottom ends at B/2 − r = 10.85 − 2.5 =
    8.35 m, so the second is on the bilge and surfaces; with r = 0 it stays on the flat bottom (8.35 →
    10.85 m) and its cross-section [8, 10] m lies 2.5 m > R = 2.15 m aside of the port axis: it misses."""
    return {
        "volume_m3": np.full(2, 4.0),
        "bbox_length_m": np.full(2, 2.0),
        "bbox_width_m": np.full(2, 2.0),
        "thickness_m": np.ones(2),
        "area_m2": np.full(2, 4.0),
        "bow_x_m": np.array([10.0, 20.0]),
        "centroid_x_m": np.array([10.0, 20.0]),
        "centroid_y_m": np.array([5.5, 9.0]),
        "run_id": np.array(["r"] * 2),
    }


def test_settings_from_text_keep_defaults_and_name_the_key():
    settings = transport_settings(
        {"slip_factor": "0.5", "hull.beam_m": 20, "shoulder_cusps_submerge": "true"}
    )
    assert settings.params.slip_factor == 0.5 and settings.hull.beam_m == 20.0
    assert settings.params.shoulder_cusps_submerge is True
    assert settings.hull.draught_m == TransportSettings().hull.draught_m  # not given: the default
    assert set(settings.as_dict()) == set(TRANSPORT_KEYS)
    for values, key, text in (
        ({"slip_factor": "1.5"}, "transport.slip_factor", "1.5 is outside (0, 1]"),
        ({"hull.draught_m": "0.1"}, "transport.hull.draught_m", "0.1 is outside [0.5, 30] m"),
        ({"arrangement.tip_clearance_m": "-1"}, "transport.arrangement.tip_clearance_m", "outside [0, 10]"),
        ({"drag_coefficient": "lots"}, "transport.drag_coefficient", "'lots' is not a number"),
        ({"shoulder_cusps_submerge": "maybe"}, "transport.shoulder_cusps_submerge", "true, false"),
        ({"lateral_spread_m": "1"}, "transport.lateral_spread_m", "needs a random generator"),
        ({"hull.bilge_radius_m": "12"}, "transport.hull.bilge_radius_m", "exceeds half the beam"),
    ):
        with pytest.raises(InputError) as info:
            transport_settings(values)
        assert info.value.field == key and text in str(info.value), str(info.value)


def test_bilge_radius_reaches_the_transport():
    never = {"surfaced": 0, "stalled": 0}  # paths only the flow transport gives
    default = analyse_cusp_loads(_cusps(), transport="hull")
    assert (
        default.summary["transport"]["paths"]
        == {"propeller": 1, "shoulder": 0, "bilge": 1, "missed": 0} | never
    )
    settings = transport_settings({"hull.bilge_radius_m": 0})
    flat = analyse_cusp_loads(_cusps(), transport_settings=settings, transport="hull")
    assert (
        flat.summary["transport"]["paths"] == {"propeller": 1, "shoulder": 0, "bilge": 0, "missed": 1} | never
    )
    assert flat.summary["transport"]["settings"]["hull.bilge_radius_m"] == 0.0


def test_propeller_command_takes_transport_parameters(tmp_path, cli):
    run = tmp_path / "run"
    run.mkdir()
    pq.write_table(pa.table({k: v for k, v in _cusps().items() if k != "run_id"}), run / "cusps.parquet")
    code, _, err = cli(
        "propeller",
        run,
        "--out",
        tmp_path / "p",
        "--transport",
        "hull",
        "--transport-parameter",
        "hull.bilge_radius_m=0",
    )
    assert code == 0, err
    summary = json.loads((tmp_path / "p" / "summary.json").read_text(encoding="utf-8"))
    assert summary["transport"]["paths"]["missed"] == 1 and summary["transport"]["paths"]["bilge"] == 0
    code, _, err = cli("propeller", run, "--out", tmp_path / "q", "--transport-parameter", "slip_factor=0")
    assert code == 2 and "transport.slip_factor: 0 is outside (0, 1]" in " ".join(err.split())
    assert not (tmp_path / "q").exists()
    code, _, err = cli("propeller", run, "--out", tmp_path / "q", "--transport-parameter", "slip_factor")
    assert code == 2 and "--transport-parameter" in err and not (tmp_path / "q").exists()


def test_flow_parameters_are_settable_and_checked(tmp_path, cli):
    """The flow transport's keys: each end of C_D's and μ's ranges and the stem angle; a range out of order
    or out of bounds names its range key, exit code 2, nothing written."""
    settings = transport_settings({"flow.friction_max": "0.2", "flow.stem_angle_deg": 30})
    assert settings.flow.friction_range == (0.05, 0.2) and settings.flow.stem_angle_deg == 30.0
    assert settings.flow.drag_coefficient_range == (0.5, 1.5)  # the ends not given keep their defaults
    assert settings.as_dict()["flow.friction_max"] == 0.2
    run = tmp_path / "run"
    run.mkdir()
    pq.write_table(pa.table({k: v for k, v in _cusps().items() if k != "run_id"}), run / "cusps.parquet")
    for value, key in (
        ("flow.drag_coefficient_min=2", "transport.flow.drag_coefficient_range"),
        ("flow.friction_max=1.5", "transport.flow.friction_range"),
        ("flow.stem_angle_deg=100", "transport.flow.stem_angle_deg"),
    ):
        code, _, err = cli("propeller", run, "--out", tmp_path / "q", "--transport-parameter", value)
        assert code == 2 and key in err and not (tmp_path / "q").exists()
