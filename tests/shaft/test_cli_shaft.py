"""`floebreak propeller RUN --shaft-line`: files, units, comparison; bad input exits 2, writes nothing."""

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import xarray as xr

from floebreak.app.inputs import load_shaft_line, synthetic_torque_path
from floebreak.shaft.analysis import shaft_response


def make_run(path, speed_m_s=None, profile="thesis"):
    """Six cusps; three to port on the port shaft's line (y = 5.5 m), two to starboard, one amidships."""
    path.mkdir()
    length = np.array([3.7, 6.5, 2.0, 9.4, 1.0, 3.0])
    n = length.size
    bow_x = np.array([1.0, 5.0, 5.0, 12.0, 20.0, 31.0])
    pq.write_table(
        pa.table(
            {
                "area_m2": 0.8 * length,
                "thickness_m": np.full(n, 0.4),
                "volume_m3": 0.8 * length * 0.4,
                "bbox_length_m": length,
                "bbox_width_m": np.ones(n),
                "step": np.arange(n),
                "bow_x_m": bow_x,
                "centroid_x_m": bow_x - 2.0,
                "centroid_y_m": np.array([5.5, -5.5, 5.5, 0.0, -5.5, 5.5]),
            }
        ),
        path / "cusps.parquet",
    )
    text = f'profile = "{profile}"\n'
    if speed_m_s is not None:
        text += f"[ship]\nspeed_m_s = {speed_m_s}\n"
    (path / "scenario.resolved.toml").write_text(text, encoding="utf-8")
    return path


def test_shaft_files_and_comparison(tmp_path, cli):
    run = make_run(tmp_path / "run")
    out = tmp_path / "out"
    code, _, err = cli(
        "propeller",
        run,
        "--out",
        out,
        "--shaft-line",
        "agulhas_ii",
        "--speed-m-s",
        "3",
        "--torque-csv",
        synthetic_torque_path(),
        "--station",
        "propeller_shaft",
    )
    assert code == 0, err
    shaft = out / "shaft"
    for name in (
        "shaft_series.nc",
        "shaft_series.csv",
        "shaft_spectra.nc",
        "shaft_spectra.csv",
        "modes.csv",
        "figures/shaft_comparison_log.png",
        "figures/shaft_comparison_linear.png",
        "figures/excitation_series.png",
        "figures/shaft_spectrum_log.png",
    ):
        assert (shaft / name).is_file(), name
    assert (out / "spectra.nc").is_file()  # the propeller torque spectrum next to it
    summary = json.loads((shaft / "summary.json").read_text())
    assert sorted(summary["q_peak_knm"]) == ["1", "2", "3", "4"]
    assert summary["station"] == "propeller_shaft"
    assert len(summary["modes_free_free"]["natural_frequencies_hz"]) == 2
    assert summary["spectra_above_threshold_knm"]["measured"]["envelope"] is not None
    with xr.open_dataset(shaft / "shaft_series.nc") as ds:
        assert ds.attrs["Conventions"] == "CF-1.8"
        assert ds["time"].attrs["units"] == "s" and ds["shaft_torque"].attrs["units"] == "kN m"
        assert ds.sizes["case"] == 4
        # mean hydrodynamic torque P/(2π n) of the built-in line: 4.5 MW at 140 rpm
        assert float(ds["load_torque"].min()) == pytest.approx(4.5e6 / (2 * np.pi * 140 / 60) / 1e3)


def test_speed_from_the_resolved_scenario(tmp_path, cli):
    run = make_run(tmp_path / "run", speed_m_s=4.5)
    code, _, err = cli(
        "propeller",
        run,
        "--out",
        tmp_path / "out",
        "--shaft-line",
        "agulhas_ii",
        "--excitation-cases",
        "2",
    )
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "shaft" / "summary.json").read_text())
    assert summary["excitation"]["ship_speed_m_s"] == 4.5 and list(summary["q_peak_knm"]) == ["2"]


def test_python_api_with_plain_arrays():
    line = load_shaft_line("agulhas_ii")
    result = shaft_response([0.0, 30.0], [4e5, 8e5], [0.4, 0.4], line, speed_m_s=3.0, mean_torque_n_m=1e5)
    peaks = result.peaks()
    assert set(peaks) == {1, 2, 3, 4}
    assert peaks[2]["load_peak_n_m"] == pytest.approx(1e5 + 8e5, rel=1e-3)  # C_q = 1
    assert result.shaft_torque_n_m.shape == result.load_torque_n_m.shape == (4, result.time_s.size)


def _line_toml(tmp_path, elements):
    text = "[shaft_line]\nrpm = 140\nmean_torque_n_m = 1e5\n"
    for e in elements:
        text += "[[shaft_line.elements]]\n" + "".join(f"{k} = {v!r}\n" for k, v in e.items())
    path = tmp_path / "line.toml"
    path.write_text(text.replace("'", '"'), encoding="utf-8")
    return path


MOTOR = {"name": "motor", "inertia_kg_m2": 1e4, "stiffness_n_m_per_rad": 1e7, "damping_ratio": 0.02}
PROP = {"name": "prop", "inertia_kg_m2": 5e3}

BAD = [
    (["--station", "tail_shaft"], None, "station"),
    (["--rpm", "0"], None, "rpm"),
    (["--rpm", "-100"], None, "rpm"),
    ([], "no speed", "speed_m_s"),
    (["--excitation-cases", "5"], None, "excitation_case"),
    ([], [PROP], "shaft_line.elements"),
    ([], [{**MOTOR, "inertia_kg_m2": 0.0}, PROP], "shaft_line.elements[0].inertia_kg_m2"),
    ([], [MOTOR, {**PROP, "inertia_kg_m2": -1.0}], "shaft_line.elements[1].inertia_kg_m2"),
    ([], [{**MOTOR, "stiffness_n_m_per_rad": -1e7}, PROP], "shaft_line.elements[0].stiffness_n_m_per_rad"),
    ([], [{**MOTOR, "damping_ratio": 1.0}, PROP], "shaft_line.elements[0].damping_ratio"),
    (["--shaft-line", "titanic"], None, "shaft_line"),
]


@pytest.mark.parametrize(("args", "line", "key"), BAD, ids=[f"{i}-{b[2]}" for i, b in enumerate(BAD)])
def test_bad_shaft_input_exit_2_nothing_written(tmp_path, args, line, key, cli):
    run = make_run(tmp_path / "run")
    shaft_line = "agulhas_ii" if not isinstance(line, list) else _line_toml(tmp_path, line)
    speed = [] if line == "no speed" else ["--speed-m-s", "3"]
    before = sorted(p.name for p in tmp_path.iterdir())
    code, _, err = cli(
        "propeller",
        run,
        "--out",
        tmp_path / "out",
        "--shaft-line",
        shaft_line,
        *speed,
        *args,
    )
    assert code == 2, err
    assert f"error: {key}:" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_shaft_options_need_a_shaft_line(tmp_path, cli):
    run = make_run(tmp_path / "run")
    code, _, err = cli("propeller", run, "--out", tmp_path / "out", "--rpm", "120")
    assert code == 2 and "error: --rpm:" in err and "--shaft-line" in err
    assert not (tmp_path / "out").exists()


def test_non_boolean_flag_names_its_key(tmp_path, cli):
    path = tmp_path / "line.toml"
    path.write_text('[shaft_line]\nbase = "agulhas_ii"\nhydrodynamic_damping = "no"\n', encoding="utf-8")
    code, _, err = cli(
        "propeller",
        make_run(tmp_path / "run"),
        "--out",
        tmp_path / "out",
        "--shaft-line",
        path,
        "--speed-m-s",
        "3",
    )
    assert code == 2 and "error: shaft_line.hydrodynamic_damping:" in err
    assert not (tmp_path / "out").exists()


PORT = [0, 2, 5]  # make_run's cusps on the port shaft's line


def _drive_run(tmp_path, cli, *args):
    run = make_run(tmp_path / "run", profile="default")
    out = tmp_path / "out"
    code, stdout, err = cli(
        "propeller",
        run,
        "--out",
        out,
        "--shaft-line",
        "agulhas_ii",
        "--speed-m-s",
        "3",
        "--mean-torque-knm",
        "105",
        *args,
    )
    assert code == 0, err
    return out / "shaft", stdout


def test_default_profile_mills_the_port_cusps_with_the_drive(tmp_path, cli):
    shaft, _ = _drive_run(tmp_path, cli, "--excitation-cases", "1,3")
    summary = json.loads((shaft / "summary.json").read_text())
    assert summary["shaft_model"] == "drive"
    assert summary["transport"]["reaching_port"] == len(PORT)
    # blade impacts: at least one per cusp, at most ⌈length / cut depth⌉ (cut depth V/(Z n) =
    # 3 / (4 · 140/60) m); fewer, since a free block is thrown out of the disc first (test_milling)
    length = np.array([3.7, 6.5, 2.0, 9.4, 1.0, 3.0])[PORT]
    drive = summary["drive"]["cases"]["1"]
    assert len(PORT) <= drive["impacts"] < int(np.ceil(length / (3.0 / (4 * 140 / 60))).sum())
    assert drive["complete"] and not drive["stalled"]
    assert 0 < drive["min_rpm"] < 140.0  # the ice slows the propeller
    # default limit: 1.6 × rated torque P/(2π n) = 1.6 × 4.5 MW / (2π · 140/60)
    assert summary["drive"]["torque_limit_knm"] == pytest.approx(1.6 * 4.5e6 / (2 * np.pi * 140 / 60) / 1e3)
    assert drive["peak_motor_torque_knm"] > 105.0
    with open(shaft / "shaft_series.csv", encoding="utf-8") as f:
        header = next(line for line in f if not line.startswith("#")).strip().split(",")
    assert header[0] == "time_s"
    assert next(h for h in header if h.startswith("shaft_torque_knm_")) == "shaft_torque_knm_case1"
    assert {"rpm_case1", "rpm_case3", "motor_torque_knm_case1"} <= set(header)
    with xr.open_dataset(shaft / "shaft_series.nc") as ds:
        assert ds.attrs["shaft_model"] == "drive" and ds["rpm"].attrs["units"] == "1/min"
        # steady running before the first cusp (arrives at 2 s): the model's mean torque, the open-water
        # torque at 95.86 % pitch exceeding the rated P/(2π n), held there by the pitch control; the
        # measured 105 kN·m is only compared
        quiet = ds["shaft_torque"].sel(case=1).where(ds["time"] < 1.5, drop=True)
        rated_knm = 4.5e6 / (2 * np.pi * 140 / 60) / 1e3
        assert float(quiet.mean()) == pytest.approx(rated_knm, rel=1e-3)
    point = summary["propeller_operating_point"]
    assert point["torque_limited"] and point["measured_mean_torque_knm"] == 105.0
    assert point["measured_over_model"] == pytest.approx(105.0 / rated_knm, rel=1e-3)
    assert 0.5 <= point["identified_pitch_ratio"] < point["pitch_ratio"] < point["set_pitch_ratio"]


def test_resonance_warning_of_the_built_in_line(tmp_path, cli):
    shaft, stdout = _drive_run(tmp_path, cli, "--excitation-cases", "4")
    resonance = json.loads((shaft / "summary.json").read_text())["resonance"]
    # first mode 7.76 Hz (docs/shaft.md §2) against the blade passage 4 · 140/60 = 9.33 Hz
    assert resonance["margin"][0][0] == pytest.approx(abs(7.76 - 4 * 140 / 60) / (4 * 140 / 60), abs=2e-3)
    assert resonance["required_margin"] == 0.2
    assert len(resonance["warnings"]) == 1 and "9.33 Hz" in resonance["warnings"][0]
    assert "assumed; IACS UR I3 text not available" in resonance["warnings"][0]
    assert "warning: mode 1 (7.76 Hz)" in stdout and "not stalled" in stdout


def test_thesis_profile_keeps_the_linear_model(tmp_path, cli):
    run = make_run(tmp_path / "run", profile="thesis")
    code, _, err = cli(
        "propeller", run, "--out", tmp_path / "out", "--shaft-line", "agulhas_ii", "--speed-m-s", "3"
    )
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "shaft" / "summary.json").read_text())
    assert summary["shaft_model"] == "linear" and summary["torque_model"] == "fem"
    assert summary["excitation"]["n_cusps"] == 6 and "drive" not in summary
    assert summary["resonance"]["warnings"]  # the margin is the line's, whatever the model


@pytest.mark.parametrize(
    ("args", "key"),
    [
        (["--torque-limit-knm", "0"], "torque_limit_knm"),
        (["--torque-limit-knm", "-300"], "torque_limit_knm"),
        (["--shaft-model", "rigid"], "shaft_model"),
        (["--shaft-model", "linear", "--torque-limit-knm", "400"], "torque_limit_knm"),
    ],
)
def test_bad_drive_input_exit_2_nothing_written(tmp_path, cli, args, key):
    run = make_run(tmp_path / "run", profile="default")
    before = sorted(p.name for p in tmp_path.iterdir())
    code, _, err = cli(
        "propeller", run, "--out", tmp_path / "out", "--shaft-line", "agulhas_ii", "--speed-m-s", "3", *args
    )
    assert code == 2 and f"error: {key}:" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == before
