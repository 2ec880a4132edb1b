"""floebreak: a ship's bow breaking sea-ice floes, and the cusps' propeller–ice loads.

Public API (see the README and docs/): ``floebreak.run(scenario) -> Result`` runs a `Scenario` (a TOML
file, a dict or None for the reference scenario) without touching files; ``Result.write(out)`` writes a run
directory.

Note: ``floebreak.run`` is the function; the module of the same name is ``sys.modules["floebreak.run"]``.
"""

from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import Observation, get_observation, thesis_observations
from floebreak.io.provenance import floebreak_version
from floebreak.run import Result, run
from floebreak.scenario import Scenario

__version__ = floebreak_version()

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
