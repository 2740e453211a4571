"""The exemplars of the built-in colors, built by code: each a seeded arrangement on its own terrain, as the engine's
scene arrays, learned when an artist appends the color (``learn``).

Every exemplar is a square region from the origin on a grid terrain reaching ``MARGIN`` beyond it (so the synthesis
around the region reads terrain); graph categories (streets, streams, lanes) are polylines that may run on beyond
the region, as drawn roads do. Categories are listed in their priority order: graphs first, then the distributions
that follow them, rarest first (as Learn Color orders a hand-made example).
"""

from dataclasses import dataclass, field

import numpy as np

from ..bridge import engine
from . import sampling
from .sampling import TAU

MARGIN = 60.0  # metres of terrain around an exemplar's region
CELL = 2.0  # the exemplar terrains' sample spacing, as the demo terrain's


def hills(rng, size, relief):
    """Smooth seeded hills over the exemplar's square and its margin, built as the engine's demo terrain is (six
    waves, the k-th ``size / (1 + k + u)`` long and ``relief * size / (1 + k)`` high): at the demo's relief (0.05)
    their slopes spread as the demo terrain's do. Returns the engine Terrain."""
    n = int(round((size + 2.0 * MARGIN) / CELL)) + 1
    x, y = np.meshgrid(-MARGIN + CELL * np.arange(n), -MARGIN + CELL * np.arange(n))
    heights = np.zeros_like(x)
    for k in range(6):
        angle, phase = rng.uniform(0.0, TAU, 2)
        wavelength = size / (1.0 + k + rng.random())
        heights += relief * size / (1.0 + k) * np.sin(TAU / wavelength * (np.cos(angle) * x + np.sin(angle) * y)
                                                      + phase)
    return engine.terrain_from_grid((-MARGIN, -MARGIN), CELL, heights)


@dataclass
class Exemplar:
    """An exemplar as the engine takes it: its terrain, categories (engine dicts, in priority order), instance
    columns and paths, in the square [0, size]²."""

    size: float
    terrain: "engine.Terrain"
    rng: np.random.Generator
    categories: list = field(default_factory=list)
    columns: dict = field(default_factory=lambda: {"positions": [], "category_index": [], "rotations": [],
                                                    "scales": []})
    paths: list = field(default_factory=list)
    pattern_region: dict | None = None  # an arrangement's reference region (None: the exemplar is learned whole)

    @property
    def region(self):
        """The region the color is learned from: the reference of an arrangement, else the whole square."""
        return self.pattern_region or {"shape": "rect", "min": [0.0, 0.0], "max": [self.size, self.size]}

    @property
    def box(self):
        return (0.0, 0.0), (self.size, self.size)

    def category(self, name, kind="distribution", layer="vegetation"):
        """The index of category ``name``, added (after the others in priority) the first time it is named."""
        names = [c["name"] for c in self.categories]
        if name in names:
            return names.index(name)
        self.categories.append({"name": name, "layer": layer, "kind": kind, "priority": len(self.categories)})
        return len(self.categories) - 1

    def add(self, name, xy, rotations=None, scales=(0.8, 1.2)):
        """Instances of ``name`` at XY (N, 2) inside the region; rotations (N,) drawn at random when not given,
        scales drawn uniformly from ``scales`` (lo, hi)."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        keep = sampling.inside(xy, *self.box)
        xy = xy[keep]
        rotations = self.rng.uniform(0.0, TAU, len(xy)) if rotations is None else np.asarray(rotations)[keep]
        self.columns["positions"].append(xy)
        self.columns["category_index"].append(np.full(len(xy), self.category(name), dtype=np.int32))
        self.columns["rotations"].append(rotations)
        low, high = scales
        self.columns["scales"].append(self.rng.uniform(low, high, len(xy)))
        return xy

    def add_path(self, name, points, layer):
        self.paths.append({"category": self.category(name, "graph", layer),
                           "points": np.ascontiguousarray(points, dtype=np.float64), "locked": True})

    def polylines(self, name):
        index = self.category(name)
        return [p["points"] for p in self.paths if p["category"] == index]

    def slope_degrees(self, xy):
        return np.degrees(self.terrain.map_at("slope", np.ascontiguousarray(xy, dtype=np.float64)))

    def counts(self):
        """{category: instances (or paths of a graph)} of the exemplar."""
        index = np.concatenate(self.columns["category_index"]) if self.columns["category_index"] else []
        out = {}
        for k, c in enumerate(self.categories):
            out[c["name"]] = (sum(p["category"] == k for p in self.paths) if c["kind"] == "graph"
                              else int(np.sum(np.asarray(index) == k)))
        return out

    def engine_scene(self):
        """The engine's Scene of the exemplar."""
        n = sum(len(xy) for xy in self.columns["positions"])
        columns = {key: np.concatenate(values) if values else np.zeros(0) for key, values in self.columns.items()}
        instances: engine.SceneColumns = {
            "categories": self.categories,
            "positions": np.ascontiguousarray(columns["positions"], dtype=np.float64).reshape(-1, 2),
            "category_index": np.ascontiguousarray(columns["category_index"], dtype=np.int32),
            "rotations": np.ascontiguousarray(columns["rotations"], dtype=np.float64),
            "scales": np.ascontiguousarray(columns["scales"], dtype=np.float64),
            "prototype": np.zeros(n, dtype=np.int32),
            "locked": np.ones(n, dtype=bool),
            "tints": np.zeros(n, dtype=np.float64),
        }
        return engine.scene(self.terrain, instances, {"paths": self.paths, "contours": []})


def start(seed, size, relief):
    rng = np.random.default_rng(seed)
    return Exemplar(size, hills(rng, size, relief), rng)


def kept(xy, min_distance, keep=()):
    return xy[sampling.hard_core(xy, min_distance, keep)]


# --- the exemplars ------------------------------------------------------------------------------------------------

def pine_slope(seed=11):
    """Pines standing 3 m apart or more, denser the steeper the hillside (sparse on the flat), and boulders among
    them, more of them on steep ground."""
    ex = start(seed, 160.0, 0.06)
    lo, hi = ex.box
    rocks = sampling.uniform(ex.rng, lo, hi, 0.006)
    rocks = sampling.thinned(ex.rng, rocks, np.clip(ex.slope_degrees(rocks) / 30.0, 0.15, 1.0))
    rocks = ex.add("Boulder", kept(rocks, 4.0), scales=(0.6, 1.4))
    pines = sampling.uniform(ex.rng, lo, hi, 0.08)
    pines = sampling.thinned(ex.rng, pines, np.clip((ex.slope_degrees(pines) - 4.0) / 20.0, 0.08, 1.0))
    ex.add("Pine", kept(pines, 3.0, keep=rocks), scales=(0.75, 1.3))
    return ex


def broadleaf_grove(seed=12):
    """Groves of broadleaf trees (clusters about 9 m across, trees 5 m apart or more) with shrubs around their
    edges and a few in the open."""
    ex = start(seed, 160.0, 0.035)
    lo, hi = ex.box
    trees, groves = sampling.clustered(ex.rng, lo, hi, 0.0007, 14.0, 9.0)
    trees = ex.add("Broadleaf", kept(trees, 5.0), scales=(0.8, 1.25))
    shrubs, _ = sampling.clustered(ex.rng, lo, hi, 0.0, 22.0, 14.0, parents=groves)
    shrubs = np.concatenate([shrubs, sampling.uniform(ex.rng, lo, hi, 0.001)])
    ex.add("Shrub", kept(shrubs, 1.8, keep=trees), scales=(0.7, 1.3))
    return ex


def meadow_with_boulders(seed=13):
    """Grass tufts over a meadow, thicker around small groups of boulders."""
    ex = start(seed, 120.0, 0.03)
    lo, hi = ex.box
    rocks, _ = sampling.clustered(ex.rng, lo, hi, 0.0006, 3.0, 2.5)
    rocks = ex.add("Boulder", kept(rocks, 1.8), scales=(0.5, 1.2))
    around, _ = sampling.clustered(ex.rng, lo, hi, 0.0, 12.0, 2.0, parents=rocks)
    grass = np.concatenate([sampling.uniform(ex.rng, lo, hi, 0.04), around])
    ex.add("Grass tuft", kept(sampling.farther_than(grass, rocks, 1.0), 0.6), scales=(0.7, 1.4))
    return ex


def scrub(seed=14):
    """Dry scrub: junipers 7 m apart or more, patches of shrubs between them and stones scattered over it all."""
    ex = start(seed, 140.0, 0.045)
    lo, hi = ex.box
    junipers = ex.add("Juniper", kept(sampling.uniform(ex.rng, lo, hi, 0.004), 7.0), scales=(0.7, 1.3))
    shrubs, _ = sampling.clustered(ex.rng, lo, hi, 0.0012, 7.0, 3.5)
    shrubs = ex.add("Shrub", kept(shrubs, 1.8, keep=junipers), scales=(0.6, 1.2))
    stones = sampling.uniform(ex.rng, lo, hi, 0.004)
    ex.add("Stone", kept(stones, 1.0, keep=np.concatenate([junipers, shrubs])), scales=(0.5, 1.5))
    return ex


def riverside_reeds(seed=15):
    """A meandering stream with brooks joining it, dense reed beds along their banks and willows a little farther
    out."""
    ex = start(seed, 160.0, 0.02)
    lo, hi = ex.box
    stream = sampling.meander(ex.rng, (-50.0, 45.0), (210.0, 115.0), 20.0, 10.0, 120.0)
    streams = [stream] + branches(ex.rng, stream, (3, 6, 9), (60.0, 100.0), 20.0, meandering=True)
    for line in streams:
        ex.add_path("Stream", line, "water")
    sides = [sampling.beside(ex.rng, line, 24.0, (7.0, 11.0)) for line in streams]
    bank, heading = np.concatenate([p for p, _ in sides]), np.concatenate([h for _, h in sides])
    clear = sampling.distance_to(bank, streams) >= 6.5  # not on a brook of the other side
    bank, heading = bank[clear], heading[clear]
    order = sampling.hard_core(bank, 9.0)
    willows = ex.add("Willow", bank[order], heading[order], scales=(0.8, 1.2))
    beds = np.concatenate([sampling.beside(ex.rng, line, 5.0, (3.8, 5.5))[0] for line in streams])
    reeds, _ = sampling.clustered(ex.rng, lo, hi, 0.0, 9.0, 1.3, parents=beds)
    distance = sampling.distance_to(reeds, streams)
    reeds = reeds[(distance >= 3.2) & (distance <= 8.0)]
    ex.add("Reed", kept(reeds, 0.45, keep=willows), scales=(0.7, 1.3))
    return ex


def branches(rng, main, nodes, lengths, spacing, meandering=False):
    """Lines leaving the polyline ``main`` at its vertices ``nodes``, to alternate sides, each ``lengths`` (lo, hi)
    metres long with a vertex every ``spacing`` metres: side lanes of a street, brooks joining a stream."""
    out = []
    for k, node in enumerate(nodes):
        side = 1.0 if k % 2 else -1.0
        tangent = main[node + 1] - main[node - 1]
        tangent /= np.linalg.norm(tangent)
        normal = side * np.array([-tangent[1], tangent[0]])
        end = main[node] + normal * rng.uniform(*lengths) + tangent * rng.normal(0.0, 0.2 * lengths[0])
        if meandering:
            out.append(sampling.meander(rng, main[node], end, spacing, 0.06 * lengths[0], lengths[1]))
        else:
            line = sampling.bent(rng, main[node], end, 5.0)
            out.append(np.vstack([line[:2], 0.5 * (line[1] + line[2]), line[2]]))
    return out


def orchard_rows(seed=16):
    """A planted block of fruit trees, 6 rows of 10, 5 m apart in a row and 7 m between rows, each row shifted by
    a third of a step so the pattern's triangulation has one way to fall; learned as an arrangement."""
    ex = start(seed, 80.0, 0.01)
    rows, cols, along, between, shear = 6, 10, 5.0, 7.0, 0.3
    row, col = np.divmod(np.arange(rows * cols), cols)
    xy = np.column_stack([(col + shear * row) * along, row * between]) + np.array([10.0, 12.0])
    xy += ex.rng.uniform(-0.08, 0.08, xy.shape)
    ex.category("Fruit tree", "arrangement", "pattern")
    ex.add("Fruit tree", xy, scales=(0.9, 1.1))
    ex.pattern_region = {"shape": "rect", "min": [9.0, 11.0],
                         "max": [10.0 + ((cols - 1) + shear * (rows - 1)) * along + 1.0,
                                 12.0 + (rows - 1) * between + 1.0]}
    return ex


def hamlet_street(seed=17):
    """A hamlet: a winding main street with side lanes, cottages facing it 7-11 m from its middle, and garden
    trees behind them."""
    ex = start(seed, 200.0, 0.035)
    lo, hi = ex.box
    main = sampling.meander(ex.rng, (-40.0, 92.0), (240.0, 112.0), 20.0, 6.0, 160.0)
    streets = [main] + branches(ex.rng, main, (3, 7, 11), (55.0, 85.0), 20.0)
    for street in streets:
        ex.add_path("Street", street, "settlement")
    sides = [sampling.beside(ex.rng, s, 15.0, (7.0, 11.0)) for s in streets]
    xy, heading = np.concatenate([p for p, _ in sides]), np.concatenate([h for _, h in sides])
    distance = sampling.distance_to(xy, streets)
    facing = (distance >= 6.5) & (distance <= 12.0)
    xy, heading = xy[facing], heading[facing]
    order = sampling.hard_core(xy, 10.0)
    cottages = ex.add("Cottage", xy[order], heading[order], scales=(0.85, 1.15))
    gardens = sampling.uniform(ex.rng, lo, hi, 0.006)
    distance = sampling.distance_to(gardens, streets)
    gardens = gardens[(distance >= 15.0) & (distance <= 32.0)]
    ex.add("Garden tree", kept(gardens, 6.0, keep=cottages), scales=(0.8, 1.2))
    return ex


def farmland_hedges(seed=18):
    """Fields about 70 m across edged by farm lanes, hedges of bushes lining one side of each lane and a few oaks
    standing in the hedgerows."""
    ex = start(seed, 220.0, 0.035)
    spacing, n = 70.0, 5
    at = np.arange(n) * spacing - 35.0
    nodes = np.stack(np.meshgrid(at, at), axis=-1).reshape(-1, 2) + ex.rng.normal(0.0, 10.0, (n * n, 2))
    edges = [(j * n + i, j * n + i + 1) for j in range(n) for i in range(n - 1)]
    edges += [(j * n + i, (j + 1) * n + i) for j in range(n - 1) for i in range(n)]
    edges = [edges[k] for k in ex.rng.permutation(len(edges))]
    parent = list(range(n * n))

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    lanes = []
    for a, b in edges:  # a spanning tree keeps every field reachable; a share of the other edges closes fields
        ra, rb = root(a), root(b)
        if ra != rb or ex.rng.random() < 0.6:
            parent[ra] = rb
            lanes.append(sampling.bent(ex.rng, nodes[a], nodes[b], 4.0))
    for lane in lanes:
        ex.add_path("Field lane", lane, "farmland")
    oaks = np.concatenate([sampling.beside(ex.rng, lane, 35.0, (3.0, 4.5))[0] for lane in lanes])
    oaks = ex.add("Field oak", kept(oaks[sampling.distance_to(oaks, lanes) >= 2.8], 16.0), scales=(0.85, 1.2))
    hedges = []
    for lane in lanes:
        side = ex.rng.choice([-1.0, 1.0])
        stations, tangent = sampling.along(lane, 2.2, ex.rng, 0.15)
        normal = side * np.column_stack([-tangent[:, 1], tangent[:, 0]])
        hedges.append(stations + normal * ex.rng.uniform(2.4, 3.2, (len(stations), 1)))
    hedges = np.concatenate(hedges)
    hedges = hedges[sampling.distance_to(hedges, lanes) >= 2.2]  # where a hedge meets a crossing lane it stops
    ex.add("Hedge bush", kept(hedges, 1.4, keep=oaks), scales=(0.8, 1.2))
    return ex
