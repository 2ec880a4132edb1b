"""floebreak: a ship's bow breaking sea-ice floes, and the cusps' propeller–ice loads.

The public API (docs/api.md): ``floebreak.run(scenario) -> Result`` runs a `Scenario` (a TOML file, a dict
or None for the reference scenario) without touching files, and ``Result.write(out)`` writes a run
directory; `generate_field`, `FloeField`, `Bow`/`get_hull`, `build_model` (profiles) and `simulate` are the
engine's parts for scripts; `register_mode` adds a failure mode; `propeller_analysis` (writes),
`analyse_propeller` (writes nothing), `run_study` and `run_voyage`: the propeller, study, voyage entry points;
`shaft_response` (with `load_shaft_line`, `write_shaft_analysis`) turns cusps into shaft torque. Everything
else is internal and may change.

The names below are imported on first use (PEP 562): ``import floebreak`` and the command line's light
commands (``floebreak --help``, ``schema``, ``observations``, ``report``) then do not load the engine's
libraries (numba, scipy.optimize, pyarrow), which take most of a start's time and memory.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from importlib.machinery import ModuleSpec
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # for type checkers and IDEs; at run time `__getattr__` imports them on first use
    from floebreak.app.inputs import load_shaft_line
    from floebreak.app.propeller import analyse_propeller, propeller_analysis
    from floebreak.app.run import Result, run
    from floebreak.app.shaft import write_shaft_analysis
    from floebreak.config.profiles import PROFILES, build_model
    from floebreak.config.scenario import Scenario
    from floebreak.engine.loop import Model, SimulationParams, SimulationResult, simulate
    from floebreak.errors import InputError
    from floebreak.failure import mode_names, register_mode, registered_mode, unregister_mode
    from floebreak.ice.field import FloeField
    from floebreak.ice.generation import generate_field
    from floebreak.ice.observations import Observation, get_observation, thesis_observations
    from floebreak.propeller.pipeline import PropellerResult
    from floebreak.shaft.analysis import shaft_response
    from floebreak.ship.bow import Bow
    from floebreak.ship.hulls import get_hull
    from floebreak.studies.aggregate import aggregate as aggregate_study
    from floebreak.studies.design import expand as expand_study
    from floebreak.studies.design import load_study, thesis_study
    from floebreak.studies.runner import run_study
    from floebreak.studies.voyage import prepare_voyage, run_voyage
    from floebreak.studies.voyage_log import read_voyage_log

# public name → the module that defines it ("module:name" where the public name differs)
_LAZY = {
    "aggregate_study": "floebreak.studies.aggregate:aggregate",
    "expand_study": "floebreak.studies.design:expand",
    "Bow": "floebreak.ship.bow",
    "FloeField": "floebreak.ice.field",
    "InputError": "floebreak.errors",
    "Model": "floebreak.engine.loop",
    "Observation": "floebreak.ice.observations",
    "PROFILES": "floebreak.config.profiles",
    "Result": "floebreak.app.run",
    "Scenario": "floebreak.config.scenario",
    "SimulationParams": "floebreak.engine.loop",
    "SimulationResult": "floebreak.engine.loop",
    "build_model": "floebreak.config.profiles",
    "generate_field": "floebreak.ice.generation",
    "get_hull": "floebreak.ship.hulls",
    "get_observation": "floebreak.ice.observations",
    "load_shaft_line": "floebreak.app.inputs",
    "load_study": "floebreak.studies.design",
    "mode_names": "floebreak.failure",
    "PropellerResult": "floebreak.propeller.pipeline",
    "analyse_propeller": "floebreak.app.propeller",
    "prepare_voyage": "floebreak.studies.voyage",
    "propeller_analysis": "floebreak.app.propeller",
    "read_voyage_log": "floebreak.studies.voyage_log",
    "register_mode": "floebreak.failure",
    "registered_mode": "floebreak.failure",
    "run": "floebreak.app.run",
    "run_study": "floebreak.studies.runner",
    "run_voyage": "floebreak.studies.voyage",
    "shaft_response": "floebreak.shaft.analysis",
    "simulate": "floebreak.engine.loop",
    "thesis_observations": "floebreak.ice.observations",
    "thesis_study": "floebreak.studies.design",
    "unregister_mode": "floebreak.failure",
    "write_shaft_analysis": "floebreak.app.shaft",
}

__all__ = [
    "PROFILES",
    "Bow",
    "FloeField",
    "InputError",
    "Model",
    "Observation",
    "PropellerResult",
    "Result",
    "Scenario",
    "SimulationParams",
    "SimulationResult",
    "__version__",
    "aggregate_study",
    "analyse_propeller",
    "build_model",
    "expand_study",
    "generate_field",
    "get_hull",
    "get_observation",
    "load_shaft_line",
    "load_study",
    "mode_names",
    "prepare_voyage",
    "propeller_analysis",
    "read_voyage_log",
    "register_mode",
    "registered_mode",
    "run",
    "run_study",
    "run_voyage",
    "shaft_response",
    "simulate",
    "thesis_observations",
    "thesis_study",
    "unregister_mode",
    "write_shaft_analysis",
]


def __getattr__(name: str):
    if name == "__version__":  # from the installed metadata: importlib.metadata takes ≈ 0.1 s to import
        from floebreak.io.provenance import floebreak_version

        globals()[name] = floebreak_version()
        return globals()[name]
    target = _LAZY.get(name)
    if target is None:
        raise AttributeError(f"module 'floebreak' has no attribute {name!r}")
    module, _, attribute = target.partition(":")
    value = getattr(importlib.import_module(module), attribute or name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY, "__version__"})


# module paths of the previous release → their new home; importing an old path warns and gives the new module
# (kept for one release, docs/architecture.md)
_MOVED = {
    "floebreak.simulation": "floebreak.engine.loop",
    "floebreak.simulation_events": "floebreak.engine.events",
    "floebreak.simulation_motion": "floebreak.engine.motion.dynamic",
    "floebreak.results": "floebreak.engine.records",
    "floebreak.scenario": "floebreak.config.scenario",
    "floebreak.profiles": "floebreak.config.profiles",
    "floebreak.report": "floebreak.output.report",
    "floebreak.replay": "floebreak.app.replay",
    "floebreak.cli_options": "floebreak.cli.options",
    "floebreak.app.run_directory": "floebreak.output.run_directory",
    "floebreak.app.poses": "floebreak.output.pose_file",
    "floebreak.app.surge": "floebreak.output.surge_file",
    "floebreak.app.figure_process": "floebreak.output.figure_process",
    "floebreak.io.propeller": "floebreak.output.propeller_files",
    "floebreak.propeller.fem": "floebreak.propeller.loads.fem",
    "floebreak.propeller.milling": "floebreak.propeller.loads.milling",
    "floebreak.io.shaft_files": "floebreak.output.shaft_files",
    "floebreak.io.field_files": "floebreak.output.field_files",
    "floebreak.io.run_files": "floebreak.output.run_files",
    "floebreak.io.voyage_log": "floebreak.studies.voyage_log",
    "floebreak.studies.cli": "floebreak.cli.study",
    "floebreak.studies.validate_cli": "floebreak.cli.validate",
    "floebreak.studies.statements": "floebreak.validation.statements",
    "floebreak.studies.chain_statements": "floebreak.validation.chain_statements",
    "floebreak.studies.scoreboard": "floebreak.validation.scoreboard",
    "floebreak.studies.validate": "floebreak.validation.validate",
    "floebreak.studies.validation_report": "floebreak.validation.validation_report",
    "floebreak.studies.sensitivity": "floebreak.validation.sensitivity",
    "floebreak.studies.inert": "floebreak.validation.inert",
}


class _MovedModules:
    """A `sys.meta_path` finder and loader: an old module path (`_MOVED`) is the module at its new path."""

    @staticmethod
    def find_spec(fullname: str, path=None, target=None) -> ModuleSpec | None:
        return ModuleSpec(fullname, _MovedModules) if fullname in _MOVED else None

    @staticmethod
    def create_module(spec: ModuleSpec):
        new = _MOVED[spec.name]
        warnings.warn(f"{spec.name} is deprecated; import {new}", DeprecationWarning, stacklevel=2)
        return importlib.import_module(new)

    @staticmethod
    def exec_module(module) -> None:
        pass  # the new module is already executed


if not any(finder is _MovedModules for finder in sys.meta_path):
    sys.meta_path.insert(0, _MovedModules)
