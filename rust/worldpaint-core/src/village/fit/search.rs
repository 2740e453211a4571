//! The search of a fit: CMA-ES over the space's coordinates, each candidate grown at the fit's seeds (common
//! random numbers), then the finalists (the best candidates of the best generations and the distribution's mean)
//! grown at four times as many held-out seeds, and the one nearest there kept: the best at the fit's seeds is
//! partly the best at those seeds' luck, the more so the more candidates were tried, so the fit's seeds do not
//! judge the finalists they chose. Last, the kept point's orientation knobs take one step towards the real
//! village's orientation to the road from the histogram its villages showed at the held-out seeds, and, where their
//! hairpins per km are off, that step's grade limit one and two steps more towards the real rate; the nearest of
//! these there is kept where it comes nearer than the point.

use super::grow::{grow_village_figures, rank_village_types};
use super::objective::{objective, pooled_hairpins};
use super::space::{Candidate, ParameterSpace};
use super::{scenario_for, FitOptions, FitProgress, FitTarget};
use crate::village::encyclopedia::{Encyclopedia, Scenario};
use crate::village::figures::{VillageFigures, ORIENTATION_BINS};
use crate::{Error, Result};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// The held-out seeds are the first after this one.
const HELD_OUT_OFFSET: u64 = 1000;

/// Held-out seeds per seed of the fit: a hamlet's figures move from one set of three or four seeds to another by as
/// much as between a finalist and the next, so a few held-out seeds would only pick the luckiest again.
const HELD_OUT_PER_SEED: usize = 4;

/// Candidates grown once the search ends: each finalist at the held-out seeds, the distribution's mean at the fit's
/// seeds too, and the orientation step and the two grade steps at both.
fn finalist_evaluations(options: &FitOptions) -> usize {
    if options.finalists == 0 {
        return 0;
    }
    options.finalists + usize::from(options.finalists > 1) + 6
}

/// The finalists' cost in candidates grown at the fit's seeds.
fn finalist_cost(options: &FitOptions) -> usize {
    if options.finalists == 0 {
        return 0;
    }
    (options.finalists + 3) * HELD_OUT_PER_SEED + usize::from(options.finalists > 1) + 3
}

/// The mean of the grown villages' histograms of the orientation to the road (`None`: none grew).
fn mean_orientation(grown: &[Option<VillageFigures>]) -> Option<[f64; ORIENTATION_BINS]> {
    let villages: Vec<&VillageFigures> = grown.iter().flatten().collect();
    (!villages.is_empty()).then(|| {
        std::array::from_fn(|i| {
            villages
                .iter()
                .map(|v| v.orientation_to_road[i])
                .sum::<f64>()
                / villages.len() as f64
        })
    })
}

/// Where a search ended.
pub(super) struct Outcome {
    /// The kept point, in the space's coordinates.
    pub(super) point: Vec<f64>,
    /// Its objective at the fit's seeds.
    pub(super) objective: f64,
    /// Its objective at the held-out seeds (`None`: no finalist was grown there).
    pub(super) held_out: Option<f64>,
    /// The base type's objective at the fit's seeds.
    pub(super) base_objective: f64,
    /// Candidates evaluated, finalists included.
    pub(super) evaluations: usize,
    /// Generations completed.
    pub(super) generations: usize,
    /// Stopped by the callback, or cut by the time budget within a generation.
    pub(super) stopped_early: bool,
}

/// A search under way: its budget, the progress it reports and the first engine error met.
pub(super) struct Search<'a> {
    target: &'a FitTarget<'a>,
    enc: &'a Encyclopedia,
    options: &'a FitOptions,
    seeds: Vec<u64>,
    started: Instant,
    stop: AtomicBool,
    state: Mutex<FitProgress>,
    // the first engine error met (not a cancellation): the fit reports it rather than learning around it
    failure: Mutex<Option<Error>>,
    progress: &'a (dyn Fn(&FitProgress) -> bool + Sync),
}

impl<'a> Search<'a> {
    pub(super) fn new(
        target: &'a FitTarget<'a>,
        enc: &'a Encyclopedia,
        options: &'a FitOptions,
        seeds: Vec<u64>,
        progress: &'a (dyn Fn(&FitProgress) -> bool + Sync),
    ) -> Search<'a> {
        Search {
            target,
            enc,
            options,
            seeds,
            started: Instant::now(),
            stop: AtomicBool::new(false),
            state: Mutex::new(FitProgress {
                evaluations: 0,
                max_evaluations: options.max_evaluations + finalist_evaluations(options),
                generation: 0,
                best: f64::INFINITY,
                seconds: 0.0,
            }),
            failure: Mutex::new(None),
            progress,
        }
    }

    /// Seconds since the search began.
    pub(super) fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Updates the progress and tells the callback; its `false` stops the search.
    fn report(&self, update: &dyn Fn(&mut FitProgress)) {
        let now = self.state.lock().ok().map(|mut s| {
            update(&mut s);
            s.seconds = self.seconds();
            *s
        });
        if now.is_some_and(|s| !(self.progress)(&s)) {
            self.stop.store(true, Ordering::Relaxed);
        }
    }

    /// Asked between buildings, so a stop is heard within a village, not a generation.
    fn keep_going(&self) -> bool {
        self.report(&|_| {});
        !self.stop.load(Ordering::Relaxed) && self.seconds() <= self.options.max_seconds
    }

    fn failed(&self) -> Result<()> {
        match self.failure.lock().ok().and_then(|mut f| f.take()) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// The scenario growing the real count of buildings with candidate `c`.
    pub(super) fn scenario(&self, c: &Candidate) -> Scenario {
        let buildings = self.target.figures.layout.houses;
        scenario_for(
            self.enc,
            &self.options.name,
            &c.village_type,
            buildings,
            c.count_factor,
            c.farm_share,
        )
    }

    /// The objective of the candidate at `x`, grown at `seeds`.
    fn objective_at(&self, space: &ParameterSpace, x: &[f64], seeds: &[u64]) -> f64 {
        self.grown_at(space, x, seeds).0
    }

    /// The candidate at `x` grown at `seeds`: its objective and its villages' figures.
    fn grown_at(
        &self,
        space: &ParameterSpace,
        x: &[f64],
        seeds: &[u64],
    ) -> (f64, Vec<Option<VillageFigures>>) {
        let c = space.candidate(x);
        let scenario = self.scenario(&c);
        let mut enc = self.enc.clone();
        enc.village_types
            .insert(self.options.name.clone(), c.village_type);
        let keep_going = || self.keep_going();
        let grown: Vec<Option<VillageFigures>> = grow_village_figures(
            self.target,
            &enc,
            &scenario,
            seeds,
            self.options.parcel_cell,
            &keep_going,
        )
        .unwrap_or_else(|err| {
            if let Ok(mut f) = self.failure.lock() {
                f.get_or_insert(err);
            }
            Vec::new()
        });
        let value = objective(&self.target.figures, &grown);
        self.report(&|s| s.evaluations += 1);
        (value, grown)
    }

    /// Whether `candidates` more and the finalists fit in the time left, at the pace of the candidates so far or of
    /// the slowest generation (`slowest`, seconds a candidate), whichever is slower: the search ends in time for its
    /// finalists rather than being cut short (one generation's villages may grow slower than the average).
    /// `since`: when the first candidate began (the ranking of the start is not a candidate's pace).
    fn time_left_for(&self, candidates: usize, since: f64, slowest: f64) -> bool {
        let seconds = self.seconds();
        let done = self.state.lock().map_or(1, |s| s.evaluations.max(1));
        let pace = ((seconds - since) / done as f64).max(slowest);
        seconds + pace * (candidates + finalist_cost(self.options)) as f64
            <= self.options.max_seconds
    }

    /// The village type of the encyclopedia whose villages come nearest the real one at the fit's seeds; the
    /// progress callback may stop it ([`Error::Cancelled`]: there is no type to keep yet).
    pub(super) fn nearest_type(&self) -> Result<String> {
        let keep_going = || self.keep_going();
        let ranked = rank_village_types(
            self.target,
            self.enc,
            &self.seeds,
            self.options.parcel_cell,
            &keep_going,
        )?;
        if !self.keep_going() {
            return Err(Error::Cancelled);
        }
        ranked
            .into_iter()
            .next()
            .map(|r| r.name)
            .ok_or_else(|| Error::invalid("encyclopedia", "it has no village type to start from"))
    }

    /// Runs the search over `space`: the base, the generations of CMA-ES, the finalists.
    pub(super) fn run(&self, space: &ParameterSpace) -> Result<Outcome> {
        let since = self.seconds();
        let start = space.start();
        let base_objective = self.objective_at(space, &start, &self.seeds);
        self.failed()?;
        self.report(&|s| s.best = base_objective);
        let dimensions = space.dimensions.len();
        let population = if self.options.population > 0 {
            self.options.population
        } else {
            4 + (3.0 * (dimensions as f64).ln()).floor() as usize
        };
        let told = |x: &cmaes::DVector<f64>| self.objective_at(space, x.as_slice(), &self.seeds);
        let mut cma = cmaes::CMAESOptions::new(start.clone(), self.options.step)
            .population_size(population)
            .seed(self.options.seed)
            .build(&told)
            .map_err(|e| Error::invalid("fit options", format!("{e:?}")))?;
        // the best of each completed generation, the base first
        let mut bests = vec![(base_objective, start)];
        let mut stopped_early = !self.keep_going();
        let evaluations = |cma: &cmaes::CMAES<_>| 1 + cma.function_evals();
        let mut slowest = 0.0f64;
        while !stopped_early
            && evaluations(&cma) + population <= self.options.max_evaluations.max(1)
            && self.time_left_for(population, since, slowest)
        {
            let began = self.seconds();
            let finished = cma.next_parallel();
            slowest = slowest.max((self.seconds() - began) / population as f64);
            self.failed()?;
            if !self.keep_going() {
                // villages of this generation were cancelled: its figures are not all there
                stopped_early = true;
                break;
            }
            if let Some(b) = cma.current_best_individual() {
                bests.push((b.value, b.point.as_slice().to_vec()));
            }
            let (generation, best) = (
                bests.len() - 1,
                bests.iter().map(|b| b.0).fold(f64::INFINITY, f64::min),
            );
            self.report(&|s| {
                s.generation = generation;
                s.best = best;
            });
            stopped_early = self.stop.load(Ordering::Relaxed);
            if finished.is_some() {
                break;
            }
        }
        let generations = bests.len() - 1;
        let mean = cma.mean().as_slice().to_vec();
        let (point, objective, held_out) = self.final_choice(space, bests, mean, stopped_early)?;
        Ok(Outcome {
            point,
            objective,
            held_out,
            base_objective,
            evaluations: self.state.lock().map_or(0, |s| s.evaluations),
            generations,
            stopped_early: stopped_early || self.stop.load(Ordering::Relaxed),
        })
    }

    /// The point kept: of the finalists (the `finalists − 1` best generation bests and the distribution's `mean`),
    /// the one whose objective at the held-out seeds is least; the best at the fit's seeds when the search was
    /// stopped or has no finalists.
    fn final_choice(
        &self,
        space: &ParameterSpace,
        mut bests: Vec<(f64, Vec<f64>)>,
        mean: Vec<f64>,
        stopped_early: bool,
    ) -> Result<(Vec<f64>, f64, Option<f64>)> {
        bests.sort_by(|a, b| a.0.total_cmp(&b.0));
        let best = bests[0].clone();
        let count = self.options.finalists;
        if stopped_early || count == 0 || bests.len() < 2 {
            return Ok((best.1, best.0, None));
        }
        let mut finalists: Vec<(f64, Vec<f64>)> = bests
            .into_iter()
            .take(count.saturating_sub(1).max(1))
            .collect();
        let held_out: Vec<u64> = (1..=(self.seeds.len() * HELD_OUT_PER_SEED) as u64)
            .map(|k| HELD_OUT_OFFSET + k)
            .collect();
        // every finalist at the held-out seeds and the mean at the fit's seeds too, in parallel as a generation's
        // candidates are (the pace the search ended by)
        let mut jobs: Vec<(&[f64], &[u64])> = finalists
            .iter()
            .map(|(_, point)| (point.as_slice(), held_out.as_slice()))
            .collect();
        if count > 1 {
            jobs.extend([
                (mean.as_slice(), held_out.as_slice()),
                (mean.as_slice(), &self.seeds),
            ]);
        }
        let mut grown: Vec<(f64, Vec<Option<VillageFigures>>)> = jobs
            .par_iter()
            .map(|(point, seeds)| self.grown_at(space, point, seeds))
            .collect();
        self.failed()?;
        if !self.keep_going() {
            return Ok((best.1, best.0, None));
        }
        if count > 1 {
            let at_fit_seeds = grown.pop().map_or(f64::INFINITY, |g| g.0);
            finalists.push((at_fit_seeds, mean));
        }
        let Some(((fit, point), (held, villages))) = finalists
            .into_iter()
            .zip(grown)
            .min_by(|(_, a), (_, b)| a.0.total_cmp(&b.0))
        else {
            return Ok((best.1, best.0, None));
        };
        let Some(orientation) = mean_orientation(&villages) else {
            return Ok((point, fit, Some(held)));
        };
        // the orientation step, and with it the grade steps where the hairpins ask for them: all grown at once
        let turned = space.orientation_step(
            &point,
            &orientation,
            &self.target.figures.orientation_to_road,
        );
        let hairpins = pooled_hairpins(&villages);
        let graded = space.grade_steps(
            &turned,
            hairpins,
            self.target.figures.network.hairpins_per_km,
        );
        let steps: Vec<&[f64]> = std::iter::once(turned.as_slice())
            .chain(graded.iter().map(Vec::as_slice))
            .collect();
        let jobs: Vec<(&[f64], &[u64])> = steps
            .iter()
            .flat_map(|x| [(*x, held_out.as_slice()), (*x, self.seeds.as_slice())])
            .collect();
        let values: Vec<f64> = jobs
            .par_iter()
            .map(|(x, seeds)| self.objective_at(space, x, seeds))
            .collect();
        self.failed()?;
        if !self.keep_going() {
            return Ok((point, fit, Some(held)));
        }
        let mut kept = (point, fit, held);
        for (x, v) in steps.iter().zip(values.chunks_exact(2)) {
            if v[0] < kept.2 {
                kept = (x.to_vec(), v[1], v[0]);
            }
        }
        Ok((kept.0, kept.1, Some(kept.2)))
    }
}
