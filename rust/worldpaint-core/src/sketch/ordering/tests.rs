//! Tests of the stroke ordering: the thesis's figures rebuilt from mountains at known depths, each cue on its own,
//! the junction threshold, bad input.

use super::*;
use crate::sketch::Camera;
use glam::DVec3;
use rand::{Rng, SeedableRng};

const EYE_HEIGHT: f64 = 50.0;
const ASPECT: f64 = 1.5;

fn v(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

fn stroke(points: &[(f64, f64)]) -> SketchStroke {
    SketchStroke {
        points: points.iter().map(|&(x, y)| v(x, y)).collect(),
    }
}

fn options() -> OrderingOptions {
    OrderingOptions {
        aspect: ASPECT,
        ..OrderingOptions::default()
    }
}

/// A level camera 50 m above flat ground, looking north, 60° across a 3:2 frame.
fn camera() -> Camera {
    let eye = DVec3::new(0.0, 0.0, EYE_HEIGHT);
    Camera::looking_at(eye, eye + DVec3::Y, 60.0, ASPECT).unwrap()
}

/// A mountain: its ridge line, at `depth` metres in front of the camera.
struct Mountain {
    depth: f64,
    ridge: Vec<DVec3>,
}

/// The ridge at `depth` that the camera sees through the image points `design` (feet on the ground where a
/// point is at [`ground`]'s height).
fn mountain(depth: f64, design: &[(f64, f64)]) -> Mountain {
    let cam = camera();
    let ridge = design
        .iter()
        .map(|&(x, y)| {
            let ray = cam.ray(v(x, y));
            cam.eye + ray * (depth / ray.dot(cam.forward))
        })
        .collect();
    Mountain { depth, ridge }
}

/// The image height of the ground at `depth`.
fn ground(depth: f64) -> f64 {
    camera().project(DVec3::new(0.0, depth, 0.0)).unwrap().0.y
}

/// The ridge as the pinhole projects it (a polyline: projection at a fixed depth is affine).
fn projected(m: &Mountain) -> Vec<DVec2> {
    let cam = camera();
    m.ridge.iter().map(|&p| cam.project(p).unwrap().0).collect()
}

fn y_on(line: &[DVec2], x: f64) -> Option<f64> {
    let (first, last) = (line.first()?, line.last()?);
    (first.x <= x && x <= last.x).then(|| height_at(line, x))
}

/// What a user would draw: each mountain's silhouette where no nearer mountain hides it (a nearer mountain's body
/// covers the image below its silhouette), inside the frame. Each mountain must show exactly one piece.
fn sketch(mountains: &[Mountain]) -> Vec<SketchStroke> {
    let lines: Vec<Vec<DVec2>> = mountains.iter().map(projected).collect();
    let mut strokes = Vec::new();
    for (i, m) in mountains.iter().enumerate() {
        let clearance = |x: f64| {
            let hider = (0..mountains.len())
                .filter(|&j| mountains[j].depth < m.depth)
                .filter_map(|j| y_on(&lines[j], x))
                .fold(f64::NEG_INFINITY, f64::max);
            y_on(&lines[i], x).unwrap() - hider
        };
        let visible = |x: f64| clearance(x) > -1e-9;
        let (x0, x1) = (lines[i][0].x.max(0.0), lines[i].last().unwrap().x.min(1.0));
        let n = ((x1 - x0) / 0.0025).ceil() as usize;
        let xs: Vec<f64> = (0..=n)
            .map(|k| x0 + (x1 - x0) * k as f64 / n as f64)
            .collect();
        let edge = |mut out: f64, mut inside: f64| {
            for _ in 0..60 {
                let mid = 0.5 * (out + inside);
                if visible(mid) {
                    inside = mid;
                } else {
                    out = mid;
                }
            }
            inside
        };
        let mut pieces: Vec<Vec<f64>> = Vec::new();
        for k in 0..xs.len() {
            match (visible(xs[k]), k > 0 && visible(xs[k - 1])) {
                (true, false) if k == 0 => pieces.push(vec![xs[k]]),
                (true, false) => pieces.push(vec![edge(xs[k - 1], xs[k]), xs[k]]),
                (true, true) => pieces.last_mut().unwrap().push(xs[k]),
                (false, true) => pieces.last_mut().unwrap().push(edge(xs[k], xs[k - 1])),
                (false, false) => {}
            }
        }
        assert_eq!(
            pieces.len(),
            1,
            "mountain {i} shows {} pieces",
            pieces.len()
        );
        let points = pieces[0]
            .iter()
            .map(|&x| v(x, y_on(&lines[i], x).unwrap()))
            .collect();
        strokes.push(SketchStroke { points });
    }
    strokes
}

/// Fig. 5.3: stroke 1 (far) disappears behind stroke 2, which disappears behind stroke 3 (near) rising from
/// inside stroke 2's mountain; strokes 2 and 3 overlap in height.
fn figure_5_3() -> Vec<Mountain> {
    vec![
        mountain(
            4000.0,
            &[
                (-0.1, 0.80),
                (0.15, 0.85),
                (0.35, 0.70),
                (0.6, 0.55),
                (0.8, ground(4000.0)),
            ],
        ),
        mountain(
            1500.0,
            &[
                (-0.1, 0.60),
                (0.2, 0.65),
                (0.45, 0.78),
                (0.65, 0.70),
                (0.9, 0.5),
                (0.95, ground(1500.0)),
            ],
        ),
        mountain(500.0, &[(0.45, ground(500.0)), (0.8, 0.72), (1.1, 0.75)]),
    ]
}

/// Fig. 5.8: five T-junctions. The farthest range shows in the gap between two nearer ones (two junctions), each
/// nearer one disappears behind the next (two more), and the nearest spur rises onto a ridge behind it (the
/// fifth, "in front of").
fn figure_5_8() -> Vec<Mountain> {
    let m2 = mountain(800.0, &[(0.70, ground(800.0)), (1.1, 0.75)]);
    let top = y_on(&projected(&m2), 0.95).unwrap();
    vec![
        mountain(
            4000.0,
            &[
                (-0.1, ground(4000.0)),
                (0.1, 0.60),
                (0.3, 0.68),
                (0.5, 0.72),
                (0.7, 0.65),
                (0.85, ground(4000.0)),
            ],
        ),
        mountain(
            2500.0,
            &[
                (-0.1, 0.80),
                (0.2, 0.78),
                (0.45, 0.55),
                (0.6, 0.50),
                (0.75, ground(2500.0)),
            ],
        ),
        mountain(
            1500.0,
            &[
                (0.40, ground(1500.0)),
                (0.6, 0.66),
                (0.7, 0.80),
                (0.85, 0.62),
                (1.0, 0.50),
                (1.1, ground(1500.0)),
            ],
        ),
        m2,
        mountain(400.0, &[(0.78, ground(400.0)), (0.95, top)]),
    ]
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for k in 0..n {
            let mut q = p.clone();
            q.insert(k, n - 1);
            out.push(q);
        }
    }
    out
}

/// Orders the strokes given in every order and drawn in every direction; the result is always the true order.
fn assert_true_order_whatever_the_drawing(mountains: &[Mountain], strokes: &[SketchStroke]) {
    let n = mountains.len();
    let mut truth: Vec<usize> = (0..n).collect();
    truth.sort_by(|&a, &b| mountains[a].depth.total_cmp(&mountains[b].depth));
    for perm in permutations(n) {
        for directions in 0..1u32 << n {
            let given: Vec<SketchStroke> = (0..n)
                .map(|k| {
                    let mut s = strokes[perm[k]].clone();
                    if directions & (1 << k) != 0 {
                        s.points.reverse();
                    }
                    s
                })
                .collect();
            let order = order_strokes(&given, &options()).unwrap();
            let expected: Vec<usize> = truth
                .iter()
                .map(|&m| perm.iter().position(|&p| p == m).unwrap())
                .collect();
            assert_eq!(
                order.front_to_back, expected,
                "given {perm:?}, reversed {directions:b}"
            );
        }
    }
}

/// (stroke, at_start, onto, relation) of each junction, in input indices.
fn labels(order: &StrokeOrder) -> Vec<(usize, bool, usize, Relation)> {
    let mut l: Vec<_> = order
        .junctions
        .iter()
        .map(|j| (j.stroke, j.at_start, j.onto, j.relation))
        .collect();
    l.sort_by_key(|&(s, a, o, _)| (s, a, o));
    l
}

/// The distance of each free extremity inside the frame to the nearest other stroke.
fn free_gaps(order: &StrokeOrder) -> Vec<f64> {
    let lines: Vec<Line> = order
        .oriented
        .iter()
        .map(|s| Line::new(&s.points, ASPECT))
        .collect();
    let mut gaps = Vec::new();
    for (s, line) in lines.iter().enumerate() {
        for at_start in [true, false] {
            let q = line.at(if at_start { 0.0 } else { line.length() });
            if q.x > 0.0
                && q.x < 1.0
                && !order
                    .junctions
                    .iter()
                    .any(|j| j.stroke == s && j.at_start == at_start)
            {
                gaps.push(
                    (0..lines.len())
                        .filter(|&r| r != s)
                        .map(|r| lines[r].closest(q).0)
                        .fold(f64::INFINITY, f64::min),
                );
            }
        }
    }
    gaps
}

/// The junctions of `order` are exact and none is overruled, every stroke has a free gap of its own, and the
/// strokes come out in the true order however they are drawn.
fn assert_exact_junctions_and_true_order(
    order: &StrokeOrder,
    mountains: &[Mountain],
    strokes: &[SketchStroke],
) {
    assert!(order
        .junctions
        .iter()
        .all(|j| j.distance < 1e-9 && !j.overruled));
    assert!(
        free_gaps(order).iter().all(|&g| g > 0.075),
        "{:?}",
        free_gaps(order)
    );
    assert_true_order_whatever_the_drawing(mountains, strokes);
}

#[test]
fn the_three_strokes_of_figure_5_3_come_out_front_to_back_however_drawn() {
    let mountains = figure_5_3();
    let strokes = sketch(&mountains);
    let order = order_strokes(&strokes, &options()).unwrap();
    assert_eq!(order.front_to_back, vec![2, 1, 0]);
    use Relation::*;
    assert_eq!(
        labels(&order),
        vec![(0, false, 1, OccludedBy), (1, false, 2, OccludedBy)]
    );
    assert_exact_junctions_and_true_order(&order, &mountains, &strokes);
}

#[test]
fn a_sketch_with_five_t_junctions_as_in_figure_5_8_comes_out_front_to_back_however_drawn() {
    let mountains = figure_5_8();
    let strokes = sketch(&mountains);
    let order = order_strokes(&strokes, &options()).unwrap();
    assert_eq!(order.front_to_back, vec![4, 3, 2, 1, 0]);
    use Relation::*;
    assert_eq!(
        labels(&order),
        vec![
            (0, false, 2, OccludedBy),
            (0, true, 1, OccludedBy),
            (1, false, 2, OccludedBy),
            (2, false, 3, OccludedBy),
            (4, false, 3, InFrontOf),
        ]
    );
    assert_exact_junctions_and_true_order(&order, &mountains, &strokes);
}

#[test]
fn a_shaky_hand_that_misses_the_junctions_by_a_little_still_gives_the_true_order() {
    let mountains = figure_5_8();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(18);
    for _ in 0..20 {
        let strokes: Vec<SketchStroke> = sketch(&mountains)
            .into_iter()
            .map(|s| SketchStroke {
                points: s
                    .points
                    .iter()
                    .map(|p| v(p.x, p.y + rng.random_range(-0.003..0.003)))
                    .collect(),
            })
            .collect();
        let order = order_strokes(&strokes, &options()).unwrap();
        assert_eq!(order.front_to_back, vec![4, 3, 2, 1, 0]);
        assert_eq!(order.junctions.len(), 5);
        assert!(order
            .junctions
            .iter()
            .all(|j| j.distance < 0.004 && !j.overruled));
    }
}

#[test]
fn without_junctions_a_stroke_whose_projection_contains_another_is_behind_it() {
    // a wide range and a small hill drawn inside its mountain, lower than the range's feet at its own feet:
    // the endpoint rule alone would put the hill behind
    let range = stroke(&[(0.05, 0.35), (0.5, 0.8), (0.95, 0.35)]);
    let hill = stroke(&[(0.4, 0.45), (0.5, 0.55), (0.6, 0.45)]);
    let order = order_strokes(&[range, hill], &OrderingOptions::default()).unwrap();
    assert!(order.junctions.is_empty());
    assert_eq!(order.front_to_back, vec![1, 0]);
}

#[test]
fn without_junctions_the_stroke_with_the_higher_lowest_endpoint_is_behind() {
    let high = stroke(&[(0.1, 0.62), (0.3, 0.75), (0.5, 0.6)]);
    let low = stroke(&[(0.4, 0.3), (0.7, 0.5), (0.9, 0.35)]);
    for strokes in [[high.clone(), low.clone()], [low.clone(), high.clone()]] {
        let order = order_strokes(&strokes, &OrderingOptions::default()).unwrap();
        assert!(order.junctions.is_empty());
        let back = if strokes[0] == high { 0 } else { 1 };
        assert_eq!(order.front_to_back, vec![1 - back, back]);
    }
}

#[test]
fn an_extremity_half_the_threshold_away_is_a_junction_and_twice_it_is_not() {
    let o = OrderingOptions::default();
    let front = stroke(&[(0.1, 0.5), (0.9, 0.5)]);
    let ending = |gap: f64| stroke(&[(0.2, 0.8), (0.5, 0.5 + gap)]);
    let near = order_strokes(&[ending(0.5 * o.junction_distance), front.clone()], &o).unwrap();
    assert_eq!(near.junctions.len(), 1);
    let j = near.junctions[0];
    assert_eq!(
        (j.stroke, j.at_start, j.onto, j.relation),
        (0, false, 1, Relation::OccludedBy)
    );
    assert!((j.distance - 0.5 * o.junction_distance).abs() < 1e-12);
    assert_eq!(near.front_to_back, vec![1, 0]);
    let far = order_strokes(&[ending(2.0 * o.junction_distance), front], &o).unwrap();
    assert!(far.junctions.is_empty());
}

#[test]
fn a_starting_point_on_another_stroke_is_labelled_with_its_tangent_flipped() {
    // behind: rises from the front stroke; in front: comes down onto the back stroke from below, left to right
    let front = stroke(&[(0.1, 0.5), (0.9, 0.5)]);
    let rising = stroke(&[(0.5, 0.5), (0.8, 0.8)]);
    let order = order_strokes(
        &[rising.clone(), front.clone()],
        &OrderingOptions::default(),
    )
    .unwrap();
    let j = order.junctions[0];
    assert_eq!(
        (j.stroke, j.at_start, j.relation),
        (0, true, Relation::OccludedBy)
    );
    let under = stroke(&[(0.5, 0.5), (0.8, 0.2)]);
    let order = order_strokes(&[under, front], &OrderingOptions::default()).unwrap();
    let j = order.junctions[0];
    assert_eq!(
        (j.stroke, j.at_start, j.relation),
        (0, true, Relation::InFrontOf)
    );
    assert_eq!(order.front_to_back, vec![0, 1]);
}

#[test]
fn a_stroke_drawn_back_over_itself_is_read_as_its_upper_envelope() {
    let s = stroke(&[(0.1, 0.5), (0.5, 0.6), (0.4, 0.7), (0.8, 0.6)]);
    let order = order_strokes(&[s], &OrderingOptions::default()).unwrap();
    let p = &order.oriented[0].points;
    assert!(p.windows(2).all(|w| w[1].x > w[0].x));
    assert_eq!(p.len(), 4);
    // at x = 0.4 the return stroke is higher than the first pass (0.575); at 0.5 the last one (0.6 on the others)
    assert!((p[1].y - 0.7).abs() < 1e-12 && (p[2].y - 0.675).abs() < 1e-12);
    let err = order_strokes(
        &[stroke(&[(0.3, 0.1), (0.3, 0.5)])],
        &OrderingOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("no width"), "{err}");
    // a long scribble back and forth across the frame is refused before its envelope is worked out
    let scribble = SketchStroke {
        points: (0..12_000)
            .map(|k| v(if k % 2 == 0 { 0.1 } else { 0.9 } + 1e-6 * k as f64, 0.5))
            .collect(),
    };
    let err = order_strokes(&[scribble], &OrderingOptions::default()).unwrap_err();
    assert!(
        err.to_string()
            .contains("sketch stroke 0 drawn back over itself"),
        "{err}"
    );
}

#[test]
fn contradictory_labels_keep_the_most_confident_and_overrule_the_rest() {
    let j = |stroke, onto| Junction {
        stroke,
        at_start: false,
        onto,
        point: DVec2::ZERO,
        distance: 0.0,
        relation: Relation::OccludedBy,
        overruled: false,
    };
    // 0 behind 1, 1 behind 2, 2 behind 0: the least sure label (2 behind 0) goes
    let mut junctions = [j(0, 1), j(1, 2), j(2, 0)];
    let front = resolve(3, &mut junctions, &[0.9, 0.8, 0.1]);
    assert_eq!(junctions.map(|j| j.overruled), [false, false, true]);
    assert!(front[2][1] && front[1][0] && front[2][0] && !front[0][2]);
}

#[test]
fn a_peak_drawn_as_two_strokes_end_to_end_is_one_junction() {
    // each end lies on the other stroke and says "in front of": equally near and equally sure both ways, the first
    // label of the sweep is the junction
    let up = stroke(&[(0.1, 0.5), (0.5, 0.7)]);
    let down = stroke(&[(0.5, 0.7), (0.9, 0.4)]);
    let order = order_strokes(&[up, down], &OrderingOptions::default()).unwrap();
    assert_eq!(order.junctions.len(), 1);
    let j = order.junctions[0];
    assert_eq!(
        (j.stroke, j.at_start, j.onto, j.relation, j.overruled),
        (0, false, 1, Relation::InFrontOf, false)
    );
    assert_eq!(order.front_to_back, vec![0, 1]);
}

/// A ridge over the left of the view that comes down onto the slope of a peak in front of it, and the peak, whose
/// foot starts 0.024 image heights (0.014 frame widths) under the ridge: within the junction distance of it, as a
/// hand draws two summits a few per cent above a skyline. Drawn as a hand does, a point every 0.01 across.
fn ridge_ending_on_a_peak() -> [SketchStroke; 2] {
    let drawn = |corners: &[(f64, f64)]| -> SketchStroke {
        let mut points = vec![corners[0]];
        for w in corners.windows(2) {
            let n = ((w[1].0 - w[0].0) / 0.01).round() as usize;
            points.extend((1..=n).map(|k| {
                let t = k as f64 / n as f64;
                (
                    w[0].0 + (w[1].0 - w[0].0) * t,
                    w[0].1 + (w[1].1 - w[0].1) * t,
                )
            }));
        }
        stroke(&points)
    };
    let peak = drawn(&[(0.5, 0.54), (0.7, 0.6), (0.92, 0.54)]);
    let ridge = drawn(&[(0.08, 0.56), (0.3, 0.6), (0.55, 0.555)]);
    [peak, ridge]
}

#[test]
fn a_stroke_ending_on_another_whose_foot_comes_near_it_is_one_junction_behind_it() {
    let [peak, ridge] = ridge_ending_on_a_peak();
    // the sweep finds both extremities near the other stroke, and their labels contradict
    let lines: Vec<Line> = [&peak, &ridge]
        .iter()
        .map(|s| Line::new(&s.points, ASPECT))
        .collect();
    let (both, _) = sweep(&[peak.clone(), ridge.clone()], &lines, &options());
    assert_eq!(both.len(), 2);
    assert_ne!(both[0].front_back(), both[1].front_back(), "{both:?}");
    let foot = both.iter().find(|j| j.stroke == 0).map(|j| j.distance);
    assert!(foot.is_some_and(|d| d > 0.01), "{foot:?}");
    for swap in [false, true] {
        for reversed in [false, true] {
            let mut given = if swap {
                [ridge.clone(), peak.clone()]
            } else {
                [peak.clone(), ridge.clone()]
            };
            if reversed {
                given.iter_mut().for_each(|s| s.points.reverse());
            }
            let (p, r) = if swap { (1, 0) } else { (0, 1) };
            let order = order_strokes(&given, &options()).unwrap();
            let j = order.junctions.first().copied();
            assert_eq!(order.junctions.len(), 1, "{:?}", order.junctions);
            assert_eq!(
                j.map(|j| (j.stroke, j.at_start, j.onto, j.relation, j.overruled)),
                Some((r, false, p, Relation::OccludedBy, false)),
                "swap {swap}, reversed {reversed}"
            );
            assert_eq!(order.front_to_back, vec![p, r]);
        }
    }
}

#[test]
fn ends_at_the_frame_edge_are_cuts_not_junctions() {
    let o = OrderingOptions::default();
    let a = stroke(&[(0.0, 0.5), (0.4, 0.6)]);
    let b = stroke(&[(-0.05, 0.51), (0.6, 0.3)]);
    assert!(order_strokes(&[a, b.clone()], &o)
        .unwrap()
        .junctions
        .is_empty());
    let inside = stroke(&[(0.01, 0.5), (0.4, 0.6)]);
    let order = order_strokes(&[inside, b], &o).unwrap();
    assert_eq!(order.junctions.len(), 1);
    assert_eq!(
        (order.junctions[0].stroke, order.junctions[0].at_start),
        (0, true)
    );
}

#[test]
fn bad_strokes_are_refused_by_name() {
    let o = OrderingOptions::default();
    let good = stroke(&[(0.1, 0.5), (0.9, 0.5)]);
    for (bad, words) in [
        (SketchStroke::default(), "is empty"),
        (stroke(&[(0.2, 0.3)]), "fewer than 2 distinct"),
        (stroke(&[(0.2, 0.3), (0.2, 0.3)]), "fewer than 2 distinct"),
        (stroke(&[(0.2, f64::NAN), (0.4, 0.3)]), "not finite"),
        (stroke(&[(0.2, 0.3), (f64::INFINITY, 0.3)]), "not finite"),
    ] {
        let err = order_strokes(&[good.clone(), bad], &o)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("sketch stroke 1") && err.contains(words),
            "{err}"
        );
    }
    let zero = OrderingOptions {
        junction_distance: 0.0,
        ..o
    };
    assert!(order_strokes(&[good], &zero).is_err());
    assert!(order_strokes(&[], &o).unwrap().front_to_back.is_empty());
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config {
        cases: 256,
        rng_seed: proptest::test_runner::RngSeed::Fixed(18),
        failure_persistence: None,
        ..Default::default()
    })]

    /// Random strokes never panic, and always come out as a permutation consistent with every kept label.
    #[test]
    fn random_strokes_give_a_permutation_consistent_with_the_kept_labels(
        strokes in proptest::collection::vec(
            proptest::collection::vec((-0.2..1.2f64, -0.2..1.2f64), 2..10), 0..8),
        distance in 0.01..0.3f64,
    ) {
        let strokes: Vec<SketchStroke> = strokes.iter().map(|s| stroke(s)).collect();
        let o = OrderingOptions { junction_distance: distance, ..OrderingOptions::default() };
        if let Ok(order) = order_strokes(&strokes, &o) {
            let mut sorted = order.front_to_back.clone();
            sorted.sort();
            proptest::prop_assert_eq!(sorted, (0..strokes.len()).collect::<Vec<_>>());
            let rank = order.rank();
            for j in order.junctions.iter().filter(|j| !j.overruled) {
                let (f, b) = j.front_back();
                proptest::prop_assert!(rank[f] < rank[b]);
            }
        }
    }
}
