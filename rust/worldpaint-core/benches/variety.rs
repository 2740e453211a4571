//! Benchmark of model variety against the requirement "assembly and the self-intersection check of 1,000 variants
//! of a 1,000-face model in at most 1 s":
//!
//! * `variety/generate_1000`: [`generate`] of 1,000 distinct random variants of the test tree with 22 leaves per
//!   branch (994 faces, 6 components; two branches get a fourth variant so that 4² × 3⁴ = 1,296 assemblies exist):
//!   the seeded draws, assembly with frames and welding, the BVH self-intersection check against the original's
//!   labels, in parallel;
//! * `variety/assemble_1000`: the same 1,000 assemblies without the check (the baseline the check adds to);
//! * `variety/labels`: labelling the original's own intersections (once per model).
//!
//! `cargo bench -p worldpaint-core --bench variety`

#[path = "../tests/common/mod.rs"]
mod common;
mod timing;

use common::variety_models::{edit, tree, tree_atlas, DVec3, Role};
use criterion::Criterion;
use rayon::prelude::*;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{generate_variants, GenerateOptions, IntersectionLabels};

const BUDGET_S: f64 = 1.0;

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let t = tree(22);
    let (d, mut atlas, _) = tree_atlas(&t);
    for c in [2, 3] {
        let thinner = edit(
            &t,
            &d,
            c,
            |r, p| match r {
                Role::Tube(3) => p * 0.999 + DVec3::Z * 0.05,
                _ => p,
            },
            |_| true,
        );
        if let Err(e) = atlas.add_variant(c, thinner) {
            panic!("the benchmark's fourth variant: {e}");
        }
    }
    let labels = IntersectionLabels::of_model(&t.model);
    let options = GenerateOptions {
        count: 1000,
        seed: 1,
        max_attempts: 0,
    };
    let first = match generate_variants(&atlas, &labels, &options) {
        Ok(g) => g,
        Err(e) => panic!("the benchmark generation: {e}"),
    };
    println!(
        "model: {} faces, {} components, #V = {}, original intersecting pairs {}; generated {} kept, {} rejected",
        t.model.faces.len(),
        d.components.len(),
        atlas.count(),
        labels.pairs().len(),
        first.accepted.len(),
        first.rejected.len()
    );
    let choices: Vec<_> = first.accepted.iter().map(|(c, _)| c.clone()).collect();
    let mut g = timing::flat_group(&mut c, "variety", 10, Duration::from_secs(30));
    let generate_s = timing::median(&mut g, "generate_1000", || {
        let start = Instant::now();
        black_box(
            generate_variants(&atlas, &labels, &options)
                .map(|g| g.accepted.len())
                .ok(),
        );
        start.elapsed()
    });
    let assemble_s = timing::median(&mut g, "assemble_1000", || {
        let start = Instant::now();
        let n: usize = choices
            .par_iter()
            .map(|c| atlas.assemble(c).map(|a| a.model.faces.len()).unwrap_or(0))
            .sum();
        black_box(n);
        start.elapsed()
    });
    let labels_s = timing::median(&mut g, "labels", || {
        let start = Instant::now();
        black_box(IntersectionLabels::of_model(&t.model));
        start.elapsed()
    });
    g.finish();
    println!(
        "summary: generate+check 1,000 variants {:.3} s (budget {BUDGET_S} s, {}), assembly alone {:.3} s, \
         labelling the original {:.4} s, on {} threads",
        generate_s,
        if generate_s <= BUDGET_S { "met" } else { "MISSED" },
        assemble_s,
        labels_s,
        rayon::current_num_threads()
    );
}
