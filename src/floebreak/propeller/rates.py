"""Rates of propeller ice loads: counts per hour in ice and per km of transit, and exceedance tables.

The thesis gives normalised densities only (Figs. 32–33). A designer needs a time base: with the ship speed
v [m/s], the transit distance L [m] over which the cusps were produced, the fraction f of cusps that reach a
propeller and the number of propellers n_p over which they are shared (the thesis pools both Agulhas II
propellers, §6.1), one propeller sees

    rate per hour = N_cusps · f / n_p / (L / v / 3600 s),    rate per km = N_cusps · f / n_p / (L / 1000 m).

f is an explicit override (`propeller.fraction_reaching`); without it (None) the cusps that reach are chosen
by the transport model or are all of them (thesis §6.2), and each of those gives 1 / n_p loads on one
propeller (`floebreak.propeller.load_models`). Several runs are pooled by summing their counts and their
transit distances (a time-weighted mean).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak import constants as c
from floebreak.errors import InputError, require_range
from floebreak.ship.agulhas_ii import AGULHAS_II

SECONDS_PER_HOUR = 3600.0


@dataclass(frozen=True)
class RateBasis:
    """Time base of the rates: ship speed [m/s], fraction of cusps reaching a propeller (an override; None:
    not stated), propellers sharing them. Defaults: 3 m/s (thesis §6.3), None, 2 (Agulhas II, thesis §6.1)."""

    speed_m_s: float = c.SHIP_SPEED_IN_ICE_M_S
    fraction_reaching: float | None = None
    n_propellers: int = AGULHAS_II.propeller_count

    def __post_init__(self) -> None:
        require_range(
            "ship.speed_m_s",
            self.speed_m_s,
            low=c.SHIP_SPEED_RANGE_M_S[0],
            high=c.SHIP_SPEED_RANGE_M_S[1],
            unit="m/s",
        )
        if self.fraction_reaching is not None:
            require_range("propeller.fraction_reaching", self.fraction_reaching, low=0.0, high=1.0)
        if (
            isinstance(self.n_propellers, bool)
            or int(self.n_propellers) != self.n_propellers
            or not c.PROPELLER_COUNT_RANGE[0] <= self.n_propellers <= c.PROPELLER_COUNT_RANGE[1]
        ):
            allowed = "an integer in [{}, {}]".format(*c.PROPELLER_COUNT_RANGE)
            raise InputError(
                "propeller.count",
                f"{self.n_propellers!r} is not {allowed}",
                value=self.n_propellers,
                allowed=allowed,
            )

    @property
    def share_per_propeller(self) -> float:
        """Expected loads on one propeller per loaded cusp: f / n_p (1 / n_p without an override: then only
        the cusps that reach carry loads)."""
        fraction = 1.0 if self.fraction_reaching is None else self.fraction_reaching
        return fraction / self.n_propellers

    def hours(self, transit_m: float) -> float:
        """Time in ice [h] to sail `transit_m` at the ship speed."""
        return transit_m / self.speed_m_s / SECONDS_PER_HOUR

    def as_dict(self) -> dict:
        return {
            "speed_m_s": self.speed_m_s,
            "fraction_reaching": self.fraction_reaching,
            "n_propellers": self.n_propellers,
        }


@dataclass(frozen=True)
class RunExposure:
    """What one run's cusps stand for: the transit distance [m] in which they were produced and the rate
    basis (speed, fraction reaching, propellers). A voyage period is one exposure like a run."""

    transit_m: float
    basis: RateBasis = RateBasis()

    def __post_init__(self) -> None:
        require_range("transit_m", self.transit_m, low=0.0, unit="m")

    @property
    def hours(self) -> float:
        return self.basis.hours(self.transit_m)

    @property
    def km(self) -> float:
        return self.transit_m / 1e3


def check_exposures(exposures, runs) -> dict[str, RunExposure]:
    """The exposures, checked: a RunExposure for every run with cusps (InputError naming the run that has
    none). Runs without cusps may have one too: their hours and km count (a run in which no cusp reached
    the propellers still took its time)."""
    for run in runs:
        if not isinstance(exposures.get(run), RunExposure):
            raise InputError("exposure", f"no RunExposure for run {run!r}", allowed="a RunExposure per run")
    for run, item in exposures.items():
        if not isinstance(item, RunExposure):
            raise InputError("exposure", f"{run!r}: {type(item).__name__} is not a RunExposure")
    return dict(exposures)


def weighted_exceedance(values, weights, levels) -> np.ndarray:
    """Σ of the weights of the finite |values| ≥ each level (weights: loads per cusp on one propeller)."""
    values = np.abs(np.asarray(values, dtype=float))
    keep = np.isfinite(values)
    order = np.argsort(values[keep])
    v, w = values[keep][order], np.asarray(weights, dtype=float)[keep][order]
    tail = np.r_[np.cumsum(w[::-1])[::-1], 0.0]
    return tail[np.searchsorted(v, np.asarray(levels, dtype=float), side="left")]
