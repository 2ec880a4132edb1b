"""Random floe fields from an ice observation (thesis §2.1, errata 1–5).

1. `floe_counts`: number of floes per diameter class. The total count m = ⌈c·A_field / Ā⌉ with the mean floe
   area Ā = Σ p_k · f π d_k² (f = 1/4 by default, the thesis prints 1/2: erratum 1); the per-class counts
   p_k·m are rounded by largest remainder so they are integers summing to m (erratum 5).
2. Placement, by one of the registered generators:
   * ``circles`` (default): circular floes placed by soft-disk relaxation (`floebreak.ice.packing`), with the
     thesis' clustering tendency. Scales to ≥ 10 000 floes. Dense targets the relaxation cannot reach fall
     back to largest-first corner insertion (`corner_circles`); the metadata key ``placement`` says which
     placed the field (``relax`` or ``corner``).
   * ``sqp``: the thesis' own SQP formulation (errata 2–4 fixed); a reference for small fields (≲ 200 floes).
   * ``voronoi``: angular floes — Voronoi cells of random seeds, each shrunk about its centroid so the field
     reaches the target concentration exactly (any concentration up to 100 %). The count per class is kept
     only as the number of cells; the cells' sizes follow the Voronoi statistics, not the observed classes
     (each floe's `diameter_class_m` is the observed class nearest its equivalent diameter).
3. Check: the generated concentration must lie within ±1 percentage point of the target, otherwise
   `ConcentrationError` (an InputError) names the highest concentration reached.

Circles become regular polygons with `CIRCLE_POLYGON_VERTICES` corners inscribed in the circle, so the
polygons never overlap when the circles do not; their area is 0.9984 of the circle's.

The field occupies x ∈ [0, L], y ∈ [−W/2, W/2] (ship frame: the bow tip starts at the origin).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import InputError, require_range
from floebreak.ice.budget import FieldBudget, check_generation_budget
from floebreak.ice.field import FloeField, circle_polygons
from floebreak.ice.observations import Observation
from floebreak.ice.packing import Packing, relax_circles, sqp_circles
from floebreak.ice.thickness import bounded_random_thickness_m

CONCENTRATION_TOLERANCE = 0.01  # ±1 percentage point (issue requirement)
SQP_MAX_FLOES = 400  # beyond this SLSQP's dense O(n²) constraint Jacobian is impractical


class ConcentrationError(InputError):
    """The user's concentration `target` (a fraction) could not be reached by `generator` in a field of
    `size_m` (length, width). `cover` is the highest share of the field the placed circles covered and
    `reason` says what it is; `reached` is that cover as a concentration in the user's units.

    A concentration counts each floe as `floe_area_factor`·π d² (thesis §2.1, erratum 1) while the floe is a
    circle of diameter d (0.25·π d²): with another factor than 0.25 the circles must cover
    target·0.25/factor of the field, and the message says so, in the user's units, with both fixes."""

    def __init__(
        self,
        target: float,
        cover: float,
        reason: str,
        generator: str,
        size_m: tuple[float, float],
        floe_area_factor: float = c.FLOE_AREA_FACTOR,
    ):
        per_cover = floe_area_factor / c.FLOE_AREA_FACTOR  # concentration per unit of circle cover
        self.cover = cover
        self.reached = cover * per_cover
        field = f"this {size_m[0]:g} m × {size_m[1]:g} m field"
        other = "or generator 'voronoi', which reaches any concentration up to 1"
        if per_cover == 1.0:
            message = (
                f"{target:g} ({100 * target:g} %) not reached by {generator!r} in {field}: highest "
                f"concentration reached {100 * cover:.2f} %, {reason}"
            )
            allowed = f"at most about {cover:.3g} with {generator!r} in this field, {other}"
        else:
            message = (
                f"{target:g} ({100 * target:g} %) not reached by {generator!r} in {field} with "
                f"{_factor_note(floe_area_factor)}, so the circles must cover "
                f"{100 * target / per_cover:.1f} % of the field; the highest cover reached is "
                f"{100 * cover:.2f} %, {reason}: a concentration of {self.reached:.3g} with this "
                "floe_area_factor"
            )
            allowed = (
                f"field.concentration ≤ about {self.reached:.3g}, or field.floe_area_factor ≥ about "
                f"{floe_area_factor * target / self.reached:.3g}, {other}"
            )
        super().__init__("concentration", message, value=target, allowed=allowed)


def _factor_note(floe_area_factor: float) -> str:
    return (
        f"field.floe_area_factor = {floe_area_factor:g}: a floe of diameter d counts as "
        f"{floe_area_factor:g}·π d² but is placed as a circle (0.25·π d²)"
    )


@dataclass(frozen=True)
class FloeCounts:
    """Floes per diameter class for a field (thesis §2.1: m_d, m_floe)."""

    diameter_classes_m: tuple[float, ...]
    counts: tuple[int, ...]
    circle_concentration: float  # Σ counts · π d²/4 / A_field (what perfect circles would cover)

    @property
    def total(self) -> int:
        return int(sum(self.counts))


def largest_remainder(fractions: np.ndarray, total: int) -> np.ndarray:
    """Integers proportional to `fractions` that sum exactly to `total` (Hamilton's method)."""
    raw = np.asarray(fractions, dtype=float) * total
    counts = np.floor(raw).astype(np.int64)
    short = total - int(counts.sum())
    if short > 0:
        order = np.argsort(-(raw - counts), kind="stable")
        counts[order[:short]] += 1
    return counts


def floe_counts(
    observation: Observation, field_area_m2: float, floe_area_factor: float = c.FLOE_AREA_FACTOR
) -> FloeCounts:
    """Number of floes per diameter class (thesis §2.1 with errata 1 and 5)."""
    require_range("field_area_m2", field_area_m2, low=0.0, unit="m²")
    require_range("floe_area_factor", floe_area_factor, low=0.0, unit="(A = factor·π d²)")
    d = np.asarray(observation.diameter_classes_m, dtype=float)
    p = observation.fractions
    mean_area = math.fsum(floe_area_factor * np.pi * d**2 * p)  # exact sum, not BLAS' dot (varies per CPU)
    thesis_total = int(np.ceil(observation.concentration * field_area_m2 / mean_area))
    best = None
    # Rounding per class can move the covered area away from the target when few large floes exist; of the
    # totals near the thesis' m, take the one whose rounded counts cover the target best (thesis' m first).
    for total in sorted(
        range(max(1, thesis_total - 3), thesis_total + 4), key=lambda t: abs(t - thesis_total)
    ):
        counts = largest_remainder(p, total)
        # compared in the model's own floe area (factor·π d²), so the thesis factor keeps the thesis count
        modelled = float(np.sum(counts * floe_area_factor * np.pi * d**2)) / field_area_m2
        if best is None or abs(modelled - observation.concentration) < best[1] - 1e-12:
            best = (counts, abs(modelled - observation.concentration))
    counts = best[0]
    covered = float(np.sum(counts * np.pi * d**2 / 4.0)) / field_area_m2
    return FloeCounts(tuple(float(v) for v in d), tuple(int(k) for k in counts), covered)


# --- generators: (radii per floe, domain, rng, options) → centres ---------------------------------------


def _place_circles(radii, domain, rng, clustering: float, on_round=None) -> Packing:
    growth_start = _growth_start(radii, domain)
    return relax_circles(
        radii, domain, rng, clustering=clustering, growth_start=growth_start, on_round=on_round
    )


def _place_sqp(radii, domain, rng, clustering: float, on_round=None) -> Packing:
    if len(radii) > SQP_MAX_FLOES:
        raise InputError(
            "generator",
            f"'sqp' is the small-field reference and cannot place {len(radii)} floes",
            allowed=f"≤ {SQP_MAX_FLOES} floes for 'sqp'; use 'circles' for larger fields",
        )
    return sqp_circles(radii, domain, rng, clustering=clustering)


def _growth_start(radii: np.ndarray, domain) -> float:
    """Dense targets start from shrunken circles (≈ 50 % cover) and grow them: reaches denser packings."""
    x0, y0, x1, y1 = domain
    cover = float(np.sum(np.pi * radii**2)) / ((x1 - x0) * (y1 - y0))
    return 1.0 if cover <= 0.6 else float(np.sqrt(0.5 / cover))


CIRCLE_GENERATORS: dict[str, Callable[..., Packing]] = {"circles": _place_circles, "sqp": _place_sqp}
GENERATORS = ("circles", "sqp", "voronoi")


def _circle_field(
    counts: FloeCounts,
    target: float,
    domain,
    rng,
    generator: str,
    clustering: float,
    vertices: int,
    on_round=None,
    floe_area_factor: float = c.FLOE_AREA_FACTOR,
):
    """Circular floes of `counts` placed by `generator`; ConcentrationError naming the user's `target`
    (not the cover of the rounded counts) when they cannot all be placed without overlap."""
    diameters = np.repeat(np.asarray(counts.diameter_classes_m), counts.counts)
    order = np.argsort(-diameters, kind="stable")  # ids: largest floes first
    diameters = diameters[order]
    packing = CIRCLE_GENERATORS[generator](diameters / 2.0, domain, rng, clustering, on_round)
    if not packing.overlap_free:
        reached = _best_subset_concentration(packing, domain)
        failed = (
            f"{int(np.sum(~packing.placed))} of {len(diameters)} floes did not fit"
            if packing.placed is not None
            else f"overlap up to {packing.max_overlap_m:.3g} m"
        )
        raise ConcentrationError(
            target,
            reached,
            f"the cover of the floes it placed without overlap ({failed})",
            generator,
            (domain[2] - domain[0], domain[3] - domain[1]),
            floe_area_factor,
        )
    polygons = circle_polygons(packing.centers_m, packing.radii_m, vertices)
    info = {
        "placement": packing.solver,
        "iterations": packing.iterations,
        "min_gap_m": float(-packing.max_overlap_m),
    }
    return polygons, diameters, info


def _best_subset_concentration(packing: Packing, domain) -> float:
    """Cover of the circles placed without overlap (the size groups before the failing one), or, without
    that information, of the circles left after dropping the smaller circle of every overlapping pair."""
    from scipy.spatial import cKDTree

    xy, r = packing.centers_m, packing.radii_m
    if packing.placed is not None:
        keep = packing.placed
    else:
        keep = np.ones(len(r), dtype=bool)
        for i, j in cKDTree(xy).query_pairs(2.0 * float(np.max(r)), output_type="ndarray"):
            if keep[i] and keep[j] and np.hypot(*(xy[i] - xy[j])) < r[i] + r[j]:
                keep[j if r[j] <= r[i] else i] = False
    x0, y0, x1, y1 = domain
    return float(np.sum(np.pi * r[keep] ** 2) / ((x1 - x0) * (y1 - y0)))


def _voronoi_field(counts: FloeCounts, concentration: float, domain, rng):
    x0, y0, x1, y1 = domain
    n = counts.total
    seeds = np.column_stack([rng.uniform(x0, x1, n), rng.uniform(y0, y1, n)])
    box = shapely.box(x0, y0, x1, y1)
    cells = shapely.get_parts(shapely.voronoi_polygons(shapely.multipoints(seeds), extend_to=box))
    cells = shapely.intersection(cells, box)
    cells = cells[shapely.area(cells) > 0.0]
    # every cell shrunk about its centroid by √c: areas scale by c, so Σ = c·A_field exactly
    factor = np.sqrt(concentration)
    centroids = shapely.get_coordinates(shapely.centroid(cells))
    polygons = np.array(
        [
            shapely.transform(
                cell,
                lambda pts, cx=cx, cy=cy: np.column_stack(
                    [cx + factor * (pts[:, 0] - cx), cy + factor * (pts[:, 1] - cy)]
                ),
            )
            for cell, (cx, cy) in zip(cells, centroids, strict=True)
        ],
        dtype=object,
    )
    equivalent = np.sqrt(4.0 * shapely.area(polygons) / np.pi)
    classes = np.asarray(counts.diameter_classes_m)
    nearest = classes[np.argmin(np.abs(np.log(equivalent[:, None] / classes[None, :])), axis=1)]
    order = np.argsort(-shapely.area(polygons), kind="stable")
    return polygons[order], nearest[order], {}


def _refuse_full_cover_by_circles(concentration: float, generator: str, floe_area_factor: float) -> None:
    """InputError when the circles would have to cover the whole field (concentration·0.25/floe_area_factor
    ≥ 1, `ConcentrationError`), before anything is placed (the placement would run to its end and fail):
    circles always leave gaps, equal ones cover at most π/√12 = 90.7 % of a plane (hexagonal packing,
    Thue's theorem)."""
    cover = concentration * c.FLOE_AREA_FACTOR / floe_area_factor
    if cover < 1.0:
        return
    gaps = (
        "circular floes always leave gaps between them (equal circles cover at most π/√12 = 90.7 % of a "
        "plane, hexagonally packed)"
    )
    voronoi = "generator 'voronoi' (any concentration up to 1)"
    if floe_area_factor == c.FLOE_AREA_FACTOR:
        raise InputError(
            "concentration",
            f"{concentration:g} (100 %) cannot be reached by {generator!r}: {gaps}",
            value=concentration,
            allowed=f"< 1 with {generator!r}, or {voronoi}",
        )
    densest = np.pi / np.sqrt(12.0)
    raise InputError(
        "concentration",
        f"{concentration:g} ({100 * concentration:g} %) cannot be reached by {generator!r} with "
        f"{_factor_note(floe_area_factor)}, so the circles would have to cover {100 * cover:.0f} % of the "
        f"field, and {gaps}",
        value=concentration,
        allowed=f"field.concentration < {densest * floe_area_factor / c.FLOE_AREA_FACTOR:.3g}, or "
        f"field.floe_area_factor > {concentration * c.FLOE_AREA_FACTOR / densest:.3g}, or {voronoi}",
    )


def _checked_floe_counts(
    observation: Observation,
    length_m: float,
    width_m: float,
    generator: str,
    clustering: float,
    floe_area_factor: float,
    max_floes: int | None,
    budget: FieldBudget | None = None,
) -> FloeCounts:
    """The floe counts of the requested field, after checking that the request can be met.

    Raises InputError for a bad size, generator or clustering, too many floes, a field smaller than its
    largest floe, or a field too small for the diameter distribution to give the target concentration.
    """
    require_range("length_m", length_m, low=0.0, unit="m")
    require_range("width_m", width_m, low=0.0, unit="m")
    if generator not in GENERATORS:
        raise InputError("generator", f"unknown generator {generator!r}", allowed=", ".join(GENERATORS))
    require_range("clustering", clustering, low=0.0, low_inclusive=True)
    if generator != "voronoi":
        _refuse_full_cover_by_circles(observation.concentration, generator, floe_area_factor)
    counts = floe_counts(observation, length_m * width_m, floe_area_factor)
    if max_floes is not None and counts.total > max_floes:
        raise InputError(
            "max_floes",
            f"a {length_m:g} m × {width_m:g} m field of this observation holds {counts.total:,} floes, more "
            f"than {max_floes:,}",
            value=counts.total,
            allowed=f"≤ {max_floes:,} floes: a smaller field, or a larger budget",
        )
    check_generation_budget(counts.total, length_m, width_m, budget or FieldBudget())
    present = [d for d, k in zip(counts.diameter_classes_m, counts.counts, strict=True) if k > 0]
    if generator != "voronoi" and present and max(present) > min(length_m, width_m):
        raise InputError(
            "width_m" if width_m <= length_m else "length_m",
            f"the field ({length_m:g} m × {width_m:g} m) is smaller than its largest floe "
            f"({max(present):g} m)",
            allowed=f"length and width ≥ {max(present):g} m",
        )
    if floe_area_factor == c.FLOE_AREA_FACTOR and generator != "voronoi":
        # discreteness: a few huge floes in a small field cannot represent the target concentration
        if abs(counts.circle_concentration - observation.concentration) > CONCENTRATION_TOLERANCE:
            raise _whole_floes_error(observation, counts, length_m, width_m)
    return counts


def _whole_floes_error(observation: Observation, counts: FloeCounts, length_m: float, width_m: float):
    """InputError for a field whose whole floes cannot give the target concentration within
    `CONCENTRATION_TOLERANCE`: it says what the rounded counts cover and names the nearest length and width
    (1 m steps, same area rule, `floe_counts`) whose counts do."""
    target = observation.concentration
    mix = ", ".join(
        f"{k} × {d:g} m" for d, k in zip(counts.diameter_classes_m, counts.counts, strict=True) if k
    )
    length = _nearest_fitting_size(observation, length_m, width_m)
    width = _nearest_fitting_size(observation, width_m, length_m)
    options = [f"length_m = {length:g}" if length else None, f"width_m = {width:g}" if width else None]
    sizes = " or ".join(option for option in options if option) or "a much larger field"
    return InputError(
        "length_m",
        f"whole floes cannot give concentration {100 * target:g} % (±{100 * CONCENTRATION_TOLERANCE:g} pp) "
        f"in this {length_m:g} m × {width_m:g} m field: its {counts.total} floes ({mix}, the observation's "
        f"shares rounded to whole floes) cover {100 * counts.circle_concentration:.1f} %; with so few floes, "
        "one floe more or less moves the cover by more than the tolerance",
        allowed=f"a field size whose whole floes give {100 * (target - CONCENTRATION_TOLERANCE):g}–"
        f"{100 * (target + CONCENTRATION_TOLERANCE):g} %: e.g. {sizes} (or any much larger field), "
        "or generator 'voronoi'",
    )


def _nearest_fitting_size(observation: Observation, size_m: float, other_m: float) -> float | None:
    """The size nearest `size_m` (whole metres, within a factor 2; the other side `other_m` kept) at which
    the whole floes of `floe_counts` cover the target concentration within the tolerance, or None."""
    for step in range(1, int(max(size_m, 2.0)) + 1):
        for candidate in (round(size_m) + step, round(size_m) - step):
            if candidate < 1 or candidate < max(observation.diameter_classes_m):
                continue
            cover = floe_counts(observation, candidate * other_m).circle_concentration
            if abs(cover - observation.concentration) <= CONCENTRATION_TOLERANCE:
                return float(candidate)
    return None


def _floe_thicknesses_m(
    observation: Observation,
    n: int,
    rng: np.random.Generator,
    thickness_m: float | None,
    thickness_range_m: tuple[float, float] | None,
    thickness_summands: int,
) -> np.ndarray:
    """The thickness of each of the `n` floes: bounded random in a range (thesis §5.3.3), or constant."""
    if thickness_range_m is not None:
        if thickness_m is not None:
            raise InputError("thickness_m", "give either a thickness or a thickness range, not both")
        return bounded_random_thickness_m(
            rng, thickness_range_m[0], thickness_range_m[1], n, thickness_summands
        )
    value = observation.mean_thickness_m if thickness_m is None else thickness_m
    require_range("thickness_m", value, low=0.0, unit="m")
    return np.full(n, float(value))


def generate_field(
    observation: Observation,
    length_m: float,
    width_m: float,
    rng: np.random.Generator,
    *,
    generator: str = "circles",
    thickness_m: float | None = None,
    thickness_range_m: tuple[float, float] | None = None,
    thickness_summands: int = c.THICKNESS_SUMMANDS_DEFAULT,
    floe_area_factor: float = c.FLOE_AREA_FACTOR,
    clustering: float = 0.05,
    vertices: int = c.CIRCLE_POLYGON_VERTICES,
    seed: int | None = None,
    max_floes: int | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    budget: FieldBudget | None = None,
) -> FloeField:
    """A random floe field for `observation` in x ∈ [0, L], y ∈ [−W/2, W/2] (thesis §2.1).

    Thickness: `thickness_m` for every floe, or bounded random in `thickness_range_m` (thesis §5.3.3,
    Bates with `thickness_summands`), or the observation's mean thickness. `seed` is only recorded in the
    metadata; the randomness comes from `rng`. Raises InputError (or ConcentrationError) when the request
    cannot be met, or, before anything is placed, past `max_floes` floes or `budget`'s memory or time bound
    (default: a run's; `floebreak.ice.budget`). `progress(stage, done, most)`, if given, is told the stage:
    the placement ("placing N floes", rounds done of at most `most`), then the polygons (progress displays).
    """
    counts = _checked_floe_counts(
        observation, length_m, width_m, generator, clustering, floe_area_factor, max_floes, budget
    )
    domain = (0.0, -width_m / 2.0, float(length_m), width_m / 2.0)
    stage = f"placing {counts.total:,} floes ({generator})"
    report = (lambda done, most: progress(stage, done, most)) if progress else None
    if report:
        report(0, 0)
    if generator == "voronoi":
        polygons, diameter_class, info = _voronoi_field(counts, observation.concentration, domain, rng)
    else:
        polygons, diameter_class, info = _circle_field(
            counts,
            observation.concentration,
            domain,
            rng,
            generator,
            clustering,
            vertices,
            report,
            floe_area_factor,
        )
    if progress:
        progress(f"{counts.total:,} floes placed", 1, 1)
    n = len(polygons)
    h = _floe_thicknesses_m(observation, n, rng, thickness_m, thickness_range_m, thickness_summands)
    field = FloeField(
        polygons=polygons,
        thickness_m=h,
        diameter_class_m=np.asarray(diameter_class, dtype=float),
        floe_id=np.arange(n, dtype=np.int64),
        domain_m=domain,
        metadata={
            "generator": generator,
            "observation": observation.key,
            "target_concentration": observation.concentration,
            "diameter_classes_m": list(counts.diameter_classes_m),
            "counts": list(counts.counts),
            "floe_area_factor": floe_area_factor,
            "clustering": clustering,
            "circle_polygon_vertices": vertices,
            "seed": seed,
            "thickness": {
                "constant_m": thickness_m,
                "range_m": thickness_range_m,
                "summands": thickness_summands,
            },
            **info,
        },
    )
    if floe_area_factor == c.FLOE_AREA_FACTOR:
        _check_concentration(field, observation.concentration, generator)
    return field


def _check_concentration(field: FloeField, target: float, generator: str) -> None:
    """ConcentrationError if the generated field's concentration is more than ±1 pp from the user's."""
    if abs(field.concentration - target) > CONCENTRATION_TOLERANCE:
        x0, y0, x1, y1 = field.domain_m
        raise ConcentrationError(
            target,
            field.concentration,
            "the cover of the generated field (more than 1 percentage point off)",
            generator,
            (x1 - x0, y1 - y0),
        )
