"""The propeller and shaft analyses' figures drawn by forked figure workers while the tables are written
(`floebreak.output.figure_process.figures_drawn_alongside`, as `floebreak propeller` does it): the same files,
byte for byte, as drawn serially; a worker's failure fails the write with nothing left behind."""

from __future__ import annotations

import multiprocessing
import os

import pytest

from floebreak.app.propeller import analyse_runs, read_runs, write_propeller
from floebreak.app.shaft import shaft_analysis_of_run
from floebreak.output import figure_process

from .test_cli_shaft import make_run

pytestmark = pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(), reason="no fork on this platform"
)


@pytest.fixture(scope="module")
def analyses(tmp_path_factory):
    """A small run's propeller analysis (PC5, so every figure is drawn) and its drive-model shaft analysis."""
    run = make_run(tmp_path_factory.mktemp("figures") / "run", speed_m_s=3.0, profile="default")
    shaft = shaft_analysis_of_run(run, "agulhas_ii", cases=(1, 2))
    return analyse_runs(read_runs(run), polar_class="PC5"), shaft


def _files(folder):
    files = sorted(p for p in folder.rglob("*") if p.is_file())
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in files}


def _sent(monkeypatch) -> list[int]:
    """Fork figure workers here (as on a Linux machine with ≥ 2 cores); the number of figures sent to each
    worker at the write, filled as they are sent."""
    monkeypatch.setattr(figure_process, "fork_for_figures", lambda: True)
    sent = []
    dumps = figure_process.pickled

    def counted(message):
        if isinstance(message, tuple) and message[0] == "write":
            sent.append(len(message[1]))
        return dumps(message)

    monkeypatch.setattr(figure_process, "pickled", counted)
    return sent


def test_figure_workers_write_the_same_files_as_the_serial_path(analyses, tmp_path, monkeypatch):
    result, shaft = analyses
    write_propeller(result, tmp_path / "serial")
    shaft.write(tmp_path / "serial" / "shaft")
    sent = _sent(monkeypatch)
    with figure_process.figure_worker() as first, figure_process.figure_worker() as second:
        write_propeller(result, tmp_path / "forked", figure_worker=first)
        shaft.write(tmp_path / "forked" / "shaft", figure_worker=second)
    serial, forked = _files(tmp_path / "serial"), _files(tmp_path / "forked")
    figures = {name for name in forked if name.endswith(".png")}
    assert {"figures/ice_class_exceedance.png", "shaft/figures/campbell.png"} <= figures
    assert len(figures) == 13
    assert forked.keys() == serial.keys()
    assert [name for name in serial if forked[name] != serial[name]] == []
    assert sent == [6, 7]  # the propeller's figures to one worker, the shaft's to the other
    assert multiprocessing.active_children() == []  # both ended and reaped


def test_a_failing_figure_fails_the_write_and_leaves_nothing(analyses, tmp_path, monkeypatch):
    result, _ = analyses
    _sent(monkeypatch)
    calls = {"broken.png": ("propeller", "no_such_plot", (), {})}
    monkeypatch.setattr("floebreak.app.propeller.propeller_figure_calls", lambda _: calls)
    with figure_process.figure_worker() as worker, pytest.raises(AttributeError, match="no_such_plot"):
        write_propeller(result, tmp_path / "out", figure_worker=worker)
    assert not (tmp_path / "out").exists()
    assert os.listdir(tmp_path) == []  # no temporary directory left either
