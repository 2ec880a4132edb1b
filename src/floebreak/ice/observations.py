"""Ship-based ice observations (thesis §2.1, Table 1).

An `Observation` is what an ice observer logs over ten minutes: mean concentration, mean thickness and
the share of floes per equivalent-diameter class. Thesis Table 1 (expedition Agu19/20) ships as package
data, addressable by a key such as ``"2019-12-18T20:20"`` (date and start time of the slot).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from importlib import resources

import numpy as np

from floebreak.errors import InputError, require_range

PERCENT_SUM_TOLERANCE = 0.5  # percentages must sum to 100 ± this


@dataclass(frozen=True)
class Observation:
    """One ice observation. Concentration is a fraction in (0, 1]; percentages are per diameter class.

    Validated on construction: concentration in (0, 1], thickness > 0, diameters > 0 and distinct,
    percentages ≥ 0 summing to 100 ± 0.5. Classes with 0 % are dropped.
    """

    concentration: float
    mean_thickness_m: float
    diameter_classes_m: tuple[float, ...]
    percentages: tuple[float, ...]
    key: str = "user"
    description: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        require_range("concentration", self.concentration, low=0.0, high=1.0)
        require_range("mean_thickness_m", self.mean_thickness_m, low=0.0, unit="m")
        diameters = tuple(float(d) for d in self.diameter_classes_m)
        percentages = tuple(float(p) for p in self.percentages)
        if len(diameters) != len(percentages) or not diameters:
            raise InputError(
                "percentages",
                f"{len(percentages)} percentages for {len(diameters)} diameter classes",
                allowed="one percentage per diameter class, at least one class",
            )
        for d in diameters:
            require_range("diameter_classes_m", d, low=0.0, unit="m")
        for p in percentages:
            require_range("percentages", p, low=0.0, high=100.0, low_inclusive=True, unit="%")
        total = sum(percentages)
        if abs(total - 100.0) > PERCENT_SUM_TOLERANCE:
            raise InputError(
                "percentages",
                f"sum to {total:g} %",
                value=total,
                allowed=f"100 ± {PERCENT_SUM_TOLERANCE:g} %",
            )
        kept = [(d, p) for d, p in zip(diameters, percentages, strict=True) if p > 0.0]
        if len({d for d, _ in kept}) != len(kept):
            raise InputError("diameter_classes_m", "contains duplicates", allowed="distinct diameters")
        object.__setattr__(self, "diameter_classes_m", tuple(d for d, _ in kept))
        object.__setattr__(self, "percentages", tuple(p for _, p in kept))
        object.__setattr__(self, "concentration", float(self.concentration))
        object.__setattr__(self, "mean_thickness_m", float(self.mean_thickness_m))

    @property
    def fractions(self) -> np.ndarray:
        """Count fractions per class, normalised to sum exactly to 1."""
        p = np.asarray(self.percentages, dtype=float)
        return p / p.sum()

    @property
    def largest_diameter_m(self) -> float:
        return max(self.diameter_classes_m)


def _read_table() -> list[dict[str, str]]:
    text = resources.files("floebreak.data").joinpath("observations_agu1920.csv").read_text("utf-8")
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    return list(csv.DictReader(io.StringIO("\n".join(lines))))


def thesis_observations() -> dict[str, Observation]:
    """Thesis Table 1 as a dict key → Observation, in table order."""
    observations: dict[str, Observation] = {}
    for row in _read_table():
        diameters, percentages = [], []
        for name, value in row.items():
            if name.startswith("pct_d"):
                diameters.append(float(name.removeprefix("pct_d").removesuffix("m")))
                percentages.append(float(value))
        observations[row["key"]] = Observation(
            concentration=float(row["concentration_pct"]) / 100.0,
            mean_thickness_m=float(row["mean_thickness_m"]),
            diameter_classes_m=tuple(diameters),
            percentages=tuple(percentages),
            key=row["key"],
            description=f"Agu19/20 {row['date']} {row['start']}–{row['end']} (thesis Table 1)",
        )
    return observations


def get_observation(key: str) -> Observation:
    """Thesis Table 1 observation for `key`, e.g. ``"2019-12-18T20:20"``; InputError lists the keys."""
    table = thesis_observations()
    if key not in table:
        raise InputError("observation", f"unknown key {key!r}", value=key, allowed=", ".join(table))
    return table[key]
