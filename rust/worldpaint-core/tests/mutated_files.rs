//! Mutated palette, color, encyclopedia and scenario files: each is read, and every color the reader accepts is
//! pasted in a 40 m square with a 3 s cancel budget. None may panic, allocate past the engine's limits (an abort), or
//! run past 30 s; a paste that finishes within a second on two threads is made again on one and must come out the
//! same. The mutations are seeded: a failing case is reproduced by its seed, and kept in `REGRESSIONS`.
//!
//! `make test` runs `MUTATED_FILES` cases (default 300); `MUTATED_FILES=2500 cargo test --release --test
//! mutated_files -- --nocapture` runs the acceptance count.
//!
//! The world command line's arguments and terrain files (`.asc`, `.npy`) are mutated by
//! `blender_tests/test_world_cli_mutated.py`, which runs the real command line (`python -m worldpaint_engine.world`)
//! in a subprocess: its checks live in the Python package, in front of the engine (`WORLD_CLI_MUTATIONS` cases).

use rand::seq::IndexedRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use worldpaint_core::{
    clustered_points, demo_terrain, hard_core_points, learn_color, scene_from_points,
    segment_distance, synthesize_with_progress, village_scene, AnalysisOptions, Color, DVec2,
    Encyclopedia, Heightfield, Palette, Region, ScenarioPresets, Scene,
};

/// Seeds of mutations that once crashed or hung, kept as regression cases.
const REGRESSIONS: &[u64] = &[];

const CANCEL_AFTER: Duration = Duration::from_secs(3);
/// Pastes finished within this on two threads are made again on one.
const COMPARED_UNDER: Duration = Duration::from_secs(1);
const HANG: Duration = Duration::from_secs(30);

/// Numbers a careless or hostile file could hold.
const EXTREMES: &[f64] = &[
    0.0,
    -1.0,
    1e-12,
    1e-9,
    1e-3,
    0.5,
    7.0,
    1e3,
    1e6,
    1e9,
    1e11,
    1e18,
    1e300,
    -1e300,
    4294967296.0,
];

fn square(min: f64, max: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(min),
        max: DVec2::splat(max),
    }
}

fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

fn read_asset(path: &str) -> Value {
    let text =
        std::fs::read_to_string(assets().join(path)).expect("the shipped assets are readable");
    serde_json::from_str(&text).expect("the shipped assets are JSON")
}

/// A palette of three colors learned here: a clustered forest with a terrain map, a hard-core one, and a village whose
/// houses face their streets.
fn palette_file() -> Value {
    let terrain = Arc::new(demo_terrain(100.0, 2.0, 1));
    let region = square(10.0, 60.0);
    let mut forest = scene_from_points("tree", &clustered_points(&region, 0.002, 8.0, 4.0, 2));
    forest.terrain = Some(terrain);
    let rocks = scene_from_points("rock", &hard_core_points(&region, 0.03, 2.0, 3));
    let opts = AnalysisOptions::default();
    let palette = Palette {
        colors: vec![
            learn_color(&forest, &region, "forest", &opts).expect("the forest is learned"),
            learn_color(&rocks, &region, "rocks", &opts).expect("the rocks are learned"),
            facing_village(),
        ],
    };
    serde_json::from_str(&palette.to_json().expect("the palette is written"))
        .expect("a palette is JSON")
}

/// A village whose houses face their streets, so that the mutations reach the facing and size fields.
fn facing_village() -> Color {
    let mut village = village_scene(150.0, 4);
    let roads: Vec<(DVec2, DVec2)> = village
        .paths
        .iter()
        .flat_map(|p| p.points.windows(2).map(|w| (w[0], w[1])))
        .collect();
    for (k, house) in village.instances.iter_mut().enumerate() {
        if house.category != 1 {
            continue;
        }
        let nearest = roads
            .iter()
            .min_by(|x, y| {
                segment_distance(house.position, x.0, x.1).total_cmp(&segment_distance(
                    house.position,
                    y.0,
                    y.1,
                ))
            })
            .map(|(a, b)| *b - *a);
        if let Some(along) = nearest {
            house.rotation = along.y.atan2(along.x) + 0.02 * (k % 5) as f64;
            house.scale = [8.0, 9.0, 20.0][k % 3];
        }
    }
    let color = learn_color(
        &village,
        &square(0.0, 150.0),
        "village",
        &Default::default(),
    )
    .expect("the village is learned");
    let house = color.category("house").expect("the village has houses");
    assert!(house.facing.is_some() && !house.size.values.is_empty());
    color
}

/// Every place in a JSON tree, as paths of keys and indices.
fn places(v: &Value, at: &mut Vec<Vec<Step>>, path: &mut Vec<Step>) {
    at.push(path.clone());
    match v {
        Value::Object(m) => {
            for (k, c) in m {
                path.push(Step::Key(k.clone()));
                places(c, at, path);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                path.push(Step::Index(i));
                places(c, at, path);
                path.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn at_mut<'v>(v: &'v mut Value, path: &[Step]) -> Option<&'v mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

/// One to four random edits: a number made extreme, a value removed or emptied, an array entry repeated, a string
/// changed, a type swapped.
fn mutate(file: &Value, rng: &mut ChaCha8Rng) -> Value {
    let mut out = file.clone();
    for _ in 0..rng.random_range(1..=4) {
        let mut all = Vec::new();
        places(&out, &mut all, &mut Vec::new());
        let Some(path) = all.choose(rng).cloned() else {
            break;
        };
        let Some(v) = at_mut(&mut out, &path) else {
            continue;
        };
        match (v.clone(), rng.random_range(0..6)) {
            (Value::Number(_), 0..=2) => {
                if let Some(n) = serde_json::Number::from_f64(*EXTREMES.choose(rng).unwrap_or(&0.0))
                {
                    *v = Value::Number(n);
                }
            }
            (Value::Array(mut a), 3) if !a.is_empty() => {
                let k = rng.random_range(0..a.len());
                let copy = a[k].clone();
                for _ in 0..rng.random_range(1..50) {
                    a.push(copy.clone());
                }
                *v = Value::Array(a);
            }
            (Value::Array(mut a), 4) => {
                a.truncate(rng.random_range(0..=a.len()));
                *v = Value::Array(a);
            }
            (Value::String(s), _) => *v = Value::String(format!("{s}{}", rng.random_range(0..3))),
            (_, 5) => *v = Value::Null,
            _ => *v = Value::Number(rng.random_range(-5..1_000_000).into()),
        }
    }
    out
}

/// A rayon pool of two threads, where the cases run, and one of one thread, to compare with.
struct Pools {
    two: rayon::ThreadPool,
    one: rayon::ThreadPool,
}

/// Pastes every color of the palette in a 40 m square of a 100 m terrain, cancelling after 3 s; counts the pastes
/// compared between two threads and one in `outcome`.
fn paste_all(palette: &Palette, terrain: &Arc<Heightfield>, pools: &Pools, outcome: &mut Outcome) {
    let (scene, square) = (Scene::on(terrain.clone()), square(30.0, 70.0));
    for color in &palette.colors {
        let paste = || {
            let started = Instant::now();
            let cancel = |_: f64| started.elapsed() < CANCEL_AFTER;
            let result =
                synthesize_with_progress(&scene, color, &square, &Default::default(), &cancel);
            (result, started.elapsed())
        };
        let (result, took) = pools.two.install(paste);
        assert!(took < HANG, "color '{}' ran {took:?}", color.name);
        match result {
            Ok(two) if took < COMPARED_UNDER => {
                let (one, _) = pools.one.install(paste);
                let one = one
                    .unwrap_or_else(|e| panic!("color '{}' failed on one thread: {e}", color.name));
                assert!(
                    one.instances == two.instances
                        && one.paths == two.paths
                        && one.contours == two.contours,
                    "color '{}' pastes differently on one thread and on two",
                    color.name
                );
                outcome.compared += 1;
            }
            Ok(_) => {}
            // refused or cancelled, with a message, is the expected end of a bad color
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

/// Reads one mutated file of each kind and pastes what it accepts.
fn run_case(seed: u64, files: &Files, terrain: &Arc<Heightfield>, pools: &Pools) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut outcome = Outcome::default();
    let palette = mutate(&files.palette, &mut rng).to_string();
    match Palette::from_json(&palette) {
        Ok(p) => {
            outcome.accepted += 1;
            paste_all(&p, terrain, pools, &mut outcome);
        }
        Err(_) => outcome.refused += 1,
    }
    // each color of the palette in turn as a file of its own
    let one = &files.palette["colors"][(seed % 3) as usize];
    let color = serde_json::json!({"format": "worldpaint-color", "version": 1, "color": one});
    match Color::from_json(&mutate(&color, &mut rng).to_string()) {
        Ok(c) => {
            outcome.accepted += 1;
            paste_all(&Palette { colors: vec![c] }, terrain, pools, &mut outcome);
        }
        Err(_) => outcome.refused += 1,
    }
    match Encyclopedia::from_json(&mutate(&files.encyclopedia, &mut rng).to_string()) {
        Ok(_) => outcome.accepted += 1,
        Err(_) => outcome.refused += 1,
    }
    match ScenarioPresets::from_json(&mutate(&files.scenarios, &mut rng).to_string()) {
        Ok(_) => outcome.accepted += 1,
        Err(_) => outcome.refused += 1,
    }
    outcome
}

struct Files {
    palette: Value,
    encyclopedia: Value,
    scenarios: Value,
}

#[derive(Default)]
struct Outcome {
    accepted: usize,
    refused: usize,
    compared: usize,
}

#[test]
fn mutated_files_are_read_and_pasted_without_a_crash_or_a_hang() {
    let files = Files {
        palette: palette_file(),
        encyclopedia: read_asset("villages/encyclopedia.json"),
        scenarios: read_asset("villages/scenarios.json"),
    };
    let terrain = Arc::new(demo_terrain(100.0, 2.0, 5));
    let cases: u64 = std::env::var("MUTATED_FILES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300);
    let pool = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
    };
    let pools = Pools {
        two: pool(2),
        one: pool(1),
    };
    let started = Instant::now();
    let (mut accepted, mut refused, mut compared, mut slowest) = (0, 0, 0, Duration::ZERO);
    for seed in REGRESSIONS.iter().copied().chain(0..cases) {
        let case = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            run_case(seed, &files, &terrain, &pools)
        }))
        .unwrap_or_else(|_| {
            panic!("mutation seed {seed} panicked: keep it in REGRESSIONS once fixed")
        });
        accepted += outcome.accepted;
        refused += outcome.refused;
        compared += outcome.compared;
        slowest = slowest.max(case.elapsed());
    }
    println!(
        "{cases} cases ({} files): {accepted} accepted and pasted, {refused} refused; {compared} pastes the same on \
         one thread and two; slowest case {slowest:.2?}, all {:.1?}",
        4 * cases,
        started.elapsed()
    );
    assert!(
        refused > 0 && accepted > 0 && compared > 0,
        "the mutations should make both kinds of file, and pastes to compare"
    );
}
