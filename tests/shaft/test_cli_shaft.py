"""`floebreak propeller RUN --shaft-line`: files, units, comparison; bad input exits 2, writes nothing."""

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import xarray as xr

from floebreak.propeller.measured import synthetic_torque_path
from floebreak.shaft.analysis import shaft_response
from floebreak.shaft.line import load_shaft_line


def make_run(path, speed_m_s=None):
    path.mkdir()
    length = np.array([3.7, 6.5, 2.0, 9.4, 1.0, 3.0])
    n = length.size
    pq.write_table(
        pa.table(
            {
                "area_m2": 0.8 * length,
                "thickness_m": np.full(n, 0.4),
                "volume_m3": 0.8 * length * 0.4,
                "bbox_length_m": length,
                "bbox_width_m": np.ones(n),
                "step": np.arange(n),
                "bow_x_m": np.array([1.0, 5.0, 5.0, 12.0, 20.0, 31.0]),
                "centroid_x_m": np.array([1.0, 5.0, 5.0, 12.0, 20.0, 31.0]),  # for the cusp transport
                "centroid_y_m": np.full(n, 5.5),
            }
        ),
        path / "cusps.parquet",
    )
    if speed_m_s is not None:
        (path / "scenario.resolved.toml").write_text(f"[ship]\nspeed_m_s = {speed_m_s}\n", encoding="utf-8")
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
