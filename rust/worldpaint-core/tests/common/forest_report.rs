//! The Luquillo forest report, shared by `tests/real_forest_painting.rs` and `benches/synthesis.rs`.
//!
//! Real data (ForestGEO's Luquillo plot, Puerto Rico), read from `shared/data/real/forest` beside the project —
//! never copied into the repository. The living trees of the one-hectare census (x 100–200 m, y 400–500 m) are
//! split in two: a color is learned from the western half (x < 150) on the plot's 5 m elevation grid, painted
//! into the eastern half (x 150–200) with the western trees as the surrounding context, and the result is
//! compared with the real eastern trees, beside reference arrangements.
//!
//! Maps: only "slope" is learned. Elevation histograms are binned over the exemplar region's own elevation range
//! and the eastern half lies partly outside the western half's range, where the learned preference would be
//! zero; slope uses fixed 2.5° bins and transfers between the halves.

use super::pcf::{count_correlation, l2, pcf, pearson, window_count_correlation};
use super::real_data::{real_data_dir, require};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use std::time::Instant;
use worldpaint_core::{
    compare, hard_core_points, learn_color, synthesize, uniform_points, AnalysisOptions, Category,
    Color, DVec2, Heightfield, Instance, Region, Scene, SynthesisOptions,
};

/// Where the forest data lives.
pub fn data_dir() -> PathBuf {
    real_data_dir().join("forest")
}

const TREES_FILE: &str = "luquillo_tree6_1ha.csv";
const ELEVATION_FILE: &str = "luquillo_elevation_5m.csv";

/// A parsed CSV file: the header and the records (all as text).
struct Csv {
    header: Vec<String>,
    records: Vec<Vec<String>>,
}

impl Csv {
    /// Index of a column by name (trimmed, case-insensitive).
    fn column(&self, name: &str) -> Result<usize, String> {
        self.header
            .iter()
            .position(|h| h.trim().eq_ignore_ascii_case(name))
            .ok_or_else(|| format!("no column '{name}' in header {:?}", self.header))
    }
}

/// Splits CSV text into records: RFC 4180 quoting (quoted fields may hold commas, doubled quotes and line
/// breaks), LF or CRLF line ends, a leading byte-order mark ignored, blank lines skipped.
fn parse_csv(text: &str) -> Result<Csv, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut records: Vec<Vec<String>> = Vec::new();
    let mut record: Vec<String> = Vec::new();
    let mut field = String::new();
    let mut in_quotes = false;
    let mut line = 1usize;
    let mut chars = text.chars().peekable();
    let end_record = |record: &mut Vec<String>, records: &mut Vec<Vec<String>>| {
        let r = std::mem::take(record);
        if !(r.len() == 1 && r[0].trim().is_empty()) {
            records.push(r);
        }
    };
    while let Some(c) = chars.next() {
        if in_quotes {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => in_quotes = false,
                '\n' => {
                    line += 1;
                    field.push(c);
                }
                _ => field.push(c),
            }
            continue;
        }
        match c {
            '"' if field.trim().is_empty() => {
                field.clear();
                in_quotes = true;
            }
            ',' => record.push(std::mem::take(&mut field)),
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                record.push(std::mem::take(&mut field));
                end_record(&mut record, &mut records);
                line += 1;
            }
            _ => field.push(c),
        }
    }
    if in_quotes {
        return Err(format!("unterminated quoted field at line {line}"));
    }
    if !field.is_empty() || !record.is_empty() {
        record.push(field);
        end_record(&mut record, &mut records);
    }
    if records.is_empty() {
        return Err("empty file".into());
    }
    let header = records.remove(0);
    Ok(Csv { header, records })
}

fn read_csv(path: &Path) -> Result<Csv, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse_csv(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Positions of the living trees (status "A"), and how many living rows had unusable coordinates.
fn read_trees(path: &Path) -> Result<(Vec<DVec2>, usize), String> {
    let csv = read_csv(path)?;
    let (gx, gy, status) = (csv.column("gx")?, csv.column("gy")?, csv.column("status")?);
    let mut trees = Vec::new();
    let mut bad = 0usize;
    for r in &csv.records {
        if r.get(status).map(|s| s.trim()) != Some("A") {
            continue;
        }
        match (
            r.get(gx).and_then(|s| number(s)),
            r.get(gy).and_then(|s| number(s)),
        ) {
            (Some(x), Some(y)) => trees.push(DVec2::new(x, y)),
            _ => bad += 1,
        }
    }
    if trees.is_empty() {
        return Err(format!("{}: no living trees", path.display()));
    }
    Ok((trees, bad))
}

/// The elevation grid (x, y, elev on a regular square lattice) as a heightfield.
fn read_elevation(path: &Path) -> Result<Heightfield, String> {
    let csv = read_csv(path)?;
    let (cx, cy, ce) = (csv.column("x")?, csv.column("y")?, csv.column("elev")?);
    let mut samples = Vec::with_capacity(csv.records.len());
    for (k, r) in csv.records.iter().enumerate() {
        let get = |c: usize| r.get(c).and_then(|s| number(s));
        match (get(cx), get(cy), get(ce)) {
            (Some(x), Some(y), Some(z)) => samples.push((x, y, z)),
            _ => return Err(format!("{}: bad record {}: {r:?}", path.display(), k + 2)),
        }
    }
    let distinct = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        v
    };
    let xs = distinct(samples.iter().map(|s| s.0).collect());
    let ys = distinct(samples.iter().map(|s| s.1).collect());
    if xs.len() < 2 || ys.len() < 2 {
        return Err(format!("{}: not a grid", path.display()));
    }
    let cell = xs[1] - xs[0];
    let regular = |v: &[f64]| {
        v.windows(2)
            .all(|w| ((w[1] - w[0]) - cell).abs() < 1e-6 * cell)
    };
    if cell <= 0.0 || !regular(&xs) || !regular(&ys) {
        return Err(format!(
            "{}: samples are not on a regular square grid",
            path.display()
        ));
    }
    let (nx, ny) = (xs.len(), ys.len());
    let mut heights = vec![f32::NAN; nx * ny];
    for (x, y, z) in samples {
        let i = ((x - xs[0]) / cell).round() as usize;
        let j = ((y - ys[0]) / cell).round() as usize;
        heights[j * nx + i] = z as f32;
    }
    if let Some(k) = heights.iter().position(|h| h.is_nan()) {
        return Err(format!(
            "{}: grid node ({}, {}) has no sample",
            path.display(),
            xs[k % nx],
            ys[k / nx]
        ));
    }
    Heightfield::new(DVec2::new(xs[0], ys[0]), cell, nx, ny, heights)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The living trees and the terrain of the plot.
pub struct ForestData {
    pub trees: Vec<DVec2>,
    /// Living trees whose coordinates could not be read.
    pub unreadable: usize,
    pub terrain: Heightfield,
}

/// Loads the forest data (panics with the reason when it is absent).
pub fn load(dir: &Path) -> Result<ForestData, String> {
    let (trees_path, elev_path) = (dir.join(TREES_FILE), dir.join(ELEVATION_FILE));
    require(&[trees_path.clone(), elev_path.clone()]);
    let (trees, unreadable) = read_trees(&trees_path)?;
    let terrain = read_elevation(&elev_path)?;
    Ok(ForestData {
        trees,
        unreadable,
        terrain,
    })
}

/// The pcf's range and ring width (m), and the side of the cells whose counts are correlated.
pub const PCF_RANGE: f64 = 50.0;
pub const PCF_RING: f64 = 1.0;
pub const COUNT_CELL: f64 = 10.0;
/// The side of the coarser squares whose counts are correlated, and the step between them (m): every 50 m square
/// in the 50 × 100 m half, 5 m apart (two 50 m cells tiling it would only tell which half is the denser: ±1).
pub const COUNT_WINDOW: f64 = 50.0;
pub const COUNT_WINDOW_STEP: f64 = 5.0;
/// Seeds of the synthesized eastern halves.
pub const SEEDS: [u64; 5] = [1, 2, 3, 4, 5];
/// Seeds of the slope-intensity Poisson draws averaged as a baseline (the first is the single draw's).
pub const POISSON_SEEDS: [u64; 5] = [13, 14, 15, 16, 17];

/// One line of the report: a candidate arrangement of the eastern half against a reference.
pub struct Row {
    pub label: String,
    pub count: usize,
    pub density_ratio: f64,
    /// The engine's rdf (to the color's radius) against the reference's.
    pub rdf_l2: f64,
    /// The translation-corrected pcf, 0–`PCF_RANGE`, against the real eastern trees'.
    pub pcf_l2: f64,
    pub slope_tv: f64,
    /// Correlation of the counts in `COUNT_CELL` cells with the real eastern trees'.
    pub count_correlation: f64,
    /// Correlation of the counts in `COUNT_WINDOW` squares with the real eastern trees'.
    pub window_correlation: f64,
    /// Correlation of the counts in `COUNT_CELL` cells with the western trees' slope intensity over the cells:
    /// how closely the candidate follows the learned slope preference, right or wrong.
    pub intensity_correlation: f64,
}

pub struct ForestReport {
    pub trees: usize,
    pub unreadable: usize,
    pub west_count: usize,
    pub east_count: usize,
    pub max_radius: f64,
    pub bin_width: f64,
    pub synthesis_seconds: f64,
    /// [`Row::intensity_correlation`] of the real eastern trees: whether the western trees' slope preference
    /// holds in the east.
    pub east_intensity_correlation: f64,
    /// Synthesized (one per seed of `SEEDS`) vs the real eastern trees.
    pub synthesized: Vec<Row>,
    /// Real western trees vs the real eastern trees (natural variation between the two halves).
    pub real_west: Row,
    /// A second synthesis (seed 2) vs the first.
    pub second_draw: Row,
    /// Poisson-disk (dart throwing) scatter at the synthesized count vs the real eastern trees.
    pub poisson_disk: Row,
    pub poisson_disk_radius: f64,
    /// Uniform random (Poisson) scatter at the synthesized count vs the real eastern trees.
    pub uniform: Row,
    /// Inhomogeneous Poisson scatter whose intensity is the western trees per slope bin over the western area
    /// per slope bin, vs the real eastern trees.
    pub slope_poisson: Row,
    /// The same process drawn with each of `POISSON_SEEDS`.
    pub slope_poisson_draws: Vec<Row>,
}

pub fn west() -> Region {
    Region::Rect {
        min: DVec2::new(100.0, 400.0),
        max: DVec2::new(150.0, 500.0),
    }
}

pub fn east() -> Region {
    Region::Rect {
        min: DVec2::new(150.0, 400.0),
        max: DVec2::new(200.0, 500.0),
    }
}

fn tree_scene(points: &[DVec2], terrain: &Heightfield) -> Scene {
    Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances: points.iter().map(|p| Instance::at(*p, 0)).collect(),
        terrain: Some(terrain.clone().into()),
        ..Default::default()
    }
}

/// The slope bin of `p` (the engine's 2.5° bins).
fn slope_bin(terrain: &Heightfield, p: DVec2) -> Option<usize> {
    let slope = terrain.map_at("slope", p)?.to_degrees();
    Some((slope / worldpaint_core::SLOPE_BIN_DEGREES).max(0.0) as usize)
}

/// The intensity an inhomogeneous Poisson process fitted on the slope map gives: per slope bin, `points` per unit
/// area of that bin in `from` (areas from a 0.5 m lattice).
pub struct SlopeIntensity<'t> {
    terrain: &'t Heightfield,
    count: Vec<f64>,
    area: Vec<f64>,
}

impl<'t> SlopeIntensity<'t> {
    pub fn fit(terrain: &'t Heightfield, points: &[DVec2], from: &Region) -> Self {
        let mut count = Vec::<f64>::new();
        let mut area = Vec::<f64>::new();
        let grow = |v: &mut Vec<f64>, k: usize| {
            if v.len() <= k {
                v.resize(k + 1, 0.0);
            }
        };
        for p in points.iter().filter(|p| from.contains(**p)) {
            if let Some(k) = slope_bin(terrain, *p) {
                grow(&mut count, k);
                count[k] += 1.0;
            }
        }
        for p in lattice(from, LATTICE_STEP) {
            if let Some(k) = slope_bin(terrain, p) {
                grow(&mut area, k);
                area[k] += LATTICE_STEP * LATTICE_STEP;
            }
        }
        SlopeIntensity {
            terrain,
            count,
            area,
        }
    }

    /// Trees per m² at `p`.
    pub fn at(&self, p: DVec2) -> f64 {
        slope_bin(self.terrain, p).map_or(0.0, |k| self.of_bin(k))
    }

    fn of_bin(&self, k: usize) -> f64 {
        match (self.count.get(k), self.area.get(k)) {
            (Some(c), Some(a)) if *a > 0.0 => c / a,
            _ => 0.0,
        }
    }

    fn peak(&self) -> f64 {
        (0..self.count.len())
            .map(|k| self.of_bin(k))
            .fold(0.0, f64::max)
    }

    /// The inhomogeneous Poisson process of this intensity on `to`, drawn by thinning uniform candidates.
    pub fn draw(&self, to: &Region, seed: u64) -> Vec<DVec2> {
        let peak = self.peak();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        uniform_points(to, peak, seed)
            .into_iter()
            .filter(|p| rng.random::<f64>() * peak < self.at(*p))
            .collect()
    }

    /// Pearson correlation of the counts of `points` in square cells of side `cell` tiling `[lo, hi]` with the
    /// intensity integrated over the cells: how closely the points follow the slope preference.
    pub fn correlation(&self, points: &[DVec2], lo: DVec2, hi: DVec2, cell: f64) -> f64 {
        let window = Region::Rect { min: lo, max: hi };
        let (nx, ny) = (
            ((hi.x - lo.x) / cell).floor() as usize,
            ((hi.y - lo.y) / cell).floor() as usize,
        );
        let cell_of = |p: DVec2| {
            let (i, j) = ((p.x - lo.x) / cell, (p.y - lo.y) / cell);
            (i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny)
                .then(|| j as usize * nx + i as usize)
        };
        let mut expected = vec![0.0; nx * ny];
        for p in lattice(&window, LATTICE_STEP) {
            if let Some(k) = cell_of(p) {
                expected[k] += self.at(p);
            }
        }
        let mut counts = vec![0.0; nx * ny];
        for k in points.iter().filter_map(|p| cell_of(*p)) {
            counts[k] += 1.0;
        }
        pearson(&counts, &expected)
    }
}

/// The lattice the slope intensity's areas are read on (m).
const LATTICE_STEP: f64 = 0.5;

/// The centres of a `step` lattice over `region`'s box that lie in it.
fn lattice(region: &Region, step: f64) -> Vec<DVec2> {
    let (lo, hi) = region.bbox();
    let (nx, ny) = (
        ((hi.x - lo.x) / step) as usize,
        ((hi.y - lo.y) / step) as usize,
    );
    (0..nx * ny)
        .map(|k| lo + DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5) * step)
        .filter(|p| region.contains(*p))
        .collect()
}

/// What every candidate is measured against: the real eastern trees, their learned color and their pcf, and the
/// western trees' slope intensity.
struct Reference<'a> {
    color: Color,
    trees: &'a [DVec2],
    pcf: Vec<f64>,
    intensity: &'a SlopeIntensity<'a>,
}

impl<'a> Reference<'a> {
    fn of(color: Color, trees: &'a [DVec2], intensity: &'a SlopeIntensity<'a>) -> Self {
        let (lo, hi) = east().bbox();
        let pcf = pcf(trees, lo, hi, PCF_RANGE, PCF_RING);
        Reference {
            color,
            trees,
            pcf,
            intensity,
        }
    }
}

fn row(
    label: impl Into<String>,
    reference: &Reference,
    candidate: &Color,
    points: &[DVec2],
) -> Row {
    let fid = compare(&reference.color, candidate);
    let (lo, hi) = east().bbox();
    Row {
        label: label.into(),
        count: candidate.categories.first().map_or(0, |c| c.count),
        density_ratio: fid.density_ratio.first().map_or(f64::NAN, |d| d.1),
        rdf_l2: fid.rdf_l2_of("tree", "tree").unwrap_or(f64::NAN),
        pcf_l2: l2(&pcf(points, lo, hi, PCF_RANGE, PCF_RING), &reference.pcf),
        slope_tv: fid
            .map_tv
            .iter()
            .find(|(c, m, _)| c == "tree" && m == "slope")
            .map_or(f64::NAN, |t| t.2),
        count_correlation: count_correlation(points, reference.trees, lo, hi, COUNT_CELL),
        window_correlation: window_count_correlation(
            points,
            reference.trees,
            lo,
            hi,
            COUNT_WINDOW,
            COUNT_WINDOW_STEP,
        ),
        intensity_correlation: reference.intensity.correlation(points, lo, hi, COUNT_CELL),
    }
}

/// Runs the whole report on loaded data.
pub fn report(data: &ForestData) -> Result<ForestReport, String> {
    let terrain = &data.terrain;
    let (west, east) = (west(), east());
    let all = tree_scene(&data.trees, terrain);
    let slope_only = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let err = |what: &str| {
        let what = what.to_string();
        move |e: worldpaint_core::Error| format!("{what}: {e}")
    };
    let west_color =
        learn_color(&all, &west, "luquillo west", &slope_only).map_err(err("learn west"))?;
    // every other color with the western color's bins, so rdfs compare bin by bin
    let same_bins = AnalysisOptions {
        bin_width: Some(west_color.bin_width),
        max_radius: Some(west_color.max_radius),
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let learn = |points: &[DVec2], name: &str| {
        learn_color(&tree_scene(points, terrain), &east, name, &same_bins)
            .map_err(err(&format!("learn {name}")))
    };
    let in_east = |points: &[DVec2]| -> Vec<DVec2> {
        points
            .iter()
            .copied()
            .filter(|p| east.contains(*p))
            .collect()
    };
    let east_trees = in_east(&data.trees);
    let (lo, hi) = east.bbox();
    let intensity = SlopeIntensity::fit(terrain, &data.trees, &west);
    let reference = Reference::of(
        learn(&east_trees, "luquillo east")?,
        &east_trees,
        &intensity,
    );

    // paint the eastern half next to the real western trees (the eastern trees are what the paste replaces)
    let context: Vec<DVec2> = data
        .trees
        .iter()
        .copied()
        .filter(|p| !east.contains(*p))
        .collect();
    let context_scene = tree_scene(&context, terrain);
    let paint = |seed: u64| -> Result<Vec<DVec2>, String> {
        let opts = SynthesisOptions {
            seed,
            ..Default::default()
        };
        let out =
            synthesize(&context_scene, &west_color, &east, &opts).map_err(err("synthesize"))?;
        Ok(out.instances.iter().map(|i| i.position).collect())
    };
    let t0 = Instant::now();
    let draws = SEEDS
        .iter()
        .map(|s| paint(*s))
        .collect::<Result<Vec<_>, _>>()?;
    let synthesis_seconds = t0.elapsed().as_secs_f64() / SEEDS.len() as f64;
    let mut synthesized = Vec::new();
    let mut colors = Vec::new();
    for (seed, points) in SEEDS.iter().zip(&draws) {
        let color = learn(points, &format!("synthesized {seed}"))?;
        synthesized.push(row(
            format!("synthesized (seed {seed}) vs real east"),
            &reference,
            &color,
            points,
        ));
        colors.push(color);
    }
    let first = &draws[0];
    let second_draw = row(
        "synthesized seed 2 vs seed 1",
        &Reference::of(colors[0].clone(), first, &intensity),
        &colors[1],
        &draws[1],
    );

    // reference scatters at the synthesized count
    let density = first.len() as f64 / east.area();
    let radius = 0.5 / density.sqrt();
    let disk = hard_core_points(&east, density, radius, 11);
    let uniform = uniform_points(&east, density, 12);
    let inhomogeneous = intensity.draw(&east, 13);
    let west_trees: Vec<DVec2> = data
        .trees
        .iter()
        .copied()
        .filter(|p| west.contains(*p))
        .collect();
    let (wlo, whi) = west.bbox();
    let west_as_candidate =
        learn_color(&all, &west, "luquillo west", &same_bins).map_err(err("learn west"))?;
    let mut real_west = row(
        "real west vs real east",
        &reference,
        &west_as_candidate,
        &[],
    );
    real_west.pcf_l2 = l2(
        &pcf(&west_trees, wlo, whi, PCF_RANGE, PCF_RING),
        &reference.pcf,
    );
    // the western trees shifted onto the eastern half, for the count correlation
    let shifted: Vec<DVec2> = west_trees.iter().map(|p| *p + (lo - wlo)).collect();
    real_west.count_correlation = count_correlation(&shifted, &east_trees, lo, hi, COUNT_CELL);
    real_west.window_correlation = window_count_correlation(
        &shifted,
        &east_trees,
        lo,
        hi,
        COUNT_WINDOW,
        COUNT_WINDOW_STEP,
    );
    real_west.intensity_correlation = intensity.correlation(&shifted, lo, hi, COUNT_CELL);
    let slope_poisson_draws = POISSON_SEEDS
        .iter()
        .map(|seed| {
            let points = intensity.draw(&east, *seed);
            Ok(row(
                format!("slope-intensity Poisson (seed {seed})"),
                &reference,
                &learn(&points, "slope poisson")?,
                &points,
            ))
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(ForestReport {
        trees: data.trees.len(),
        unreadable: data.unreadable,
        west_count: west_color.categories.first().map_or(0, |c| c.count),
        east_count: east_trees.len(),
        max_radius: west_color.max_radius,
        bin_width: west_color.bin_width,
        synthesis_seconds,
        east_intensity_correlation: intensity.correlation(&east_trees, lo, hi, COUNT_CELL),
        synthesized,
        real_west,
        second_draw,
        poisson_disk: row(
            "Poisson-disk vs real east",
            &reference,
            &learn(&disk, "poisson disk")?,
            &disk,
        ),
        poisson_disk_radius: radius,
        uniform: row(
            "uniform random vs real east",
            &reference,
            &learn(&uniform, "uniform")?,
            &uniform,
        ),
        slope_poisson: row(
            "slope-intensity Poisson vs real east",
            &reference,
            &learn(&inhomogeneous, "slope poisson")?,
            &inhomogeneous,
        ),
        slope_poisson_draws,
    })
}

/// Mean of a figure over rows.
pub fn mean(rows: &[Row], figure: impl Fn(&Row) -> f64) -> f64 {
    rows.iter().map(figure).sum::<f64>() / rows.len().max(1) as f64
}

/// The mean of every figure over rows, as one row.
pub fn mean_row(label: impl Into<String>, rows: &[Row]) -> Row {
    Row {
        label: label.into(),
        count: mean(rows, |r| r.count as f64).round() as usize,
        density_ratio: mean(rows, |r| r.density_ratio),
        rdf_l2: mean(rows, |r| r.rdf_l2),
        pcf_l2: mean(rows, |r| r.pcf_l2),
        slope_tv: mean(rows, |r| r.slope_tv),
        count_correlation: mean(rows, |r| r.count_correlation),
        window_correlation: mean(rows, |r| r.window_correlation),
        intensity_correlation: mean(rows, |r| r.intensity_correlation),
    }
}

impl ForestReport {
    /// The mean of the synthesized rows.
    pub fn synthesized_mean(&self) -> Row {
        mean_row(
            format!("synthesized, mean of {} seeds", self.synthesized.len()),
            &self.synthesized,
        )
    }

    /// The mean of the slope-intensity Poisson draws.
    pub fn slope_poisson_mean(&self) -> Row {
        mean_row(
            format!(
                "slope-intensity Poisson, mean of {}",
                self.slope_poisson_draws.len()
            ),
            &self.slope_poisson_draws,
        )
    }

    /// The report as a plain-text table.
    pub fn table(&self) -> String {
        let mut s = format!(
            "Luquillo forest plot, living trees: {} ({} unreadable rows skipped); western half (x 100-150 m) {} \
             trees, eastern half (x 150-200 m) {} trees; rdf to {:.2} m in {:.3} m bins; map: slope\n\
             eastern half painted with the western color next to the real western trees in {:.2} s per seed\n\
             pcf: translation-corrected, 0-{PCF_RANGE} m in {PCF_RING} m rings; count correlations with the real \
             eastern trees over {COUNT_CELL} m cells (10 m) and over every {COUNT_WINDOW} m square of the half, \
             {COUNT_WINDOW_STEP} m apart (50 m); slope λ: count correlation over {COUNT_CELL} m cells with the \
             western trees' slope intensity (the slope-intensity Poisson's), {:.3} for the real eastern trees\n",
            self.trees,
            self.unreadable,
            self.west_count,
            self.east_count,
            self.max_radius,
            self.bin_width,
            self.synthesis_seconds,
            self.east_intensity_correlation,
        );
        s.push_str(&format!(
            "{:<40} {:>6} {:>8} {:>8} {:>8} {:>9} {:>7} {:>7} {:>7}\n",
            "candidate vs reference",
            "count",
            "density",
            "rdf L2",
            "pcf L2",
            "slope TV",
            "10 m",
            "50 m",
            "slope λ"
        ));
        let line = |r: &Row| {
            format!(
                "{:<40} {:>6} {:>8.3} {:>8.4} {:>8.4} {:>9.4} {:>7.3} {:>7.3} {:>7.3}\n",
                r.label,
                r.count,
                r.density_ratio,
                r.rdf_l2,
                r.pcf_l2,
                r.slope_tv,
                r.count_correlation,
                r.window_correlation,
                r.intensity_correlation
            )
        };
        for r in &self.synthesized {
            s.push_str(&line(r));
        }
        s.push_str(&line(&self.synthesized_mean()));
        for r in [
            &self.real_west,
            &self.second_draw,
            &self.poisson_disk,
            &self.uniform,
            &self.slope_poisson,
            &self.slope_poisson_mean(),
        ] {
            s.push_str(&line(r));
        }
        s.push_str(&format!(
            "(Poisson-disk: dart throwing, hard core {:.2} m = half the mean spacing; uniform: Poisson process; \
             both at the synthesized density; slope-intensity Poisson: the western trees per slope bin over the \
             western area per slope bin, seed {}, and the mean of seeds {:?})\n",
            self.poisson_disk_radius, POISSON_SEEDS[0], POISSON_SEEDS
        ));
        s
    }
}

/// Loads the data and runs the report.
pub fn run() -> Result<ForestReport, String> {
    report(&load(&data_dir())?)
}
