"""Failure modes behind one interface (`base.FailureMode`), a registry, and the dispatch policy.

Adding a mode: write one module with a frozen dataclass that has ``name`` and ``evaluate``, and add it to
`MODES` below.
"""

from __future__ import annotations

from types import MappingProxyType

from floebreak.failure.base import FailureContext, FailureInput, FailureMode, Fate, NewPiece, Outcome
from floebreak.failure.dispatch import FailureModel, bow_region, resolve_failure
from floebreak.failure.none import NoFailure
from floebreak.failure.rotation import DirectRotation

MODES: MappingProxyType[str, type] = MappingProxyType(
    {
        NoFailure.name: NoFailure,
        DirectRotation.name: DirectRotation,
    }
)

__all__ = [
    "MODES",
    "DirectRotation",
    "FailureContext",
    "FailureInput",
    "FailureMode",
    "FailureModel",
    "Fate",
    "NewPiece",
    "NoFailure",
    "Outcome",
    "bow_region",
    "resolve_failure",
]
