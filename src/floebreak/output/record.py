"""What the writers read of a finished run: `RunRecord`, a protocol that `floebreak.app.run.Result`
satisfies. The writers depend on this shape, not on the application layer that builds the result."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Protocol

import numpy as np

from floebreak.config.scenario import Scenario
from floebreak.engine.loop import SimulationResult
from floebreak.engine.records import ContactRecords
from floebreak.ice.field import FloeField
from floebreak.output.figure_process import FigureCall


class PoseTables(Protocol):
    """The moved pieces' poses of a run (`floebreak.output.pose_file.PoseRecorder`)."""

    @property
    def interval_steps(self) -> int: ...

    def tables(self) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]: ...


class RunRecord(Protocol):
    """A finished run as its writers read it: resolved scenario, simulation result, contact records (in
    memory, or spooled to `contacts_file`), summary, recorded poses, provenance and figure calls."""

    @property
    def scenario(self) -> Scenario: ...

    @property
    def simulation(self) -> SimulationResult: ...

    @property
    def contact_records(self) -> ContactRecords: ...

    @property
    def summary(self) -> dict[str, Any]: ...

    @property
    def contacts_file(self) -> Path | None: ...

    @property
    def poses(self) -> PoseTables | None: ...

    @property
    def contacts(self) -> dict[str, np.ndarray]: ...

    @property
    def field(self) -> FloeField: ...

    def provenance(self, kind: str) -> dict[str, Any]: ...

    def figure_call(self, key: str) -> FigureCall: ...
