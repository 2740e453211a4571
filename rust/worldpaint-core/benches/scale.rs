//! The engine at scale (issue "a million instances in seconds"): the 3-category color of the Blender benchmark
//! (`blender_tests/bench_blender.py`: hard-core trees, uniform rocks, clustered grass, 0.1 instances per m² in all,
//! learned on a 100 m square) painted over 1 km² (~100,000 instances) and over 10 km² (~1,000,000), each timed
//! with all threads and with one, with the peak memory the synthesis allocates (a counting allocator).
//!
//! The baseline of the same run: plain dart throwing (hard core, no statistics) of the same count, per point.
//!
//! `cargo bench -p worldpaint-core --bench scale`

mod timing;

use criterion::Criterion;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};
use worldpaint_core::{
    hard_core_points, learn_color, synthesize, undergrowth_scene, AnalysisOptions, Color, DVec2,
    Region, Scene, SynthesisOptions,
};

/// Counts the bytes allocated now and at most since the last reset.
struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let now = NOW.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        NOW.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The peak of bytes allocated while `work` runs, above what was allocated before it.
fn peak_bytes<T>(work: impl FnOnce() -> T) -> (T, usize) {
    let base = NOW.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = work();
    (out, PEAK.load(Ordering::Relaxed).saturating_sub(base))
}

const EXEMPLAR: f64 = 100.0;

fn square(side: f64) -> Region {
    Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(side),
    }
}

/// The Blender benchmark's color: trees hard-core, rocks uniform, grass clustered.
fn bench_color() -> Color {
    let ex = square(EXEMPLAR);
    let scene = undergrowth_scene(EXEMPLAR);
    match learn_color(&scene, &ex, "Bench", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning the bench color failed: {e}"),
    }
}

/// One synthesis over a square of `side`: (instances, seconds, peak bytes).
fn paint(color: &Color, side: f64, threads: usize) -> (usize, f64, usize) {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(p) => p,
        Err(e) => panic!("thread pool: {e}"),
    };
    let scene = Scene {
        categories: color
            .categories
            .iter()
            .map(|c| c.category.clone())
            .collect(),
        ..Default::default()
    };
    let opts = SynthesisOptions {
        seed: 1,
        ..Default::default()
    };
    let t0 = Instant::now();
    let (out, peak) =
        peak_bytes(|| pool.install(|| synthesize(&scene, color, &square(side), &opts)));
    let secs = t0.elapsed().as_secs_f64();
    match out {
        Ok(out) => (out.instances.len(), secs, peak),
        Err(e) => panic!("synthesis failed: {e}"),
    }
}

/// Dart throwing of `n` points with a hard core over a square of `side`: seconds.
fn darts(n: usize, side: f64) -> f64 {
    let t0 = Instant::now();
    let density = n as f64 / (side * side);
    let points = hard_core_points(&square(side), density, 0.5 / density.sqrt(), 7);
    std::hint::black_box(points.len());
    t0.elapsed().as_secs_f64()
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let color = bench_color();
    let mut rows = Vec::new();
    for (name, side) in [("100k_3_categories", 1000.0), ("1M_3_categories", 3162.3)] {
        let mut g = timing::flat_group(&mut c, "scale", 10, Duration::from_secs(5));
        g.warm_up_time(Duration::from_millis(1));
        let mut last = (0, 0.0, 0);
        let secs = timing::median(&mut g, name, || {
            last = paint(&color, side, rayon::current_num_threads());
            Duration::from_secs_f64(last.1)
        });
        g.finish();
        if last.0 == 0 {
            continue; // filtered out
        }
        let one = paint(&color, side, 1);
        rows.push((name, last.0, secs, one.1, last.2, darts(last.0, side)));
    }
    c.final_summary();
    println!();
    println!(
        "== scale summary ({} threads) ==",
        rayon::current_num_threads()
    );
    for (name, n, secs, one, peak, dart) in rows {
        println!(
            "{name}: {n} instances in {secs:.3} s (one thread {one:.3} s, ×{:.2}), peak {:.0} MB; \
             dart throwing of as many points {dart:.3} s, engine / darts per point {:.1}",
            one / secs,
            peak as f64 / 1e6,
            secs / dart
        );
    }
}
