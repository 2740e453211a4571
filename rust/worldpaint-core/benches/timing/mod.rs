//! What the benchmarks share: their groups' sampling, each sample timed by the benchmark itself (its set-up left
//! out), and the median of the samples kept for the summary that compares it with a baseline of the same run.

#![allow(dead_code)] // each benchmark that includes this file uses a part of it

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode};
use std::time::Duration;

/// A group of `samples` samples measured for about `measurement` in all, each sample running the work the same
/// number of times (flat sampling: for work of a second or more, where criterion's linear ramp would take hours).
pub fn flat_group<'a>(
    c: &'a mut Criterion,
    name: &str,
    samples: usize,
    measurement: Duration,
) -> BenchmarkGroup<'a, WallTime> {
    let mut g = c.benchmark_group(name);
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(samples)
        .measurement_time(measurement);
    g
}

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

/// [`median`] of the only benchmark of the group `g`, which it finishes.
pub fn median_alone(
    mut g: BenchmarkGroup<'_, WallTime>,
    name: &str,
    sample: impl FnMut() -> Duration,
) -> f64 {
    let m = median(&mut g, name, sample);
    g.finish();
    m
}
