//! Benchmark of the import of a real place against the goal "the Bayreuth, Andorra and Kirchberg layers and their
//! SRTM tiles import in under 30 s each", beside a baseline measured in the same run:
//!
//! * `place/north_bayreuth`, `place/andorra`: the whole import (four OpenStreetMap layers and the SRTM 3″ grid:
//!   read, classify, project, crop, fill, resample at the grid's own spacing);
//! * baseline `place/<name>_json_only`: parsing the same GeoJSON files with `serde_json` and nothing else (what any
//!   reader of these layers pays).
//!
//! The data lives beside the project (`shared/data/real`); without it the benchmark says so and measures nothing.
//!
//! `cargo bench -p worldpaint-core --bench place`

mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use worldpaint_core::{import_place, PlaceOptions};

const GOAL_S: f64 = 30.0;

fn real_data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/real")
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut g = timing::flat_group(&mut c, "place", 10, Duration::from_secs(20));
    let mut rows = Vec::new();
    for stem in ["north_bayreuth", "andorra"] {
        let dir = real_data_dir();
        let layers: Vec<PathBuf> = ["buildings", "roads", "areas", "places"]
            .iter()
            .map(|n| dir.join(format!("villages/{stem}_{n}.geojson")))
            .collect();
        let dem = dir.join(format!("terrain/{stem}_srtm3.asc"));
        if let Some(missing) = layers.iter().chain([&dem]).find(|p| !p.is_file()) {
            println!(
                "{stem}: skipped, {} not found (the real data lives beside the project, in shared/data/real)",
                missing.display()
            );
            continue;
        }
        let options = PlaceOptions::default();
        let import = || import_place(&layers, Some(&dem), None, &options, &|_, _| true);
        let place = match import() {
            Ok(p) => p,
            Err(e) => panic!("{stem}: {e}"),
        };
        let terrain = place
            .terrain
            .as_ref()
            .map_or((0, 0, 0.0), |t| (t.nx, t.ny, t.cell));
        println!(
            "{stem}: {} buildings, {} roads, {} areas, {} places; terrain {} x {} nodes of {:.1} m",
            place.buildings.len(),
            place.roads.len(),
            place.areas.len(),
            place.places.len(),
            terrain.0,
            terrain.1,
            terrain.2
        );
        let full_s = timing::median(&mut g, stem, || {
            let t0 = Instant::now();
            black_box(import().ok());
            t0.elapsed()
        });
        let json_s = timing::median(&mut g, &format!("{stem}_json_only"), || {
            let t0 = Instant::now();
            for path in &layers {
                if let Ok(bytes) = std::fs::read(path) {
                    black_box(serde_json::from_slice::<serde_json::Value>(&bytes).ok());
                }
            }
            t0.elapsed()
        });
        rows.push((stem, full_s, json_s));
    }
    g.finish();
    c.final_summary();

    println!();
    println!("== place summary ==");
    for (stem, full_s, json_s) in rows {
        println!(
            "{stem}: import {full_s:.3} s; the layers' JSON parsed alone {json_s:.3} s; import / JSON = {:.1}; goal \
             ≤ {GOAL_S} s: {} ({:.4} of it)",
            full_s / json_s,
            if full_s <= GOAL_S { "met" } else { "NOT met" },
            full_s / GOAL_S
        );
    }
}
