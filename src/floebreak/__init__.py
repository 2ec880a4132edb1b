"""floebreak: a ship's bow breaking sea-ice floes, and the cusps' propeller–ice loads.

Public API (see the README and docs/): ``floebreak.run(scenario) -> Result`` runs a `Scenario` (a TOML
file, a dict or None for the reference scenario) without touching files; ``Result.write(out)`` writes a run
directory. ``floebreak.run`` and ``Result`` live in `floebreak.api`.

The names below are imported on first use (PEP 562): ``import floebreak`` and the command line's light
commands (``floebreak --help``, ``schema``, ``observations``, ``report``) then do not load the engine's
libraries (numba, scipy.optimize, pyarrow), which take most of a start's time and memory.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from floebreak.io.provenance import floebreak_version

if TYPE_CHECKING:  # for type checkers and IDEs; at run time `__getattr__` imports them on first use
    from floebreak.api import Result, run
    from floebreak.errors import InputError
    from floebreak.ice.field import FloeField
    from floebreak.ice.generation import generate_field
    from floebreak.ice.observations import Observation, get_observation, thesis_observations
    from floebreak.scenario import Scenario

__version__ = floebreak_version()

_LAZY = {
    "FloeField": "floebreak.ice.field",
    "InputError": "floebreak.errors",
    "Observation": "floebreak.ice.observations",
    "Result": "floebreak.api",
    "Scenario": "floebreak.scenario",
    "generate_field": "floebreak.ice.generation",
    "get_observation": "floebreak.ice.observations",
    "run": "floebreak.api",
    "thesis_observations": "floebreak.ice.observations",
}

__all__ = [
    "FloeField",
    "InputError",
    "Observation",
    "Result",
    "Scenario",
    "__version__",
    "generate_field",
    "get_observation",
    "run",
    "thesis_observations",
]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'floebreak' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})
