"""The point processes and line geometry the built-in exemplars are drawn with: numpy only, every random choice from
the ``numpy.random.Generator`` passed in, so an exemplar is the same on every machine and every run."""

import numpy as np

TAU = 2.0 * np.pi


def uniform(rng, lo, hi, density):
    """A Poisson process of ``density`` (per m²) in the box [lo, hi]: XY (N, 2)."""
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    count = rng.poisson(density * float(np.prod(hi - lo)))
    return rng.uniform(lo, hi, (count, 2))


def clustered(rng, lo, hi, parent_density, children, sigma, parents=None):
    """A Thomas cluster process: parents of ``parent_density`` in the box (or the ``parents`` given), each with a
    Poisson number (mean ``children``) of children spread normally by ``sigma`` metres around it; children outside
    the box are dropped. Returns (children XY (N, 2), parents XY (P, 2))."""
    if parents is None:
        parents = uniform(rng, lo, hi, parent_density)
    counts = rng.poisson(children, len(parents))
    xy = np.repeat(parents, counts, axis=0) + rng.normal(0.0, sigma, (int(counts.sum()), 2))
    return xy[inside(xy, lo, hi)], parents


def inside(xy, lo, hi):
    """bool (N,): which points lie in the box [lo, hi]."""
    return np.all((xy >= np.asarray(lo)) & (xy <= np.asarray(hi)), axis=1)


def hard_core(xy, min_distance, keep=()):
    """The candidates ``xy`` thinned in their order so that no two kept points (nor a kept one and a point of
    ``keep``) are closer than ``min_distance``: a sequential hard core. Returns the kept rows' indices."""
    cell = float(min_distance)
    grid: dict[tuple[int, int], list[tuple[float, float]]] = {}

    def near(p):
        i, j = int(np.floor(p[0] / cell)), int(np.floor(p[1] / cell))
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                for q in grid.get((i + di, j + dj), ()):
                    if (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 < cell * cell:
                        return True
        return False

    def put(p):
        grid.setdefault((int(np.floor(p[0] / cell)), int(np.floor(p[1] / cell))), []).append((p[0], p[1]))

    for p in np.asarray(keep, dtype=np.float64).reshape(-1, 2):
        put(p)
    kept = []
    for k, p in enumerate(np.asarray(xy, dtype=np.float64)):
        if not near(p):
            put(p)
            kept.append(k)
    return np.asarray(kept, dtype=np.int64)


def farther_than(xy, points, distance):
    """The rows of ``xy`` at ``distance`` metres or more from every one of ``points``."""
    xy, points = np.asarray(xy, dtype=np.float64).reshape(-1, 2), np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not len(points):
        return xy
    nearest = np.sqrt(((xy[:, None, :] - points[None]) ** 2).sum(axis=2)).min(axis=1)
    return xy[nearest >= distance]


def thinned(rng, xy, probability):
    """The rows of ``xy`` kept each with its ``probability`` (N,) or a scalar one."""
    return xy[rng.random(len(xy)) < probability]


def segments(polylines):
    """(starts (M, 2), ends (M, 2)) of every segment of the polylines (N_k, 2)."""
    starts = np.concatenate([p[:-1] for p in polylines])
    ends = np.concatenate([p[1:] for p in polylines])
    return starts, ends


def distance_to(xy, polylines):
    """The distance from each point (N, 2) to the nearest segment of the polylines."""
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    if not len(xy) or not polylines:
        return np.full(len(xy), np.inf)
    starts, ends = segments(polylines)
    d = ends - starts
    length2 = np.maximum((d * d).sum(axis=1), 1e-12)
    best = np.full(len(xy), np.inf)
    for chunk in range(0, len(xy), 512):  # bounded memory for many points and segments
        p = xy[chunk:chunk + 512, None, :]
        t = np.clip(((p - starts[None]) * d[None]).sum(axis=2) / length2, 0.0, 1.0)
        nearest = starts[None] + t[..., None] * d[None]
        best[chunk:chunk + 512] = np.sqrt(((p - nearest) ** 2).sum(axis=2)).min(axis=1)
    return best


def along(polyline, spacing, rng=None, jitter=0.0, start=0.0):
    """Stations every ``spacing`` metres (moved by up to ``jitter`` of a spacing) along a polyline (N, 2): their XY
    (M, 2) and unit tangents (M, 2)."""
    polyline = np.asarray(polyline, dtype=np.float64)
    steps = np.diff(polyline, axis=0)
    lengths = np.linalg.norm(steps, axis=1)
    cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
    s = np.arange(start, cumulative[-1], spacing)
    if rng is not None and jitter > 0.0:
        s = np.clip(s + rng.uniform(-jitter, jitter, len(s)) * spacing, 0.0, cumulative[-1] - 1e-9)
    k = np.clip(np.searchsorted(cumulative, s, side="right") - 1, 0, len(steps) - 1)
    tangent = steps[k] / np.maximum(lengths[k], 1e-12)[:, None]
    return polyline[k] + tangent * (s - cumulative[k])[:, None], tangent


def beside(rng, polyline, spacing, offset, jitter=0.25):
    """Points on both sides of a polyline: a station every ``spacing`` metres per side, pushed out across it by a
    distance drawn uniformly from ``offset`` (lo, hi). Returns XY (N, 2) and the heading (N,) facing the line."""
    xy, heading = [], []
    for side in (-1.0, 1.0):
        at, tangent = along(polyline, spacing, rng, jitter, start=rng.uniform(0.0, spacing))
        normal = side * np.column_stack([-tangent[:, 1], tangent[:, 0]])
        xy.append(at + normal * rng.uniform(*offset, (len(at), 1)))
        heading.append(np.arctan2(-normal[:, 1], -normal[:, 0]))
    return np.concatenate(xy), np.mod(np.concatenate(heading), TAU)


def meander(rng, start, end, spacing, amplitude, wavelength):
    """A polyline from ``start`` to ``end`` with a vertex every ``spacing`` metres, swinging sideways in two seeded
    sine waves (``amplitude`` metres, ``wavelength`` metres for the longer one) between its two ends: a stream's or
    a street's course."""
    start, end = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
    length = float(np.linalg.norm(end - start))
    t = np.linspace(0.0, 1.0, max(int(round(length / spacing)), 1) + 1)
    phases = rng.uniform(0.0, TAU, 2)
    s = t * length
    swing = amplitude * (np.sin(TAU * s / wavelength + phases[0]) + 0.4 * np.sin(TAU * s / (0.45 * wavelength)
                                                                                    + phases[1]))
    swing -= swing[0] + (swing[-1] - swing[0]) * t  # it starts and ends exactly at its ends (a junction)
    direction = (end - start) / max(length, 1e-12)
    normal = np.array([-direction[1], direction[0]])
    return start + np.outer(s, direction) + np.outer(swing, normal)


def bent(rng, a, b, bend):
    """The segment a-b with its middle moved sideways by a normal draw of ``bend`` metres: a street's gentle kink."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    d = b - a
    normal = np.array([-d[1], d[0]]) / max(float(np.linalg.norm(d)), 1e-12)
    return np.array([a, 0.5 * (a + b) + normal * rng.normal(0.0, bend), b])
