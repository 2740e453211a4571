//! Learn Village in the engine, on a village of the test's own: a "real" village grown by a shipped type on a
//! synthetic hillside (its houses turned a few degrees and shifted a metre, as surveyed footprints are), then
//! learned. The shipped type that grew it is recognised as the nearest, the fit is the same whatever the number of
//! threads, and a stop keeps the best type found so far. The real villages of Andorra are learned in
//! `real_village_learning`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worldpaint_core::{
    fit_village_type, generate_village, rank_village_types, scenario_for, village_terrain, DVec2,
    Encyclopedia, Environment, FitOptions, FitTarget, FittedVillage, Heightfield, Region, Site,
    SitedBuilding, VillageRequest,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const SIDE: f64 = 500.0;
/// The type that grows the "real" village.
const TRUTH: &str = "farming";
/// Buildings it is asked for.
const BUILDINGS: usize = 30;

fn encyclopedia() -> Encyclopedia {
    match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    }
}

fn site(terrain: &Heightfield) -> Site<'_> {
    Site {
        terrain,
        region: Region::Rect {
            min: DVec2::splat(20.0),
            max: DVec2::splat(SIDE - 20.0),
        },
        environment: Environment::default(),
        cell: 2.0,
    }
}

/// The village `TRUTH` grows at seed 77, as a survey gives it: centres shifted up to a metre, long axes turned up
/// to 5°.
fn surveyed<'a>(terrain: &'a Heightfield, enc: &Encyclopedia) -> FitTarget<'a> {
    let scenario = scenario_for(enc, TRUTH, &enc.village_types[TRUTH], BUILDINGS, 1.0, 0.2);
    let request = VillageRequest {
        site: site(terrain),
        connections: Vec::new(),
        existing_roads: Vec::new(),
        encyclopedia: enc,
        scenario: &scenario,
        seed: 77,
        parcel_cell: 1.0,
    };
    let village = match generate_village(&request, &|_, _| true) {
        Ok(v) => v,
        Err(e) => panic!("the surveyed village did not grow: {e}"),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let buildings: Vec<SitedBuilding> = village
        .footprints
        .iter()
        .map(|f| {
            let b = SitedBuilding::of_footprint(f);
            SitedBuilding {
                centre: b.centre
                    + DVec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)),
                orientation: b.orientation + rng.random_range(-5f64..5.0).to_radians(),
            }
        })
        .collect();
    // grown without ways in, as the survey's village was
    match FitTarget::new(site(terrain), Vec::new(), &buildings, &village.roads) {
        Ok(t) => t,
        Err(e) => panic!("the surveyed village cannot be learned from: {e}"),
    }
}

fn options() -> FitOptions {
    FitOptions {
        name: "like the survey".into(),
        population: 4,
        max_evaluations: 9,
        finalists: 2,
        ..FitOptions::default()
    }
}

fn fit(target: &FitTarget, enc: &Encyclopedia, options: &FitOptions) -> FittedVillage {
    match fit_village_type(target, enc, options, &|_| true) {
        Ok(f) => f,
        Err(e) => panic!("the fit failed: {e}"),
    }
}

#[test]
fn the_type_that_grew_a_village_is_the_nearest_and_the_fit_starts_from_it() {
    let terrain = village_terrain(SIDE, 2.0, 4);
    let enc = encyclopedia();
    let target = surveyed(&terrain, &enc);
    let ranked = match rank_village_types(&target, &enc, &[1, 2], 1.0, &|| true) {
        Ok(r) => r,
        Err(e) => panic!("ranking failed: {e}"),
    };
    let names: Vec<(&str, f64)> = ranked
        .iter()
        .map(|r| (r.name.as_str(), r.objective))
        .collect();
    println!("ranked: {names:?}");
    assert_eq!(ranked.len(), enc.village_types.len());
    assert_eq!(ranked[0].name, TRUTH, "nearest first: {names:?}");
    assert!(
        ranked.windows(2).all(|w| w[0].objective <= w[1].objective),
        "{names:?}"
    );

    let fitted = fit(&target, &enc, &options());
    assert_eq!(fitted.base_type, TRUTH);
    assert_eq!(fitted.generations, 2);
    // the finalists were grown at held-out seeds, and the kept type is valid in the encyclopedia it returns
    let held_out = fitted.held_out_objective.unwrap_or(f64::NAN);
    assert!(
        held_out.is_finite() && held_out >= 0.0,
        "held-out objective {held_out}"
    );
    assert!(fitted
        .encyclopedia
        .village_types
        .contains_key("like the survey"));
    assert!(Encyclopedia::from_json(&fitted.encyclopedia.to_json()).is_ok());
    assert!(!fitted.stopped_early);

    // the same fit on one thread: the same type, to the byte
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => panic!("a one-thread pool: {e}"),
    };
    let alone = pool.install(|| fit(&target, &enc, &options()));
    assert_eq!(alone.encyclopedia.to_json(), fitted.encyclopedia.to_json());
    assert_eq!(alone.objective, fitted.objective);
}

#[test]
fn a_stopped_fit_keeps_the_best_type_so_far_and_a_taken_name_is_refused() {
    let terrain = village_terrain(SIDE, 2.0, 4);
    let enc = encyclopedia();
    let target = surveyed(&terrain, &enc);
    let options = FitOptions {
        base_type: Some("highland".into()),
        max_evaluations: 200,
        ..options()
    };
    // stopped once the first generation is done
    let stopped = match fit_village_type(&target, &enc, &options, &|p| p.generation < 1) {
        Ok(f) => f,
        Err(e) => panic!("a stopped fit keeps its best: {e}"),
    };
    assert!(stopped.stopped_early);
    assert!(stopped.evaluations < 200);
    assert!(stopped.objective <= stopped.base_objective);
    assert_eq!(stopped.held_out_objective, None);
    assert!(stopped
        .encyclopedia
        .village_types
        .contains_key("like the survey"));

    let taken = FitOptions {
        name: TRUTH.into(),
        ..options
    };
    match fit_village_type(&target, &enc, &taken, &|_| true) {
        Err(e) => assert!(e.to_string().contains("already a village type"), "{e}"),
        Ok(_) => panic!("a learned type may not replace a shipped one"),
    }
}
