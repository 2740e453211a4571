//! The size of synthesized islands. The dense points of a polygon category are synthesized by their rdf (module
//! `rdf`) and traced into contours (`crate::contour::trace`); the rdf holds the land share and the points'
//! clustering, but not how the land splits into islands: one island of the learned size and two of half its
//! size have much the same pair counts at short range, and the chain's tiles, which move points only within
//! themselves, break the larger clusters sooner than they build them. An archipelago came out with twice the
//! exemplar's contours per area at half their size, and more iterations made it worse; from a small exemplar
//! (four islands) the chain leaves a few large clusters and dozens of strays of a few points each, which trace
//! as islets of a few spacings².
//!
//! So the traced islands (outer contours with their lakes, [`crate::contour::islands`]) are matched to the
//! learned ones ([`PolygonColor::islands_per_area`], [`PolygonColor::island_areas`],
//! [`PolygonColor::lakes_per_area`]) after tracing. The islands the pass may change are the synthesis's own:
//! those within one spacing of the region (the trace rounds a coast up to about half a spacing beyond its
//! points), not the coasts merged from around it.
//!
//! * **Count.** The region should hold `N = islands per area × its area` islands (by their centroids, as they
//!   were learned). While it holds more, the smallest of its own islands is removed with its lakes, as long as it
//!   is smaller than the learned median island: islands of the learned sizes stay, and islands the synthesis
//!   makes too large are left as they are.
//! * **Lakes.** Likewise, while the region holds more lakes than the learned lakes per area give, the smallest
//!   lake of its own islands is filled (a loose cluster traces with holes the exemplar never had).
//! * **Land.** The region's islands should hold the land of the dense points (one spacing² each, as `fill`
//!   lays them): the land share the chain matched, which the removed islets held and which the trace loses on
//!   loose clusters. The islands that stay get target areas from the learned ones by rank (the `r`-th smallest
//!   of `K` gets the learned quantile `(r + ½) / K`), scaled to that land, and grow towards them: their coast
//!   moves out evenly (cells of a lattice of one spacing, nearest to the coast first, each joined to the island)
//!   within the region and at least `GAP_SPACINGS` spacings clear of every other island, the sea it encloses
//!   joins it (no lake the learned count did not ask for), and the grown island is traced again from its cells,
//!   as one island. Land an island cannot take (near the border, crowded) goes to those that can, over a few
//!   passes. Should the islands still lose more than `LAND_LOSS` of the traced land, they stay as
//!   traced: the land share matters more than their count.
//!
//! Why not a term of the rdf chain or births of whole islands: the chain moves single points in parallel
//! tiles, and a term on component sizes needs the connectivity of the whole region at every move; whole-island
//! births would bypass the dense points that carry the islands' interactions with the categories around them.
//! Here the islands that stay are the chain's largest clusters, where it put them. The pass is deterministic
//! (islands in order of area, then of tracing; the growth's ties broken by lattice index).

use crate::analysis::structure::centroid;
use crate::contour::{islands, trace_contours, Island, Polygons};
use crate::geom::{polygon_contains, polygon_signed_area, DVec2, PreparedRegion, RegionQueries};
use crate::grid::Grid;
use crate::palette::PolygonColor;
use crate::search::MinHeap;

/// Islands are kept at least this many dense-point spacings apart when they grow.
const GAP_SPACINGS: f64 = 2.0;
/// The largest share of the traced land the matching may lose (when the islands that stay cannot grow).
const LAND_LOSS: f64 = 0.1;
/// Passes of growth: the land an island could not take goes to the others in the next one.
const GROWTH_PASSES: usize = 4;

/// The traced contours with their islands matched to the learned count and sizes (see the module
/// documentation). `dense_land` is the land of the dense points traced (their count × spacing²), `obstacles`
/// the other contours of the category (kept, not traced again), `area` the region's.
pub(super) fn match_sizes(
    traced: Vec<Vec<DVec2>>,
    dense_land: f64,
    pc: Option<&PolygonColor>,
    obstacles: &Polygons,
    region: &PreparedRegion,
    area: f64,
) -> Vec<Vec<DVec2>> {
    let Some(pc) = pc.filter(|pc| pc.islands_per_area > 0.0 && !pc.island_areas.is_empty()) else {
        return traced;
    };
    let all = islands(&traced);
    let spacing = pc.spacing;
    let own: Vec<bool> = all
        .iter()
        .map(|i| {
            traced[i.outer]
                .iter()
                .all(|p| region.distance_outside(*p) <= spacing)
        })
        .collect();
    let counted = |i: &Island| region.contains(centroid(&traced[i.outer]));
    let traced_land: f64 = all.iter().map(|i| i.area).sum();

    // count: the smallest of the region's own islands go first (stable: ties keep the tracing order)
    let target = (pc.islands_per_area * area).round().max(1.0) as usize;
    let median = pc.island_areas[pc.island_areas.len() / 2];
    let kept = islands_kept(&all, &own, &counted, target, median);

    // lakes: the smallest lakes of the region's own islands are filled
    let contour_area = |c: usize| polygon_signed_area(&traced[c]).abs();
    let filled = lakes_filled(
        &traced,
        &all,
        &kept,
        &own,
        &counted,
        pc.lakes_per_area.map(|l| l * area),
    );
    let land = |k: usize| {
        all[k].area
            + all[k]
                .lakes
                .iter()
                .filter(|&&c| filled[c])
                .map(|&c| contour_area(c))
                .sum::<f64>()
    };

    // land: the region's own islands grow towards their learned sizes by rank
    let growing: Vec<usize> = kept.iter().copied().filter(|&k| own[k]).collect();
    let fixed: f64 = kept.iter().filter(|&&k| !own[k]).map(|&k| land(k)).sum();
    let mut ranked = growing.clone();
    ranked.sort_by(|&a, &b| land(a).total_cmp(&land(b)));
    let quantiles: Vec<f64> = (0..ranked.len())
        .map(|r| quantile(&pc.island_areas, (r as f64 + 0.5) / ranked.len() as f64))
        .collect();
    let goal = (dense_land - fixed).max(0.0);
    let scale = goal / quantiles.iter().sum::<f64>().max(1e-12);
    let mut want = vec![0.0; all.len()];
    for (&k, q) in ranked.iter().zip(&quantiles) {
        want[k] = (q * scale - land(k)).max(0.0);
    }
    let needed = goal - growing.iter().map(|&k| land(k)).sum::<f64>();
    let wanted: f64 = want.iter().sum();
    if wanted > 0.0 {
        // islands above their target keep their land: the others take what remains
        let share = (needed / wanted).clamp(0.0, 1.0);
        want.iter_mut().for_each(|w| *w *= share);
    }
    let mut grown = vec![0.0; all.len()];
    let mut cells: Vec<Option<Vec<DVec2>>> = vec![None; all.len()];
    if needed > spacing * spacing {
        if let Some(mut coast) =
            Coast::new(&traced, &all, &kept, &filled, obstacles, region, spacing)
        {
            coast.grow_all(&growing, &mut want, &mut grown);
            for &k in &growing {
                if grown[k] > 0.0 {
                    grown[k] += coast.fill_pockets(k);
                    cells[k] = Some(coast.land_of(k));
                }
            }
        }
    }

    // islands too close to the border or to each other to grow would lose the land the chain matched: the
    // islands stay as traced rather than the land share falling
    let final_land: f64 = kept.iter().map(|&k| land(k) + grown[k]).sum();
    if final_land < (1.0 - LAND_LOSS) * traced_land {
        return traced;
    }
    contours_of(&traced, &all, &kept, &cells, &filled, spacing)
}

/// The islands kept so that the region holds `target` of those `counted` in it: the smallest of its `own` islands
/// under the `median` learned size go first (stable: ties keep the tracing order).
fn islands_kept(
    all: &[Island],
    own: &[bool],
    counted: &dyn Fn(&Island) -> bool,
    target: usize,
    median: f64,
) -> Vec<usize> {
    let mut order: Vec<usize> = (0..all.len()).filter(|&k| own[k]).collect();
    order.sort_by(|&a, &b| all[a].area.total_cmp(&all[b].area));
    let mut removed = vec![false; all.len()];
    let mut count = all.iter().filter(|i| counted(i)).count();
    for &k in &order {
        if count <= target || all[k].area >= median {
            break;
        }
        removed[k] = true;
        count -= 1;
    }
    (0..all.len()).filter(|&k| !removed[k]).collect()
}

/// Which lakes are filled so that the region's islands hold `lakes_wanted` lakes (None: as traced): the smallest
/// lakes of the region's `own` islands first, counting those of the islands `counted` in the region.
fn lakes_filled(
    traced: &[Vec<DVec2>],
    all: &[Island],
    kept: &[usize],
    own: &[bool],
    counted: &dyn Fn(&Island) -> bool,
    lakes_wanted: Option<f64>,
) -> Vec<bool> {
    let contour_area = |c: usize| polygon_signed_area(&traced[c]).abs();
    let mut filled = vec![false; traced.len()];
    if let Some(lakes_wanted) = lakes_wanted {
        let lake_target = lakes_wanted.round() as usize;
        let mut lakes = kept
            .iter()
            .filter(|&&k| counted(&all[k]))
            .map(|&k| all[k].lakes.len())
            .sum::<usize>();
        let mut fillable: Vec<usize> = kept
            .iter()
            .filter(|&&k| own[k])
            .flat_map(|&k| all[k].lakes.iter().copied())
            .collect();
        fillable.sort_by(|&a, &b| contour_area(a).total_cmp(&contour_area(b)));
        for c in fillable {
            if lakes <= lake_target {
                break;
            }
            filled[c] = true;
            lakes -= 1;
        }
    }
    filled
}

/// The contours of the `kept` islands: those grown as their lattice `cells` traced (the largest piece), the others
/// as traced with their lakes that are not `filled`.
fn contours_of(
    traced: &[Vec<DVec2>],
    all: &[Island],
    kept: &[usize],
    cells: &[Option<Vec<DVec2>>],
    filled: &[bool],
    spacing: f64,
) -> Vec<Vec<DVec2>> {
    let mut out = Vec::new();
    for &k in kept {
        match &cells[k] {
            Some(points) => {
                // one island: a piece the lattice leaves apart (a neck thinner than a spacing) is dropped
                let loops = trace_contours(points, spacing);
                let largest = islands(&loops)
                    .into_iter()
                    .max_by(|a, b| a.area.total_cmp(&b.area));
                if let Some(i) = largest {
                    out.extend(
                        std::iter::once(i.outer)
                            .chain(i.lakes)
                            .map(|c| loops[c].clone()),
                    );
                }
            }
            None => out.extend(
                std::iter::once(all[k].outer)
                    .chain(all[k].lakes.iter().copied().filter(|&c| !filled[c]))
                    .map(|c| traced[c].clone()),
            ),
        }
    }
    out
}

/// The `q`-quantile of ascending `values` (not empty), interpolated between order statistics at `(i + ½) / n`.
fn quantile(values: &[f64], q: f64) -> f64 {
    let n = values.len();
    let at = (q * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
    let (i, t) = (at.floor() as usize, at.fract());
    let next = values[(i + 1).min(n - 1)];
    values[i] + t * (next - values[i])
}

/// Sea on the lattice of the islands' coasts.
const SEA: u32 = u32::MAX;

/// The islands on a lattice of one spacing over the region: which island each node belongs to (its lakes
/// included), and which nodes are water inside an island.
struct Coast<'a> {
    grid: Grid,
    owner: Vec<u32>,
    lake: Vec<bool>,
    /// The nodes of each island (by index in `all`), so that work on one island stays near it.
    members: Vec<Vec<usize>>,
    /// Outer contour of each island, for the distance its coast moves.
    outers: Vec<Option<Polygons>>,
    obstacles: &'a Polygons,
    region: &'a PreparedRegion<'a>,
    /// Lattice offsets within the gap kept between islands.
    gap_offsets: Vec<(i64, i64)>,
    gap: f64,
    /// The nodes a growth has queued, by the growth's stamp.
    seen: Vec<u32>,
    stamp: u32,
}

impl<'a> Coast<'a> {
    /// The lattice with the `kept` islands of `all` (their `filled` lakes as land); `None` when the region is
    /// too large for one.
    fn new(
        traced: &[Vec<DVec2>],
        all: &[Island],
        kept: &[usize],
        filled: &[bool],
        obstacles: &'a Polygons,
        region: &'a PreparedRegion<'a>,
        spacing: f64,
    ) -> Option<Coast<'a>> {
        let gap = GAP_SPACINGS * spacing;
        let (lo, hi) = region.bbox();
        let pad = DVec2::splat(gap + 2.0 * spacing);
        let grid = Grid::nodes_covering(lo - pad, hi + pad, spacing).ok()?;
        let mut owner = vec![SEA; grid.len()];
        let mut lake = vec![false; grid.len()];
        // larger islands first, so that an island in another's lake takes its nodes back
        let mut by_size = kept.to_vec();
        by_size.sort_by(|&a, &b| {
            let area = |k: usize| polygon_signed_area(&traced[all[k].outer]).abs();
            area(b).total_cmp(&area(a))
        });
        let mut outers: Vec<Option<Polygons>> = (0..all.len()).map(|_| None).collect();
        let mut inside: Vec<Vec<usize>> = vec![Vec::new(); all.len()];
        for &k in &by_size {
            let outer = &traced[all[k].outer];
            inside[k] = nodes_inside(&grid, outer);
            for &n in &inside[k] {
                owner[n] = k as u32;
                lake[n] = false;
            }
            for &c in all[k].lakes.iter().filter(|&&c| !filled[c]) {
                for n in nodes_inside(&grid, &traced[c]) {
                    lake[n] = true;
                }
            }
            outers[k] = Some(Polygons::new(std::slice::from_ref(outer)));
        }
        // an island's nodes less those of the islands in its lakes
        let members = inside
            .into_iter()
            .enumerate()
            .map(|(k, nodes)| {
                nodes
                    .into_iter()
                    .filter(|&n| owner[n] == k as u32)
                    .collect()
            })
            .collect();
        let r = (gap / spacing).ceil() as i64;
        let gap_offsets = (-r..=r)
            .flat_map(|j| (-r..=r).map(move |i| (i, j)))
            .filter(|&(i, j)| ((i * i + j * j) as f64).sqrt() * spacing <= gap + 1e-9)
            .collect();
        let seen = vec![0; grid.len()];
        Some(Coast {
            grid,
            owner,
            lake,
            members,
            outers,
            obstacles,
            region,
            gap_offsets,
            gap,
            seen,
            stamp: 0,
        })
    }

    /// Grows the `growing` islands by `want` (m² each) over the passes, adding what each took to `grown`.
    fn grow_all(&mut self, growing: &[usize], want: &mut [f64], grown: &mut [f64]) {
        let cell_area = self.grid.cell * self.grid.cell;
        let mut open = vec![true; want.len()];
        for _ in 0..GROWTH_PASSES {
            let mut short = 0.0;
            for &k in growing {
                if want[k] < 0.5 * cell_area {
                    continue;
                }
                let took = self.grow(k, want[k]);
                grown[k] += took;
                if took + 0.5 * cell_area < want[k] {
                    short += want[k] - took;
                    open[k] = false;
                }
                want[k] = 0.0;
            }
            let takers: Vec<usize> = growing.iter().copied().filter(|&k| open[k]).collect();
            if short < cell_area || takers.is_empty() {
                break;
            }
            // what the blocked islands could not take goes to the others, by their size
            let sizes: f64 = takers.iter().map(|&k| self.land_of(k).len() as f64).sum();
            for &k in &takers {
                want[k] = short * self.land_of(k).len() as f64 / sizes.max(1.0);
            }
        }
    }

    /// The nodes next to node `n` (eight neighbours).
    fn neighbours(&self, n: usize) -> impl Iterator<Item = usize> {
        let (nx, ny) = (self.grid.nx as i64, self.grid.ny as i64);
        let (i, j) = ((n % self.grid.nx) as i64, (n / self.grid.nx) as i64);
        (-1..=1)
            .flat_map(move |dj| (-1..=1).map(move |di| (i + di, j + dj)))
            .filter(move |&(a, b)| a >= 0 && b >= 0 && a < nx && b < ny && (a, b) != (i, j))
            .map(move |(a, b)| (b * nx + a) as usize)
    }

    /// Moves island `k`'s coast out by up to `want` m² of sea nodes, nearest to its traced coast first and each
    /// next to the island; the area it took.
    fn grow(&mut self, k: usize, want: f64) -> f64 {
        let Some(outer) = self.outers[k].take() else {
            return 0.0;
        };
        let reach = self.grid.cell * (self.grid.nx + self.grid.ny) as f64;
        let cell_area = self.grid.cell * self.grid.cell;
        self.stamp += 1;
        let mut heap: MinHeap<usize> = MinHeap::new();
        let queue = |coast: &mut Coast, n: usize, heap: &mut MinHeap<usize>| {
            let next: Vec<usize> = coast.neighbours(n).collect();
            for m in next {
                if coast.owner[m] == SEA && coast.seen[m] != coast.stamp {
                    coast.seen[m] = coast.stamp;
                    heap.push(outer.distance(coast.grid.point_of(m), reach), m);
                }
            }
        };
        for idx in 0..self.members[k].len() {
            let n = self.members[k][idx];
            queue(self, n, &mut heap);
        }
        let mut took = 0.0;
        while took + 0.5 * cell_area < want {
            let Some(entry) = heap.pop() else {
                break;
            };
            let n = entry.item;
            if !self.claimable(k, n) {
                continue;
            }
            self.owner[n] = k as u32;
            self.members[k].push(n);
            took += cell_area;
            queue(self, n, &mut heap);
        }
        self.outers[k] = Some(outer);
        took
    }

    /// Whether sea node `n` may join island `k`: its cell in the region, the gap clear of other islands.
    fn claimable(&self, k: usize, n: usize) -> bool {
        let p = self.grid.point_of(n);
        let (nx, ny) = (self.grid.nx as i64, self.grid.ny as i64);
        let (i, j) = ((n % self.grid.nx) as i64, (n / self.grid.nx) as i64);
        self.owner[n] == SEA
            && self.region.covers_disc(p, 0.5 * self.grid.cell)
            && self.gap_offsets.iter().all(|&(di, dj)| {
                let (a, b) = (i + di, j + dj);
                a < 0 || b < 0 || a >= nx || b >= ny || {
                    let o = self.owner[(b * nx + a) as usize];
                    o == SEA || o == k as u32
                }
            })
            && !self.obstacles.contains(p)
            && self.obstacles.distance(p, self.gap) >= self.gap
    }

    /// Makes the sea that island `k`'s growth enclosed its land (it would trace as lakes the learned count did not
    /// ask for); the area it took.
    fn fill_pockets(&mut self, k: usize) -> f64 {
        let Some((i0, j0, i1, j1)) = self.window(k) else {
            return 0.0;
        };
        // the sea reached from the window's rim, which lies beyond the island
        let w = i1 - i0 + 1;
        let at = |i: usize, j: usize| (j - j0) * w + (i - i0);
        let mut open = vec![false; w * (j1 - j0 + 1)];
        let mut stack: Vec<(usize, usize)> = (j0..=j1)
            .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
            .filter(|&(i, j)| i == i0 || j == j0 || i == i1 || j == j1)
            .collect();
        stack.iter().for_each(|&(i, j)| open[at(i, j)] = true);
        while let Some((i, j)) = stack.pop() {
            let sides = [
                (i > i0).then(|| (i - 1, j)),
                (i < i1).then_some((i + 1, j)),
                (j > j0).then(|| (i, j - 1)),
                (j < j1).then_some((i, j + 1)),
            ];
            for (a, b) in sides.into_iter().flatten() {
                if !open[at(a, b)] && self.owner[self.grid.index(a, b)] != k as u32 {
                    open[at(a, b)] = true;
                    stack.push((a, b));
                }
            }
        }
        let mut took = 0.0;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let n = self.grid.index(i, j);
                if !open[at(i, j)] && self.owner[n] == SEA {
                    self.owner[n] = k as u32;
                    self.members[k].push(n);
                    took += self.grid.cell * self.grid.cell;
                }
            }
        }
        took
    }

    /// The lattice box of island `k`'s nodes grown by one node (clamped to the lattice).
    fn window(&self, k: usize) -> Option<(usize, usize, usize, usize)> {
        let nx = self.grid.nx;
        let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
        for &n in &self.members[k] {
            let (i, j) = (n % nx, n / nx);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
        (i0 <= i1).then(|| {
            (
                i0.saturating_sub(1),
                j0.saturating_sub(1),
                (i1 + 1).min(nx - 1),
                (j1 + 1).min(self.grid.ny - 1),
            )
        })
    }

    /// The centres of island `k`'s land nodes, to trace it again.
    fn land_of(&self, k: usize) -> Vec<DVec2> {
        self.members[k]
            .iter()
            .filter(|&&n| !self.lake[n])
            .map(|&n| self.grid.point_of(n))
            .collect()
    }
}

/// The nodes of `grid` inside the closed polygon `points`.
fn nodes_inside(grid: &Grid, points: &[DVec2]) -> Vec<usize> {
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    if !(lo.x.is_finite() && hi.x.is_finite()) {
        return Vec::new();
    }
    let to = |v: f64, o: f64, n: usize| ((v - o) / grid.cell).clamp(0.0, (n - 1) as f64);
    let (i0, i1) = (
        to(lo.x, grid.origin.x, grid.nx).floor() as usize,
        to(hi.x, grid.origin.x, grid.nx).ceil() as usize,
    );
    let (j0, j1) = (
        to(lo.y, grid.origin.y, grid.ny).floor() as usize,
        to(hi.y, grid.origin.y, grid.ny).ceil() as usize,
    );
    (j0..=j1)
        .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
        .filter(|&(i, j)| polygon_contains(points, grid.point(i, j)))
        .map(|(i, j)| grid.index(i, j))
        .collect()
}
