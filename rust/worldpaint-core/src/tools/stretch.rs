//! Seam-carving stretch (Section 5.5, Fig. 15–16; thesis 6.4.3): "When the user scales a region in our system,
//! our seamcarving algorithm finds a cut that minimizes scene deformation. We then only deform the objects near
//! the path, thus preserving the rest of the scene."
//!
//! The user drags one side of a rectangular region by `amount` metres (positive stretches, negative shrinks).
//! In the region's frame `u` runs across the dragged side (towards it) and `v` along it.
//!
//! * **Energy map.** The region is rasterized and every cell gets the repulsion energy
//!   `e(p) = 1 / min_i d(p, o_i)` (the distance to the nearest instance or road, river or coast point, floored
//!   at half a cell), computed with an exact Euclidean distance transform (Felzenszwalb & Huttenlocher): the cut
//!   crosses roads rather than running along them.
//! * **Cut.** The least-energy path across the region along `v`, "in the direction perpendicular to the main
//!   deformation", by dynamic programming over 8-connected cells (Avidan & Shamir's seam), kept in the middle
//!   80 % of the region so that it cuts through the content rather than along its edge.
//! * **Stretch.** "We use a move operation for the objects on one side of a cut, and synthesize new objects in
//!   the free space left": the content beyond the cut moves by `amount` along `u` (replacing what it lands on
//!   outside the region, and adapting to its new ground like any move), and the band it opens between the cut
//!   and its displaced copy is synthesized with the region's color (given, or learned from the region).
//! * **Shrink.** "We fold the selected region onto itself along a cut by using a move operation": the content
//!   inside the band of width `|amount|` beyond the cut is removed and the content beyond the band moves back by
//!   `|amount|`. The strip this releases at the dragged side is synthesized with the color of the content just
//!   outside that side, so the region's surroundings close over it (left empty when there is nothing there).
//! * **Roads, rivers and coasts** are stretched with the ground they lie on, so none is torn: their points beyond
//!   the cut move with the instances, and where a line crosses the cut it is rejoined by a straight piece across
//!   the band (a road crossing the band is a road stretched along its way). Parts in the space the drag removes
//!   (the band of a shrink, the ground the moved side lands on beyond the region) go, and the line runs on from
//!   where it left that space. The synthesis of the opened space paints only the color's distributions, conditioned
//!   on these lines: it adds no road that could end in the band.

use super::moving::move_instances;
use super::{color_of_region, Clearing, ToolEdit, Working};
use crate::distance::squared_distance_1d;
use crate::error::{check, Error, Result};
use crate::geom::{DVec2, Region};
use crate::palette::Color;
use crate::scene::{CategoryKind, Scene};
use crate::synthesis::{AdaptOptions, SynthesisOptions};
use std::borrow::Cow;

/// Fraction of the region's width the cut keeps away from each of the two other sides.
const CUT_MARGIN: f64 = 0.1;
/// "Infinite" squared distance of the distance transform.
const FAR: f64 = 1e20;

/// The side of the region that is dragged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StretchSide {
    /// +X
    East,
    /// −X
    West,
    /// +Y
    North,
    /// −Y
    South,
}

/// Stretch settings.
#[derive(Clone, Debug, Default)]
pub struct StretchOptions {
    /// Cell of the energy map (None: a third of the content's mean spacing, within sensible bounds).
    pub cell: Option<f64>,
    /// Seed, region of influence and proposals of the synthesis of the opened space.
    pub synthesis: SynthesisOptions,
    /// How the moved side adapts to its new place.
    pub adapt: AdaptOptions,
}

/// What a stretch did.
#[derive(Clone, Debug)]
pub struct Stretched {
    /// The change to the scene.
    pub edit: ToolEdit,
    /// The cut, a polyline across the region (world XY).
    pub seam: Vec<DVec2>,
    /// The band that was opened (stretch) or removed (shrink).
    pub band: Region,
    /// The region after the stretch.
    pub region: Region,
    /// Instances beyond the cut that the stretch would have pushed off the terrain: they were not moved.
    pub pushed_off: usize,
}

/// The region's frame: `u` across the dragged side, `v` along it, origin at the opposite side's start.
struct Frame {
    origin: DVec2,
    u: DVec2,
    v: DVec2,
    width: f64,
    height: f64,
}

impl Frame {
    fn new(min: DVec2, max: DVec2, side: StretchSide) -> Frame {
        let (w, h) = (max.x - min.x, max.y - min.y);
        let (origin, u, v, width, height) = match side {
            StretchSide::East => (min, DVec2::X, DVec2::Y, w, h),
            StretchSide::West => (DVec2::new(max.x, min.y), -DVec2::X, DVec2::Y, w, h),
            StretchSide::North => (min, DVec2::Y, DVec2::X, h, w),
            StretchSide::South => (DVec2::new(min.x, max.y), -DVec2::Y, DVec2::X, h, w),
        };
        Frame {
            origin,
            u,
            v,
            width,
            height,
        }
    }

    fn local(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    fn world(&self, l: DVec2) -> DVec2 {
        self.origin + self.u * l.x + self.v * l.y
    }

    /// The world rectangle of local `[u0, u1] × [0, height]`.
    fn rect(&self, u0: f64, u1: f64) -> Region {
        let (a, b) = (
            self.world(DVec2::new(u0, 0.0)),
            self.world(DVec2::new(u1, self.height)),
        );
        Region::Rect {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The world polygon between the local polylines `left` and `right` (both ascending in `v`).
    fn between(&self, left: &[DVec2], right: &[DVec2]) -> Region {
        let mut points: Vec<DVec2> = left.iter().map(|l| self.world(*l)).collect();
        points.extend(right.iter().rev().map(|l| self.world(*l)));
        Region::Polygon { points }
    }
}

/// The repulsion energy `1 / d` of an `nu × nv` raster (row-major along `u`) with instances at `seeds` (cells).
fn energy_map(nu: usize, nv: usize, cell: f64, seeds: &[(usize, usize)]) -> Vec<f64> {
    let mut d2 = vec![FAR; nu * nv];
    for &(i, j) in seeds {
        d2[j * nu + i] = 0.0;
    }
    if seeds.is_empty() {
        return vec![0.0; nu * nv];
    }
    let mut col = vec![0.0; nv];
    let mut col_out = vec![0.0; nv];
    for i in 0..nu {
        for j in 0..nv {
            col[j] = d2[j * nu + i];
        }
        squared_distance_1d(&col, &mut col_out);
        for j in 0..nv {
            d2[j * nu + i] = col_out[j];
        }
    }
    let mut row_out = vec![0.0; nu];
    for j in 0..nv {
        squared_distance_1d(&d2[j * nu..(j + 1) * nu], &mut row_out);
        d2[j * nu..(j + 1) * nu].copy_from_slice(&row_out);
    }
    d2.iter()
        .map(|&q| 1.0 / (q.sqrt() * cell).max(0.5 * cell))
        .collect()
}

/// The least-energy 8-connected path across the raster along `v`, within columns `lo..=hi`: a column per row.
fn least_energy_cut(energy: &[f64], nu: usize, nv: usize, lo: usize, hi: usize) -> Vec<usize> {
    let mut cost = vec![f64::INFINITY; nu * nv];
    let mut from = vec![0usize; nu * nv];
    cost[lo..=hi].copy_from_slice(&energy[lo..=hi]);
    for j in 1..nv {
        for i in lo..=hi {
            let mut best = (f64::INFINITY, i);
            for pi in i.saturating_sub(1).max(lo)..=(i + 1).min(hi) {
                let c = cost[(j - 1) * nu + pi];
                // ties go to the straight step, then to the smaller column
                if c < best.0 || (c == best.0 && pi == i) {
                    best = (c, pi);
                }
            }
            cost[j * nu + i] = best.0 + energy[j * nu + i];
            from[j * nu + i] = best.1;
        }
    }
    let last = (nv - 1) * nu;
    let mut i = (lo..=hi)
        .min_by(|&a, &b| cost[last + a].total_cmp(&cost[last + b]))
        .unwrap_or(lo);
    let mut cut = vec![0usize; nv];
    for j in (0..nv).rev() {
        cut[j] = i;
        i = from[j * nu + i];
    }
    cut
}

/// `u` of a polyline ascending in `v`, at `v` (clamped at its ends).
fn u_at(line: &[DVec2], v: f64) -> f64 {
    let k = line.partition_point(|p| p.y < v);
    if k == 0 {
        return line[0].x;
    }
    if k >= line.len() {
        return line[line.len() - 1].x;
    }
    let (a, b) = (line[k - 1], line[k]);
    let t = if b.y > a.y {
        (v - a.y) / (b.y - a.y)
    } else {
        0.0
    };
    a.x + t * (b.x - a.x)
}

/// Stretches (`amount > 0`) or shrinks (`amount < 0`) the rectangle `region` by dragging its `side` (see the
/// module documentation). `color` fills the opened band and adapts the moved content; `None` learns it from the
/// region.
pub fn stretch(
    scene: &Scene,
    region: &Region,
    side: StretchSide,
    amount: f64,
    color: Option<&Color>,
    opts: &StretchOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Stretched> {
    region.validate()?;
    let Region::Rect { min, max } = *region else {
        return Err(Error::invalid(
            "stretch region",
            "stretching works on a rectangle region",
        ));
    };
    if !(amount.is_finite() && amount != 0.0) {
        return Err(Error::OutOfRange {
            what: "stretch amount".into(),
            rule: "a non-zero length".into(),
            value: amount,
        });
    }
    let frame = Frame::new(min, max, side);
    let width = frame.width;
    let shrink = (-amount).max(0.0);
    if shrink >= (1.0 - 2.0 * CUT_MARGIN) * width {
        return Err(Error::invalid(
            "stretch amount",
            format!(
                "cannot shrink a region {width:.2} m wide by {shrink:.2} m (at most {:.2} m)",
                (1.0 - 2.0 * CUT_MARGIN) * width
            ),
        ));
    }
    let mut inside: Vec<DVec2> = scene
        .instances
        .iter()
        .filter(|i| region.contains(i.position))
        .map(|i| frame.local(i.position))
        .collect();
    let cell = energy_cell(opts.cell, &frame, inside.len())?;
    inside.extend(
        line_samples(scene, cell)
            .filter(|p| region.contains(*p))
            .map(|p| frame.local(p)),
    );
    let seam = least_energy_seam(&frame, &inside, cell, shrink);
    let color = stretch_color(scene, region, color)?;
    let color = color.as_ref();
    let drag = Drag {
        scene,
        region,
        frame,
        seam,
        amount,
        shrink,
    };
    let band = drag.band();
    let mut work = Working::new(scene);
    if shrink > 0.0 {
        work.remove_inside(&band);
    }
    work.reshape_structures(|points, closed| drag.reshape(points, closed));
    let moved = move_instances(
        &work.scene,
        &work.scene,
        color,
        &drag.landing(),
        &drag.moving(&work.scene),
        drag.frame.u * amount,
        &opts.adapt,
    )?;
    work.apply(&moved.edit);
    if !progress(0.5) {
        return Err(Error::Cancelled);
    }
    let report = |f: f64| progress(0.5 + 0.5 * f);
    let resized = drag.fill(&mut work, color, &band, &opts.synthesis, &report)?;
    Ok(Stretched {
        edit: work.edit(),
        seam: drag.seam.iter().map(|l| drag.frame.world(*l)).collect(),
        band,
        region: resized,
        pushed_off: moved.stayed,
    })
}

/// The given color, or the one learned from the region.
fn stretch_color<'c>(
    scene: &Scene,
    region: &Region,
    color: Option<&'c Color>,
) -> Result<Cow<'c, Color>> {
    match color {
        Some(c) => Ok(Cow::Borrowed(c)),
        None => match color_of_region(scene, region, "stretched region")? {
            Some(c) => Ok(Cow::Owned(c)),
            None => Err(Error::EmptyExemplar {
                reason: "the region holds no instances to stretch".to_string(),
            }),
        },
    }
}

/// The cell of the energy map: the option's (when valid), else a third of the content's mean spacing within
/// sensible bounds.
fn energy_cell(cell: Option<f64>, frame: &Frame, count: usize) -> Result<f64> {
    let (width, height) = (frame.width, frame.height);
    match cell {
        Some(c) => check::positive("stretch energy cell", c),
        None => {
            let spacing = (width * height / count.max(1) as f64).sqrt();
            Ok((spacing / 3.0)
                .max(width.max(height) / 1000.0)
                .min(width.min(height) / 20.0))
        }
    }
}

/// The cut (local coordinates, ascending in `v` from 0 to the height): the least-energy path through the energy
/// map of the content `inside`, kept clear of the region's sides by `CUT_MARGIN` and of the band a shrink
/// removes.
fn least_energy_seam(frame: &Frame, inside: &[DVec2], cell: f64, shrink: f64) -> Vec<DVec2> {
    let (width, height) = (frame.width, frame.height);
    let nu = ((width / cell).ceil() as usize).max(1);
    let nv = ((height / cell).ceil() as usize).max(1);
    let seeds: Vec<(usize, usize)> = inside
        .iter()
        .map(|l| {
            (
                ((l.x / cell) as usize).min(nu - 1),
                ((l.y / cell) as usize).min(nv - 1),
            )
        })
        .collect();
    let energy = energy_map(nu, nv, cell, &seeds);
    let lo = ((CUT_MARGIN * nu as f64).ceil() as usize).min(nu - 1);
    let hi = ((((1.0 - CUT_MARGIN) * width - shrink) / cell).floor() as usize)
        .min(nu - 1)
        .max(lo);
    let cut = least_energy_cut(&energy, nu, nv, lo, hi);
    let mut seam: Vec<DVec2> = cut
        .iter()
        .enumerate()
        .map(|(j, &i)| {
            DVec2::new(
                (i as f64 + 0.5) * cell,
                ((j as f64 + 0.5) * cell).min(height),
            )
        })
        .collect();
    seam.insert(0, DVec2::new(seam[0].x, 0.0));
    seam.push(DVec2::new(seam[seam.len() - 1].x, height));
    seam
}

/// A polyline moved by `du` along `u`.
fn shifted(line: &[DVec2], du: f64) -> Vec<DVec2> {
    line.iter().map(|p| DVec2::new(p.x + du, p.y)).collect()
}

/// The drag of one side of a region, along its cut.
struct Drag<'a> {
    /// The scene before the drag.
    scene: &'a Scene,
    region: &'a Region,
    frame: Frame,
    /// The cut, local.
    seam: Vec<DVec2>,
    amount: f64,
    /// `−amount` when shrinking, else 0.
    shrink: f64,
}

impl Drag<'_> {
    /// The straight line across the region at `u`, local.
    fn edge(&self, u: f64) -> Vec<DVec2> {
        vec![DVec2::new(u, 0.0), DVec2::new(u, self.frame.height)]
    }

    /// The band between the cut and its copy `|amount|` further: opened by a stretch, removed by a shrink.
    fn band(&self) -> Region {
        self.frame
            .between(&self.seam, &shifted(&self.seam, self.amount.abs()))
    }

    /// The unlocked instances of the region beyond the cut (beyond the band when shrinking): they move by
    /// `amount` along u.
    fn moving(&self, scene: &Scene) -> Vec<usize> {
        let beyond = if self.shrink > 0.0 { self.shrink } else { 0.0 };
        (0..scene.instances.len())
            .filter(|&k| {
                let i = &scene.instances[k];
                let l = self.frame.local(i.position);
                !i.locked
                    && self.region.contains(i.position)
                    && l.x > u_at(&self.seam, l.y) + beyond
            })
            .collect()
    }

    /// Where the moving content lands.
    fn landing(&self) -> Region {
        let width = self.frame.width;
        if self.shrink > 0.0 {
            self.frame
                .between(&self.seam, &self.edge(width - self.shrink))
        } else {
            self.frame.between(
                &shifted(&self.seam, self.amount),
                &self.edge(width + self.amount),
            )
        }
    }

    /// Synthesizes the space the drag opened: the band with `color` (stretch), or the strip released at the
    /// dragged side with the color of what lies beyond that side (shrink). Returns the region after the drag.
    fn fill(
        &self,
        work: &mut Working,
        color: &Color,
        band: &Region,
        synthesis: &SynthesisOptions,
        report: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<Region> {
        let (frame, width, shrink) = (&self.frame, self.frame.width, self.shrink);
        if shrink > 0.0 {
            // the strip released at the dragged side takes the color of what lies beyond that side
            let strip = frame.rect(width - shrink, width);
            let outside = frame.rect(width, width + shrink.max(2.0 * color.max_radius));
            if let Some(around) = color_of_region(self.scene, &outside, "beyond the region")? {
                fill_distributions(work, &around, &strip, synthesis, report)?;
            }
            Ok(frame.rect(0.0, width - shrink))
        } else {
            fill_distributions(work, color, band, synthesis, report)?;
            Ok(frame.rect(0.0, width + self.amount))
        }
    }

    /// Where a point of a road, river or coast goes (see the module documentation).
    fn zone(&self, p: DVec2) -> Zone {
        let l = self.frame.local(p);
        let seam = u_at(&self.seam, l.y);
        if self.region.contains(p) {
            if l.x > seam + self.shrink {
                Zone::Moves
            } else if l.x > seam && self.shrink > 0.0 {
                Zone::Gone
            } else {
                Zone::Stays
            }
        } else if self.shrink == 0.0
            && (0.0..=self.frame.height).contains(&l.y)
            && l.x > self.frame.width
            && l.x <= self.frame.width + self.amount
        {
            Zone::Gone
        } else {
            Zone::Stays
        }
    }

    /// The line `points` (closed: a contour) stretched with the ground; `None` when the drag leaves it as it is. Where it crosses from one zone to another, the crossing (found by bisection between samples a
    /// fraction of the energy cell apart) is added in both zones' places, so a line across the cut is rejoined.
    fn reshape(&self, points: &[DVec2], closed: bool) -> Option<Vec<DVec2>> {
        let n = points.len();
        if n < 2 {
            return None;
        }
        let step = self.frame.width.min(self.frame.height) / LINE_SAMPLES_ACROSS;
        let place = |zone: Zone, p: DVec2| match zone {
            Zone::Stays => Some(p),
            Zone::Moves => Some(p + self.frame.u * self.amount),
            Zone::Gone => None,
        };
        let mut out: Vec<DVec2> = Vec::with_capacity(n + 4);
        let mut emit = |p: Option<DVec2>| {
            if let Some(p) = p.filter(|p| out.last() != Some(p)) {
                out.push(p);
            }
        };
        let mut changed = false;
        let first = self.zone(points[0]);
        emit(place(first, points[0]));
        let segments = if closed { n } else { n - 1 };
        for k in 0..segments {
            let (a, b) = (points[k], points[(k + 1) % n]);
            let samples = ((a.distance(b) / step).ceil() as usize).max(1);
            let (mut t0, mut z0) = (0.0, self.zone(a));
            changed |= z0 != Zone::Stays;
            for s in 1..=samples {
                let t1 = s as f64 / samples as f64;
                let z1 = self.zone(a.lerp(b, t1));
                if z1 != z0 {
                    let (lo, hi) = self.crossing(a, b, t0, t1, z0);
                    emit(place(z0, a.lerp(b, lo)));
                    emit(place(z1, a.lerp(b, hi)));
                    changed = true;
                }
                (t0, z0) = (t1, z1);
            }
            if !(closed && k + 1 == n) {
                emit(place(z0, b));
            }
        }
        if closed && out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
        changed.then_some(out)
    }

    /// The parameters just before and just after the point between `t0` (in `zone`) and `t1` where the segment
    /// `a`–`b` leaves `zone`.
    fn crossing(&self, a: DVec2, b: DVec2, mut t0: f64, mut t1: f64, zone: Zone) -> (f64, f64) {
        for _ in 0..CROSSING_BISECTIONS {
            let mid = 0.5 * (t0 + t1);
            if self.zone(a.lerp(b, mid)) == zone {
                t0 = mid;
            } else {
                t1 = mid;
            }
        }
        (t0, t1)
    }
}

/// Where a drag puts a point of a road, river or coast.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Zone {
    Stays,
    Moves,
    /// In the space the drag removes.
    Gone,
}

/// Samples per side of the region along a line, to find where it crosses from one zone to another.
const LINE_SAMPLES_ACROSS: f64 = 400.0;
/// Bisections that place a crossing (to 2^-30 of the sample step).
const CROSSING_BISECTIONS: usize = 30;

/// Points every `cell` along the scene's roads, rivers and coasts: the cut keeps off them like off instances.
fn line_samples(scene: &Scene, cell: f64) -> impl Iterator<Item = DVec2> + '_ {
    let paths = scene.paths.iter().map(|p| (&p.points, false));
    let contours = scene.contours.iter().map(|c| (&c.points, true));
    paths.chain(contours).flat_map(move |(points, closed)| {
        let n = points.len();
        let segments = if closed { n } else { n.saturating_sub(1) };
        (0..segments).flat_map(move |k| {
            let (a, b) = (points[k], points[(k + 1) % n]);
            let steps = ((a.distance(b) / cell).ceil() as usize).max(1);
            (0..steps).map(move |s| a.lerp(b, s as f64 / steps as f64))
        })
    })
}

/// Synthesizes the color's distributions in `region` (its roads, rivers and coasts are the stretched ones).
fn fill_distributions(
    work: &mut Working,
    color: &Color,
    region: &Region,
    synthesis: &SynthesisOptions,
    report: &(dyn Fn(f64) -> bool + Sync),
) -> Result<()> {
    let distributions: Vec<String> = color
        .categories
        .iter()
        .filter(|c| c.category.kind == CategoryKind::Distribution)
        .map(|c| c.category.name.clone())
        .filter(|name| {
            synthesis
                .categories
                .as_ref()
                .is_none_or(|only| only.contains(name))
        })
        .collect();
    work.remove_inside(region);
    if distributions.is_empty() {
        return Ok(());
    }
    let opts = SynthesisOptions {
        categories: Some(distributions),
        ..synthesis.clone()
    };
    work.fill(Clearing::Done, color, region, &opts, report)?;
    Ok(())
}
