//! Benchmark of sketch-based terrain editing against the requirement "the whole sketch pipeline in at most 0.5 s
//! on a 512 × 512 terrain", beside a baseline measured in the same run:
//!
//! * `sketch/features_512`: feature detection (§5.3.1), the visible silhouettes from a camera 15 m above the
//!   ground looking across the terrain and the ridges (PPA with a spanning forest), on `exemplar::rough_terrain`
//!   (512 × 512 samples, 2 m cells);
//! * `sketch/silhouettes_512` and `sketch/ridges_512`: each detector alone;
//! * baseline `sketch/outline_256_columns`: the terrain's visible outline by ray casting, one
//!   `Sight::column_silhouette` per column of a 256-column image (what drawing the horizon costs).
//!
//! The summary prints the medians, their ratio to the baseline, and the ratio to the thesis's Table 5.1
//! (0.12–0.15 s for the features of its 512² terrains).
//!
//! `cargo bench -p worldpaint-core --bench sketch`

#[path = "support/timing.rs"]
mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::exemplar::rough_terrain;
use worldpaint_core::geom::DVec2;
use worldpaint_core::sketch::features::{detect_features, ridges, silhouettes, FeatureOptions};
use worldpaint_core::sketch::{Camera, FeatureKind, Sight};

const BUDGET_S: f64 = 0.5;

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut g = timing::flat_group(&mut c, "sketch", 20, Duration::from_secs(20));
    let size = 2.0 * 511.0;
    let terrain = rough_terrain(size, 2.0, 3);
    let at = |x: f64, y: f64| {
        let p = DVec2::new(x, y) * size;
        p.extend(terrain.height_at(p).unwrap_or(0.0))
    };
    let eye = at(0.15, 0.15) + glam::DVec3::Z * 15.0;
    let camera = match Camera::looking_at(eye, at(0.7, 0.7), 60.0, 1.5) {
        Ok(c) => c,
        Err(e) => panic!("the benchmark camera: {e}"),
    };
    let sight = Sight::new(&terrain);
    let options = FeatureOptions::default();
    let one = match detect_features(&sight, &camera, &options) {
        Ok(f) => f,
        Err(e) => panic!("the benchmark features: {e}"),
    };
    let count = |kind| one.iter().filter(|f| f.kind == kind).count();
    println!(
        "{}×{} terrain: {} silhouette curves, {} ridge polylines, {} points",
        terrain.nx,
        terrain.ny,
        count(FeatureKind::Silhouette),
        count(FeatureKind::Ridge),
        one.iter().map(|f| f.points.len()).sum::<usize>()
    );

    let features_s = timing::median(&mut g, "features_512", || {
        let t0 = Instant::now();
        black_box(detect_features(&sight, &camera, &options).ok());
        t0.elapsed()
    });
    let silhouettes_s = timing::median(&mut g, "silhouettes_512", || {
        let t0 = Instant::now();
        black_box(silhouettes(&sight, &camera, &options).ok());
        t0.elapsed()
    });
    let ridges_s = timing::median(&mut g, "ridges_512", || {
        let t0 = Instant::now();
        black_box(ridges(&terrain, &options).ok());
        t0.elapsed()
    });
    let base_s = timing::median(&mut g, "outline_256_columns", || {
        let t0 = Instant::now();
        for k in 0..256 {
            let x = (k as f64 + 0.5) / 256.0;
            black_box(sight.column_silhouette(&camera, x, 0.0, 1.0));
        }
        t0.elapsed()
    });
    g.finish();
    c.final_summary();

    println!();
    println!("== sketch summary ==");
    println!(
        "features on 512²: {:.3} s (silhouettes {:.3} s, ridges {:.3} s); outline of 256 columns: {:.3} s; features / baseline = {:.1}",
        features_s,
        silhouettes_s,
        ridges_s,
        base_s,
        features_s / base_s
    );
    println!(
        "budget ≤ {BUDGET_S} s for the whole pipeline: features take {:.2} of it; thesis Table 5.1 features 0.12–0.15 s: {:.1}–{:.1}× faster",
        features_s / BUDGET_S,
        0.12 / features_s,
        0.15 / features_s
    );
}
