"""Non-overlapping circle placement inside a rectangle (thesis §2.1, errata 2–4).

Three solvers for the same problem — place circles of given radii in a rectangle, no two overlapping,
each entirely inside, pulled together the way the thesis' objective pulls floes together:

* `relax_circles` (default, scales to ≥ 10 000 circles): soft-disk overlap relaxation. The energy
  E = Σ_pairs max(0, r_i + r_j + gap − d_ij)² + λ Σ_i max(0, δ_i)² / n, with δ_i the gap from circle i to
  its nearest neighbour, is minimised with a projected L-BFGS in fixed-order arithmetic (`_minimise_in_box`,
  the same result on every CPU). The walls are the optimiser's box bounds
  (r_i ≤ x_i − x_min, …: erratum 3), pairs come from a KD-tree neighbour list (rebuilt between rounds,
  Verlet skin), so one evaluation costs O(n). The radii grow from a fraction of their size to full size
  over a few rounds (Lubachevsky–Stillinger-style compression), which reaches much denser packings than
  relaxing full-size circles from random positions.
* `corner_circles` (dense fallback of `relax_circles`, few distinct radii): largest-first insertion of
  each circle at the corner position (tangent to two placed circles or walls) of maximum hole degree, so
  the large floes form a dense frame and the smaller classes fill its voids. Reaches what relaxation
  cannot, e.g. 88 % cover with 7.5/15/60 m floes in a field only 4 large floes wide.
* `sqp_circles` (reference, small n): the thesis' formulation solved with SLSQP — all pairwise
  non-overlap constraints g1^{ij} = r_i + r_j + gap − d_ij ≤ 0 for i < j (erratum 2), bounds including
  the radius (erratum 3), the same clustering objective (nearest neighbour excludes j = i, erratum 4).

The clustering term is the smooth counterpart of the thesis' objective |min_i δ_i − max_i δ_i|: it drives
every circle's nearest gap towards zero (floes conglomerate, thesis §2.1 citing Herman).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np
from scipy.optimize import Bounds, minimize
from scipy.spatial import cKDTree

DEFAULT_GAP_M = 0.01  # target gap between circles [m]: invisible at floe scale, keeps them strictly apart
DEFAULT_CLUSTERING = 0.05  # λ, weight of the clustering term relative to overlap
GROWTH_START = 1.0  # radii start at this fraction of their size in `relax_circles` (1: no growth)
GROWTH_ROUNDS = 5
CLUSTERING_ROUNDS = 1
ROUND_ITERATIONS = 200  # optimiser iterations per round (a round re-checks overlap exactly)
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
    i, j = np.ascontiguousarray(pairs[:, 0]), np.ascontiguousarray(pairs[:, 1])
    delta, dist, surface_gap, overlap, coef = _pair_terms(xy, radii, i, j, gap, middle)
    energy = _sum_of_squares(overlap)
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
        energy += weight * _sum_of_squares(np.where(pull_i, surface_gap, 0.0))
        energy += weight * _sum_of_squares(np.where(pull_j, surface_gap, 0.0))
        coef = coef + 2.0 * weight * surface_gap * (pull_i.astype(float) + pull_j.astype(float)) / dist
    return energy, _gradient(i, j, coef, delta, n).ravel()


@numba.njit(cache=True, nogil=True)
def _pair_terms(xy, radii, i, j, gap, middle):
    """Per pair: centre offset x_i − x_j, distance, surface gap, overlap max(0, gap − surface gap) and
    dE/dd / d = −2·overlap / d. Compiled, with numpy's operation order, so that the energy's optimiser path
    (and every generated field) is the same as with the array expressions it replaces."""
    m = len(i)
    delta, dist = np.empty((m, 2)), np.empty(m)
    surface_gap, overlap, coef = np.empty(m), np.empty(m), np.empty(m)
    for k in range(m):
        a, b = i[k], j[k]
        dx, dy = xy[a, 0] - xy[b, 0], xy[a, 1] - xy[b, 1]
        d = np.sqrt(dx * dx + dy * dy)
        if d < 1e-9:  # two circles projected onto the same corner: move i towards the middle
            ix, iy = middle[0] - xy[a, 0] + 1e-3, middle[1] - xy[a, 1] + 1e-3
            length = np.hypot(ix, iy)
            dx, dy, d = 1e-9 * ix / length, 1e-9 * iy / length, 1e-9
        delta[k, 0], delta[k, 1], dist[k] = dx, dy, d
        surface_gap[k] = d - radii[a] - radii[b]
        overlap[k] = max(0.0, gap - surface_gap[k])
        coef[k] = -2.0 * overlap[k] / d
    return delta, dist, surface_gap, overlap, coef


@numba.njit(cache=True, nogil=True)
def _gradient(i, j, coef, delta, n):
    """Σ over pairs of coef · (x_i − x_j) into circle i, minus the same into circle j, summed pair by pair
    in order (as `np.bincount` sums)."""
    into_i, into_j = np.zeros((n, 2)), np.zeros((n, 2))
    for k in range(len(i)):
        for axis in range(2):
            force = coef[k] * delta[k, axis]
            into_i[i[k], axis] += force
            into_j[j[k], axis] += force
    return into_i - into_j


def compile_now() -> None:
    """Compile (or load from numba's on-disk cache) the energy kernels; see `mechanics.compile_kernels`."""
    xy, radii, pairs = np.array([0.0, 0.0, 1.5, 0.0]), np.array([1.0, 1.0]), np.array([[0, 1]])
    args = (radii, pairs, 0.01, 0.05, np.zeros(2))
    _minimise_in_box(_energy, xy, args, Bounds(np.full(4, -5.0), np.full(4, 5.0)), 3, 1e-14, 1e-10)


def _box_bounds(radii: np.ndarray, domain: tuple[float, float, float, float]) -> Bounds:
    x0, y0, x1, y1 = domain
    lo = np.stack([x0 + radii, y0 + radii], axis=1).ravel()
    hi = np.stack([x1 - radii, y1 - radii], axis=1).ravel()
    return Bounds(lo, np.maximum(lo, hi))


@numba.njit(cache=True, nogil=True)
def _sum_of_squares(values):
    """Σ v², summed in index order (`np.dot` would use the BLAS kernel of the CPU, whose order varies)."""
    total = 0.0
    for v in values:
        total += v * v
    return total


@numba.njit(cache=True, nogil=True)
def _free_dot(a, b, free):
    """Σ a·b over the free variables, in index order."""
    total = 0.0
    for k in range(len(a)):
        if free[k]:
            total += a[k] * b[k]
    return total


@numba.njit(cache=True, nogil=True)
def _lbfgs_direction(gradient, free, s, y, stored, newest):
    """−H·g by the L-BFGS two-loop recursion on the free variables (the others stay 0), from the `stored`
    newest pairs (s, y) of the ring buffers, slot `newest` last; pairs with s·y ≤ 0 there are skipped."""
    memory = s.shape[0]
    q = np.where(free, -gradient, 0.0)
    alpha, rho = np.zeros(memory), np.zeros(memory)
    scale = 0.0  # H0 = (s·y / y·y)·I of the newest usable pair
    for age in range(stored):
        slot = (newest - age) % memory
        sy = _free_dot(s[slot], y[slot], free)
        if sy <= 0.0:
            continue
        if scale == 0.0:
            scale = sy / _free_dot(y[slot], y[slot], free)
        rho[slot] = 1.0 / sy
        alpha[slot] = rho[slot] * _free_dot(s[slot], q, free)
        q -= np.where(free, alpha[slot] * y[slot], 0.0)
    q *= scale if scale > 0.0 else 1.0
    for age in range(stored - 1, -1, -1):
        slot = (newest - age) % memory
        if rho[slot] > 0.0:
            beta = rho[slot] * _free_dot(y[slot], q, free)
            q += np.where(free, (alpha[slot] - beta) * s[slot], 0.0)
    return q


def _line_search(fun, args, x, value, gradient, direction, free, step, lo, hi):
    """(point, value, gradient) along the projected path x + t·direction: the first t (halving from `step`)
    with sufficient decrease (Armijo), doubled while the slope is still steep (weak Wolfe: the slope must
    rise to 0.9 of its start) and the decrease holds, as L-BFGS-B's line search extrapolates; None when
    no step decreases the value."""
    slope = _free_dot(gradient, direction, free)
    best = None
    for _ in range(60):
        trial = np.clip(x + step * direction, lo, hi)
        trial_value, trial_gradient = fun(trial, *args)
        if trial_value > value + 1e-4 * _free_dot(gradient, trial - x, free):  # no sufficient decrease
            if best is not None:
                return best
            step *= 0.5
            continue
        if best is not None and (trial_value >= best[1] or np.array_equal(trial, best[0])):
            return best  # no further decrease, or the bounds stop the path
        best = (trial, trial_value, trial_gradient)
        if _free_dot(trial_gradient, direction, free) >= 0.9 * slope:
            return best
        step *= 2.0
    return best


def _minimise_in_box(fun, x0, args, bounds: Bounds, maxiter: int, ftol: float, gtol: float, memory: int = 10):
    """(x, iterations) minimising `fun(x, *args) -> (value, gradient)` over the box `bounds`: projected
    L-BFGS (variables at a bound the gradient pushes against are held; `_line_search` along the projected
    path). Every reduction runs in a fixed order, so the result is the same on every CPU (scipy's
    L-BFGS-B reduces through BLAS and LAPACK, whose kernels differ from one CPU to another). Stops when
    the projected gradient is below `gtol`, the relative decrease below `ftol`, or after `maxiter`."""
    lo, hi = bounds.lb, bounds.ub
    x = np.clip(x0, lo, hi)
    value, gradient = fun(x, *args)
    s, y = np.zeros((memory, len(x))), np.zeros((memory, len(x)))
    stored, newest = 0, memory - 1
    for iteration in range(maxiter):
        held = ((x <= lo) & (gradient > 0.0)) | ((x >= hi) & (gradient < 0.0))
        if not np.any(np.abs(np.where(held, 0.0, gradient)) > gtol):
            return x, iteration
        free = ~held
        direction = _lbfgs_direction(gradient, free, s, y, stored, newest)
        if not _free_dot(gradient, direction, free) < 0.0:  # lost curvature: steepest descent again
            stored, direction = 0, np.where(free, -gradient, 0.0)
        step = 1.0 if stored else min(1.0, 1.0 / np.sqrt(_sum_of_squares(direction)))
        found = _line_search(fun, args, x, value, gradient, direction, free, step, lo, hi)
        if found is None:
            return x, iteration
        trial, trial_value, trial_gradient = found
        newest = (newest + 1) % memory
        s[newest], y[newest] = trial - x, trial_gradient - gradient
        stored = min(stored + 1, memory)
        decrease = value - trial_value
        x, value, gradient = trial, trial_value, trial_gradient
        if decrease <= ftol * max(abs(value) + decrease, abs(value), 1.0):
            return x, iteration + 1
    return x, maxiter


def random_centers_m(
    radii_m: np.ndarray, domain_m: tuple[float, float, float, float], rng: np.random.Generator
) -> np.ndarray:
    """Uniform random centres with every circle inside the rectangle (thesis §2.1 first step)."""
    x0, y0, x1, y1 = domain_m
    u = rng.random((len(radii_m), 2))
    x = x0 + radii_m + u[:, 0] * np.maximum(0.0, (x1 - x0) - 2 * radii_m)
    y = y0 + radii_m + u[:, 1] * np.maximum(0.0, (y1 - y0) - 2 * radii_m)
    return np.stack([x, y], axis=1)


def _in_mean_radius_units(
    radii: np.ndarray, domain_m: tuple[float, float, float, float], gap_m: float
) -> tuple[float, np.ndarray, tuple[float, float, float, float], float]:
    """(scale, radii, domain, gap) in units of the mean radius: the energy is O(1) per contact."""
    scale = float(np.mean(radii))
    r = radii / scale
    x0, y0, x1, y1 = domain_m
    margin = 0.5 * gap_m  # walls keep half the floe gap: polygons stay strictly inside
    domain = ((x0 + margin) / scale, (y0 + margin) / scale, (x1 - margin) / scale, (y1 - margin) / scale)
    return scale, r, domain, gap_m / scale


def _dense_packing(
    radii, domain_m, gap_m, r, scale, domain, groups, rng, clustering, gap, max_polish_rounds
) -> Packing:
    """Above `DENSE_COVER`: hierarchical relaxation, else (when it jams) corner insertion if better."""
    packing = _relax_hierarchical(r, scale, domain, groups, rng, clustering, gap, max_polish_rounds)
    if packing.overlap_free or len(np.unique(radii)) > CORNER_MAX_CLASSES:
        return packing
    # the relaxation jams before the target (e.g. 89 % with 7.5/15/60 m floes): corner insertion
    dense = corner_circles(radii, domain_m, rng, gap_m=gap_m)
    if dense.overlap_free or _placed_cover(dense) > _placed_cover(packing):
        return dense
    return packing


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
    on_round: Callable[[int, int], None] | None = None,
) -> Packing:
    """Place circles without overlap by soft-disk relaxation (module docstring). Large circles first.

    `on_round(done, most)`, if given, is called after each relaxation round (`most`: the rounds at most,
    the polish stops early once the exact check passes); for progress displays.

    Above `DENSE_COVER`, when the relaxation jams before every circle fits, `corner_circles` (dense
    corner insertion) is tried. Returns the best packing found; `Packing.overlap_free` tells whether it
    succeeded.
    """
    radii = np.asarray(radii_m, dtype=float)
    n = len(radii)
    scale, r, domain, gap = _in_mean_radius_units(radii, domain_m, gap_m)
    if n < 2:
        return Packing(random_centers_m(r, domain, rng) * scale, radii, -np.inf, 0, "relax")
    x0s, y0s, x1s, y1s = domain
    cover = float(np.sum(np.pi * r**2)) / ((x1s - x0s) * (y1s - y0s))
    groups = _size_groups(r)[::-1]  # largest first
    if cover > DENSE_COVER and len(groups) > 1:
        return _dense_packing(
            radii, domain_m, gap_m, r, scale, domain, groups, rng, clustering, gap, max_polish_rounds
        )
    xy = random_centers_m(r, domain, rng)
    iterations = 0
    growth = max(1, growth_rounds) if growth_start < 1.0 else 0
    most_rounds = growth + (clustering_rounds if clustering > 0.0 else 0) + max_polish_rounds
    rounds = [0]
    middle = np.array([(domain[0] + domain[2]) / 2.0, (domain[1] + domain[3]) / 2.0])

    def run(current, lam, maxiter):
        nonlocal xy, iterations
        flat, nit = _minimise_in_box(
            _energy,
            xy.ravel(),
            (
                current,
                _VerletList(current, CLUSTERING_REACH if lam > 0.0 else gap, VERLET_SKIN),
                gap,
                lam,
                middle,
            ),
            _box_bounds(current, domain),
            maxiter,
            ftol=1e-14,
            gtol=1e-10,
        )
        iterations += nit
        xy = flat.reshape(n, 2)
        rounds[0] += 1
        if on_round is not None:
            on_round(rounds[0], most_rounds)

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


def _placed_cover(packing: Packing) -> float:
    """Σ r² of the circles a failed packing placed without overlap (all of them when it succeeded)."""
    placed = np.ones(len(packing.radii_m), bool) if packing.placed is None else packing.placed
    return float(np.sum(packing.radii_m[placed] ** 2))


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
    xy = np.full((len(r), 2), np.nan)  # groups not placed yet have no centres (see `Packing.placed`)
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
        flat, nit = _minimise_in_box(
            _energy,
            xy.ravel(),
            (r, _VerletList(r, CLUSTERING_REACH if lam > 0.0 else gap, VERLET_SKIN), gap, lam, middle),
            _box_bounds(r, domain),
            ROUND_ITERATIONS,
            ftol=1e-14,
            gtol=1e-10,
        )
        iterations += nit
        xy = flat.reshape(-1, 2)
        overlap = max_pair_overlap_m(xy, r)
    return xy, iterations, overlap


# --- dense fallback: largest-first insertion at corner positions -----------------------------------------


class _PlacedByClass:
    """Placed circles grouped by exact radius, for exact nearest-gap queries.

    Within one class all radii are equal, so the k nearest centres (KD-tree) are exactly the k smallest
    surface gaps of that class. The newest circles of a class sit in a small list searched by brute force;
    the class tree is rebuilt when that list grows past `rebuild`.
    """

    def __init__(self, class_radii: np.ndarray, rebuild: int = 128):
        self.class_radii = class_radii
        self.rebuild = rebuild
        self.stored = [np.empty((0, 2)) for _ in class_radii]
        self.trees: list[cKDTree | None] = [None for _ in class_radii]
        self.recent: list[list[np.ndarray]] = [[] for _ in class_radii]

    def add(self, q: int, xy: np.ndarray) -> None:
        self.recent[q].append(xy)
        if len(self.recent[q]) >= self.rebuild:
            self.stored[q] = self.centres(q)
            self.trees[q] = cKDTree(self.stored[q])
            self.recent[q] = []

    def centres(self, q: int) -> np.ndarray:
        return np.concatenate([self.stored[q], np.reshape(self.recent[q], (-1, 2))])

    def all(self) -> tuple[np.ndarray, np.ndarray]:
        xy = [self.centres(q) for q in range(len(self.class_radii))]
        r = [np.full(len(c), rq) for c, rq in zip(xy, self.class_radii, strict=True)]
        return np.concatenate(xy), np.concatenate(r)

    def excess(self, pts: np.ndarray, rho: float, clearance: np.ndarray, k: int = 3) -> np.ndarray:
        """The k smallest (surface gap − required clearance) from circles of radius `rho` at `pts`."""
        columns = [np.full((len(pts), k), np.inf)]
        for q, rq in enumerate(self.class_radii):
            offset = rq + rho + clearance[q]
            if len(self.stored[q]):
                kq = min(k, len(self.stored[q]))
                d, _ = self.trees[q].query(pts, k=kq)
                columns.append(np.reshape(d, (len(pts), kq)) - offset)
            if self.recent[q]:
                recent = np.asarray(self.recent[q])
                d = np.hypot(pts[:, None, 0] - recent[None, :, 0], pts[:, None, 1] - recent[None, :, 1])
                columns.append(d - offset)
        gaps = np.concatenate(columns, axis=1)
        return np.sort(np.partition(gaps, k - 1, axis=1)[:, :k], axis=1) if gaps.shape[1] > k else gaps

    def near(self, xy: np.ndarray, reach: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Centres and radii of the circles whose centre lies within reach[q] of `xy` (q: their class)."""
        found_xy, found_r = [], []
        for q, rq in enumerate(self.class_radii):
            if len(self.stored[q]):
                close = self.stored[q][self.trees[q].query_ball_point(xy, reach[q])]
                found_xy.append(close)
                found_r.append(np.full(len(close), rq))
            if self.recent[q]:
                recent = np.asarray(self.recent[q])
                close = recent[np.hypot(*(recent - xy).T) <= reach[q]]
                found_xy.append(close)
                found_r.append(np.full(len(close), rq))
        if not found_xy:
            return np.empty((0, 2)), np.empty(0)
        return np.concatenate(found_xy), np.concatenate(found_r)


def _tangent_points(ci: np.ndarray, ri: np.ndarray, cj: np.ndarray, rj: np.ndarray) -> np.ndarray:
    """Both points at distance ri from ci and rj from cj (pairs where the two circles intersect)."""
    delta = cj - ci
    d = np.hypot(*delta.T)
    ok = (d > 0.0) & (d <= ri + rj) & (d >= np.abs(ri - rj))
    delta, d, ci, ri, rj = delta[ok], d[ok], ci[ok], ri[ok], rj[ok]
    a = (ri**2 - rj**2 + d**2) / (2.0 * d)
    h = np.sqrt(np.maximum(ri**2 - a**2, 0.0))
    unit = delta / d[:, None]
    base = ci + a[:, None] * unit
    normal = np.stack([-unit[:, 1], unit[:, 0]], axis=1) * h[:, None]
    return np.concatenate([base + normal, base - normal])


def _wall_points(c: np.ndarray, reach: np.ndarray, rho: float, domain) -> np.ndarray:
    """Points on the walls' centre lines (offset rho inside) at distance `reach` from the centres c."""
    x0, y0, x1, y1 = domain
    found = []
    for axis, line in ((0, x0 + rho), (0, x1 - rho), (1, y0 + rho), (1, y1 - rho)):
        off = np.abs(c[:, axis] - line)
        ok = off <= reach
        h = np.sqrt(np.maximum(reach[ok] ** 2 - off[ok] ** 2, 0.0))
        for sign in (-1.0, 1.0):
            p = np.empty((int(ok.sum()), 2))
            p[:, axis] = line
            p[:, 1 - axis] = c[ok, 1 - axis] + sign * h
            found.append(p)
    return np.concatenate(found) if found else np.empty((0, 2))


def _corner_attempt(radii, domain, rng, gap, spread, noise, stop_on_failure):
    """One largest-first pass of corner insertion (see `corner_circles`). Returns centres and placed mask."""
    n = len(radii)
    order = np.argsort(-radii, kind="stable")
    class_radii = np.unique(radii)[::-1]
    placed_by_class = _PlacedByClass(class_radii)
    xy = np.full((n, 2), np.nan)
    placed = np.zeros(n, dtype=bool)
    x0, y0, x1, y1 = domain
    tol = 1e-9 * max(x1 - x0, y1 - y0)  # rounding of the tangent construction
    start = 0
    while start < n:
        q = int(np.flatnonzero(class_radii == radii[order[start]])[0])
        rho = float(class_radii[q])
        members = order[start : start + int(np.sum(radii == rho))]
        start += len(members)
        # the clearance a circle of this class keeps from each class: `spread` widens it within the class
        clearance = np.full(len(class_radii), gap)
        clearance[q] += 2.0 * spread * rho
        lo, hi = np.array([x0 + rho, y0 + rho]), np.array([x1 - rho, y1 - rho])
        if np.any(lo > hi + tol):
            if stop_on_failure:
                return xy, placed
            continue

        def feasible_scored(points, lo=lo, hi=hi, rho=rho, clearance=clearance):
            inside = np.all((points >= lo - tol) & (points <= hi + tol), axis=1)
            points = np.clip(points[inside], lo, hi)
            walls = np.concatenate([points - lo, hi - points], axis=1)
            three = np.sort(np.concatenate([placed_by_class.excess(points, rho, clearance), walls], 1), 1)
            ok = three[:, 0] >= -tol
            return points[ok], three[ok, :3]

        p_xy, p_r = placed_by_class.all()
        reach = p_r + rho + clearance[np.searchsorted(-class_radii, -p_r)] if len(p_r) else p_r
        points = [np.array([lo, [hi[0], lo[1]], [lo[0], hi[1]], hi])]
        if len(p_r):
            points.append(_wall_points(p_xy, reach, rho, domain))
            pairs = _close_pairs(p_xy, p_r, _size_groups(p_r), 2.0 * (rho + gap))
            if len(pairs):
                i, j = pairs[:, 0], pairs[:, 1]
                points.append(_tangent_points(p_xy[i], reach[i], p_xy[j], reach[j]))
        candidates, three = feasible_scored(np.concatenate(points))
        own_reach = 2.0 * rho + clearance[q]
        for k in members:
            if len(candidates) == 0:
                if stop_on_failure:
                    return xy, placed
                continue
            # hole degree: the third-smallest gap (the first two are the defining contacts); ties at random
            score = -three[:, 2] / rho + noise * rng.random(len(candidates))
            p = candidates[int(np.argmax(score))]
            xy[k], placed[k] = p, True
            placed_by_class.add(q, p)
            # the new circle invalidates candidates it covers and may lower their hole-degree gaps
            new_gap = np.hypot(*(candidates - p).T) - own_reach
            keep = new_gap >= -tol
            candidates = candidates[keep]
            three = np.sort(np.concatenate([three[keep], new_gap[keep, None]], 1), 1)[:, :3]
            # new corner positions: tangent to the new circle and a neighbour or a wall
            near_reach = own_reach + class_radii + rho + clearance
            n_xy, n_r = placed_by_class.near(p, near_reach)
            n_reach = n_r + rho + clearance[np.searchsorted(-class_radii, -n_r)]
            fresh = [
                _wall_points(p[None, :], np.array([own_reach]), rho, domain),
                _tangent_points(
                    np.repeat(p[None, :], len(n_r), 0), np.full(len(n_r), own_reach), n_xy, n_reach
                ),
            ]
            new_points, new_three = feasible_scored(np.concatenate(fresh))
            candidates = np.concatenate([candidates, new_points])
            three = np.concatenate([three, new_three])
    return xy, placed


CORNER_SPREADS = (0.0, 0.0025, 0.005, 0.0075, 0.01, 0.015)  # relative extra clearance within a size class
CORNER_NOISE = 0.05  # random tie-breaking between corner positions, in units of the circle's radius
CORNER_MAX_CLASSES = 32  # the corner packer queries per exact radius: only for a few distinct radii


def corner_circles(
    radii_m: np.ndarray,
    domain_m: tuple[float, float, float, float],
    rng: np.random.Generator,
    *,
    gap_m: float = DEFAULT_GAP_M,
    spreads: tuple[float, ...] = CORNER_SPREADS,
    noise: float = CORNER_NOISE,
) -> Packing:
    """Dense placement for targets the relaxation cannot reach: largest-first corner insertion.

    Circles are inserted one by one, largest first, each at a *corner position* — tangent (at the gap) to
    two objects among the placed circles and the four walls, overlapping nothing — choosing the position of
    maximum hole degree (the third-nearest object closest, i.e. the snuggest hole; Huang, Li, Akeb & Li
    2005, J. Oper. Res. Soc. 56: 539), ties broken at random with `rng`. Large floes first build a
    dense frame; each smaller class then fills the voids that are left (gap filling), so the small floes
    end up between the large ones. Every floe touches (at the gap) at least two neighbours or walls: the
    thesis' clustering objective (nearest gap → 0) holds by construction. A pass that cannot place a floe
    is repeated with floes of one class kept slightly further apart (`spreads`, relative extra clearance
    2·spread·r within the class): a touching frame of large floes can leave voids a hair too small for the
    next class (e.g. 15 m floes between 60 m ones), a frame opened by a few decimetres fits them.

    Returns the first complete packing, or the most complete one with `Packing.placed` marking the
    circles placed (the others are parked at the field's centre and overlap).
    """
    radii = np.asarray(radii_m, dtype=float)
    n = len(radii)
    x0, y0, x1, y1 = domain_m
    margin = 0.5 * gap_m  # walls keep half the floe gap, as in `relax_circles`
    domain = (x0 + margin, y0 + margin, x1 - margin, y1 - margin)
    best = None
    for k, spread in enumerate(spreads):
        last = k == len(spreads) - 1
        xy, placed = _corner_attempt(radii, domain, rng, gap_m, spread, noise, stop_on_failure=not last)
        cover = float(np.sum(radii[placed] ** 2))
        if best is None or cover > best[2]:
            best = (xy, placed, cover, spread)
        if np.all(placed):
            break
    xy, placed, _, spread = best
    if not np.all(placed) and best[3] != spreads[-1]:  # aborted pass: fill what fits, for the report
        xy, placed = _corner_attempt(radii, domain, rng, gap_m, spread, noise, stop_on_failure=False)
    xy = np.where(placed[:, None], xy, [[(x0 + x1) / 2.0, (y0 + y1) / 2.0]])
    overlap = max_pair_overlap_m(xy, radii) if n > 1 else -np.inf
    return Packing(xy, radii, overlap, 0, "corner", None if np.all(placed) else placed)


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
    iterations = int(result.get("nit", 0))  # none when the bounds fix every circle (scipy: no nit)
    return Packing(xy * scale, radii, max_pair_overlap_m(xy, r) * scale, iterations, "sqp")
