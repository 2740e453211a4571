//! Waterfall scenes, the hydraulic part (thesis ch. 4): flow conservation, minimum slope, the Fig. 4.9 type
//! change, terrain-following subdivision, determinism and refusal of bad input. Run with
//! `cargo test -p worldpaint-core --release --test waterfall -- --nocapture` to see the figures.

use glam::DVec3;
use std::collections::BTreeMap;
use worldpaint_core::{
    build_waterfall_network, classify_waterfall, demo_terrain, detail_length, downhill,
    max_imbalance, segment_distance, village_terrain, waterfall_controllers, Controller,
    ControllerKind, DVec2, Heightfield, HydraulicNodeKind, WaterfallNetwork, WaterfallParams,
    WaterfallType, MAX_DEVIATION_FACTOR,
};

fn scene() -> (Heightfield, Vec<Controller>) {
    let t = village_terrain(1000.0, 2.0, 3);
    let c = waterfall_controllers(&t, 20, 7);
    assert_eq!(c.len(), 20);
    (t, c)
}

fn built(t: &Heightfield, c: &[Controller], seed: u64) -> WaterfallNetwork {
    match build_waterfall_network(t, c, &WaterfallParams::default(), seed) {
        Ok(n) => n,
        Err(e) => panic!("the test scene: {e}"),
    }
}

fn run(a: DVec3, b: DVec3) -> f64 {
    a.truncate().distance(b.truncate())
}

#[test]
fn flow_is_conserved_at_every_node() {
    let (t, c) = scene();
    let net = built(&t, &c, 1);
    let g = &net.graph;
    let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
    let mut worst: f64 = 0.0;
    let (mut supplied, mut taken) = (0.0, 0.0);
    for (n, node) in g.nodes.iter().enumerate() {
        *kinds.entry(format!("{:?}", node.kind)).or_default() += 1;
        let inflow: f64 = node.arcs_in.iter().map(|&a| g.arcs[a].flow).sum();
        let outflow: f64 = node.arcs_out.iter().map(|&a| g.arcs[a].flow).sum();
        if node.arcs_in.is_empty() {
            supplied += outflow;
            assert!(outflow > 0.0, "source {n} supplies nothing");
        } else if node.arcs_out.is_empty() {
            taken += inflow;
        } else {
            let rel = (inflow - outflow).abs() / inflow.max(outflow);
            worst = worst.max(rel);
            assert!(
                rel <= 1e-9,
                "node {n} ({:?}): in {inflow} out {outflow}",
                node.kind
            );
        }
    }
    let global = (supplied - taken).abs() / supplied;
    println!(
        "{} nodes {kinds:?}, {} arcs; worst node imbalance {worst:.2e}, engine's own check {:.2e}; sources supply {supplied:.6}, wells take {taken:.6} (relative difference {global:.2e})",
        g.nodes.len(),
        g.arcs.len(),
        max_imbalance(g)
    );
    assert!(
        kinds.get("Branch").copied().unwrap_or(0) >= 4,
        "the scene has joins"
    );
    assert!(kinds.get("Pool").copied().unwrap_or(0) >= 1);
    assert!(global <= 1e-9);
    assert!(max_imbalance(g) <= 1e-9);
}

/// A tilted plane falling towards -x at 10 %.
fn plane() -> Heightfield {
    let n = 201;
    let heights = (0..n * n).map(|k| (0.1 * (k % n) as f64) as f32).collect();
    match Heightfield::new(DVec2::ZERO, 1.0, n, n, heights) {
        Ok(h) => h,
        Err(e) => panic!("{e}"),
    }
}

fn on(t: &Heightfield, x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, t.height_at(DVec2::new(x, y)).unwrap_or(0.0))
}

#[test]
fn branches_follow_angles_and_pools_follow_strengths() {
    let t = plane();
    let p = |x, y| on(&t, x, y);
    // a river down the slope splits: straight on, and sideways
    let river = Controller::new(
        ControllerKind::Contact,
        vec![p(180.0, 100.0), p(150.0, 100.0)],
    );
    let straight = Controller::new(
        ControllerKind::Contact,
        vec![p(150.0, 100.0), p(120.0, 100.0)],
    );
    let side = Controller::new(
        ControllerKind::Contact,
        vec![p(150.0, 100.0), p(148.0, 130.0)],
    );
    let params = WaterfallParams {
        subdivide: false,
        ..Default::default()
    };
    let net = match build_waterfall_network(&t, &[river, straight, side], &params, 0) {
        Ok(n) => n,
        Err(e) => panic!("{e}"),
    };
    let flows: Vec<f64> = net.graph.arcs.iter().map(|a| a.flow).collect();
    println!(
        "split at a branch: in {:.4}, straight on {:.4}, sideways {:.4}",
        flows[0], flows[1], flows[2]
    );
    assert!(
        flows[1] > 1.5 * flows[2],
        "most of the flow keeps its direction"
    );
    assert!(((flows[1] + flows[2]) - flows[0]).abs() <= 1e-12 * flows[0]);

    // a pool with three outlets: equal shares, then 3 : 1 : 1 when the first is given strength 3
    let pool: Vec<DVec3> = (0..16)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 16.0;
            DVec3::new(100.0 + 10.0 * a.cos(), 100.0 + 10.0 * a.sin(), 5.0)
        })
        .collect();
    let inlet = Controller::new(
        ControllerKind::FreeFall,
        vec![
            DVec3::new(100.0, 100.0, 15.0),
            DVec3::new(101.0, 100.0, 5.0),
        ],
    )
    .with_strength(5.0);
    let outlet = |dir: DVec2, strength: Option<f64>| {
        let s = DVec2::splat(100.0) + dir * 10.0;
        let e = s + dir * 30.0;
        Controller {
            kind: ControllerKind::Contact,
            points: vec![s.extend(5.0), e.extend(4.0)],
            strength,
        }
    };
    for strength in [None, Some(3.0)] {
        let c = vec![
            Controller::new(ControllerKind::Pool, pool.clone()),
            inlet.clone(),
            outlet(DVec2::X, strength),
            outlet(DVec2::Y, None),
            outlet(DVec2::NEG_Y, None),
        ];
        let net = match build_waterfall_network(&t, &c, &params, 0) {
            Ok(n) => n,
            Err(e) => panic!("{e}"),
        };
        let f: Vec<f64> = net.graph.arcs.iter().map(|a| a.flow).collect();
        println!(
            "pool outlets with strength {strength:?}: inflow {:.3}, outflows {:.4} {:.4} {:.4}",
            f[0], f[1], f[2], f[3]
        );
        let s = strength.unwrap_or(1.0);
        assert!((f[1] - 5.0 * s / (s + 2.0)).abs() < 1e-12);
        assert!((f[2] - 5.0 / (s + 2.0)).abs() < 1e-12);
        assert_eq!(
            net.graph
                .nodes
                .iter()
                .filter(|n| n.kind == HydraulicNodeKind::Pool)
                .count(),
            1
        );
    }
}

#[test]
fn contact_segments_run_downhill_by_the_minimum_slope() {
    let (t, c) = scene();
    let params = WaterfallParams::default();
    let net = built(&t, &c, 1);
    let tan = params.min_slope.tan();
    let (mut lowered, mut worst_ctrl, mut worst_path) = (0, f64::INFINITY, f64::INFINITY);
    for (a, arc) in net.graph.arcs.iter().enumerate() {
        if arc.kind != ControllerKind::Contact {
            continue;
        }
        for s in arc.points.windows(2) {
            let need = tan * run(s[0], s[1]);
            assert!(
                s[0].z - s[1].z >= need - 1e-9,
                "arc {a}: control step {s:?} drops too little"
            );
            worst_ctrl = worst_ctrl.min((s[0].z - s[1].z).atan2(run(s[0], s[1])));
        }
        for s in net.paths[a].windows(2) {
            assert!(
                s[0].z - s[1].z >= tan * run(s[0], s[1]) - 1e-9,
                "arc {a}: path step drops too little"
            );
            worst_path = worst_path.min((s[0].z - s[1].z).atan2(run(s[0], s[1])));
        }
    }
    for (before, after) in c.iter().zip(&net.controllers) {
        lowered += before
            .points
            .iter()
            .zip(&after.points)
            .filter(|(p, q)| q.z < p.z - 1e-9)
            .count();
        assert!(before
            .points
            .iter()
            .zip(&after.points)
            .all(|(p, q)| q.z <= p.z + params.snap_distance));
    }
    for arc in net
        .graph
        .arcs
        .iter()
        .filter(|a| a.kind == ControllerKind::FreeFall)
    {
        assert!(arc.points[1].z < arc.points[0].z, "a free-fall falls");
    }
    println!(
        "ω_min = {:.4} rad; smallest contact inclination after correction: control points {worst_ctrl:.4}, subdivided paths {worst_path:.4}; {lowered} control points lowered",
        params.min_slope
    );
    assert!(lowered > 0, "the scene has points below the falls to lower");

    // a curve drawn uphill is flattened into a minimum-slope descent
    let tp = plane();
    let up = Controller::new(
        ControllerKind::Contact,
        (0..5)
            .map(|k| on(&tp, 50.0 + 20.0 * k as f64, 50.0))
            .collect(),
    );
    let net = match build_waterfall_network(&tp, &[up], &params, 0) {
        Ok(n) => n,
        Err(e) => panic!("{e}"),
    };
    let z: Vec<f64> = net.controllers[0].points.iter().map(|p| p.z).collect();
    println!("uphill curve corrected to heights {z:.3?}");
    for k in 1..z.len() {
        assert!((z[k - 1] - z[k] - 20.0 * tan).abs() < 1e-9);
    }
}

/// A plateau at 40 m ending in a cliff at x = 100 above a floor at 10 m, and a second cliff at x = 150 down to
/// 0 m: a stream, a fall into a pool, a fall out of it into a second pool.
fn cliffs() -> (Heightfield, Vec<Controller>) {
    let n = 201;
    let heights = (0..n * n)
        .map(|k| {
            let x = (k % n) as f64;
            if x < 100.0 {
                40.0
            } else if x < 150.0 {
                10.0
            } else {
                0.0
            }
        })
        .map(|h| h as f32)
        .collect();
    let t = match Heightfield::new(DVec2::ZERO, 1.0, n, n, heights) {
        Ok(h) => h,
        Err(e) => panic!("{e}"),
    };
    let circle = |cx: f64, z: f64| -> Vec<DVec3> {
        (0..12)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 12.0;
                DVec3::new(cx + 6.0 * a.cos(), 100.0 + 6.0 * a.sin(), z)
            })
            .collect()
    };
    // a free-fall along y = 100 from `x0` at height `top` down to `x1` at `bottom`
    let fall = |x0: f64, top: f64, x1: f64, bottom: f64| {
        Controller::new(
            ControllerKind::FreeFall,
            vec![DVec3::new(x0, 100.0, top), DVec3::new(x1, 100.0, bottom)],
        )
    };
    let c = vec![
        Controller::new(
            ControllerKind::Contact,
            (0..=8)
                .map(|k| DVec3::new(20.0 + 10.0 * k as f64, 100.0, 40.0))
                .collect(),
        )
        .with_strength(5.0),
        fall(100.0, 40.0, 104.0, 10.0),
        Controller::new(ControllerKind::Pool, circle(106.0, 10.0)),
        Controller::new(
            ControllerKind::Contact,
            vec![
                DVec3::new(112.0, 100.0, 10.0),
                DVec3::new(130.0, 100.0, 10.0),
                DVec3::new(150.0, 100.0, 10.0),
            ],
        ),
        fall(150.0, 10.0, 152.0, 0.0),
        Controller::new(ControllerKind::Pool, circle(156.0, 0.0)),
    ];
    (t, c)
}

#[test]
fn less_upstream_flow_turns_ledges_into_plunges() {
    let (t, mut c) = cliffs();
    let types = |c: &[Controller]| -> (Vec<(ControllerKind, WaterfallType, f64)>, Vec<f64>) {
        let net = built(&t, c, 5);
        let falls = net
            .segments
            .iter()
            .filter(|s| s.kind == ControllerKind::FreeFall)
            .map(|s| (s.kind, s.kind_of_water, s.flow))
            .collect();
        let flows = net.graph.arcs.iter().map(|a| a.flow).collect();
        (falls, flows)
    };
    let (high, high_flows) = types(&c);
    c[0].strength = Some(2.0);
    let (low, low_flows) = types(&c);
    println!("upstream flow 5: free-falls {high:?}\nupstream flow 2: free-falls {low:?}");
    println!("arc flows {high_flows:?} → {low_flows:?}");
    assert_eq!(high.len(), 2);
    assert!(
        high.iter().all(|f| f.1 == WaterfallType::Ledge),
        "flow 5 falls are ledges"
    );
    assert!(
        low.iter().all(|f| f.1 == WaterfallType::Plunge),
        "flow 2 falls are plunges"
    );
    for (h, l) in high_flows.iter().zip(&low_flows) {
        assert!(
            (l / h - 0.4).abs() < 1e-12,
            "every arc downstream carries the reduced flow"
        );
    }
}

#[test]
fn classification_and_section_follow_the_table() {
    // each seed of Table 4.1 is in its own cell
    for s in worldpaint_core::TABLE_4_1 {
        assert_eq!(classify_waterfall(s.slope, s.flow), s.kind);
    }
    let (t, c) = scene();
    let params = WaterfallParams::default();
    let net = built(&t, &c, 1);
    let mut hist: BTreeMap<String, usize> = BTreeMap::new();
    for s in &net.segments {
        *hist.entry(format!("{:?}", s.kind_of_water)).or_default() += 1;
        let x = s.section;
        assert!(
            (x.speed * x.width * x.depth / 2.0 - s.flow).abs() <= 1e-9 * s.flow,
            "γ = δεζ/2"
        );
        assert!((x.speed - params.speed_factor * s.slope).abs() < 1e-12);
        assert_eq!(
            s.valid,
            s.kind_of_water.is_free_fall() == (s.kind == ControllerKind::FreeFall)
        );
    }
    for (k, s) in net.invalid_segments() {
        println!(
            "flagged segment {k}: {:?} arc {} of slope {:.3} rad and flow {:.2} is closest to {:?}",
            s.kind, s.arc, s.slope, s.flow, s.kind_of_water
        );
    }
    let flagged = net.invalid_segments().count();
    println!(
        "{} segments, types {hist:?}; {flagged} flagged outside the valid range",
        net.segments.len()
    );
    // a free-fall drawn on flat ground is flagged, as the thesis's red segments
    let tp = plane();
    let flat_fall = Controller::new(
        ControllerKind::FreeFall,
        vec![on(&tp, 100.0, 100.0), on(&tp, 60.0, 100.0)],
    );
    let net = match build_waterfall_network(&tp, &[flat_fall], &params, 0) {
        Ok(n) => n,
        Err(e) => panic!("{e}"),
    };
    let s = &net.segments[0];
    println!(
        "free-fall on a 10 % slope: slope {:.3} rad, type {:?}, valid {}",
        s.slope, s.kind_of_water, s.valid
    );
    assert!(!s.valid);
}

/// Steepest-descent curves on the demo hills: control points on the terrain 40 m apart, ending before a step
/// would not descend by the minimum slope (a valley).
fn descents(t: &Heightfield) -> Vec<Controller> {
    let starts = [
        (300.0, 300.0),
        (700.0, 250.0),
        (500.0, 600.0),
        (250.0, 750.0),
        (800.0, 800.0),
        (600.0, 450.0),
    ];
    starts
        .iter()
        .map(|&(x, y)| {
            let mut p = DVec2::new(x, y);
            let mut pts = vec![on(t, p.x, p.y)];
            for _ in 0..8 {
                let g = downhill(t, p);
                let d = if g.length() > 1e-6 {
                    g.normalize()
                } else {
                    DVec2::X
                };
                let q = p + d * 40.0;
                let drop = t.height_at(p).unwrap_or(0.0) - t.height_at(q).unwrap_or(f64::INFINITY);
                if !t.contains(q) || drop < 40.0 * WaterfallParams::default().min_slope.tan() {
                    break;
                }
                p = q;
                pts.push(on(t, p.x, p.y));
            }
            Controller::new(ControllerKind::Contact, pts)
        })
        .collect()
}

#[test]
fn subdivision_follows_the_terrain() {
    let t = demo_terrain(1000.0, 2.0, 4);
    let c = descents(&t);
    let params = WaterfallParams::default();
    let net = built(&t, &c, 9);
    let tan = params.min_slope.tan();
    let (mut new_points, mut on_ground, mut worst_dev, mut longest) = (0, 0, 0.0f64, 0.0f64);
    for (a, arc) in net.graph.arcs.iter().enumerate() {
        let path = &net.paths[a];
        let ctrl: Vec<DVec2> = arc.points.iter().map(|p| p.truncate()).collect();
        let seg_len = ctrl
            .windows(2)
            .map(|s| s[0].distance(s[1]))
            .fold(0.0, f64::max);
        let l = detail_length(arc.flow, &params, t.cell);
        assert!(path.len() > arc.points.len(), "arc {a} is subdivided");
        for s in path.windows(2) {
            assert!(s[0].z - s[1].z >= tan * run(s[0], s[1]) - 1e-9, "downhill");
            longest = longest.max(run(s[0], s[1]) / l);
        }
        for p in path {
            let dev = ctrl
                .windows(2)
                .map(|s| segment_distance(p.truncate(), s[0], s[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(
                dev <= MAX_DEVIATION_FACTOR * seg_len + 1e-9,
                "arc {a} strays {dev} m"
            );
            worst_dev = worst_dev.max(dev / seg_len);
            let h = t.height_at(p.truncate()).unwrap_or(f64::NAN);
            if !arc.points.contains(p) {
                new_points += 1;
                if (p.z - h).abs() <= 0.01 {
                    on_ground += 1;
                }
            }
        }
    }
    let share = on_ground as f64 / new_points as f64;
    println!(
        "{new_points} new points, {:.1} % within 1 cm of the terrain; farthest from its control segment {worst_dev:.3} L (bound {MAX_DEVIATION_FACTOR:.3} L); longest step {longest:.3} l",
        100.0 * share
    );
    assert!(share >= 0.8);
    assert!(longest < 1.0);

    // the gradient cost is what makes the path run down the slope: compare with random displacements alone
    let alignment = |params: &WaterfallParams| -> f64 {
        let net = match build_waterfall_network(&t, &c, params, 9) {
            Ok(n) => n,
            Err(e) => panic!("{e}"),
        };
        let (mut sum, mut len) = (0.0, 0.0);
        for path in &net.paths {
            for s in path.windows(2) {
                let d = s[1].truncate() - s[0].truncate();
                let g = downhill(&t, 0.5 * (s[0].truncate() + s[1].truncate()));
                if g.length() > 0.0 {
                    sum += d.dot(g.normalize());
                    len += d.length();
                }
            }
        }
        sum / len
    };
    let with = alignment(&params);
    let without = alignment(&WaterfallParams {
        w_gradient: 0.0,
        w_angle: 0.0,
        ..params.clone()
    });
    println!("mean cosine between path and downhill direction: with the gradient cost {with:.3}, random cost alone {without:.3}");
    assert!(with > without);
}

#[test]
fn seeded_runs_are_deterministic() {
    let (t, c) = scene();
    let a = built(&t, &c, 42);
    let b = built(&t, &c, 42);
    let single = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p.install(|| built(&t, &c, 42)),
        Err(e) => panic!("{e}"),
    };
    let other = built(&t, &c, 43);
    assert_eq!(a.paths, b.paths);
    assert_eq!(a.paths, single.paths);
    assert_eq!(a.segments, single.segments);
    let differing = a
        .paths
        .iter()
        .zip(&other.paths)
        .filter(|(p, q)| p != q)
        .count();
    let points: usize = a.paths.iter().map(|p| p.len()).sum();
    println!("seed 42 twice and on one thread: identical ({points} path points); seed 43 changes {differing} of {} arcs", a.paths.len());
    assert!(differing > 0);
}

fn refused(t: &Heightfield, c: &[Controller], words: &[&str]) {
    match build_waterfall_network(t, c, &WaterfallParams::default(), 0) {
        Err(e) if e.is_invalid_input() => {
            let m = e.to_string();
            println!("refused: {m}");
            for w in words {
                assert!(m.contains(w), "'{m}' should say '{w}'");
            }
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted {c:?}"),
    }
}

#[test]
fn bad_input_is_refused() {
    let t = plane();
    let ok = Controller::new(
        ControllerKind::Contact,
        vec![on(&t, 150.0, 50.0), on(&t, 100.0, 50.0)],
    );
    let mut nan = ok.clone();
    nan.points[1].z = f64::NAN;
    refused(
        &t,
        &[ok.clone(), nan],
        &["controller 1", "point 1", "not finite"],
    );
    let one = Controller::new(ControllerKind::Contact, vec![on(&t, 10.0, 10.0)]);
    refused(&t, &[one], &["controller 0", "1 point"]);
    let off = Controller::new(
        ControllerKind::FreeFall,
        vec![on(&t, 10.0, 10.0), DVec3::new(-5.0, 10.0, 0.0)],
    );
    refused(
        &t,
        &[ok.clone(), off],
        &["controller 1", "point 1", "outside the terrain"],
    );
    let back = Controller::new(
        ControllerKind::Contact,
        vec![
            on(&t, 100.0, 50.0),
            on(&t, 120.0, 80.0),
            on(&t, 150.0, 50.0),
        ],
    );
    refused(&t, &[ok.clone(), back], &["cycle", "0, 1"]);
    let up = Controller::new(
        ControllerKind::FreeFall,
        vec![DVec3::new(10.0, 10.0, 1.0), DVec3::new(10.0, 10.0, 5.0)],
    );
    refused(&t, &[up], &["free-fall controller 0"]);
    let weak = ok.clone().with_strength(-1.0);
    refused(&t, &[weak], &["controller 0", "strength"]);
    let twice = Controller::new(
        ControllerKind::Contact,
        vec![on(&t, 10.0, 10.0), on(&t, 10.0, 10.0)],
    );
    refused(&t, &[twice], &["controller 0", "points 0 and 1"]);
    let bad = WaterfallParams {
        min_slope: f64::NAN,
        ..Default::default()
    };
    assert!(build_waterfall_network(&t, std::slice::from_ref(&ok), &bad, 0).is_err());
    // an empty scene is an empty network
    match build_waterfall_network(&t, &[], &WaterfallParams::default(), 0) {
        Ok(n) => assert!(n.segments.is_empty()),
        Err(e) => panic!("{e}"),
    }
}
