//! What the benchmarks share: each sample is timed by the benchmark itself (its set-up left out), and the median of
//! the samples is kept for the summary that compares it with a baseline of the same run.

use criterion::measurement::WallTime;
use criterion::BenchmarkGroup;
use std::time::Duration;

/// Runs `sample` (which returns the time of the work it measures) as the benchmark `name` of the configured group
/// and returns the median of its samples in seconds.
pub fn median(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    mut sample: impl FnMut() -> Duration,
) -> f64 {
    let mut times: Vec<f64> = Vec::new();
    g.bench_function(name, |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let dt = sample();
                times.push(dt.as_secs_f64());
                total += dt;
            }
            total
        })
    });
    times.sort_by(f64::total_cmp);
    times.get(times.len() / 2).copied().unwrap_or(f64::NAN)
}
