"""floebreak: a ship's bow breaking sea-ice floes, and the cusps' propeller–ice loads.

Public API (see the README and docs/):
"""

from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import Observation, get_observation, thesis_observations
from floebreak.io.provenance import floebreak_version

__version__ = floebreak_version()

__all__ = [
    "FloeField",
    "InputError",
    "Observation",
    "__version__",
    "generate_field",
    "get_observation",
    "thesis_observations",
]
