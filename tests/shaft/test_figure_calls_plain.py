"""What `floebreak propeller` sends its figure processes is plain data: loading and drawing the
propeller's and the shaft's figure calls needs neither xarray nor dask. The parent builds the spectra as an
xarray Dataset for spectra.nc; sent as such, each figure process imported xarray to read it and, where dask
is installed, dask.array the first time xarray indexed it (≈ 0.4 s in each of the two drawing processes)."""

from __future__ import annotations

import json
import pickle
import subprocess
import sys
from contextlib import nullcontext

import pytest

from floebreak.app.inputs import synthetic_torque_path
from floebreak.app.propeller import analyse_runs, read_runs, write_propeller
from floebreak.app.shaft import shaft_analysis_of_run

from .test_cli_shaft import make_run


@pytest.fixture(scope="module")
def sent_calls(tmp_path_factory):
    """The figure calls the propeller command hands its figure workers (`figures_in_worker`), with a
    measured series so that the comparison figures are among them."""
    folder = tmp_path_factory.mktemp("calls")
    run = make_run(folder / "run", speed_m_s=3.0, profile="default")
    torque_csv = synthetic_torque_path()
    result = analyse_runs(read_runs(run), polar_class="PC5", torque_csv=torque_csv)
    shaft = shaft_analysis_of_run(run, "agulhas_ii", cases=(1, 2), torque_csv=torque_csv)
    sent = {}

    def capture(calls, worker):
        sent.update(calls)
        return lambda figures_folder: nullcontext(figures_folder.mkdir())

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr("floebreak.app.propeller.figures_in_worker", capture)
        patch.setattr("floebreak.app.shaft.figures_in_worker", capture)
        write_propeller(result, folder / "p", figure_worker=object())
        shaft.write(folder / "p" / "shaft", figure_worker=object())
    path = folder / "calls.pickle"
    path.write_bytes(pickle.dumps(sent))
    return sent, path


def test_the_figure_calls_load_and_draw_without_xarray_or_dask(sent_calls):
    sent, path = sent_calls
    assert {"torque_spectrum_log.png", "torque_comparison_log.png", "shaft_series.png"} <= sent.keys()
    code = (
        "import json, pickle, sys\n"
        "from floebreak.output.figure_process import draw_figure\n"
        f"calls = pickle.loads(open({str(path)!r}, 'rb').read())\n"
        "loaded = sorted(sys.modules)\n"
        "for call in calls.values():\n"
        "    draw_figure(call)\n"
        "print(json.dumps([loaded, sorted(sys.modules)]))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    loaded, drawn = (set(names) for names in json.loads(out.splitlines()[-1]))
    for modules in (loaded, drawn):
        assert not {name.split(".")[0] for name in modules} & {"xarray", "dask", "distributed"}
    assert "matplotlib" in drawn  # the figures were drawn there
