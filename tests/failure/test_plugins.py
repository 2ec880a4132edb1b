"""Failure modes that load everywhere: the toy `Halving` mode of test_registry.py as a plug-in
module named by a scenario (``[failure] plugins``) — from the command line and in a 2-worker study, whose
spawned workers never saw the parent's registration — and as an installed package's entry point
(``floebreak.failure_modes``); a bad plug-in is an InputError naming ``failure.plugins`` and the module."""

from __future__ import annotations

import inspect
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import floebreak
from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.failure import registry
from floebreak.studies.design import StudySpec, expand
from floebreak.studies.executors import ProcessPoolExecutor
from floebreak.studies.runner import run_study

from .test_registry import SCENARIO, Halving, HalvingSettings

SRC = Path(floebreak.__file__).resolve().parents[1]
MODULE = "halving_plugin"

# the toy mode's own source, as a module that registers it when imported
PLUGIN_SOURCE = "\n".join(
    [
        "from dataclasses import dataclass",
        "from typing import ClassVar",
        "import shapely",
        "import floebreak",
        "from floebreak.failure import Fate, NewPiece, Outcome, Status",
        inspect.getsource(HalvingSettings),
        inspect.getsource(Halving),
        "floebreak.register_mode(Halving, settings=HalvingSettings)",
    ]
)
PLUGGED = f'[failure]\nplugins = ["{MODULE}"]\n' + SCENARIO


@pytest.fixture
def plugin_dir(tmp_path, monkeypatch):
    """A directory on the path (this process's and its children's) holding the plug-in module; whatever it
    registered here is removed afterwards."""
    (tmp_path / f"{MODULE}.py").write_text(PLUGIN_SOURCE, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), str(SRC)]))
    yield tmp_path
    for name in ("halving", "shadow"):
        if name in registry._MODES:
            floebreak.unregister_mode(name)
    for module in [m for m in sys.modules if m.startswith(("halving_plugin", "bad_plugin"))]:
        del sys.modules[module]
    assert "halving" not in floebreak.mode_names()


def test_the_plugin_runs_from_the_command_line(plugin_dir):
    """`floebreak run` in a fresh process: the scenario's plug-in registers the mode before the policy that
    names it is read."""
    (plugin_dir / "halving.toml").write_text(PLUGGED, encoding="utf-8")
    out = plugin_dir / "run"
    command = [sys.executable, "-m", "floebreak", "run", "halving.toml", "--out", str(out), "--quiet"]
    done = subprocess.run(command, cwd=plugin_dir, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    modes = json.loads((out / "summary.json").read_text(encoding="utf-8"))["breaks_by_mode"]
    assert modes.get("halving", 0) > 0 and set(modes) <= {"halving", "rotation"}
    # the resolved scenario keeps the plug-in, so the run directory reruns on its own
    assert MODULE in (out / "scenario.resolved.toml").read_text(encoding="utf-8")


def test_the_plugin_runs_in_a_two_worker_study(plugin_dir):
    """Spawned pool workers start without the parent's registry: each resolves the plug-in when it reads its
    run's scenario (a dict), and runs the same as the parent would."""
    spec = StudySpec(name="plugged", n_fields=2, base=Scenario.from_toml_text(PLUGGED).to_dict())
    runs, members = expand(spec)
    pool = ProcessPoolExecutor(2)
    try:
        state = run_study(spec, runs, members, plugin_dir / "study", pool, run_figures=False)
    finally:
        pool.close()
    assert (state.done, state.failed) == (2, 0), state.failures
    serial = floebreak.run(Scenario.from_toml_text(PLUGGED)).simulation.breaks_by_mode
    for run in runs:
        summary = json.loads((plugin_dir / "study" / "runs" / run.run_name / "summary.json").read_text())
        assert summary["breaks_by_mode"] == dict(sorted(serial.items())) and serial["halving"] > 0


def test_a_plugin_is_resolved_once_and_again_after_it_was_unregistered(plugin_dir):
    assert registry.resolve_plugins([MODULE, MODULE]) == ("halving", "halving")
    assert floebreak.mode_names().count("halving") == 1
    floebreak.unregister_mode("halving")
    # read again, the module (imported before) is run again and registers its mode anew
    assert Scenario.from_toml_text(PLUGGED).failure.plugins == [MODULE]
    assert "halving" in floebreak.mode_names()


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (None, "No module named 'bad_plugin'"),
        ("X = 1\n", "registers no failure mode"),
        ("raise RuntimeError('broken')\n", "RuntimeError: broken"),
        # a name clash with a built-in mode; the mode registered before the clash is removed
        (
            "import floebreak\nclass Shadow:\n    name = 'shadow'\n    def evaluate(self, inp, ctx): ...\n"
            "class Rotation(Shadow):\n    name = 'rotation'\n"
            "floebreak.register_mode(Shadow)\nfloebreak.register_mode(Rotation)\n",
            "'rotation' is taken",
        ),
    ],
)
def test_a_bad_plugin_is_an_input_error_naming_the_key_and_the_module(plugin_dir, source, message):
    if source is not None:
        (plugin_dir / "bad_plugin.py").write_text(source, encoding="utf-8")
    with pytest.raises(InputError) as info:
        Scenario.from_toml_text('[failure]\nplugins = ["bad_plugin"]\n')
    assert info.value.field == "failure.plugins"
    assert "'bad_plugin'" in str(info.value) and message in str(info.value)
    assert "shadow" not in floebreak.mode_names()


@pytest.mark.parametrize("plugins", ['"halving_plugin"', '["halving-plugin"]', "[1]"])
def test_plugins_must_be_a_list_of_module_names(plugins):
    with pytest.raises(InputError) as info:
        Scenario.from_toml_text(f"[failure]\nplugins = {plugins}\n")
    assert info.value.field == "failure.plugins"


def test_a_bad_plugin_exits_with_code_2_and_writes_nothing(tmp_path, cli):
    (tmp_path / "s.toml").write_text('[failure]\nplugins = ["no_such_plugin_module"]\n', encoding="utf-8")
    code, _, err = cli("run", tmp_path / "s.toml", "--out", tmp_path / "out", "--quiet")
    assert code == 2 and "failure.plugins" in err and "no_such_plugin_module" in err
    assert not (tmp_path / "out").exists()


ENTRY_POINTS = f"[floebreak.failure_modes]\nhalving = {MODULE}:Halving\n"

CHECK_ENTRY_POINT = """
from floebreak.failure import get_mode
from floebreak.config.scenario import Scenario
spec = get_mode("halving")
print(spec.settings.__name__, Scenario.from_toml_text({scenario!r}).failure.mode_tables())
"""


def test_an_installed_package_registers_its_mode_by_entry_point(tmp_path):
    """A package installed beside floebreak (its dist-info on the path) names its mode class in the entry
    point group: in a fresh process the mode exists with its settings, with no import or plug-in key."""
    module = PLUGIN_SOURCE.replace("floebreak.register_mode(Halving, settings=HalvingSettings)", "")
    (tmp_path / f"{MODULE}.py").write_text(module, encoding="utf-8")
    info = tmp_path / "halving_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: halving-plugin\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(ENTRY_POINTS, encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(SRC)])}
    code = textwrap.dedent(CHECK_ENTRY_POINT).format(scenario=SCENARIO)
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split(maxsplit=1) == ["HalvingSettings", "{'halving': {'min_area_m2': 2.0}}\n"]
