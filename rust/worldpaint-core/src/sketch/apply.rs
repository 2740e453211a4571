//! The whole edit: strokes ordered, features detected and matched, curves built, terrain deformed (thesis §5.1).

use super::checks::{check_camera, check_change, check_matching_work, check_strokes, SketchLimits};
use super::curves::{complete, embed, embedding_depth, fallback_depth};
use super::deform::{deform_to_targets, Deformation, SketchDeformOptions, StrokeTarget};
use super::features::{detect_features, FeatureOptions};
use super::matching::{
    assign_until, feature_pieces, priority_list, Assignment, Candidate, MatchingContext,
    MatchingOptions, Neighbours, StrokeCurve,
};
use super::ordering::{order_strokes, OrderingOptions, StrokeOrder};
use super::view::{Camera, Sight};
use super::{Feature, SketchStroke};
use crate::error::{Error, Result};
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};
use std::time::Instant;

/// How a stroke got its curve.
#[derive(Clone, Debug, PartialEq)]
pub enum CurveSource {
    /// A terrain feature (index in the features detected), deformed onto the stroke.
    Feature(usize),
    /// The skyline under the stroke (the highest visible silhouettes of its columns), deformed onto the stroke.
    Skyline,
    /// No feature could serve: the stroke was embedded at this depth (m, along the camera's forward axis).
    Embedded(f64),
}

/// The curves of the strokes and how they were chosen.
#[derive(Clone, Debug)]
pub struct Targets {
    /// Per stroke (in the order given), its curve.
    pub targets: Vec<StrokeTarget>,
    /// Per stroke, where its curve comes from.
    pub sources: Vec<CurveSource>,
    /// Per stroke, its priority list.
    pub lists: Vec<Vec<Candidate>>,
    /// The assignment found by branch and bound.
    pub assignment: Assignment,
}

/// Share of a curve's length it may be extended by at each end to reach the ground (feature completion).
const COMPLETION_SHARE: f64 = 0.5;

/// The 3D curves for `strokes` (oriented left to right), `front_to_back` their depth order: each stroke's priority
/// list among `features`, the assignment by branch and bound, the embedding of the strokes left without a feature,
/// and, if `completion`, every curve extended to the ground. Refuses a matching past
/// [`super::checks::MAX_MATCHING_WORK`] before any of it; `stop` is asked after each priority list and inside the
/// assignment's search whether to give up ([`Error::Cancelled`]).
#[allow(clippy::too_many_arguments)]
pub fn stroke_targets(
    sight: &Sight,
    camera: &Camera,
    strokes: &[SketchStroke],
    front_to_back: &[usize],
    features: &[Feature],
    options: &MatchingOptions,
    completion: bool,
    stop: &dyn Fn() -> bool,
) -> Result<Targets> {
    let pieces = feature_pieces(camera, features);
    check_matching_work(strokes, pieces.len(), options.columns)?;
    let curves: Vec<StrokeCurve> = strokes.iter().map(StrokeCurve::new).collect();
    let context = MatchingContext::new(sight, camera, &pieces, options);
    let mut lists: Vec<Vec<Candidate>> = Vec::with_capacity(curves.len());
    for (s, c) in curves.iter().enumerate() {
        if stop() {
            return Err(Error::Cancelled);
        }
        let neighbours = Neighbours::of(s, &curves, front_to_back);
        lists.push(priority_list(&context, c, &neighbours, &pieces, options));
    }
    let assignment = assign_until(front_to_back, &lists, context.separation, stop)?;
    let mut chosen: Vec<Option<&Candidate>> = assignment
        .chosen
        .iter()
        .enumerate()
        .map(|(s, c)| c.and_then(|c| lists[s].get(c)))
        .collect();
    chosen.resize(strokes.len(), None);
    let mean_depth = |c: &Candidate| c.depths.iter().sum::<f64>() / c.depths.len().max(1) as f64;
    let depths: Vec<Option<f64>> = front_to_back
        .iter()
        .map(|&s| chosen[s].map(mean_depth))
        .collect();
    let mut sources = vec![CurveSource::Embedded(0.0); strokes.len()];
    let mut built: Vec<(Vec<glam::DVec3>, Vec<usize>)> = vec![Default::default(); strokes.len()];
    for (k, &s) in front_to_back.iter().enumerate() {
        match chosen[s] {
            Some(c) => {
                sources[s] = c.feature.map_or(CurveSource::Skyline, CurveSource::Feature);
                built[s] = (c.curve.clone(), c.breaks.clone());
            }
            None => {
                let depth = embedding_depth(k, &depths, fallback_depth(sight, camera, &curves[s]));
                sources[s] = CurveSource::Embedded(depth);
                built[s] = (embed(camera, &curves[s], depth), Vec::new());
            }
        }
    }
    let targets = curves
        .into_iter()
        .zip(built)
        .map(|(stroke, (curve, breaks))| {
            if completion {
                let length: f64 = curve
                    .windows(2)
                    .enumerate()
                    .filter(|(k, _)| !breaks.contains(&(k + 1)))
                    .map(|(_, w)| w[0].distance(w[1]))
                    .sum();
                let (curve, before) = complete(sight, &curve, &breaks, COMPLETION_SHARE * length);
                let breaks = breaks.iter().map(|b| b + before).collect();
                StrokeTarget {
                    stroke,
                    curve,
                    breaks,
                }
            } else {
                StrokeTarget {
                    stroke,
                    curve,
                    breaks,
                }
            }
        })
        .collect();
    Ok(Targets {
        targets,
        sources,
        lists,
        assignment,
    })
}

/// Everything an edit needs besides the terrain, the camera and the strokes.
#[derive(Clone, Debug)]
pub struct SketchOptions {
    /// Stroke ordering (§5.2).
    pub ordering: OrderingOptions,
    /// Feature detection (§5.3.1).
    pub features: FeatureOptions,
    /// Matching (§5.3.2).
    pub matching: MatchingOptions,
    /// Deformation and lowering (§5.3.3, §5.4).
    pub deform: SketchDeformOptions,
    /// Whether the curves are extended to the ground at their ends (§5.3.2, "an optional step").
    pub completion: bool,
    /// How far the camera may be from the terrain and how much the terrain may change.
    pub limits: SketchLimits,
}

impl Default for SketchOptions {
    /// Every step's defaults, with the curves completed to the ground.
    fn default() -> Self {
        SketchOptions {
            ordering: OrderingOptions::default(),
            features: FeatureOptions::default(),
            matching: MatchingOptions::default(),
            deform: SketchDeformOptions::default(),
            completion: true,
            limits: SketchLimits::default(),
        }
    }
}

/// Seconds spent in each step, as the thesis's Table 5.1 reports them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepSeconds {
    /// Stroke ordering.
    pub ordering: f64,
    /// Feature detection.
    pub features: f64,
    /// Priority lists, assignment and curves.
    pub matching: f64,
    /// The first deformation.
    pub deformation: f64,
    /// Lowering protruding silhouettes (finding them and deforming again).
    pub lowering: f64,
}

/// A sketch applied: the strokes' order, the features, the curves and the deformed terrain.
#[derive(Clone, Debug)]
pub struct SketchEdit {
    /// The strokes ordered in depth and oriented left to right.
    pub order: StrokeOrder,
    /// The terrain features detected.
    pub features: Vec<Feature>,
    /// The strokes' curves and how they were chosen.
    pub targets: Targets,
    /// The deformed terrain.
    pub deformation: Deformation,
    /// Time per step.
    pub seconds: StepSeconds,
}

/// Applies a sketch (thesis §5.1): orders the strokes, detects the terrain's features, matches them to the strokes,
/// deforms the terrain and lowers what would hide the strokes. `progress` hears the share done (0 to 1) and cancels
/// ([`Error::Cancelled`]) by returning `false`.
pub fn apply_sketch(
    terrain: &Heightfield,
    camera: &Camera,
    strokes: &[SketchStroke],
    options: &SketchOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<SketchEdit> {
    if strokes.is_empty() {
        return Err(Error::invalid("the sketch", "has no stroke"));
    }
    check_strokes(strokes)?;
    let sight = Sight::new(terrain);
    check_camera(camera, &sight, &options.limits)?;
    let step = |fraction: f64| {
        if progress(fraction) {
            Ok(())
        } else {
            Err(Error::Cancelled)
        }
    };
    let clock = Instant::now();
    let mut lap = {
        let mut last = 0.0;
        move || {
            let now = clock.elapsed().as_secs_f64();
            let d = now - last;
            last = now;
            d
        }
    };
    step(0.0)?;
    let order = order_strokes(strokes, &options.ordering)?;
    let ordering = lap();
    let features = detect_features(&sight, camera, &options.features)?;
    let features_seconds = lap();
    step(0.2)?;
    let targets = stroke_targets(
        &sight,
        camera,
        &order.oriented,
        &order.front_to_back,
        &features,
        &options.matching,
        options.completion,
        &|| !progress(0.2),
    )?;
    let matching = lap();
    // the change asked for, before the deformation; and the change made, lowering included
    let asked = targets
        .targets
        .iter()
        .flat_map(|t| t.curve.iter())
        .filter_map(|p| {
            terrain
                .height_at(p.truncate())
                .map(|h| ((p.z - h).abs(), *p))
        })
        .fold((0.0, DVec3::ZERO), |a, b| if b.0 > a.0 { b } else { a });
    check_change("the sketch", asked.0, asked.1, terrain, &options.limits)?;
    step(0.3)?;
    let deformation =
        deform_to_targets(terrain, camera, &targets.targets, &options.deform, &|f| {
            progress(0.3 + 0.7 * f)
        })?;
    let (mut largest, mut at) = (0.0, DVec3::ZERO);
    for (k, d) in deformation.displacement.iter().enumerate() {
        if d.abs() > largest {
            largest = d.abs();
            let node = DVec2::new((k % terrain.nx) as f64, (k / terrain.nx) as f64);
            at = (terrain.origin + node * terrain.cell).extend(terrain.heights[k] as f64);
        }
    }
    check_change(
        "the sketch's deformation",
        largest,
        at,
        terrain,
        &options.limits,
    )?;
    Ok(SketchEdit {
        seconds: StepSeconds {
            ordering,
            features: features_seconds,
            matching,
            deformation: deformation.seconds.0,
            lowering: deformation.seconds.1,
        },
        order,
        features,
        targets,
        deformation,
    })
}
