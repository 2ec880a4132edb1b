"""Failure modes behind one interface (`base.FailureMode`), their registry, and the dispatch policy.

Adding a mode: one module (or a test file, or a notebook) with a frozen dataclass that has ``name`` and
``evaluate``, its settings dataclass, and a call to `register_mode` (see `registry`); a scenario then
names it in ``[failure.policy]`` and sets it in ``[failure.<name>]``. The built-in modes register
themselves when this package is imported.
"""

from __future__ import annotations

from floebreak.failure.base import FailureContext, FailureInput, FailureMode, Fate, NewPiece, Outcome, Status
from floebreak.failure.bending import Bending, BendingSettings
from floebreak.failure.cracking import Cracking, CrackingSettings
from floebreak.failure.dispatch import (
    BOW_REGIONS,
    FAILURE_CLASSES,
    FailureModel,
    bow_region,
    check_policy,
    complete_policy,
    default_policy,
    normalise_policy,
    resolve_failure,
)
from floebreak.failure.local_cracking import LocalCracking
from floebreak.failure.none import NoFailure
from floebreak.failure.registry import (
    DISPATCH_KEYS,
    ModeSpec,
    get_mode,
    mode_names,
    register_mode,
    registered_mode,
    unregister_mode,
)
from floebreak.failure.rotation import DirectRotation

__all__ = [
    "BOW_REGIONS",
    "DISPATCH_KEYS",
    "FAILURE_CLASSES",
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
    "ModeSpec",
    "NewPiece",
    "NoFailure",
    "Outcome",
    "Status",
    "bow_region",
    "check_policy",
    "complete_policy",
    "default_policy",
    "get_mode",
    "mode_names",
    "normalise_policy",
    "register_mode",
    "registered_mode",
    "resolve_failure",
    "unregister_mode",
]
