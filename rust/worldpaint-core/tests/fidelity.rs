//! A color learned from an exemplar and painted into a region 16× larger reproduces the exemplar's density and
//! pair statistics about as well as a second draw of the process that made the exemplar.

use std::sync::Arc;
use worldpaint_core::{
    clustered_points, compare, demo_terrain, hard_core_points, learn_color, scene_from_points,
    slope_scene, synthesize, undergrowth_scene, uniform_points, AnalysisOptions, Color, DVec2,
    Heightfield, Region, Scene, SynthesisOptions, SynthesisResult,
};

fn exemplar_region() -> Region {
    Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    }
}

fn paint_region() -> Region {
    Region::Rect {
        min: DVec2::new(1000.0, 1000.0),
        max: DVec2::new(1400.0, 1400.0),
    }
}

fn same_bins(c: &Color) -> AnalysisOptions {
    AnalysisOptions {
        bin_width: Some(c.bin_width),
        max_radius: Some(c.max_radius),
        ..Default::default()
    }
}

/// The color `name` learned, with the bins of `color`, from what `out` painted over `paint` on `terrain`.
fn learned_back(
    color: &Color,
    out: SynthesisResult,
    terrain: Option<Arc<Heightfield>>,
    paint: &Region,
    name: &str,
) -> Color {
    let painted = Scene {
        categories: out.categories,
        instances: out.instances,
        terrain,
        ..Default::default()
    };
    learn_color(&painted, paint, name, &same_bins(color)).unwrap()
}

/// (density ratio, synthesized rdf L2, second-draw rdf L2) for one seed.
fn fidelity_of(make: &dyn Fn(&Region, u64) -> Vec<DVec2>, seed: u64) -> (f64, f64, f64) {
    let region = exemplar_region();
    let ex = scene_from_points("tree", &make(&region, seed));
    let color = learn_color(&ex, &region, "ex", &Default::default()).unwrap();
    let second = scene_from_points("tree", &make(&region, seed + 1000));
    let second_color = learn_color(&second, &region, "second", &same_bins(&color)).unwrap();
    let reference_l2 = compare(&color, &second_color).max_rdf_l2();

    let paint = paint_region();
    let opts = SynthesisOptions {
        seed,
        ..Default::default()
    };
    let out = synthesize(&Scene::default(), &color, &paint, &opts).unwrap();
    let painted_color = learned_back(&color, out, None, &paint, "painted");
    let fid = compare(&color, &painted_color);
    println!(
        "seed {seed}: exemplar n={} max_radius={:.2} | density ratio {:.3} | rdf L2 synth {:.4} vs second draw {:.4}",
        color.categories[0].count,
        color.max_radius,
        fid.density_ratio[0].1,
        fid.max_rdf_l2(),
        reference_l2
    );
    (fid.density_ratio[0].1, fid.max_rdf_l2(), reference_l2)
}

fn check(kind: &str, make: &dyn Fn(&Region, u64) -> Vec<DVec2>) {
    let seeds = [1u64, 2];
    let results: Vec<_> = seeds.iter().map(|s| fidelity_of(make, *s)).collect();
    let n = results.len() as f64;
    let synth_l2 = results.iter().map(|r| r.1).sum::<f64>() / n;
    let ref_l2 = results.iter().map(|r| r.2).sum::<f64>() / n;
    println!(
        "{kind}: mean rdf L2 synthesized {synth_l2:.4}, second draw {ref_l2:.4}, ratio {:.2}",
        synth_l2 / ref_l2
    );
    for (ratio, _, _) in &results {
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "{kind}: density ratio {ratio:.3} is off by more than 10%"
        );
    }
    assert!(
        synth_l2 <= 1.5 * ref_l2,
        "{kind}: rdf L2 {synth_l2:.4} exceeds 1.5 × the second-draw error {ref_l2:.4}"
    );
}

#[test]
fn uniform_exemplar_is_reproduced() {
    check("uniform", &|r, s| uniform_points(r, 0.05, s));
}

#[test]
fn clustered_exemplar_is_reproduced() {
    check("clustered", &|r, s| clustered_points(r, 0.004, 8.0, 2.0, s));
}

#[test]
fn hard_core_exemplar_is_reproduced() {
    check("hard-core", &|r, s| hard_core_points(r, 0.04, 3.0, s));
}

/// Slope, tree density, rock density, grass density, rock–grass rdf L2 (synthesized, second draw) for one seed.
struct SlopeFidelity {
    tree_slope_tv: f64,
    trees_on_unseen_slopes: f64,
    density: Vec<(String, f64)>,
    synth_l2: f64,
    reference_l2: f64,
}

fn slope_fidelity(seed: u64) -> SlopeFidelity {
    // the slope scene's terrain repeats every 100 m across X (size / 4): the exemplar holds one period, the
    // painted region 16× its area on the same terrain
    let size = 400.0;
    let learn_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let paint = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let scene = slope_scene(size, seed);
    let color = learn_color(&scene, &learn_region, "slope", &Default::default()).unwrap();
    let second = slope_scene(size, seed + 1000);
    let second_color = learn_color(&second, &learn_region, "second", &same_bins(&color)).unwrap();
    let reference_l2 = compare(&color, &second_color)
        .rdf_l2_of("grass", "rock")
        .unwrap();

    let out = synthesize(
        &scene,
        &color,
        &paint,
        &SynthesisOptions {
            seed,
            ..Default::default()
        },
    )
    .unwrap();
    let back = learned_back(&color, out, scene.terrain.clone(), &paint, "painted");
    let fid = compare(&color, &back);
    let slope_of = |c: &Color| {
        c.maps
            .iter()
            .find(|m| m.category == "tree" && m.map == "slope")
            .map(|m| m.hist.clone())
            .unwrap()
    };
    let (ex_slope, syn_slope) = (slope_of(&color), slope_of(&back));
    let trees_on_unseen_slopes = ex_slope
        .values
        .iter()
        .zip(&syn_slope.values)
        .filter(|(e, _)| **e == 0.0)
        .map(|(_, s)| *s)
        .sum::<f64>();
    let result = SlopeFidelity {
        tree_slope_tv: ex_slope.total_variation(&syn_slope),
        trees_on_unseen_slopes,
        density: fid.density_ratio.clone(),
        synth_l2: fid.rdf_l2_of("grass", "rock").unwrap(),
        reference_l2,
    };
    println!(
        "slope seed {seed}: tree slope TV {:.4} (unseen-bin mass {:.4}), density {:?}, rock–grass rdf L2 synth \
         {:.4} vs second draw {:.4}",
        result.tree_slope_tv,
        result.trees_on_unseen_slopes,
        result.density,
        result.synth_l2,
        result.reference_l2
    );
    result
}

#[test]
fn forest_learned_on_a_slope_stays_on_the_slope_and_grass_stays_around_rocks() {
    let results: Vec<SlopeFidelity> = [1u64, 2].iter().map(|s| slope_fidelity(*s)).collect();
    for r in &results {
        assert!(
            r.tree_slope_tv <= 0.15,
            "tree slope histogram TV {:.3} > 0.15",
            r.tree_slope_tv
        );
        assert_eq!(
            r.trees_on_unseen_slopes, 0.0,
            "trees synthesized on slopes the exemplar never had trees on"
        );
        for (cat, ratio) in &r.density {
            assert!(
                (ratio - 1.0).abs() <= 0.10,
                "{cat}: density ratio {ratio:.3} is off by more than 10%"
            );
        }
    }
    let n = results.len() as f64;
    let synth = results.iter().map(|r| r.synth_l2).sum::<f64>() / n;
    let reference = results.iter().map(|r| r.reference_l2).sum::<f64>() / n;
    println!(
        "slope: mean rock–grass rdf L2 synthesized {synth:.4}, second draw {reference:.4}, ratio {:.2}",
        synth / reference
    );
    assert!(
        synth <= 1.5 * reference,
        "rock–grass rdf L2 {synth:.4} exceeds 1.5 × the second-draw error {reference:.4}"
    );
}

/// `color` painted with the default options over the square kilometre from the origin: the region and the result.
fn paint_square_kilometre(color: &Color) -> (Region, SynthesisResult) {
    let paint = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(1000.0),
    };
    let out = synthesize(
        &Scene::default(),
        color,
        &paint,
        &SynthesisOptions::default(),
    )
    .unwrap();
    (paint, out)
}

/// The undergrowth of the benchmarks at scale (hard-core trees, uniform rocks, clumped grass) learned on 100 m and
/// painted over 1 km²: a paste a hundred examples large, whose chain stops as soon as it matches its targets within
/// the example's own noise (see "When to stop"), still matches every pair's rdf as well as a second draw does.
#[test]
fn a_paste_a_hundred_examples_large_matches_them_as_well_as_a_second_draw() {
    let region = exemplar_region();
    let color = learn_color(
        &undergrowth_scene(100.0),
        &region,
        "bench",
        &Default::default(),
    )
    .unwrap();
    let mut second = undergrowth_scene(100.0);
    second.instances.clear();
    let layers = [
        hard_core_points(&region, 0.03, 3.0, 11),
        uniform_points(&region, 0.03, 12),
        clustered_points(&region, 0.004, 10.0, 2.0, 13),
    ];
    for (c, points) in layers.iter().enumerate() {
        second
            .instances
            .extend(points.iter().map(|p| worldpaint_core::Instance::at(*p, c)));
    }
    let second_color = learn_color(&second, &region, "second", &same_bins(&color)).unwrap();
    let reference = compare(&color, &second_color);

    let (paint, out) = paint_square_kilometre(&color);
    let n = out.instances.len();
    let fid = compare(&color, &learned_back(&color, out, None, &paint, "painted"));
    println!(
        "{n} instances: rdf L2 per pair painted {:.3?}, a second draw {:.3?}; density {:.3?}",
        fid.rdf_l2, reference.rdf_l2, fid.density_ratio
    );
    for (cat, ratio) in &fid.density_ratio {
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "{cat}: density ratio {ratio:.3}"
        );
    }
    assert!(
        fid.max_rdf_l2() <= 1.5 * reference.max_rdf_l2(),
        "rdf L2 {:.4} exceeds 1.5 × the second draw's {:.4}",
        fid.max_rdf_l2(),
        reference.max_rdf_l2()
    );
}

/// Per window of `side` over the square kilometre: the mean number of neighbours within `reach` of `points` in
/// the window (those whose own neighbourhood the window holds whole).
fn neighbours_per_window(points: &[DVec2], side: f64, reach: f64) -> Vec<f64> {
    let n = (1000.0 / side).round() as usize;
    let mut grid: Vec<Vec<DVec2>> = vec![Vec::new(); n * n];
    let at = |p: DVec2| {
        let ix = ((p.x / side).floor().max(0.0) as usize).min(n - 1);
        let iy = ((p.y / side).floor().max(0.0) as usize).min(n - 1);
        iy * n + ix
    };
    for &p in points {
        grid[at(p)].push(p);
    }
    let inner =
        |p: DVec2| p.x >= reach && p.y >= reach && p.x <= 1000.0 - reach && p.y <= 1000.0 - reach;
    (0..n * n)
        .map(|w| {
            let (wx, wy) = ((w % n) as isize, (w / n) as isize);
            let mine: Vec<DVec2> = grid[w].iter().copied().filter(|p| inner(*p)).collect();
            let mut pairs = 0usize;
            for &p in &mine {
                for y in (wy - 1).max(0)..=(wy + 1).min(n as isize - 1) {
                    for x in (wx - 1).max(0)..=(wx + 1).min(n as isize - 1) {
                        pairs += grid[y as usize * n + x as usize]
                            .iter()
                            .filter(|q| **q != p && q.distance(p) < reach)
                            .count();
                    }
                }
            }
            pairs as f64 / mine.len().max(1) as f64
        })
        .collect()
}

fn mean_and_spread(v: &[f64]) -> (f64, f64) {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
    (m, var.sqrt())
}

/// The clumped grass of the benchmark color painted over 1 km² is as even as the process it was learned from: per
/// 62.5 m square (about the size of the chain's tiles), its instances have as many neighbours within the clumps'
/// reach on average, and the squares differ from one another no more than in a square kilometre of the process
/// itself (see "Tiles match their own pairs" in the synthesis module: tiles pushed by the region's deviation
/// alone left a patchwork of tight and loose clumps that the paste's pooled statistics do not show; 1.79 against
/// the process's 1.41, 2.7–3.1 when started from clusters).
#[test]
fn a_large_paste_is_as_even_from_square_to_square_as_the_process_it_was_learned_from() {
    let color = learn_color(
        &undergrowth_scene(100.0),
        &exemplar_region(),
        "bench",
        &Default::default(),
    )
    .unwrap();
    let (_, out) = paint_square_kilometre(&color);
    let grass = out
        .categories
        .iter()
        .position(|c| c.name == "Grass")
        .unwrap();
    let painted: Vec<DVec2> = out
        .instances
        .iter()
        .filter(|i| i.category == grass)
        .map(|i| i.position)
        .collect();
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(1000.0),
    };
    let process = clustered_points(&square, 0.004, 10.0, 2.0, 31);
    let (side, reach) = (62.5, 4.0);
    let (pm, ps) = mean_and_spread(&neighbours_per_window(&painted, side, reach));
    let (rm, rs) = mean_and_spread(&neighbours_per_window(&process, side, reach));
    println!(
        "grass neighbours within {reach} m per {side} m square: painted {pm:.2} ± {ps:.2}, the process {rm:.2} ± {rs:.2}"
    );
    assert!(
        (pm / rm - 1.0).abs() <= 0.15,
        "mean neighbours {pm:.2} against the process's {rm:.2}"
    );
    assert!(
        ps <= 1.3 * rs,
        "squares differ by {ps:.2} neighbours, the process's by {rs:.2}"
    );
}

/// Three categories at 0.1 instances / m² (hard-core trees, uniform rocks, clustered grass) learned on
/// 200 m × 200 m and painted on 1 km²: ~100k instances. A timing harness, not a pass / fail test:
/// `cargo test -p worldpaint-core --release --test fidelity -- --ignored --nocapture timing`.
#[test]
#[ignore = "timing harness"]
fn timing_100k_instances_three_categories_on_a_square_kilometre() {
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(200.0),
    };
    let mut ex = Scene {
        categories: vec![
            worldpaint_core::Category::distribution("tree", "vegetation", 0),
            worldpaint_core::Category::distribution("rock", "vegetation", 1),
            worldpaint_core::Category::distribution("grass", "vegetation", 2),
        ],
        ..Default::default()
    };
    let layers = [
        hard_core_points(&region, 0.03, 3.0, 1),
        uniform_points(&region, 0.02, 2),
        clustered_points(&region, 0.005, 10.0, 2.0, 3),
    ];
    for (c, pts) in layers.iter().enumerate() {
        ex.instances
            .extend(pts.iter().map(|p| worldpaint_core::Instance::at(*p, c)));
    }
    let color = learn_color(&ex, &region, "mix", &Default::default()).unwrap();
    let t0 = std::time::Instant::now();
    let (paint, out) = paint_square_kilometre(&color);
    let secs = t0.elapsed().as_secs_f64();
    let n = out.instances.len();
    println!(
        "synthesized {n} instances in {secs:.3} s ({:.2} µs / instance); paper Table 2: 13.9 s for 83,209 \
         ({:.1} µs / instance), ratio {:.1}x",
        1e6 * secs / n as f64,
        1e6 * 13.9 / 83209.0,
        (13.9 / 83209.0) / (secs / n as f64)
    );
    let back = learned_back(&color, out, None, &paint, "back");
    let fid = compare(&color, &back);
    println!("{fid:?}");
}

#[test]
fn a_grove_learned_on_flat_ground_pastes_on_hills_at_its_density() {
    // the flat exemplar shows only slope 0: it holds no evidence against steeper ground
    let flat =
        worldpaint_core::Heightfield::new(DVec2::splat(-10.0), 2.0, 61, 61, vec![0.0; 61 * 61])
            .unwrap();
    let mut grove = scene_from_points(
        "tree",
        &clustered_points(&exemplar_region(), 0.002, 8.0, 3.0, 4),
    );
    grove.terrain = Some(flat.into());
    let maps = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let color = learn_color(&grove, &exemplar_region(), "grove", &maps).unwrap();

    let hills = demo_terrain(600.0, 2.0, 11);
    let slopes: Vec<f64> = hills.maps["slope"]
        .iter()
        .map(|s| f64::from(*s).to_degrees())
        .collect();
    assert!(
        slopes.iter().filter(|s| **s > 10.0).count() * 4 > slopes.len(),
        "the hills are not flat"
    );
    let scene = Scene::on(hills.into());
    let paint = Region::Rect {
        min: DVec2::splat(100.0),
        max: DVec2::splat(500.0),
    };
    let out = synthesize(&scene, &color, &paint, &SynthesisOptions::default()).unwrap();
    let expected = color.categories[0].density * paint.area();
    let ratio = out.instances.len() as f64 / expected;
    assert!(
        (ratio - 1.0).abs() <= 0.1,
        "density ratio {ratio:.3} on hills"
    );
}

/// Writes a plot as a binary PPM under the directory `WORLDPAINT_PLOT_DIR` names, when it is set (to look at it).
fn keep_plot(plot: &worldpaint_core::FidelityPlot, name: &str) {
    let Ok(dir) = std::env::var("WORLDPAINT_PLOT_DIR") else {
        return;
    };
    let mut bytes = format!("P6\n{} {}\n255\n", plot.width, plot.height).into_bytes();
    bytes.extend(plot.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]));
    std::fs::write(
        std::path::Path::new(&dir).join(format!("{name}.ppm")),
        bytes,
    )
    .unwrap();
}

/// Standard deviation of the plot's pixel values over all channels but alpha.
fn pixel_spread(plot: &worldpaint_core::FidelityPlot) -> f64 {
    let values: Vec<f64> = plot
        .rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .map(f64::from)
        .collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

#[test]
fn a_clustered_colors_self_synthesis_is_far_closer_to_its_example_than_a_uniform_scatter() {
    use worldpaint_core::draw_fidelity;
    let region = exemplar_region();
    let ex = scene_from_points("tree", &clustered_points(&region, 0.004, 8.0, 2.0, 5));
    let color = learn_color(&ex, &region, "grove", &Default::default()).unwrap();
    let density = color.categories[0].density;

    let t0 = std::time::Instant::now();
    let own = worldpaint_core::self_synthesis(&color, None, 1, &|_| true).unwrap();
    let seconds = t0.elapsed().as_secs_f64();
    let again = worldpaint_core::self_synthesis(&color, None, 1, &|_| true).unwrap();
    assert_eq!(own, again, "the self-synthesis is seeded");
    let own_fid = compare(&color, &own);

    // a uniform scatter of the same density in the same region, learned with the same bins
    let uniform = scene_from_points("tree", &uniform_points(&region, density, 6));
    let uniform_color = learn_color(&uniform, &region, "uniform", &same_bins(&color)).unwrap();
    let uniform_fid = compare(&color, &uniform_color);
    println!(
        "clustered example (n={}, max_radius {:.2} m): self-synthesis rdf L2 {:.3} (density ×{:.3}, {seconds:.3} s), \
         uniform scatter rdf L2 {:.3} (density ×{:.3})",
        color.categories[0].count,
        color.max_radius,
        own_fid.max_rdf_l2(),
        own_fid.density_ratio[0].1,
        uniform_fid.max_rdf_l2(),
        uniform_fid.density_ratio[0].1,
    );
    assert!(
        own_fid.max_rdf_l2() < 0.5 * uniform_fid.max_rdf_l2(),
        "self-synthesis rdf L2 {:.3} is not well below the uniform scatter's {:.3}",
        own_fid.max_rdf_l2(),
        uniform_fid.max_rdf_l2()
    );
    assert!((own_fid.density_ratio[0].1 - 1.0).abs() <= 0.2);

    let plot = draw_fidelity(&color, &own, 256, 160).unwrap();
    assert_eq!(
        (plot.width, plot.height, plot.rgba.len()),
        (256, 160, 256 * 160 * 4)
    );
    assert_eq!(
        plot.extent.max_slope_degrees, None,
        "no terrain, no slope panel"
    );
    let spread = pixel_spread(&plot);
    assert!(spread > 5.0, "the plot is blank (pixel spread {spread:.2})");
    assert_eq!(
        plot,
        draw_fidelity(&color, &own, 256, 160).unwrap(),
        "the plot is deterministic"
    );
    keep_plot(&plot, "clustered");
    assert!(
        draw_fidelity(&color, &own, 8, 160).is_err(),
        "a plot too small is refused"
    );
}

#[test]
fn a_forest_on_a_slope_shows_its_slope_histograms_beside_its_pcf() {
    use worldpaint_core::draw_fidelity;
    let scene = slope_scene(400.0, 3);
    let region = exemplar_region();
    let color = learn_color(&scene, &region, "slope", &Default::default()).unwrap();
    let t0 = std::time::Instant::now();
    let own = worldpaint_core::self_synthesis(&color, scene.terrain.clone(), 1, &|_| true).unwrap();
    let seconds = t0.elapsed().as_secs_f64();
    let fid = compare(&color, &own);
    println!(
        "slope forest: self-synthesis in {seconds:.3} s, density {:?}, rdf L2 {:?}, map TV {:?}",
        fid.density_ratio, fid.rdf_l2, fid.map_tv
    );
    assert!(fid.max_rdf_l2().is_finite() && fid.worst_density_error() <= 0.25);
    let plot = draw_fidelity(&color, &own, 320, 160).unwrap();
    let slope = plot.extent.max_slope_degrees.expect("a slope panel");
    assert!(slope > 10.0 && slope <= 92.5, "slope axis to {slope}°");
    assert!(pixel_spread(&plot) > 5.0);
    keep_plot(&plot, "slope");
}

#[test]
fn a_slope_color_without_its_terrain_is_painted_without_its_terrain_maps() {
    let scene = slope_scene(400.0, 3);
    let region = exemplar_region();
    let color = learn_color(&scene, &region, "slope", &Default::default()).unwrap();
    let own = worldpaint_core::self_synthesis(&color, None, 1, &|_| true).unwrap();
    assert!(own.maps.is_empty() && own.categories.len() == 3);
    let plot = worldpaint_core::draw_fidelity(&color, &own, 256, 128).unwrap();
    assert_eq!(
        plot.extent.max_slope_degrees, None,
        "no slope histogram of the self-synthesis, no slope panel"
    );
}

#[test]
fn a_category_with_one_instance_in_the_example_does_not_set_the_figures() {
    // a village's one chapel beside its trees: whether a paste gets a chapel is counting noise, not fidelity
    let region = exemplar_region();
    let mut ex = scene_from_points("tree", &uniform_points(&region, 0.02, 3));
    ex.categories.push(worldpaint_core::Category::distribution(
        "chapel",
        "buildings",
        1,
    ));
    ex.instances
        .push(worldpaint_core::Instance::at(DVec2::new(50.0, 50.0), 1));
    let color = learn_color(&ex, &region, "ex", &Default::default()).unwrap();
    let trees_only = learn_color(
        &scene_from_points("tree", &uniform_points(&region, 0.02, 3)),
        &region,
        "trees",
        &same_bins(&color),
    )
    .unwrap();
    let paint = paint_region();
    let opts = SynthesisOptions {
        seed: 1,
        ..Default::default()
    };
    let out = synthesize(&Scene::default(), &color, &paint, &opts).unwrap();
    let fid = compare(&color, &learned_back(&color, out, None, &paint, "painted"));
    let out = synthesize(&Scene::default(), &trees_only, &paint, &opts).unwrap();
    let tree_fid = compare(
        &trees_only,
        &learned_back(&trees_only, out, None, &paint, "painted"),
    );
    println!(
        "with the chapel: density error {:.3}, rdf L2 {:.3}, too few {:?} (per pair {:?}); trees alone: {:.3}, {:.3}",
        fid.worst_density_error(),
        fid.max_rdf_l2(),
        fid.too_few,
        fid.rdf_l2,
        tree_fid.worst_density_error(),
        tree_fid.max_rdf_l2()
    );
    assert_eq!(fid.too_few, vec!["chapel".to_string()]);
    // the chapel's own figures stay listed, but the worst ones read the trees, as the trees alone do
    assert!(fid.density_ratio.iter().any(|(c, _)| c == "chapel"));
    assert!(
        fid.worst_density_error() <= 0.1,
        "{}",
        fid.worst_density_error()
    );
    assert!(
        fid.max_rdf_l2() <= 1.5 * tree_fid.max_rdf_l2().max(0.05),
        "{} against the trees alone {}",
        fid.max_rdf_l2(),
        tree_fid.max_rdf_l2()
    );
}
