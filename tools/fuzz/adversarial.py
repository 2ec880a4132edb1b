"""The fuzz campaign's adversarial generator (issue 31): hostile files and policies, not valid scenarios.

`fuzz.scenario_dicts` draws valid scenarios over the options and the edges of their ranges. This
generator (``python -m fuzz --generator adversarial``, run by ``make fuzz`` after the first) draws
what a user's own files and policies can hold, valid or not, and expects each run to finish or to be refused
(exit 2), never to crash or run away:

- **field files**, written with the project's writer (`floebreak.io.geoparquet.write_geoparquet`, as
  `floebreak.output.field_files.save_field` does): outlines with repeated vertices, collinear (zero-area) and
  self-crossing ones, slivers and spikes, floes overlapping each other, tiny (millimetre) and huge
  (kilometre) floes, the whole field offset by up to 10⁷ m (projected coordinates); ``floe_id`` unique,
  repeated, negative, huge, float or text; ``thickness_m`` valid, at the range's edges, zero, negative,
  NaN, huge or text; the ``domain_m`` metadata matching, inverted, text, or missing; a table of 0 rows;
  one valid floe 10⁷ m across; the only floe on the bow's line 10⁷ m ahead (no ``x_end_m``);
- **bow CSV files**: a built-in hull's waterlines with rows repeated, collinear nodes inserted, rows
  dropped down to two, the order reversed, the line scaled by 10⁻⁶ … 10⁶ or moved by up to 10⁷ m, a cell
  NaN or empty; stations (format b) with repeated or non-decreasing x;
- **failure policies**: per failure class any list of registered modes (repeats, only ``none``, a class
  left to a mode that cannot handle it), per-region tables, an empty list, an unknown mode, on ice from
  1 cm to 10 m thick.

Alongside, `deep_toml_text`, `fem_table_texts` and `torque_csv_texts` draw TOML nested thousands deep, FEM
tables with finite extreme cells (1e-300 … 1e300) and measured torque files from no sample to more than the
row bound, for the readers' own campaign (tests/campaign/test_fuzz_readers.py).

A record has the shape of `fuzz.scenario_dicts`'s (the files under `fuzz.FILES`); a
field file's recipe is ``{"adversarial_field": {...}}``, which `write_field_file` writes. Each run has the
fuzz budgets: `fuzz.MAX_PIECES` pieces and `fuzz.MAX_WALL_S` of wall time (a run that
reaches one is a refusal, exit 2, as for a user), and a transit of at most `MAX_TRANSIT_M`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st

from floebreak.config import scenario as sc
from floebreak.failure import BOW_REGIONS, FAILURE_CLASSES, mode_names
from floebreak.ship import bow as bows
from floebreak.ship.hulls import HULLS
from fuzz.limits import FILES, MAX_PIECES, MAX_WALL_S

MAX_TRANSIT_M = 60.0
MAX_FLOES = 12
OFFSETS_M = (0.0, 0.0, 0.0, 1.0e-9, 1.0e4, 1.0e7, -1.0e7)  # the field moved by (dx, dy) from the bow's path


def _pick(rng: np.random.Generator, choices):
    """One of `choices`, uniformly."""
    return choices[int(rng.integers(len(choices)))]


OUTLINES = ("regular", "repeated", "collinear", "bowtie", "sliver", "spike", "point")


def _outline(rng: np.random.Generator, centre: tuple[float, float], hostile: bool) -> list[list[float]]:
    """One floe's ring (closed): a regular polygon, or (`hostile`) one drawn to be hostile (module
    docstring)."""
    kind = _pick(rng, OUTLINES) if hostile else "regular"
    radius = _pick(rng, [1e-3, 0.05, 1.0, 4.0, 10.0, 1e3]) if hostile else float(rng.uniform(1.0, 6.0))
    n = int(rng.integers(3, 12, endpoint=True))
    angles = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)]) * radius
    if kind == "repeated":
        ring = np.repeat(ring, int(rng.integers(2, 4, endpoint=True)), axis=0)
    elif kind == "collinear":
        ring = np.column_stack([np.linspace(-radius, radius, n), np.zeros(n)])
    elif kind == "bowtie":
        ring = np.array([[-1.0, -1.0], [1.0, 1.0], [1.0, -1.0], [-1.0, 1.0]]) * radius
    elif kind == "sliver":
        ring = np.array([[-1.0, 0.0], [1.0, 0.0], [1.0, 1e-9], [-1.0, 1e-9]]) * radius
    elif kind == "spike":
        ring = np.vstack([ring, [[radius * 50.0, 0.0], ring[0]]])
    elif kind == "point":
        ring = np.zeros((4, 2))
    ring = ring + np.asarray(centre)
    return [[float(x), float(y)] for x, y in [*ring, ring[0]]]


def _ids(rng: np.random.Generator, n: int, hostile: bool) -> list[Any]:
    kind = _pick(rng, ["repeated", "negative", "huge", "float", "text"]) if hostile else "unique"
    if kind == "repeated":
        return [i // 2 for i in range(n)]
    if kind == "negative":
        return [-i for i in range(n)]
    if kind == "huge":
        return [2**62 + i for i in range(n)]
    if kind == "float":
        return [i + 0.5 for i in range(n)]
    if kind == "text":
        return [f"floe-{i}" for i in range(n)]
    return list(range(n))


def _thicknesses(rng: np.random.Generator, n: int, hostile: bool) -> list[Any]:
    if not hostile:
        return [float(rng.uniform(0.2, 2.0)) for _ in range(n)]
    kind = _pick(rng, ["edges", "zero", "negative", "nan", "huge", "text"])
    if kind == "edges":
        return [sc.THICKNESS_M[i % 2] for i in range(n)]
    special = {"zero": 0.0, "negative": -1.0, "nan": float("nan"), "huge": 1e6, "text": "1.0"}[kind]
    return [special if i == n - 1 else 1.0 for i in range(n)]


FIELD_HOSTILITIES = (
    "outline",
    "ids",
    "thickness",
    "domain",
    "offset",
    "overlap",
    "empty",
    "several",
    "huge",
    "far",
)
HUGE_RADIUS_M = 5.0e6  # a floe 10⁷ m across: past the largest floe class (`floebreak.ice.budget`)
FAR_AHEAD_M = 1.0e7  # the only floe on the bow's line this far ahead: past the longest transit


def field_recipes(rng: np.random.Generator) -> dict[str, Any]:
    """The recipe of a hostile field file (written by `write_field_file`): one hostile trait (or several at
    once), the rest benign, so that each trait reaches the code that meets it."""
    trait = _pick(rng, FIELD_HOSTILITIES)
    every = trait == "several"
    n = 0 if trait == "empty" else int(rng.integers(1, MAX_FLOES, endpoint=True))
    centres = [(float(rng.uniform(5.0, 50.0)), float(rng.uniform(-15.0, 15.0))) for _ in range(n)]
    if n > 1 and (trait == "overlap" or every):  # two floes on one spot
        centres[1] = centres[0]
    offset = (0.0, 0.0)
    if trait == "offset" or every:
        offset = (_pick(rng, OFFSETS_M), _pick(rng, OFFSETS_M))
    domain = _pick(rng, ["inverted", "text", "missing"]) if trait == "domain" or every else "match"
    if trait == "far":  # one floe on the bow's line, far ahead
        centres, offset = centres[:1], (FAR_AHEAD_M, -centres[0][1])
    hostile_outline = trait == "outline" or every
    rings = [
        _outline(rng, (x + offset[0], y + offset[1]), hostile_outline and bool(rng.integers(2)))
        for x, y in centres
    ]
    if trait == "huge":  # one valid floe, 10⁷ m across, centred ahead of the bow
        angles = np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
        rings = [[[HUGE_RADIUS_M * (1.0 + np.cos(a)), HUGE_RADIUS_M * np.sin(a)] for a in angles]]
    return {
        "trait": trait,
        "rings": rings,
        "floe_id": _ids(rng, len(rings), trait == "ids" or every),
        "thickness_m": _thicknesses(rng, len(rings), trait == "thickness" or every),
        "domain": domain,
    }


def write_field_file(recipe: dict[str, Any], path: Path) -> None:
    """Write a `field_recipes` recipe as GeoParquet with the project's writer (invalid outlines as they
    are: GEOS builds them, the reader must refuse or repair them)."""
    import shapely

    from floebreak.io.geoparquet import write_geoparquet
    from floebreak.io.provenance import provenance

    polygons = np.empty(len(recipe["rings"]), dtype=object)
    polygons[:] = [shapely.Polygon(ring) for ring in recipe["rings"]]
    bounds = shapely.total_bounds(polygons) if len(polygons) else np.array([0.0, -10.0, 60.0, 10.0])
    domain = {
        "match": [float(v) for v in bounds],
        "inverted": [float(bounds[2]), float(bounds[3]), float(bounds[0]), float(bounds[1])],
        "text": "abc",
        "missing": None,
    }[recipe["domain"]]
    meta = provenance(kind="floe_field") if domain is None else provenance(kind="floe_field", domain_m=domain)
    columns = {
        "floe_id": np.array(recipe["floe_id"]),
        "thickness_m": np.array(recipe["thickness_m"]),
    }
    write_geoparquet(path, polygons, columns, meta)


def bow_csv_texts(rng: np.random.Generator) -> str:
    """A hostile bow CSV file's text (see the module docstring)."""
    bow = HULLS[_pick(rng, sorted(HULLS))]()
    if bool(rng.integers(2)):  # format (b): stations from the stem aft
        port = bow.upper_xy_m[bow.stem_index :: -1]
        rows = [[float(x), float(abs(y)), 30.0] for x, y in port]
        if bool(rng.integers(2)):
            rows.insert(1, list(rows[1]))  # a repeated station
        if bool(rng.integers(2)):
            rows[-1][0] = rows[-2][0]  # x not decreasing
        header = ",".join(bows.STATIONS_COLUMNS)
        return header + "\n" + "".join(",".join(repr(v) for v in row) + "\n" for row in rows)
    lines = {"upper": np.array(bow.upper_xy_m), "lower": np.array(bow.lower_xy_m)}
    scale = _pick(rng, [1.0, 1.0, 1e-6, 1e-3, 1e3, 1e6])
    shift = np.array([_pick(rng, OFFSETS_M), _pick(rng, OFFSETS_M)])
    mutation = _pick(rng, ["none", "repeated", "collinear", "two rows", "reversed", "nan", "empty"])
    out = ["# z_upper_m = 0.1", "# z_lower_m = -0.9", ",".join(bows.LINES_COLUMNS)]
    for name, xy in lines.items():
        xy = xy * scale + shift
        if mutation == "repeated":
            xy = np.repeat(xy, 2, axis=0)
        elif mutation == "collinear":
            xy = np.vstack([xy[:1], 0.5 * (xy[:1] + xy[1:2]), xy[1:]])
        elif mutation == "two rows":
            xy = xy[:2]
        elif mutation == "reversed":
            xy = xy[::-1]
        cells = [[repr(float(x)), repr(float(y))] for x, y in xy]
        if mutation in ("nan", "empty") and name == "upper":
            cells[len(cells) // 2][1] = "nan" if mutation == "nan" else ""
        out += [f"{name},{x},{y}" for x, y in cells]
    return "\n".join(out) + "\n"


def policies(rng: np.random.Generator) -> dict[str, Any]:
    """A hostile `[failure.policy]` (see the module docstring)."""
    names = [*mode_names()] * 8 + ["no_such_mode"]  # an unknown mode now and then

    def modes() -> list[str]:  # 0 to 4 modes, repeats allowed: an empty list now and then (a refusal)
        return [str(_pick(rng, names)) for _ in range(int(rng.integers(0, 4, endpoint=True)))]

    policy: dict[str, Any] = {}
    for failure_class in FAILURE_CLASSES:
        if rng.random() < 0.4:
            continue
        if bool(rng.integers(2)):
            policy[failure_class] = modes()
        else:
            regions = [r for r in BOW_REGIONS if bool(rng.integers(2))] or [str(_pick(rng, BOW_REGIONS))]
            policy[failure_class] = {region: modes() for region in regions}
    return policy


@st.composite
def adversarial_dicts(draw) -> dict[str, Any]:
    """A scenario with hostile files and policy (the shape of `fuzz.scenario_dicts`' records)."""
    # hypothesis gives the seed (the campaign's reproducibility); the choices come from numpy, uniformly:
    # hypothesis' own draws of a long chain of sampled_from favour the first elements
    rng = np.random.default_rng(draw(st.integers(0, 2**63 - 1)))

    files: dict[str, Any] = {}
    thickness = _pick(rng, [sc.THICKNESS_M[0], 0.05, 0.3, 1.0, sc.THICKNESS_M[1]])
    data: dict[str, Any] = {
        "profile": _pick(rng, ["default", "thesis"]),
        "seed": int(rng.integers(0, 2**31, endpoint=True)),
        "ice": {"thickness_m": thickness},
        "ship": {"step_m": _pick(rng, [0.1, 0.25, 1.0])},
        "simulation": {"max_pieces": MAX_PIECES, "max_wall_s": MAX_WALL_S},
    }
    far = False
    if bool(rng.integers(2)):
        data["field"] = {"file": "field.parquet"}
        recipe = field_recipes(rng)
        files["field.parquet"] = {"adversarial_field": recipe}
        far = recipe["trait"] == "far"  # no x_end_m: the transit to the far floe must be refused
    else:
        data["field"] = {
            "floes": [
                {"x_m": 8.0, "y_m": 0.0, "diameter_m": 10.0},
                {"x_m": 20.0, "y_m": 3.0, "diameter_m": 6.0},
            ]
        }
    if bool(rng.integers(2)):
        data["ship"]["file"] = "bow.csv"
        files["bow.csv"] = {"text": bow_csv_texts(rng)}
    if bool(rng.integers(2)):
        data["failure"] = {"policy": policies(rng)}
    if not far:
        data["ship"]["x_end_m"] = 10.0 if thickness < 0.1 else MAX_TRANSIT_M
    data[FILES] = files
    return data


def deep_toml_text(rng: np.random.Generator) -> str:
    """A scenario text with an array nested far deeper than any floebreak file (up to 5 000 levels)."""
    depth = int(_pick(rng, [33, 100, 1000, 5000]))
    return "[ice]\nthickness_m = " + "[" * depth + "]" * depth + "\n"


def fem_table_texts(rng: np.random.Generator) -> str:
    """A FEM table CSV with finite but extreme cells (1e-300 … 1e300 in any column), or a sane one."""
    extremes = [1e-300, 1e-30, 1e-7, 1.0, 1e5, 1e12, 1e300, -1e300]
    rows = [[0.0] * 6] + [[0.5 * k, 1.0, 1.0, 0.5 * k, 100.0 * k, -100.0 * k] for k in range(1, 5)]
    for _ in range(int(rng.integers(0, 3, endpoint=True))):
        rows[int(rng.integers(1, len(rows)))][int(rng.integers(0, 6))] = float(_pick(rng, extremes))
    header = "# pitch_percent: 95\nvolume_m3,length_m,width_m,height_m,force_kN,torque_kNm\n"
    return header + "".join(",".join(repr(v) for v in row) + "\n" for row in rows)


def torque_csv_texts(rng: np.random.Generator, max_rows: int) -> str:
    """A measured torque CSV: no rows, one sample, a few, or more than `max_rows`; values sane or beyond
    any shaft (1e300 kN·m)."""
    n = int(_pick(rng, [0, 1, 2, 10, max_rows + 1]))
    value = float(_pick(rng, [300.0, -300.0, 1e5, 1e300]))
    return "time_s,torque_kNm\n" + "".join(
        f"{k * 1e-3:.3f},{value if k == n // 2 else 300.0}\n" for k in range(n)
    )
