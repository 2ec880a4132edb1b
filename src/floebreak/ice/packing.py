"""Non-overlapping circle placement inside a rectangle (thesis §2.1, errata 2–4).

Two solvers for the same problem — place circles of given radii in a rectangle, no two overlapping, each
entirely inside, pulled together the way the thesis' objective pulls floes together:

* `relax_circles` (default, scales to ≥ 10 000 circles): soft-disk overlap relaxation. The energy
  E = Σ_pairs max(0, r_i + r_j + gap − d_ij)² + λ Σ_i max(0, δ_i)² / n, with δ_i the gap from circle i to
  its nearest neighbour, is minimised with L-BFGS-B. The walls are the optimiser's box bounds
  (r_i ≤ x_i − x_min, …: erratum 3), pairs come from a KD-tree neighbour list (rebuilt between rounds,
  Verlet skin), so one evaluation costs O(n). The radii grow from a fraction of their size to full size
  over a few rounds (Lubachevsky–Stillinger-style compression), which reaches much denser packings than
  relaxing full-size circles from random positions.
* `sqp_circles` (reference, small n): the thesis' formulation solved with SLSQP — all pairwise
  non-overlap constraints g1^{ij} = r_i + r_j + gap − d_ij ≤ 0 for i < j (erratum 2), bounds including
  the radius (erratum 3), the same clustering objective (nearest neighbour excludes j = i, erratum 4).

The clustering term is the smooth counterpart of the thesis' objective |min_i δ_i − max_i δ_i|: it drives
every circle's nearest gap towards zero (floes conglomerate, thesis §2.1 citing Herman).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import Bounds, minimize
from scipy.spatial import cKDTree

DEFAULT_GAP_M = 0.01  # target gap between circles [m]: invisible at floe scale, keeps them strictly apart
DEFAULT_CLUSTERING = 0.05  # λ, weight of the clustering term relative to overlap
GROWTH_START = 1.0  # radii start at this fraction of their size in `relax_circles` (1: no growth)
GROWTH_ROUNDS = 5
CLUSTERING_ROUNDS = 1
ROUND_ITERATIONS = 200  # L-BFGS-B iterations per round (a round re-checks overlap exactly)
VERLET_SKIN = 1.0  # in mean radii
CLUSTERING_REACH = 1.0
DENSE_COVER = 0.6  # above this cover, circles are placed size group by size group (largest first)
CANDIDATES_PER_CIRCLE = 8  # in mean radii: a circle is pulled only towards neighbours this close


@dataclass(frozen=True)
class Packing:
    """Result of a placement: centres, and how good it is."""

    centers_m: np.ndarray  # (n, 2)
    radii_m: np.ndarray  # (n,)
    max_overlap_m: float  # largest r_i + r_j − d_ij over all pairs (≤ 0 means no overlap)
    iterations: int
    solver: str
    placed: np.ndarray | None = None  # circles placed without overlap when the packing failed (None: all)

    @property
    def overlap_free(self) -> bool:
        return self.max_overlap_m < 0.0


def max_pair_overlap_m(centers_m: np.ndarray, radii_m: np.ndarray) -> float:
    """Largest r_i + r_j − d_ij over all pairs (exact: every pair that could overlap is checked)."""
    n = len(radii_m)
    if n < 2:
        return -np.inf
    tree = cKDTree(centers_m)
    pairs = tree.query_pairs(3.0 * float(np.max(radii_m)), output_type="ndarray")
    if len(pairs) == 0:
        return -np.inf
    i, j = pairs[:, 0], pairs[:, 1]
    d = np.hypot(*(centers_m[i] - centers_m[j]).T)
    return float(np.max(radii_m[i] + radii_m[j] - d))


def _size_groups(radii: np.ndarray) -> list[np.ndarray]:
    """Indices grouped by radius (factor-2 bins), so a neighbour search never uses a huge cut-off."""
    bins = np.floor(np.log2(radii / np.min(radii))).astype(int)
    return [np.flatnonzero(bins == b) for b in np.unique(bins)]


def _close_pairs(xy: np.ndarray, radii: np.ndarray, groups: list[np.ndarray], reach: float) -> np.ndarray:
    """All pairs (i, j) whose surface gap d_ij − r_i − r_j is below `reach` (exact, KD-trees per group)."""
    trees = [cKDTree(xy[g]) for g in groups]
    r_max = [float(np.max(radii[g])) for g in groups]
    found = []
    for a, ga in enumerate(groups):
        for b in range(a, len(groups)):
            gb = groups[b]
            cutoff = r_max[a] + r_max[b] + reach
            if a == b:
                local = trees[a].query_pairs(cutoff, output_type="ndarray")
                if len(local):
                    found.append(np.stack([ga[local[:, 0]], ga[local[:, 1]]], axis=1))
            else:
                matrix = trees[a].sparse_distance_matrix(trees[b], cutoff, output_type="ndarray")
                if len(matrix):
                    found.append(np.stack([ga[matrix["i"]], gb[matrix["j"]]], axis=1))
    if not found:
        return np.empty((0, 2), dtype=np.int64)
    pairs = np.concatenate(found)
    d = np.hypot(*(xy[pairs[:, 0]] - xy[pairs[:, 1]]).T)
    return pairs[d - radii[pairs[:, 0]] - radii[pairs[:, 1]] < reach]


class _VerletList:
    """Candidate pairs with a skin: rebuilt only when some circle moved more than half the skin.

    The list is a superset of the pairs within `reach` at every call, so the energy it feeds is an exact
    function of the positions; most evaluations skip the KD-tree search (the expensive part).
    """

    def __init__(self, radii: np.ndarray, reach: float, skin: float):
        self.radii, self.reach, self.skin = radii, reach, skin
        self.groups = _size_groups(radii)
        self.reference: np.ndarray | None = None
        self.pairs = np.empty((0, 2), dtype=np.int64)

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        if self.reference is None or np.max(np.abs(xy - self.reference)) > 0.5 * self.skin / np.sqrt(2.0):
            self.pairs = _close_pairs(xy, self.radii, self.groups, self.reach + self.skin)
            self.reference = xy.copy()
        return self.pairs


def _energy(
    flat: np.ndarray,
    radii: np.ndarray,
    candidates: _VerletList | np.ndarray,
    gap: float,
    clustering: float,
    middle: np.ndarray,
):
    """Overlap + clustering energy and gradient (see module docstring); lengths scaled to O(1).

    `candidates` is a Verlet list (exact at every evaluation, so the optimiser can take long steps
    without circles passing through each other) or a fixed array of all pairs.
    """
    n = len(radii)
    xy = flat.reshape(n, 2)
    pairs = candidates(xy) if isinstance(candidates, _VerletList) else candidates
    i, j = pairs[:, 0], pairs[:, 1]
    delta = xy[i] - xy[j]
    dist = np.sqrt(np.einsum("ij,ij->i", delta, delta))
    coincident = dist < 1e-9  # two circles projected onto the same corner: move i towards the middle
    if np.any(coincident):
        inward = middle - xy[i[coincident]] + 1e-3
        delta[coincident] = 1e-9 * inward / np.hypot(*inward.T)[:, None]
        dist[coincident] = 1e-9
    surface_gap = dist - radii[i] - radii[j]
    overlap = np.maximum(0.0, gap - surface_gap)
    energy = float(np.dot(overlap, overlap))
    # dE/dd = −2·overlap for each pair
    coef = -2.0 * overlap / dist
    if clustering > 0.0 and len(pairs):
        # nearest-neighbour gap per circle among listed pairs
        nearest = np.full(n, np.inf)
        order = np.argsort(surface_gap)[::-1]  # fancy assignment keeps the last write: the smallest gap
        nearest[i[order]] = surface_gap[order]
        nearest[j[order]] = np.minimum(nearest[j[order]], surface_gap[order])
        nearest[i[order]] = np.minimum(nearest[i[order]], surface_gap[order])
        reachable = (surface_gap > 0.0) & (surface_gap < CLUSTERING_REACH)
        pull_i = (surface_gap == nearest[i]) & reachable
        pull_j = (surface_gap == nearest[j]) & reachable
        weight = clustering / n
        energy += weight * float(np.sum(np.where(pull_i, surface_gap, 0.0) ** 2))
        energy += weight * float(np.sum(np.where(pull_j, surface_gap, 0.0) ** 2))
        coef = coef + 2.0 * weight * surface_gap * (pull_i.astype(float) + pull_j.astype(float)) / dist
    force = coef[:, None] * delta
    grad = np.empty_like(xy)
    for axis in (0, 1):  # bincount is much faster than np.add.at
        grad[:, axis] = np.bincount(i, force[:, axis], n) - np.bincount(j, force[:, axis], n)
    return energy, grad.ravel()


def _box_bounds(radii: np.ndarray, domain: tuple[float, float, float, float]) -> Bounds:
    x0, y0, x1, y1 = domain
    lo = np.stack([x0 + radii, y0 + radii], axis=1).ravel()
    hi = np.stack([x1 - radii, y1 - radii], axis=1).ravel()
    return Bounds(lo, np.maximum(lo, hi))


def random_centers_m(
    radii_m: np.ndarray, domain_m: tuple[float, float, float, float], rng: np.random.Generator
) -> np.ndarray:
    """Uniform random centres with every circle inside the rectangle (thesis §2.1 first step)."""
    x0, y0, x1, y1 = domain_m
    u = rng.random((len(radii_m), 2))
    x = x0 + radii_m + u[:, 0] * np.maximum(0.0, (x1 - x0) - 2 * radii_m)
    y = y0 + radii_m + u[:, 1] * np.maximum(0.0, (y1 - y0) - 2 * radii_m)
    return np.stack([x, y], axis=1)


def relax_circles(
    radii_m: np.ndarray,
    domain_m: tuple[float, float, float, float],
    rng: np.random.Generator,
    *,
    clustering: float = DEFAULT_CLUSTERING,
    gap_m: float = DEFAULT_GAP_M,
    growth_start: float = GROWTH_START,
    growth_rounds: int = GROWTH_ROUNDS,
    clustering_rounds: int = CLUSTERING_ROUNDS,
    max_polish_rounds: int = 60,
) -> Packing:
    """Place circles without overlap by soft-disk relaxation (module docstring). Large circles first.

    Returns the best packing found; `Packing.overlap_free` tells whether it succeeded.
    """
    radii = np.asarray(radii_m, dtype=float)
    n = len(radii)
    scale = float(np.mean(radii))  # work in units of the mean radius: the energy is O(1) per contact
    r = radii / scale
    x0, y0, x1, y1 = domain_m
    margin = 0.5 * gap_m  # walls keep half the floe gap: polygons stay strictly inside
    domain = ((x0 + margin) / scale, (y0 + margin) / scale, (x1 - margin) / scale, (y1 - margin) / scale)
    gap = gap_m / scale
    if n < 2:
        return Packing(random_centers_m(r, domain, rng) * scale, radii, -np.inf, 0, "relax")
    x0s, y0s, x1s, y1s = domain
    cover = float(np.sum(np.pi * r**2)) / ((x1s - x0s) * (y1s - y0s))
    groups = _size_groups(r)[::-1]  # largest first
    if cover > DENSE_COVER and len(groups) > 1:
        return _relax_hierarchical(r, scale, domain, groups, rng, clustering, gap, max_polish_rounds)
    xy = random_centers_m(r, domain, rng)
    iterations = 0
    middle = np.array([(domain[0] + domain[2]) / 2.0, (domain[1] + domain[3]) / 2.0])

    def run(current, lam, maxiter):
        nonlocal xy, iterations
        result = minimize(
            _energy,
            xy.ravel(),
            args=(
                current,
                _VerletList(current, CLUSTERING_REACH if lam > 0.0 else gap, VERLET_SKIN),
                gap,
                lam,
                middle,
            ),
            jac=True,
            method="L-BFGS-B",
            bounds=_box_bounds(current, domain),
            options={"maxiter": maxiter, "ftol": 1e-14, "gtol": 1e-10, "maxcor": 10},
        )
        iterations += int(result.nit)
        xy = result.x.reshape(n, 2)

    # 1. compression: grow the radii from `growth_start` to full size (dense targets need it)
    for factor in np.linspace(growth_start, 1.0, max(1, growth_rounds)) if growth_start < 1.0 else []:
        run(r * factor, 0.0, ROUND_ITERATIONS)
    # 2. clustering: a fixed effort pulling every circle towards its nearest neighbour
    for _ in range(clustering_rounds if clustering > 0.0 else 0):
        run(r, clustering, ROUND_ITERATIONS)
    # 3. remove the remaining overlap; done when the exact check passes
    best_overlap = max_pair_overlap_m(xy, r)
    for _ in range(max_polish_rounds):
        if best_overlap < 0.0:
            break
        run(r, 0.0, ROUND_ITERATIONS)
        best_overlap = max_pair_overlap_m(xy, r)
    return Packing(xy * scale, radii, best_overlap * scale, iterations, "relax")


def _free_space_centers(
    placed_xy: np.ndarray, placed_r: np.ndarray, radii: np.ndarray, domain, rng: np.random.Generator
) -> np.ndarray:
    """Random centres for new circles, preferring spots not covered by the circles already placed."""
    n = len(radii)
    candidates = random_centers_m(np.repeat(radii, CANDIDATES_PER_CIRCLE), domain, rng)
    tree = cKDTree(placed_xy)
    k = min(len(placed_r), 8)
    d, idx = tree.query(candidates, k=k)
    d, idx = d.reshape(len(candidates), k), idx.reshape(len(candidates), k)
    clearance = np.min(d - placed_r[idx], axis=1) - np.repeat(radii, CANDIDATES_PER_CIRCLE)
    order = np.argsort(-clearance, kind="stable")  # the freest spots first; shuffled among the free ones
    free = order[clearance[order] >= 0.0]
    pick = rng.permutation(free)[:n] if len(free) >= n else order[:n]
    chosen = candidates[pick]
    return chosen[np.argsort(np.repeat(np.arange(n), CANDIDATES_PER_CIRCLE)[pick], kind="stable")]


def _relax_hierarchical(r, scale, domain, groups, rng, clustering, gap, max_polish_rounds) -> Packing:
    """Dense targets: relax the largest size group first, then add each smaller group into the voids."""
    active = np.empty(0, dtype=np.int64)
    xy = np.empty((len(r), 2))
    iterations, overlap = 0, np.inf
    for k, group in enumerate(groups):
        if k == 0:
            sub = relax_circles(
                r[group] * scale,
                tuple(v * scale for v in domain),
                rng,
                clustering=0.0,
                gap_m=gap * scale,
                growth_start=0.7,
                max_polish_rounds=max_polish_rounds,
            )
            xy[group] = sub.centers_m / scale
            iterations += sub.iterations
        else:
            xy[group] = _free_space_centers(xy[active], r[active], r[group], domain, rng)
        active = np.concatenate([active, group])
        last = k == len(groups) - 1
        moved, its, overlap = _polish(
            xy[active], r[active], domain, gap, clustering if last else 0.0, max_polish_rounds
        )
        iterations += its
        if overlap >= 0.0:  # this group does not fit: report what was placed before it
            placed = np.zeros(len(r), dtype=bool)
            placed[active[: len(active) - len(group)]] = True
            xy[active] = moved
            return Packing(xy * scale, r * scale, overlap * scale, iterations, "relax", placed)
        xy[active] = moved
    return Packing(xy * scale, r * scale, overlap * scale, iterations, "relax")


def _polish(xy, r, domain, gap, clustering, max_rounds) -> tuple[np.ndarray, int, float]:
    """Minimise overlap (+ clustering for one round) until the exact overlap check passes."""
    middle = np.array([(domain[0] + domain[2]) / 2.0, (domain[1] + domain[3]) / 2.0])
    iterations = 0
    rounds = ([clustering] * CLUSTERING_ROUNDS if clustering > 0.0 else []) + [0.0] * max_rounds
    overlap = max_pair_overlap_m(xy, r)
    for k, lam in enumerate(rounds):
        if lam == 0.0 and overlap < 0.0 and k > 0:
            break
        result = minimize(
            _energy,
            xy.ravel(),
            args=(r, _VerletList(r, CLUSTERING_REACH if lam > 0.0 else gap, VERLET_SKIN), gap, lam, middle),
            jac=True,
            method="L-BFGS-B",
            bounds=_box_bounds(r, domain),
            options={"maxiter": ROUND_ITERATIONS, "ftol": 1e-14, "gtol": 1e-10, "maxcor": 10},
        )
        iterations += int(result.nit)
        xy = result.x.reshape(-1, 2)
        overlap = max_pair_overlap_m(xy, r)
    return xy, iterations, overlap


def sqp_circles(
    radii_m: np.ndarray,
    domain_m: tuple[float, float, float, float],
    rng: np.random.Generator,
    *,
    clustering: float = DEFAULT_CLUSTERING,
    gap_m: float = DEFAULT_GAP_M,
    max_iterations: int = 500,
) -> Packing:
    """The thesis' SQP formulation (SLSQP, all pairwise constraints). O(n²) constraints: small n only."""
    radii = np.asarray(radii_m, dtype=float)
    n = len(radii)
    scale = float(np.mean(radii))
    r = radii / scale
    x0, y0, x1, y1 = domain_m
    margin = 0.5 * gap_m  # walls keep half the floe gap: polygons stay strictly inside
    domain = ((x0 + margin) / scale, (y0 + margin) / scale, (x1 - margin) / scale, (y1 - margin) / scale)
    xy = random_centers_m(r, domain, rng)
    iu, ju = np.triu_indices(n, 1)
    gap = gap_m / scale

    def constraint(flat):  # SLSQP wants c(x) ≥ 0: d_ij − r_i − r_j − gap ≥ 0
        p = flat.reshape(n, 2)
        d = np.hypot(*(p[iu] - p[ju]).T)
        return d - r[iu] - r[ju] - gap

    def constraint_jac(flat):
        p = flat.reshape(n, 2)
        delta = p[iu] - p[ju]
        d = np.hypot(*delta.T) + 1e-300
        unit = delta / d[:, None]
        jac = np.zeros((len(iu), 2 * n))
        rows = np.arange(len(iu))
        jac[rows, 2 * iu] = unit[:, 0]
        jac[rows, 2 * iu + 1] = unit[:, 1]
        jac[rows, 2 * ju] = -unit[:, 0]
        jac[rows, 2 * ju + 1] = -unit[:, 1]
        return jac

    all_pairs = np.stack([iu, ju], axis=1)
    middle = np.array([(domain[0] + domain[2]) / 2.0, (domain[1] + domain[3]) / 2.0])

    def objective(flat):  # clustering term only; overlap is a hard constraint here
        energy, grad = _energy(flat, r, all_pairs, -np.inf, clustering, middle)
        return energy, grad

    result = minimize(
        objective,
        xy.ravel(),
        jac=True,
        method="SLSQP",
        bounds=_box_bounds(r, domain),
        constraints=[{"type": "ineq", "fun": constraint, "jac": constraint_jac}],
        options={"maxiter": max_iterations, "ftol": 1e-10},
    )
    xy = result.x.reshape(n, 2)
    return Packing(xy * scale, radii, max_pair_overlap_m(xy, r) * scale, int(result.nit), "sqp")
