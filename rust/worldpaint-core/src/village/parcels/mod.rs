//! Land parcels by anisotropic conquest: thesis 3.3.1–3.3.4 ("Land Parcel Generation"). Each building seed `B_i`
//! gets a parcel `P_i` in three conquest steps on a grid of cells, the unclaimed land around it, then a simplified
//! contour:
//!
//! 1. **Road conquest** (3.3.1). The source `S_i` is the projection of `B_i` on the closest road. The cells along
//!    the road corridor's edge, on the seed's side, are conquered from `S_i` in both directions along the road
//!    "until collision with a neighboring parcel or until a maximum distance from `S_i` is reached"
//!    ([`ParcelParams::road_reach`]). All seeds advance together, so two neighbours meet half-way; the cells
//!    round a dead end's cap are no road front, so a parcel does not follow its road round its end.
//! 2. **Corner conquest** (3.3.2). "We allow parcel `P_i` arrived first at a junction to annex its
//!    neighborhood": in each junction sector narrower than [`ParcelOptions::corner_angle_degrees`], the parcel
//!    whose road cells come nearest the corner annexes the sector's road cells on both roads within its road
//!    reach (at most its depth `c_max / ω_conquest`) of the corner, and at most half-way to the next junction. The corner lot then fronts
//!    both roads and its neighbours begin where its land ends, instead of meeting it along a diagonal with sharp
//!    angles. "Building seeds that lose access to roads are suppressed": a seed left with no road cell, or with
//!    less than half of its front, gets `None`.
//! 3. **Anisotropic land conquest** (3.3.3). Every road cell a parcel owns is a source with the fund
//!    `c_max` ([`ParcelParams::budget`]), and the parcel spreads until the cost from its source reaches `c_max`:
//!
//!    > dc_s(d_s, n) = Σ_{i=0}^{n−1} ω_i c_i(d_s, n)
//!
//!    * the *conquest cost* is the infinite-norm distance to the source in the frame of the road normal `n` and
//!      tangent `t` at the source. The thesis prints it as `|max(p·n, p·t)|`; the infinite norm it names is
//!      `max(|p·n|, |p·t|)`, which is what is used (a square around each source, so parcels come out almost
//!      quadrilateral). A tiny multiple of the Euclidean distance breaks its ties, so a cell goes to the source
//!      straight in front of it and neighbouring parcels part along the road normal. A source conquers only in
//!      front of itself (`p·n ≥ 0`): parcels grow away from their road;
//!    * *water, wall and road* cells cost `+∞`; so do cells outside `Ω` and road cells owned by another parcel;
//!    * the *slope cost* is quadratic in the directional gradients of the terrain along the conquest directions
//!      `n` and `t` of the source: each grid step adds `(∇h·n)²·|Δ·n| + (∇h·t)²·|Δ·t|` for its displacement
//!      `Δ`, which on a uniform slope sums to `(∇h·n)²·|p·n| + (∇h·t)²·|p·t|` whatever the path. Spreading along
//!      the main slope is expensive, along the contour lines free, so parcels grow along the contour lines.
//!      (Measured along each step instead, the squared rise would make a zig-zag climb cheaper than a straight
//!      one; measured along the line to the source, the infinite norm's indifference to lateral offsets would
//!      let cells pick far sources to halve their slope.)
//!
//!    Every parcel conquers its own neighbourhood (within `c_max / ω_conquest` of its road cells) on its own, in
//!    parallel; a cell claimed by several parcels goes to the lowest cost, exact ties to the source cell first
//!    in grid order (so that two facing rows part along a straight line). The result does not depend on the
//!    number of threads. Only the 4-connected component holding the parcel's source is kept; a mode filter
//!    trims one-cell spikes and fills unclaimed cells enclosed between parcels, and pinch points (two cells of
//!    one parcel touching at a corner only) and enclosed holes are resolved, so that every parcel is a simple
//!    polygon.
//! 4. **Unclaimed land** (our addition). A real cadastre has no no-man's-land, while the budget leaves some:
//!    small pockets enclosed by parcels and roads (at most [`ParcelOptions::pocket_area`]), whose outlines notch
//!    the parcels around them, and in a sparse village the gaps between strips along the roads that never meet.
//!    Every parcel grows over the unclaimed open land from its cells, at the Euclidean length of 8-connected
//!    steps, the nearest parcel taking each cell: a pocket wholly, other land within the parcel's
//!    [`ParcelParams::fill`] metres (the fields of a mountain hamlet's farms: `highland` reads 40 m), and never
//!    the strip beside the road corridor, so that each frontage, on which the house is centred, stays the road
//!    conquest's. The labels are then cleaned again. On the real terrains of `tests/real_village_generation.rs`
//!    the pockets raise the parcel neighbours north of Bayreuth from 2.26-2.47 to 2.45-2.57, and the 40 m fill
//!    those in Andorra from 0.63-1.0 to 1.05-1.71 (the strips of houses 20-100 m apart meet behind their roads;
//!    across a road parcels never neighbour, which keeps a village strung along its roads below the thesis's
//!    2.8). The price is in edges there: 6.8-8.4 instead of 5.5-5.8, the grown parcels wrapping round the
//!    switchbacks' hairpins and stepping back beside the road strip. So a parcel that grows fields first keeps
//!    behind straight road fronts (`fronts`: one line along its road, two on a corner; where its road bends,
//!    its cells behind the chord go back to the unclaimed land) and its fields grow in front of them only: 6.4,
//!    7.5 and 5.9 edges instead of 6.8, 8.4 and 7.2, for 1.52, 1.61 and 1.05 neighbours instead of 1.58, 1.71
//!    and 1.05.
//! 5. **Parcel simplification** (3.3.4). The cell outlines of all parcels form one planar boundary graph; each
//!    chain between junctions (points where three or more parcels or the unclaimed land meet) is simplified once,
//!    so neighbours keep sharing their boundary exactly. A side two parcels share (where their conquests met, no
//!    road drew it) first becomes one straight edge between its two corners, when that moves it by at most
//!    [`ParcelOptions::far_deviation`] and 0.4 of its length and makes no angle below
//!    [`ParcelOptions::acute_angle_degrees`] with the other chains at its corners (our choice: the thesis's real
//!    parcels have straight sides; on the real terrains of `tests/real_village_generation.rs` 5.3-5.4 contour
//!    edges north of Bayreuth instead of 5.7-5.8, and 5.5-6.7 in Andorra instead of 5.7-7.1, for the same
//!    neighbours and footprints; at a quarter of the length 5.5-5.6 north of Bayreuth, at 0.6 no fewer edges
//!    there and 7.0 near les Bons). Otherwise staircases are first straightened (Douglas–Peucker
//!    within [`ParcelOptions::straighten`] cells), then "we remove vertices that have little influence on the
//!    contour shape": a vertex whose edges turn by less than `ε` ([`ParcelOptions::merge_angle_degrees`]) goes,
//!    and so does a vertex of an edge shorter than [`ParcelOptions::short_edge`] cells (a clipped corner). Behind
//!    the road fronts — a stretch of boundary away from the roads, whose line the conquests' budgets and costs drew,
//!    not a road: a parcel's far side, or where two parcels' conquests met — vertices go up to
//!    [`ParcelOptions::far_merge_angle_degrees`] (on a side two parcels share,
//!    [`ParcelOptions::shared_merge_angle_degrees`]) and [`ParcelOptions::far_deviation`], so that far sides on slopes
//!    come out straight instead of following the iso-cost curve, and the sides two neighbours share do not bend
//!    where one conquest's square ends (our choice: the thesis's real parcels have straight sides, 4.068 edges in
//!    all).
//!    Junctions are simplified by edge collapses, as in mesh simplification: a chain of a cell or so between two
//!    junctions collapses onto one of them, and — "we remove unplausible acute angles that appear at some
//!    T-vertices" — a junction where a parcel has an angle below [`ParcelOptions::acute_angle_degrees`] moves
//!    onto the neighbouring vertex that best opens it. Last, a T behind the road fronts (two of a junction's three
//!    chains turning by less than `ε`) moves onto the straight line of the boundary running through it, by at most
//!    the merge deviation: the side it lies on stays one straight edge, as it would without the junction (our
//!    choice, the same vertex-removal rule applied at junctions). No simplified edge may come within
//!    `road_width / 2` of a road's centre line or swallow a water, wall or out-of-`Ω` node, and simplified chains
//!    may not cross; a chain that breaks a rule is simplified less, down to its cell outline.
//!
//! The conquest grid has cells of side `cell` over the land's box (water, walls and `Ω` are read at the nearest
//! land node); it is allocated only over the neighbourhoods the seeds can reach.
//!
//! | file | step |
//! |---|---|
//! | `grid` | the conquest grid, the road corridor and its front |
//! | `road_conquest` | road conquest (3.3.1) |
//! | `corner` | road junctions and corner conquest (3.3.2) |
//! | `land_conquest` | anisotropic land conquest and the resolution of claims (3.3.3) |
//! | `labels` | from claimed cells to simple regions (3.3.3) |
//! | `fronts` | straight road fronts of the parcels that grow fields |
//! | `fill` | unclaimed pockets and gaps given to the parcels around them |
//! | `boundary` | the boundary graph of all parcels (3.3.4) |
//! | `simplify` | chain simplification and the rules it keeps (3.3.4) |
//! | `junctions` | edge collapses at the junctions (3.3.4) |
//! | `statistics` | the statistics of a layout (3.5) |
//!
//! The roads' segment index both parcels and footprints query lives in `village::road_index`.

mod boundary;
mod corner;
mod fill;
mod fronts;
mod grid;
mod junctions;
mod labels;
mod land_conquest;
mod road_conquest;
mod simplify;
mod statistics;

pub use statistics::{parcel_statistics, parcel_statistics_with, ParcelStatistics};

use super::encyclopedia::ParcelParams;
use super::land::Land;
use super::road_index::{Projection, RoadIndex};
use super::{Parcel, Road};
use crate::error::{check, Error, Result};
use crate::progress::Counted;
use corner::{corner_conquest, junctions, keeping_access};
use fill::fill_unclaimed;
use fronts::{cut_behind_fronts, parcel_fronts, reanchor};
use glam::DVec2;
use grid::Work;
use labels::clean_labels;
use land_conquest::{conquer, resolve_claims, Claim};
use rayon::prelude::*;
use road_conquest::{fronts_and_anchors, road_conquest, RoadConquest};
use simplify::simplified_contours;

/// No parcel.
const NONE: u32 = u32::MAX;

/// A building seed asking for a parcel: its position and the conquest parameters of its (village, building) type.
#[derive(Clone, Copy, Debug)]
pub struct ParcelSeed<'a> {
    /// The seed's position, world XY (m).
    pub position: DVec2,
    /// The conquest parameters.
    pub params: &'a ParcelParams,
}

/// How parcel contours are simplified and corners resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParcelOptions {
    /// Largest distance (in cells) a straightened boundary may stray from the cell outline.
    pub straighten: f64,
    /// `ε` of 3.3.4: a vertex whose edges turn by less than this (degrees) is removed.
    pub merge_angle_degrees: f64,
    /// Largest distance (in cells) the removal of vertices may move a boundary away from the cell outline.
    pub merge_deviation: f64,
    /// An edge shorter than this (in cells) loses one of its vertices, within the same deviation.
    pub short_edge: f64,
    /// `ε` (degrees) behind the road fronts: on boundaries (free, or between two parcels) farther than
    /// `road_width / 2 + merge_deviation` cells from the roads, where the conquests' budgets and costs, not a road,
    /// drew the line.
    pub far_merge_angle_degrees: f64,
    /// `ε` (degrees) behind the road fronts on a side two parcels share (where their conquests met).
    pub shared_merge_angle_degrees: f64,
    /// Largest distance (in cells) the removal of vertices behind the road fronts, or the straightening of a side
    /// two parcels share, may move a boundary.
    pub far_deviation: f64,
    /// A parcel angle below this (degrees) at a junction of the boundary graph is opened by an edge collapse.
    pub acute_angle_degrees: f64,
    /// Junction sectors (between two consecutive roads) narrower than this (degrees) get a corner conquest.
    pub corner_angle_degrees: f64,
    /// Unclaimed open land enclosed by parcels and roads in pieces of at most this area (m²) goes to the parcels
    /// around it.
    pub pocket_area: f64,
}

impl Default for ParcelOptions {
    /// `ε` = 45°, vertices moved by up to 5 cells and edges shorter than 6 cells merged: the thesis gives no value,
    /// and at 30°, 3 and 4 cells a dense village's parcels kept 8 contour edges on average against the 4.068 of
    /// its real village (3.5), most of them shallow bends of the far side. Behind the road fronts, 20 cells and
    /// 60° on far sides (with the straightened T-junctions, 5.5-6.1 edges instead of 5.9-6.4 on the real terrains
    /// of `tests/real_village_generation.rs`; at 75° a lone parcel's far side on a slope cuts across its width), 75°
    /// on the sides two parcels share (5.7-5.8 edges north of Bayreuth instead of 5.9-6.1, for 1-3 footprints of
    /// 400-458); 45° and larger deviations everywhere lose footprints to narrowed parcels rather than edges. Pockets up to 2000 m² (about three village lots) go to the parcels around them:
    /// 2.45-2.57 neighbours north of Bayreuth instead of 2.26-2.47.
    fn default() -> Self {
        ParcelOptions {
            straighten: 1.5,
            merge_angle_degrees: 45.0,
            merge_deviation: 5.0,
            short_edge: 6.0,
            far_merge_angle_degrees: 60.0,
            shared_merge_angle_degrees: 75.0,
            far_deviation: 20.0,
            acute_angle_degrees: 30.0,
            corner_angle_degrees: 150.0,
            pocket_area: 2000.0,
        }
    }
}

/// One parcel per seed, or `None` for a seed that lost access to the roads (3.3.2: "building seeds that lose
/// access to roads are suppressed"), with the default [`ParcelOptions`].
///
/// `cell` is the side of the conquest grid's cells (metres): no coarser than the land's grid, so that no water,
/// wall or out-of-`Ω` node falls between two conquest nodes (1 m suits villages; 100 parcels on 1 km² take a
/// fraction of a second). The road corridor is every point within `road_width / 2` of a road's centre line;
/// parcels keep out of it, and of water, walls and the outside of `Ω`. Contours are counter-clockwise, simple,
/// pairwise disjoint, and neighbours share their common boundary vertex for vertex.
pub fn parcels(
    land: &Land,
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
) -> Result<Vec<Option<Parcel>>> {
    parcels_with(
        land,
        roads,
        road_width,
        seeds,
        cell,
        &ParcelOptions::default(),
        &|_| true,
    )
}

/// [`parcels`] with explicit simplification and corner options, reporting its progress (0 to 1) as it goes;
/// `progress` returning `false` cancels ([`Error::Cancelled`]).
pub fn parcels_with(
    land: &Land,
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
    options: &ParcelOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Vec<Option<Parcel>>> {
    validate(roads, road_width, seeds, cell, options)?;
    let reached = |fraction: f64| {
        if progress(fraction) {
            Ok(())
        } else {
            Err(Error::Cancelled)
        }
    };
    let n = seeds.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let half = 0.5 * road_width;
    let index = RoadIndex::new(roads, road_width.max(4.0 * cell));
    if index.is_empty() {
        return Ok(vec![None; n]);
    }
    let projections: Vec<Projection> = seeds.iter().map(|s| index.project(s.position)).collect();
    let Some(work) = Work::new(land, roads, &index, half, cell, seeds, &projections)? else {
        return Ok(vec![None; n]);
    };

    // 3.3.1 road conquest, 3.3.2 corner conquest
    let (road, fronts, anchors) = conquer_roads(
        &work,
        &index,
        roads,
        &projections,
        seeds,
        road_width,
        options,
        &reached,
    )?;

    // 3.3.3 anisotropic land conquest, each parcel on its own
    let (mut label, mut best) = conquer_land(
        &work, land, &index, &road, &fronts, &anchors, seeds, progress,
    )?;
    settle_labels(
        &work,
        &index,
        &road.owner,
        seeds,
        options,
        anchors,
        (&mut label, &mut best),
        &reached,
    )?;

    // 3.3.4 simplification of the shared boundary graph
    let contours = simplified_contours(&work, &index, half, &label, n, options);
    reached(1.0)?;
    Ok(contours
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            c.filter(|c| c.len() >= 3)
                .map(|contour| Parcel { seed: i, contour })
        })
        .collect())
}

fn finite(p: DVec2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

fn validate(
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
    options: &ParcelOptions,
) -> Result<()> {
    let bad = |what: String| Err(Error::invalid("parcels", what));
    check::positive("parcels grid cell", cell)?;
    check::non_negative("parcels road width", road_width)?;
    for (r, road) in roads.iter().enumerate() {
        if road.points.iter().any(|p| !finite(*p)) {
            return bad(format!("road {r} has a point that is not finite"));
        }
    }
    for (i, s) in seeds.iter().enumerate() {
        if !finite(s.position) {
            return bad(format!("seed {i} position is not finite"));
        }
        s.params.validate(&format!("parcels: seed {i} params"))?;
    }
    let o = options;
    for (name, v) in [
        ("straighten", o.straighten),
        ("merge_angle_degrees", o.merge_angle_degrees),
        ("merge_deviation", o.merge_deviation),
        ("far_merge_angle_degrees", o.far_merge_angle_degrees),
        ("shared_merge_angle_degrees", o.shared_merge_angle_degrees),
        ("far_deviation", o.far_deviation),
        ("acute_angle_degrees", o.acute_angle_degrees),
        ("corner_angle_degrees", o.corner_angle_degrees),
        ("pocket_area", o.pocket_area),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(format!("option {name} = {v} must be zero or more"));
        }
    }
    Ok(())
}

/// 3.3.3: each parcel anchored on the road conquers its land on its own (in parallel); the claims are resolved
/// into each cell's label and its cost. Reports progress from 0.2 to 0.5.
#[allow(clippy::too_many_arguments)]
fn conquer_land(
    work: &Work,
    land: &Land,
    index: &RoadIndex,
    road: &RoadConquest,
    fronts: &[Vec<usize>],
    anchors: &[Option<usize>],
    seeds: &[ParcelSeed],
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<(Vec<u32>, Vec<f64>)> {
    let n = seeds.len();
    let conquests = Counted::new(n, |f| progress(0.2 + 0.3 * f));
    let claims: Vec<Vec<Claim>> = (0..n)
        .into_par_iter()
        .map(|i| {
            if anchors[i].is_none() || !conquests.go_on() {
                return Vec::new();
            }
            let claim = conquer(
                work,
                land,
                index,
                &road.owner,
                i as u32,
                &fronts[i],
                seeds[i].params,
            );
            conquests.done_one();
            claim
        })
        .collect();
    conquests.finish()?;
    Ok(resolve_claims(&claims, work.grid.len()))
}

/// 3.3.1 and 3.3.2: the road edge conquered from each seed's source cell (its projection on the roads), then the
/// corners at the junctions, keeping each parcel's access; returns the conquest with each parcel's fronts and anchor.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn conquer_roads(
    work: &Work,
    index: &RoadIndex,
    roads: &[Road],
    projections: &[Projection],
    seeds: &[ParcelSeed],
    road_width: f64,
    options: &ParcelOptions,
    reached: &dyn Fn(f64) -> Result<()>,
) -> Result<(RoadConquest, Vec<Vec<usize>>, Vec<Option<usize>>)> {
    let half = 0.5 * road_width;
    let sources: Vec<Option<usize>> = projections
        .iter()
        .map(|p| work.source_cell(index, p, half))
        .collect();
    reached(0.0)?;
    let mut road = road_conquest(work, seeds, &sources);
    reached(0.1)?;
    let junctions = junctions(roads, work, seeds, road_width, options);
    keeping_access(seeds.len(), &mut road, |road| {
        corner_conquest(work, seeds, &junctions, half, options, road)
    });
    let (fronts, anchors) = fronts_and_anchors(&road, &sources);
    reached(0.2)?;
    Ok((road, fronts, anchors))
}

/// After the land conquest: the labels cleaned (islands of a label joined to their neighbours' or smoothed), a
/// parcel that grows fields cut back behind its road front (and cleaned again), the unclaimed pockets and the gaps of
/// a sparse village given to the parcels around them, and a last clean-up. Reports progress from 0.5 to 0.85.
#[allow(clippy::too_many_arguments)]
fn settle_labels(
    work: &Work,
    index: &RoadIndex,
    owner: &[u32],
    seeds: &[ParcelSeed],
    options: &ParcelOptions,
    mut anchors: Vec<Option<usize>>,
    (label, best): (&mut [u32], &mut [f64]),
    reached: &dyn Fn(f64) -> Result<()>,
) -> Result<()> {
    let cell = work.grid.cell;
    let mut is_anchor = vec![false; work.grid.len()];
    anchors.iter().flatten().for_each(|&k| is_anchor[k] = true);
    // the labels' clean-up, reporting its rounds within `span` of the progress from `from`
    let clean = |anchors: &[Option<usize>],
                 is_anchor: &[bool],
                 cells: (&mut [u32], &mut [f64]),
                 smooth: bool,
                 (from, span): (f64, f64)| {
        clean_labels(work, owner, (anchors, is_anchor), cells, smooth, &|round| {
            reached(from + span * round)
        })
    };
    clean(&anchors, &is_anchor, (label, best), true, (0.5, 0.2))?;
    // unclaimed pockets and the gaps of a sparse village go to the parcels around them
    let pocket_cells = (options.pocket_area / (cell * cell)).floor() as usize;
    let tolerance = options.straighten * cell;
    // a parcel that grows fields keeps behind one straight road front (or two, on a corner)
    let grown = |x: usize| seeds[x].params.fill > 0.0;
    let fronts = parcel_fronts(work, index, seeds.len(), label);
    if cut_behind_fronts(work, &fronts, tolerance, &grown, (label, best)) {
        reanchor(work, label, &mut anchors, &mut is_anchor);
        clean(&anchors, &is_anchor, (label, best), false, (0.6, 0.05))?;
    }
    let fronts = parcel_fronts(work, index, seeds.len(), label);
    fill_unclaimed(
        work,
        owner,
        seeds,
        pocket_cells,
        (&fronts, tolerance),
        (label, best),
    );
    clean(&anchors, &is_anchor, (label, best), true, (0.7, 0.15))?;
    Ok(())
}
