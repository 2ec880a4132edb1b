"""The pure propeller and shaft analyses take FemTables and TorqueSeries (the
application layer reads the files), and the long stages report progress through a plain callback whose
counts rise to the total (no timing involved)."""

from __future__ import annotations

import numpy as np
import pytest

from floebreak.app.inputs import (
    load_shaft_line,
    measured_series,
    read_torque_csv,
    resolve_fem_tables,
    shipped_fem_tables,
    synthetic_torque_path,
)
from floebreak.app.propeller import analyse_propeller as analyse_with_files
from floebreak.errors import InputError
from floebreak.io.figures import save_figures
from floebreak.propeller.measured import TorqueSeries
from floebreak.propeller.pipeline import ANALYSIS_STAGES, analyse_cusp_loads
from floebreak.shaft.analysis import cusp_torque_inputs, shaft_drive_response, shaft_response


def _cusps():
    length = np.array([3.7073, 6.5232, 9.4535, 2.0])
    ones = np.ones(4)
    return {
        "volume_m3": 0.8 * length,
        "bbox_length_m": length,
        "bbox_width_m": ones,
        "thickness_m": ones,
        "area_m2": 0.8 * length,
        "run_id": np.array(["r1"] * 4),
    }


class Recorder:
    def __init__(self):
        self.calls = []

    def __call__(self, stage: str, done: int, total: int) -> None:
        self.calls.append((stage, done, total))

    def check_rises_to_the_total(self) -> None:
        done = [d for _, d, _ in self.calls]
        totals = {t for _, _, t in self.calls}
        assert len(totals) == 1, self.calls
        assert done == list(range(1, len(done) + 1)), self.calls
        assert done[-1] == totals.pop()


def test_the_pure_analysis_refuses_paths_and_fem_without_tables(tmp_path):
    with pytest.raises(InputError) as info:
        analyse_cusp_loads(_cusps(), load_model="fem", transport="all")
    assert info.value.field == "fem_tables"
    with pytest.raises(InputError, match="is not a FemTable"):
        analyse_cusp_loads(_cusps(), fem_tables=[tmp_path / "table.csv"], transport="all")
    with pytest.raises(InputError) as info:
        analyse_cusp_loads(_cusps(), measured=synthetic_torque_path(), transport="all")
    assert info.value.field == "measured"


def test_the_application_layer_reads_the_files_the_pure_analysis_is_given():
    path = synthetic_torque_path()
    by_path = analyse_with_files(_cusps(), load_model="fem", transport="all", torque_csv=path)
    tables, series = shipped_fem_tables(), read_torque_csv(path)
    by_data = analyse_cusp_loads(_cusps(), fem_tables=tables, measured=series, transport="all")
    assert by_path.pitches == by_data.pitches == (0.0, 95.0)
    for pitch in by_data.pitches:
        assert np.array_equal(by_path.amplitudes(pitch).torque_nm, by_data.amplitudes(pitch).torque_nm)
    assert np.array_equal(by_path.measured.density_per_knm, by_data.measured.density_per_knm)
    # the same analysis from a TorqueSeries object at the application level; flipping negates the torque
    assert measured_series(series) is series
    assert np.array_equal(measured_series(series, flip_sign=True).torque_nm, -series.torque_nm)
    assert measured_series(None) is None
    assert list(resolve_fem_tables(None)) == [0.0, 95.0]


def test_the_propeller_analysis_reports_its_stages():
    recorder = Recorder()
    analyse_cusp_loads(_cusps(), transport="all", progress=recorder)
    recorder.check_rises_to_the_total()
    assert [stage for stage, _, _ in recorder.calls] == list(ANALYSIS_STAGES)


def test_the_linear_shaft_analysis_reports_each_case():
    columns = {
        "bow_x_m": np.array([1.0, 5.0, 9.0]),
        "step": np.arange(3),
        "bbox_length_m": np.array([3.0, 4.0, 5.0]),
        "bbox_width_m": np.ones(3),
        "thickness_m": np.ones(3),
        "volume_m3": np.array([2.4, 3.2, 4.0]),
    }
    cusps = cusp_torque_inputs(columns, shipped_fem_tables())
    recorder = Recorder()
    result = shaft_response(
        cusps["bow_x_m"],
        cusps["torque_n_m"],
        cusps["thickness_m"],
        load_shaft_line("agulhas_ii"),
        speed_m_s=3.0,
        cases=(1, 3),
        samples_per_blade_passage=20,
        tail_s=0.5,
        progress=recorder,
    )
    recorder.check_rises_to_the_total()
    assert [stage for stage, _, _ in recorder.calls] == ["shaft case 1", "shaft case 3"]
    assert result.cases == (1, 3)
    with pytest.raises(InputError, match="str is not a FemTable"):
        cusp_torque_inputs(columns, ["table.csv"])


def test_the_drive_shaft_analysis_reports_each_case():
    recorder = Recorder()
    shaft_drive_response(
        np.array([0.5]),
        np.array([1]),
        lambda cusp, rpm: 1e4,
        load_shaft_line("agulhas_ii"),
        speed_m_s=3.0,
        cases=(1, 2, 4),
        tail_s=0.2,
        progress=recorder,
    )
    recorder.check_rises_to_the_total()
    assert recorder.calls[-1] == ("shaft case 4", 3, 3)


def test_saving_figures_reports_each_one_after_the_earlier_steps(tmp_path):
    from matplotlib.figure import Figure

    recorder = Recorder()
    recorder("tables", 1, 3)  # as the writers do: their own steps first, then the figures count on
    save_figures({"a.png": Figure(), "b.png": Figure()}, tmp_path / "figures", recorder, done=1)
    recorder.check_rises_to_the_total()
    assert sorted(p.name for p in (tmp_path / "figures").iterdir()) == ["a.png", "b.png"]


def test_a_torque_series_is_accepted_where_a_csv_was(tmp_path):
    series = TorqueSeries(np.array([0.0, 1.0, 2.0]), np.array([1e5, 2e5, 1.5e5]), "given")
    result = analyse_with_files(_cusps(), transport="all", torque_csv=series)
    assert result.measured.series is series
