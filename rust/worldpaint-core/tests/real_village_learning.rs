//! Learn Village on real villages: a village type fitted to each real village of `real_village_generation` (the
//! densest 1 km squares of Andorra), grown again on the same terrain at three seeds the fit never saw, and beside
//! it every shipped village type grown alike. Needs `shared/data/real`, so it is `#[ignore]`d with the reason;
//! `make test-rust` runs it where the data is present.
//!
//! Printed (`--nocapture`): per village, the real figures, the fitted type's (mean of the three seeds) and the
//! nearest shipped preset's (the one whose objective is lowest), and the fit's evaluations, generations and time.
//!
//! Checked, on the mean of the three new seeds: the learned type nearer the real village than the nearest preset by
//! the fit's objective, and its buildings per hectare within ±15 % of the real village's. The other bands
//! are listed in [`OPEN`]: printed as targets ("OUT" where missed), not asserted yet: nearest neighbour and road
//! length per house within ±15 %, the share within 20 m within ±10 points, hairpins per km within ±0.5, the
//! orientation-to-road histogram within TV 0.15, and a type fitted on one village and grown on another village's
//! terrain keeping nearest neighbour, road per house and buildings per hectare within ±25 %: each learned type on the
//! next village's square (villages of other kinds: a valley town, a hillside village, a hamlet), and the hamlet's
//! type on the square of Andorra's next hamlet (the fourth densest square, a village of the same kind).
//!
//! The search's budget is [`FIT_EVALUATIONS`] candidates (`WORLDPAINT_FIT_EVALUATIONS`), so the test learns the
//! same types on a loaded machine as on an idle one; `WORLDPAINT_FIT_SECONDS` bounds it in time too (default
//! [`FIT_SECONDS`], as Learn Village's default in Blender: the "one village in 10 minutes"), and
//! `WORLDPAINT_FIT_VILLAGES` takes only the first villages. The full search, Learn Village's default budget (0: as
//! many candidates as grow about 60,000 buildings), on Encamp, timed: `WORLDPAINT_FIT_VILLAGES=1
//! WORLDPAINT_FIT_EVALUATIONS=0 cargo test --release --test real_village_learning -- --ignored --nocapture`.

mod common;

use common::real_places::{self, Place, Window};
use worldpaint_core::{
    fit_village_type, grow_village_figures, rank_village_types, village_objective, Encyclopedia,
    Environment, Error, FitFigure, FitOptions, FitTarget, FittedVillage, RankedType, Scenario,
    Site, SitedBuilding, VillageFigures,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const SIDE: f64 = 1000.0;
const WINDOWS: usize = 3;
const MIN_BUILDINGS: usize = 15;
/// Buildings of the next hamlet, the fourth densest square (12 buildings), the third village's type is grown on.
const NEXT_HAMLET_BUILDINGS: usize = 10;
const CELL: f64 = 2.0;
const PARCEL_CELL: f64 = 1.0;
/// Seconds a fit may take unless `WORLDPAINT_FIT_SECONDS` says otherwise.
const FIT_SECONDS: f64 = 540.0;
/// Candidates a fit evaluates unless `WORLDPAINT_FIT_EVALUATIONS` says otherwise: the base type and four
/// generations of CMA-ES's default population for the 39 coordinates.
const FIT_EVALUATIONS: usize = 57;
/// The bands not met yet by a fit of [`FIT_EVALUATIONS`]: printed, not asserted.
const OPEN: [FitFigure; 5] = [
    FitFigure::NearestNeighbour,
    FitFigure::ShareWithin20m,
    FitFigure::RoadPerHouse,
    FitFigure::HairpinsPerKm,
    FitFigure::OrientationToRoad,
];
/// Seeds the fitted types are judged at: none of them is a seed of the fit.
const NEW_SEEDS: [u64; 3] = [101, 102, 103];
/// Three more sets of three new seeds, for the spread of the objective between sets.
const MORE_SEEDS: [u64; 9] = [201, 202, 203, 204, 205, 206, 207, 208, 209];

/// A number of 0 or more from the environment variable `name`, else `default`.
fn from_env(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0)
        .unwrap_or(default)
}

/// A real village: its window, the site, connection points and the target of a fit.
struct RealVillage<'a> {
    window: Window,
    target: FitTarget<'a>,
}

fn real_village<'a>(place: &'a Place, window: Window) -> Result<RealVillage<'a>, Error> {
    let real = real_places::real_window(place, &window);
    let buildings: Vec<SitedBuilding> = place
        .houses
        .iter()
        .zip(&place.orientations)
        .filter(|(c, _)| window.region.contains(**c))
        .map(|(c, o)| SitedBuilding {
            centre: *c,
            orientation: *o,
        })
        .collect();
    let site = Site {
        terrain: &place.terrain.heightfield,
        region: window.region.clone(),
        environment: Environment {
            water_areas: real_places::water_near(place, &window),
            ..Default::default()
        },
        cell: CELL,
    };
    let target = FitTarget::new(site, real.connections, &buildings, &real.roads)?;
    Ok(RealVillage { window, target })
}

/// The figures of villages grown on `target` with `enc` and `scenario`, one per seed (`None`: no village grew).
fn grow(
    target: &FitTarget,
    enc: &Encyclopedia,
    scenario: &Scenario,
    seeds: &[u64],
) -> Vec<Option<VillageFigures>> {
    match grow_village_figures(target, enc, scenario, seeds, PARCEL_CELL, &|| true) {
        Ok(grown) => grown,
        Err(e) => panic!("a village failed to grow: {e}"),
    }
}

/// The mean of each figure over the grown villages, as one `VillageFigures` (the histogram averaged bin by bin).
fn mean_figures(grown: &[Option<VillageFigures>]) -> Option<VillageFigures> {
    let all: Vec<&VillageFigures> = grown.iter().flatten().collect();
    if all.len() < grown.len() || all.is_empty() {
        return None;
    }
    let n = all.len() as f64;
    let mean = |f: &dyn Fn(&VillageFigures) -> f64| all.iter().map(|g| f(g)).sum::<f64>() / n;
    let mut m = all[0].clone();
    m.layout.mean_nearest_neighbour = mean(&|g| g.layout.mean_nearest_neighbour);
    m.layout.share_within_20m = mean(&|g| g.layout.share_within_20m);
    m.layout.road_length_per_house = mean(&|g| g.layout.road_length_per_house);
    m.layout.mean_road_distance = mean(&|g| g.layout.mean_road_distance);
    m.layout.houses = mean(&|g| g.layout.houses as f64).round() as usize;
    m.buildings_per_hectare = mean(&|g| g.buildings_per_hectare);
    m.road_length = mean(&|g| g.road_length);
    m.network.hairpins_per_km = mean(&|g| g.network.hairpins_per_km);
    m.network.dead_end_share = mean(&|g| g.network.dead_end_share);
    for b in 0..m.orientation_to_road.len() {
        m.orientation_to_road[b] = mean(&|g| g.orientation_to_road[b]);
    }
    Some(m)
}

fn figure_row(label: &str, f: &VillageFigures) -> String {
    format!(
        "{label:<26} {:>6.1} {:>6.1} {:>7.1} {:>6.2} {:>6.2} {:>6.2} {:>6.1} {:>5}  {}",
        f.layout.mean_nearest_neighbour,
        100.0 * f.layout.share_within_20m,
        f.layout.road_length_per_house,
        f.buildings_per_hectare,
        f.network.hairpins_per_km,
        f.network.dead_end_share,
        f.layout.mean_road_distance,
        f.layout.houses,
        f.orientation_to_road
            .iter()
            .map(|s| format!("{:.0}", 100.0 * s))
            .collect::<Vec<_>>()
            .join(" "),
    )
}

/// The acceptance bands, as (figure, within).
fn within_bands(real: &VillageFigures, grown: &VillageFigures) -> Vec<(FitFigure, f64, bool)> {
    [
        FitFigure::NearestNeighbour,
        FitFigure::ShareWithin20m,
        FitFigure::RoadPerHouse,
        FitFigure::BuildingsPerArea,
        FitFigure::HairpinsPerKm,
        FitFigure::OrientationToRoad,
    ]
    .into_iter()
    .map(|f| {
        let e = f.error(real, grown);
        (f, e, e <= 1.0)
    })
    .collect()
}

struct Learned<'a> {
    village: RealVillage<'a>,
    fitted: FittedVillage,
}

/// The fit's budget, from the environment.
struct Budget {
    seconds: f64,
    evaluations: usize,
}

/// Learns `village`, starting from the shipped type nearest it at the new seeds; prints the real, preset and
/// learned figures and pushes what misses an asserted band to `failures`. `None` when the learned type grew no
/// village at a new seed.
fn learn<'a>(
    village: RealVillage<'a>,
    enc: &Encyclopedia,
    budget: &Budget,
    failures: &mut Vec<String>,
) -> Option<Learned<'a>> {
    let real = &village.target.figures;
    let name = format!("like {}", village.window.name);
    println!("{}", village.window.name);
    println!("{}", figure_row("  real", real));
    // every shipped type grown alike; the nearest by the objective is the one to beat
    let presets = match rank_village_types(&village.target, enc, &NEW_SEEDS, PARCEL_CELL, &|| true)
    {
        Ok(r) => r,
        Err(e) => panic!("a shipped type failed to grow: {e}"),
    };
    let RankedType {
        name: preset,
        objective: preset_objective,
        grown: preset_grown,
    } = presets[0].clone();
    let preset_figures = mean_figures(&preset_grown);
    if let Some(f) = &preset_figures {
        println!("{}", figure_row(&format!("  preset {preset}"), f));
    }
    let options = FitOptions {
        base_type: Some(preset.clone()),
        name: name.clone(),
        max_seconds: budget.seconds,
        max_evaluations: budget.evaluations,
        ..FitOptions::default()
    };
    let fitted = match fit_village_type(&village.target, enc, &options, &|_| true) {
        Ok(f) => f,
        Err(e) => panic!("{}: the fit failed: {e}", village.window.name),
    };
    let grown = grow(
        &village.target,
        &fitted.encyclopedia,
        &fitted.scenario,
        &NEW_SEEDS,
    );
    // the fit's own objective, so "nearer" means what the fit minimised
    let fitted_objective = village_objective(real, &grown);
    let Some(mean) = mean_figures(&grown) else {
        failures.push(format!(
            "{}: the learned type grew no village at a new seed",
            village.window.name
        ));
        return None;
    };
    println!("{}", figure_row(&format!("  {name}"), &mean));
    // the bands judge three seeds; how much three others move the objective says what a band missed means
    let others: Vec<String> = MORE_SEEDS
        .chunks(NEW_SEEDS.len())
        .map(|seeds| {
            let grown = grow(
                &village.target,
                &fitted.encyclopedia,
                &fitted.scenario,
                seeds,
            );
            format!("{:.3}", village_objective(real, &grown))
        })
        .collect();
    println!(
        "  objective: learned {fitted_objective:.3} (at the fit's seeds {:.3}, held-out {}, its base {:.3}), preset \
         {preset} {preset_objective:.3}; {} evaluations in {} generations, {:.0} s; at three other seeds, \
         three times: {}",
        fitted.objective,
        fitted.held_out_objective.map_or("-".into(), |h| format!("{h:.3}")),
        fitted.base_objective,
        fitted.evaluations,
        fitted.generations,
        fitted.seconds,
        others.join(", ")
    );
    for (f, e, ok) in within_bands(real, &mean) {
        let preset_e = preset_figures
            .as_ref()
            .map_or(f64::NAN, |p| f.error(real, p));
        println!(
            "    {:<26} {e:>5.2} bands (preset {preset_e:.2}){}",
            f.name(),
            if ok { "" } else { "  OUT" }
        );
        if !ok && !OPEN.contains(&f) {
            failures.push(format!(
                "{}: {} {e:.2} bands off",
                village.window.name,
                f.name()
            ));
        }
    }
    if fitted_objective >= preset_objective {
        failures.push(format!(
            "{}: learned objective {fitted_objective:.3}, nearest preset {preset} {preset_objective:.3}",
            village.window.name
        ));
    }
    Some(Learned { village, fitted })
}

/// `from`'s learned type grown on `to`'s terrain and region (the learned village's count on a square of the same
/// size: its density, on another terrain); prints how far it lands from the village it was learned on.
fn grow_elsewhere(from: &Learned, to: &RealVillage, failures: &mut Vec<String>) {
    let grown = grow(
        &to.target,
        &from.fitted.encyclopedia,
        &from.fitted.scenario,
        &NEW_SEEDS,
    );
    let Some(mean) = mean_figures(&grown) else {
        failures.push(format!(
            "{} grown on {}: no village",
            from.village.window.name, to.window.name
        ));
        return;
    };
    let real = &from.village.target.figures;
    println!(
        "{}",
        figure_row(
            &format!("{} on {}", from.village.window.name, to.window.name),
            &mean
        )
    );
    for f in [
        FitFigure::NearestNeighbour,
        FitFigure::RoadPerHouse,
        FitFigure::BuildingsPerArea,
    ] {
        // a target (OPEN), printed
        let off = f.error(real, &mean) * f.tolerance();
        println!(
            "    {:<26} {:>4.0} % off the village it was learned on{}",
            f.name(),
            100.0 * off,
            if off > 0.25 { "  OUT" } else { "" }
        );
    }
}

#[test]
#[ignore = "needs shared/data/real (make test-rust runs it where present)"]
fn learn_village_on_andorra() {
    let place = match real_places::load_place(real_places::ANDORRA) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let enc = match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    };
    let windows = real_places::densest_windows(&place, SIDE, WINDOWS + 1, NEXT_HAMLET_BUILDINGS);
    assert!(
        windows.len() == WINDOWS + 1
            && windows[..WINDOWS]
                .iter()
                .all(|w| w.buildings >= MIN_BUILDINGS),
        "Andorra has {WINDOWS} villages of {MIN_BUILDINGS} buildings and another hamlet"
    );
    let next_hamlet = match real_village(&place, windows[WINDOWS].clone()) {
        Ok(v) => v,
        Err(e) => panic!("the next hamlet cannot be grown on: {e}"),
    };
    // the first villages only, when timing the full search on one
    let first = from_env("WORLDPAINT_FIT_VILLAGES", WINDOWS as f64) as usize;
    let budget = Budget {
        seconds: from_env("WORLDPAINT_FIT_SECONDS", FIT_SECONDS),
        evaluations: from_env("WORLDPAINT_FIT_EVALUATIONS", FIT_EVALUATIONS as f64) as usize,
    };
    let header = [
        "nn m", "<20m%", "road/h", "b/ha", "hp/km", "dead", "road m", "n",
    ];
    println!(
        "{:<26} {:>6} {:>6} {:>7} {:>6} {:>6} {:>6} {:>6} {:>5}  orientation to road % (0-90 deg)",
        "", header[0], header[1], header[2], header[3], header[4], header[5], header[6], header[7]
    );
    let mut failures = Vec::new();
    let mut learned = Vec::new();
    for window in windows.into_iter().take(first.min(WINDOWS)) {
        let village = match real_village(&place, window) {
            Ok(v) => v,
            Err(e) => panic!("a real village cannot be learned from: {e}"),
        };
        learned.extend(learn(village, &enc, &budget, &mut failures));
    }
    for (k, from) in learned.iter().enumerate() {
        grow_elsewhere(
            from,
            &learned[(k + 1) % learned.len()].village,
            &mut failures,
        );
    }
    if let Some(hamlet) = learned.get(WINDOWS - 1) {
        grow_elsewhere(hamlet, &next_hamlet, &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
