"""Each extension point is one file plus its registration (docs/architecture.md, "Extension points"): a toy
load model, ice motion, run-directory writer and command, written outside the package in one module and
registered by an installed package's entry points (its dist-info on the path, as a pip install leaves it), are
used by a fresh floebreak process with no other change. Failure modes: tests/failure/test_plugins.py."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import floebreak

SRC = Path(floebreak.__file__).resolve().parents[1]
MODULE = "toy_extensions"

TOYS = '''
import numpy as np
import typer

from floebreak.propeller.cusps import cusp_geometry
from floebreak.propeller.spectra import pitch_label


class ConstantLoads:
    """Every cusp: 1 kN and -1 kN·m at the spec's pitch."""

    name = "constant"
    label = "constant loads"
    description = "one kN per cusp"
    rpm_text = "independent of the rpm"
    needs_tables = False
    places_on_blade = False

    def pitches(self, propeller, tables):
        return (float(propeller.pitch_percent),)

    def cusp_loads(self, columns, tables, options, propeller, speed_m_s, engaged=None):
        loads = cusp_geometry(columns, options["cusp_speed_m_s"])
        label = pitch_label(float(propeller.pitch_percent))
        n = loads["run_id"].size
        loads[f"force_n_{label}"] = np.full(n, 1e3)
        loads[f"torque_nm_{label}"] = np.full(n, -1e3)
        loads[f"beyond_table_{label}"] = np.zeros(n, dtype=bool)
        return loads


class Halt:
    """Ice that does not move and stops the ship 5 m into the transit."""

    moves = False

    def __init__(self, run):
        self.last_contact_x_m = {}
        self.stuck = False

    def advance_to(self, bow_x):
        self.stuck = bow_x > 5.0

    def flush(self, pids=None):
        pass

    def failure_contact(self, pid, contact):
        return contact

    def contact(self, pid, contact, bow_x):
        pass

    def leave(self, pid):
        pass

    def broken(self, pid, floe_children):
        pass

    def outputs(self, n_steps):
        return {}


def write_cusp_count(record, folder):
    (folder / "cusp_count.txt").write_text(f"{len(record.cusps['area_m2'])}\\n", encoding="utf-8")


def register(app: typer.Typer) -> None:
    @app.command("hello")
    def hello() -> None:
        """Say hello from a plug-in."""
        print("hello from a plug-in command")
'''

ENTRY_POINTS = f"""[floebreak.load_models]
constant = {MODULE}:ConstantLoads

[floebreak.ice_motions]
halt = {MODULE}:Halt

[floebreak.writers]
cusp_count = {MODULE}:write_cusp_count

[floebreak.commands]
toy = {MODULE}
"""

# one floe ahead of the bow: a short run
FLOE = {"field": {"floes": [{"x_m": 12.0, "y_m": 0.0, "diameter_m": 10.0}]}, "ice": {"thickness_m": 1.0}}


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict[str, str]:
    """The environment of a process that has the toy package installed beside floebreak."""
    root = tmp_path_factory.mktemp("site")
    (root / f"{MODULE}.py").write_text(TOYS, encoding="utf-8")
    info = root / f"{MODULE}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: toy-extensions\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(ENTRY_POINTS, encoding="utf-8")
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), str(SRC)])}


def _python(code: str, env: dict[str, str], cwd: Path) -> str:
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        env=env,
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_a_load_model_is_one_class_and_an_entry_point(installed, tmp_path):
    code = """
        import numpy as np
        from floebreak.propeller.loads import load_model_names
        from floebreak.propeller.pipeline import analyse_cusp_loads

        n = 3
        cusps = {"run_id": np.array(["a"] * n), "volume_m3": np.full(n, 2.0), "area_m2": np.full(n, 2.0)}
        cusps |= {"bbox_length_m": np.full(n, 2.0), "bbox_width_m": np.full(n, 1.0)}
        cusps["thickness_m"] = np.full(n, 1.0)
        result = analyse_cusp_loads(cusps, load_model="constant", transport="all")
        force = [v for k, v in result.loads.items() if k.startswith("force_n_")]
        print(load_model_names()[-1], result.summary["load_model"]["description"], float(np.nanmax(force)))
    """
    assert _python(code, installed, tmp_path).split() == ["constant", "one", "kN", "per", "cusp", "1000.0"]


def test_an_ice_motion_is_one_class_and_an_entry_point(installed, tmp_path):
    code = f"""
        import floebreak
        scenario = {FLOE!r}
        static = floebreak.run(scenario)
        halted = floebreak.run({{**scenario, "simulation": {{"ice_motion": "halt"}}}})
        print(static.simulation.n_steps, halted.simulation.n_steps, halted.scenario.simulation.ice_motion)
    """
    static_steps, halted_steps, name = _python(code, installed, tmp_path).split()
    # the ship stops after the first search beyond 5 m (steps of 0.25 m from 0 m): 21 searches, 0 … 5 m
    assert name == "halt" and int(halted_steps) == 21 < int(static_steps)


def test_a_writer_is_one_function_and_an_entry_point(installed, tmp_path):
    code = f"""
        import floebreak
        result = floebreak.run({FLOE!r})
        result.write("out", report=False, figures=False)
        print(len(result.cusps["area_m2"]))
    """
    cusps = _python(code, installed, tmp_path).strip()
    assert (tmp_path / "out" / "cusp_count.txt").read_text(encoding="utf-8") == f"{cusps}\n"
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert "cusp_count.txt" in summary["files"]  # checksummed with the run's other files


def test_a_command_is_one_module_and_an_entry_point(installed, tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", "hello"],
        env=installed,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "hello from a plug-in command\n"
    listed = subprocess.run(
        [sys.executable, "-m", "floebreak", "--help"],
        env=installed,
        capture_output=True,
        text=True,
        timeout=300,
    ).stdout
    assert "hello" in listed
