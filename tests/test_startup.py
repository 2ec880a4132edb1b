"""Each command imports only what it uses: checked on `sys.modules` of a fresh interpreter,
not on timings (benchmarks/startup.py measures those)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

# the libraries of figures, NetCDF, studies on Dask, the engine, Parquet, the shaft line and rigid bodies
HEAVY = ("matplotlib", "xarray", "dask", "numba", "scipy", "pyarrow", "opentorsion", "pymunk", "pandas")


def loaded_after(statement: str) -> set[str]:
    """The top-level packages (and `scipy.*` modules) loaded by a fresh interpreter running `statement`."""
    code = f"{statement}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return set(json.loads(out.splitlines()[-1]))


@pytest.mark.parametrize(
    "statement", ["import floebreak", "import floebreak.cli", "import floebreak.__main__"]
)
def test_the_package_and_the_command_line_load_no_heavy_library(statement):
    loaded = {name.split(".")[0] for name in loaded_after(statement)}
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_a_run_loads_no_figure_netcdf_or_dask_library_before_it_draws():
    # a run imports the engine (numba, scipy.interpolate for the Nevel table) but neither matplotlib (the
    # figures import it when they are drawn) nor scipy.integrate (only the Nevel table's generation)
    loaded = loaded_after("import floebreak.app.run, floebreak.config.scenario")
    assert not {"matplotlib", "xarray", "dask", "scipy.integrate"} & loaded


def test_a_run_and_its_run_directory_load_no_arrow_compute_kernels(tmp_path):
    # pyarrow.compute (≈ 0.1 s) is what `Table.cast` imports; the Parquet writers attach the units and
    # append row groups without a cast where the types already agree (`floebreak.io.geoparquet.as_schema`)
    out = tmp_path / "out"
    scenario = Path(__file__).resolve().parents[1] / "examples" / "reference.toml"
    argv = ["floebreak", "run", str(scenario), "--quiet", "--out", str(out)]
    argv += ["--set", "field.length_m=40"]
    statement = f"import sys\nfrom floebreak import cli\nsys.argv = {argv!r}\n"
    statement += "try:\n    cli.main()\nexcept SystemExit:\n    pass"
    loaded = loaded_after(statement)
    assert (out / "contacts.parquet").is_file() and (out / "pieces.parquet").is_file()
    assert "pyarrow.parquet" in loaded and "pyarrow.compute" not in loaded
