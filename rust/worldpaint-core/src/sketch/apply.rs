//! The whole edit: strokes ordered, features detected and matched, curves built, terrain deformed (thesis §5.1).

use super::curves::{complete, embed, embedding_depth, fallback_depth};
use super::deform::StrokeTarget;
use super::matching::{
    assign, feature_pieces, priority_list, Assignment, Candidate, MatchingOptions, StrokeCurve,
};
use super::view::{Camera, Sight};
use super::{Feature, Stroke};

/// How a stroke got its curve.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A terrain feature (index in the features detected), deformed onto the stroke.
    Feature(usize),
    /// No feature could serve: the stroke was embedded at this depth (m, along the camera's forward axis).
    Embedded(f64),
}

/// The curves of the strokes and how they were chosen.
#[derive(Clone, Debug)]
pub struct Targets {
    /// Per stroke (in the order given), its curve.
    pub targets: Vec<StrokeTarget>,
    /// Per stroke, where its curve comes from.
    pub sources: Vec<Source>,
    /// Per stroke, its priority list.
    pub lists: Vec<Vec<Candidate>>,
    /// The assignment found by branch and bound.
    pub assignment: Assignment,
}

/// Share of a curve's length it may be extended by at each end to reach the ground (feature completion).
const COMPLETION_SHARE: f64 = 0.5;

/// The 3D curves for `strokes` (oriented left to right), `front_to_back` their depth order: each stroke's priority
/// list among `features`, the assignment by branch and bound, the embedding of the strokes left without a feature,
/// and, if `completion`, every curve extended to the ground.
pub fn targets(
    sight: &Sight,
    camera: &Camera,
    strokes: &[Stroke],
    front_to_back: &[usize],
    features: &[Feature],
    options: &MatchingOptions,
    completion: bool,
) -> Targets {
    let curves: Vec<StrokeCurve> = strokes.iter().map(StrokeCurve::new).collect();
    let pieces = feature_pieces(camera, features);
    let lists: Vec<Vec<Candidate>> = curves
        .iter()
        .map(|c| priority_list(sight, camera, c, &pieces, options))
        .collect();
    let assignment = assign(front_to_back, &lists);
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
    let mut sources = vec![Source::Embedded(0.0); strokes.len()];
    let mut built: Vec<Vec<glam::DVec3>> = vec![Vec::new(); strokes.len()];
    for (k, &s) in front_to_back.iter().enumerate() {
        match chosen[s] {
            Some(c) => {
                sources[s] = Source::Feature(c.feature);
                built[s] = c.curve.clone();
            }
            None => {
                let depth = embedding_depth(k, &depths, fallback_depth(sight, camera, &curves[s]));
                sources[s] = Source::Embedded(depth);
                built[s] = embed(camera, &curves[s], depth);
            }
        }
    }
    let targets = curves
        .into_iter()
        .zip(built)
        .map(|(stroke, curve)| {
            let curve = if completion {
                let length: f64 = curve.windows(2).map(|w| w[0].distance(w[1])).sum();
                complete(sight, &curve, COMPLETION_SHARE * length)
            } else {
                curve
            };
            StrokeTarget { stroke, curve }
        })
        .collect();
    Targets {
        targets,
        sources,
        lists,
        assignment,
    }
}
