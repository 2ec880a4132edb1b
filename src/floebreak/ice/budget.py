"""The cost bounds a field must fit before any work starts: a generated field's floe count (from the
observation and the area, `floebreak.ice.generation.floe_counts`) times the measured cost per floe must stay
within the run's memory and time bounds, and a field read from a file may not hold a floe larger than the
largest observed class nor make the bow travel farther than the longest generated field.

The costs per floe are measured (the `circles` generator, one core, 10 000–190 000 floes of the observation
2019-12-18T20:20): ≈ 0.5 ms and 5–8 kB of peak memory per floe placed; the larger figure is taken. The
memory bound is the run's own: ``simulation.max_pieces`` × ≈ 1.2 kB per piece (`floebreak.engine.loop`),
1.2 GB by default, so ≈ 150 000 floes; the time bound is the run's ``simulation.max_wall_s`` (default 600 s
+ 60 s per km of transit), or 600 s for ``floebreak field``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from floebreak.errors import InputError

GENERATION_SECONDS_PER_FLOE = 5.0e-4  # measured: 0.50 ms per floe placed (10 000–190 000 floes)
GENERATION_BYTES_PER_FLOE = 8.0e3  # measured: 4.4–8 kB of peak memory per floe placed; the larger taken
RUN_BYTES_PER_PIECE = 1.2e3  # the run's memory per piece (`floebreak.engine.loop.MAX_PIECES_DEFAULT`)
DEFAULT_MAX_PIECES = 1_000_000  # `floebreak.engine.loop.MAX_PIECES_DEFAULT`
DEFAULT_TIME_BOUND_S = 600.0  # `floebreak.engine.loop.WALL_S_BASE`
TIME_BOUND_S_PER_KM = 60.0  # `floebreak.engine.loop.WALL_S_PER_KM`
MAX_TRANSIT_M = 1.0e6  # the longest generated field (field.length_m's range): the farthest a bow travels
MAX_FLOE_SIZE_M = 1.0e4  # the largest diameter class an observation may give (field.diameter_classes_m)


@dataclass(frozen=True)
class FieldBudget:
    """The memory [bytes] and time [s] bounds a field's generation must fit, the keys that set them and the
    key(s) of the field's size, for the error message."""

    memory_bytes: float = DEFAULT_MAX_PIECES * RUN_BYTES_PER_PIECE
    time_s: float = DEFAULT_TIME_BOUND_S
    memory_key: str = "the memory bound of a run (1 000 000 pieces × 1.2 kB)"
    time_key: str = "the time bound of a run (600 s)"
    size_keys: str = "length_m/width_m"
    raise_hint: str = ""

    @classmethod
    def of_run(cls, max_pieces: int | None, max_wall_s: float | None, length_m: float) -> FieldBudget:
        """A run's bounds: its ``simulation.max_pieces`` and ``simulation.max_wall_s`` (or their defaults)."""
        # a small piece budget bounds the run's count (its own check), not the placement's memory: the
        # memory bound is never below the default's
        pieces = max(max_pieces or DEFAULT_MAX_PIECES, DEFAULT_MAX_PIECES)
        wall = (
            max_wall_s
            if max_wall_s is not None
            else DEFAULT_TIME_BOUND_S + TIME_BOUND_S_PER_KM * length_m / 1e3
        )
        return cls(
            memory_bytes=pieces * RUN_BYTES_PER_PIECE,
            time_s=wall,
            memory_key=f"simulation.max_pieces ({pieces:,} pieces × 1.2 kB)",
            time_key=f"simulation.max_wall_s ({wall:g} s)",
            size_keys="field.length_m/field.width_m",
            raise_hint="raise simulation.max_pieces (memory) or simulation.max_wall_s (time)",
        )


def check_generation_budget(n_floes: int, length_m: float, width_m: float, budget: FieldBudget) -> None:
    """InputError naming the size keys and the bound passed when placing `n_floes` floes would need more
    memory or time than `budget` allows (checked before anything is placed)."""
    need_bytes = n_floes * GENERATION_BYTES_PER_FLOE
    need_s = n_floes * GENERATION_SECONDS_PER_FLOE
    most = int(
        min(budget.memory_bytes / GENERATION_BYTES_PER_FLOE, budget.time_s / GENERATION_SECONDS_PER_FLOE)
    )
    if need_bytes > budget.memory_bytes:
        cost = (
            f"≈ {need_bytes / 1e9:.3g} GB, more than {budget.memory_key}: {budget.memory_bytes / 1e9:.3g} GB"
        )
    elif need_s > budget.time_s:
        cost = f"≈ {need_s:.3g} s, more than {budget.time_key}"
    else:
        return
    # the example shrinks the longer side (the floe count scales with the area), or both if it would become
    # the shorter
    shrink = most / max(n_floes, 1)
    long, short = max(length_m, width_m), min(length_m, width_m)
    if long * shrink >= short:
        long *= shrink
    else:
        long, short = long * shrink**0.5, short * shrink**0.5
    sides = (long, short) if length_m >= width_m else (short, long)
    example = f"{sides[0]:.4g} m × {sides[1]:.4g} m"
    raise InputError(
        budget.size_keys,
        f"a {length_m:g} m × {width_m:g} m field of this observation holds ≈ {n_floes:,} floes; placing them "
        f"takes {cost} (measured ≈ {GENERATION_BYTES_PER_FLOE / 1e3:g} kB and "
        f"{GENERATION_SECONDS_PER_FLOE * 1e3:g} ms per floe)",
        value=n_floes,
        allowed=f"≤ {most:,} floes, e.g. {example}"
        + (f", or {budget.raise_hint}" if budget.raise_hint else ""),
    )


def check_floe_sizes(polygons: np.ndarray, key: str) -> None:
    """InputError naming `key` (``field.file: 'f.parquet'``) and the row (counted from 1) of the first floe
    larger than `MAX_FLOE_SIZE_M` across: breaking it would cost as much as a field of that size."""
    bounds = shapely.bounds(polygons).reshape(-1, 4)
    size = np.maximum(bounds[:, 2] - bounds[:, 0], bounds[:, 3] - bounds[:, 1])
    big = np.flatnonzero(size > MAX_FLOE_SIZE_M)
    if big.size:
        i = int(big[0])
        raise InputError(
            f"{key}, row {i + 1}, column 'geometry'",
            f"a floe {size[i]:.6g} m across, larger than the largest floe class ({MAX_FLOE_SIZE_M:g} m)",
            value=float(size[i]),
            allowed=f"floes at most {MAX_FLOE_SIZE_M:g} m across",
        )


def check_transit_length(
    polygons: np.ndarray,
    domain_m: tuple[float, float, float, float],
    source: str | None,
    x_start_m: float,
    x_end_m: float,
    x_end_given: bool,
) -> None:
    """InputError when the bow would travel from `x_start_m` to `x_end_m` farther than `MAX_TRANSIT_M` (the
    longest generated field), naming what sets the end: ``ship.x_end_m``, or the field's farthest floe (its
    row, counted from 1, in file order) or its domain."""
    transit = x_end_m - x_start_m
    if transit <= MAX_TRANSIT_M:
        return
    name = "the field" if source is None else f"field.file: {str(source)!r}"
    x_max = shapely.bounds(polygons).reshape(-1, 4)[:, 2] if len(polygons) else np.empty(0)
    if x_end_given:
        key, what = "ship.x_end_m", f"ship.x_end_m = {x_end_m:.6g} m"
    elif x_max.size and x_max.max() - x_start_m > MAX_TRANSIT_M:
        row = int(np.argmax(x_max))
        key, what = f"{name}, row {row + 1}", f"its floe in row {row + 1} reaches x = {x_max[row]:.6g} m"
    else:
        key, what = f"{name}, domain_m", f"its domain reaches x = {domain_m[2]:.6g} m"
    raise InputError(
        key,
        f"{what}: the bow would travel {transit:.6g} m from x = {x_start_m:.6g} m, farther than the longest "
        f"transit ({MAX_TRANSIT_M:g} m, the longest field)",
        value=transit,
        allowed=f"a transit of at most {MAX_TRANSIT_M:g} m: floes in the field frame (the bow's stem tip at "
        "the origin at the start), or a nearer ship.x_end_m",
    )
