"""Failure modes behind one interface (`base.FailureMode`), a registry, and the dispatch policy.

Adding a mode: write one module with a frozen dataclass that has ``name`` and ``evaluate``, and add it to
`MODES` below.
"""

from __future__ import annotations

from types import MappingProxyType

from floebreak.failure.base import FailureContext, FailureInput, FailureMode, Fate, NewPiece, Outcome
from floebreak.failure.bending import Bending, BendingSettings
from floebreak.failure.cracking import Cracking, CrackingSettings
from floebreak.failure.dispatch import FailureModel, bow_region, resolve_failure
from floebreak.failure.local_cracking import LocalCracking
from floebreak.failure.none import NoFailure
from floebreak.failure.rotation import DirectRotation

MODES: MappingProxyType[str, type] = MappingProxyType(
    {
        NoFailure.name: NoFailure,
        DirectRotation.name: DirectRotation,
        Bending.name: Bending,
        Cracking.name: Cracking,
        LocalCracking.name: LocalCracking,
    }
)

__all__ = [
    "MODES",
    "Bending",
    "BendingSettings",
    "Cracking",
    "CrackingSettings",
    "DirectRotation",
    "FailureContext",
    "FailureInput",
    "FailureMode",
    "FailureModel",
    "Fate",
    "LocalCracking",
    "NewPiece",
    "NoFailure",
    "Outcome",
    "bow_region",
    "resolve_failure",
]
