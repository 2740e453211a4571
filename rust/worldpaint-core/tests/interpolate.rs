//! Distribution interpolation (Section 5.2): histogram shapes are transported, not cross-faded; an
//! interpolated hard-core color paints a hard core between the two; the ends give the two colors back.

use worldpaint_core::{
    displacement_interpolate, hard_core_points, interpolate_colors, learn_color, scene_from_points,
    synthesize, AnalysisOptions, Color, DVec2, Error, Histogram, Interaction, Region, Scene,
    SynthesisOptions,
};

fn square(min: f64, max: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(min),
        max: DVec2::splat(max),
    }
}

fn gaussian(mean: f64, std: f64) -> Histogram {
    let mut h = Histogram::zeros(0.0, 0.05, 240);
    for (k, v) in h.values.iter_mut().enumerate() {
        let x = (k as f64 + 0.5) * 0.05;
        *v = (-0.5 * ((x - mean) / std).powi(2)).exp();
    }
    h
}

fn mean_std(h: &Histogram) -> (f64, f64) {
    let total = h.total();
    let centre = |k: usize| h.start + (k as f64 + 0.5) * h.bin_width;
    let mean = h
        .values
        .iter()
        .enumerate()
        .map(|(k, v)| v * centre(k))
        .sum::<f64>()
        / total;
    let var = h
        .values
        .iter()
        .enumerate()
        .map(|(k, v)| v * (centre(k) - mean).powi(2))
        .sum::<f64>()
        / total;
    (mean, var.sqrt())
}

#[test]
fn gaussians_are_transported_not_cross_faded() {
    let (a, b) = (gaussian(2.0, 0.5), gaussian(8.0, 1.5));
    let h = displacement_interpolate(&a, &b, 0.5);
    let (mean, std) = mean_std(&h);
    let max = h.values.iter().copied().fold(0.0, f64::max);
    let argmax =
        h.start + (h.values.iter().position(|v| *v == max).unwrap() as f64 + 0.5) * h.bin_width;
    println!(
        "t=0.5: mean {mean:.4}, std {std:.4}, mode at {argmax:.3}, h(2)/max {:.2e}, h(5)/max {:.3}, h(8)/max {:.2e}",
        h.value_at(2.0) / max,
        h.value_at(5.0) / max,
        h.value_at(8.0) / max
    );
    assert!((mean - 5.0).abs() <= 0.1, "mean {mean}");
    assert!((std - 1.0).abs() <= 0.1, "std {std}");
    assert!((argmax - 5.0).abs() <= 0.25, "mode at {argmax}");
    assert!(h.value_at(5.0) >= 0.95 * max);
    assert!(h.value_at(2.0) <= 0.05 * max && h.value_at(8.0) <= 0.05 * max);
    // unimodal: rises to the mode, then falls
    let m = h.values.iter().position(|v| *v == max).unwrap();
    assert!(h.values[..=m].windows(2).all(|w| w[1] >= w[0] - 1e-12));
    assert!(h.values[m..].windows(2).all(|w| w[1] <= w[0] + 1e-12));
    // total mass is interpolated linearly
    let expected = 0.5 * (a.total() + b.total());
    assert!((h.total() - expected).abs() <= 1e-9 * expected);
    // a cross-fade would be bimodal, with little at 5 (b's tail) and its peaks at 2 and 8
    let fade: Vec<f64> = a
        .values
        .iter()
        .zip(&b.values)
        .map(|(x, y)| 0.5 * (x + y))
        .collect();
    assert!(fade[100] < 0.2 * fade.iter().copied().fold(0.0, f64::max));
}

fn hard_core_color(min_distance: f64, density: f64, seed: u64, opts: &AnalysisOptions) -> Color {
    let region = square(0.0, 100.0);
    let scene = scene_from_points(
        "tree",
        &hard_core_points(&region, density, min_distance, seed),
    );
    learn_color(&scene, &region, &format!("hard core {min_distance}"), opts).unwrap()
}

fn min_pair_distance(points: &[DVec2]) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            best = best.min(points[i].distance(points[j]));
        }
    }
    best
}

#[test]
fn interpolated_hard_core_paints_between_the_two() {
    let opts = AnalysisOptions::default();
    let a = hard_core_color(2.0, 0.04, 3, &opts);
    let b = hard_core_color(6.0, 0.01, 4, &opts);
    let mid = interpolate_colors(&a, &b, 0.5, "between").unwrap();
    let region = square(0.0, 200.0);
    let scene = Scene {
        categories: vec![],
        instances: vec![],
        terrain: None,
        ..Default::default()
    };
    let result = synthesize(&scene, &mid, &region, &SynthesisOptions::default()).unwrap();
    let points: Vec<DVec2> = result.instances.iter().map(|i| i.position).collect();
    let d_min = min_pair_distance(&points);
    let density = points.len() as f64 / region.area();
    let (da, db) = (a.categories[0].density, b.categories[0].density);
    println!(
        "a: min distance {:.3}, density {da:.4}, max_radius {:.2}; b: min distance {:.3}, density {db:.4}, \
         max_radius {:.2}; interpolated min_distance {:.3}, density {:.4}; synthesized {} instances, \
         min pair distance {d_min:.3} m, density {density:.4}",
        a.categories[0].min_distance,
        a.max_radius,
        b.categories[0].min_distance,
        b.max_radius,
        mid.categories[0].min_distance,
        mid.categories[0].density,
        points.len()
    );
    assert!(
        (2.5..=5.5).contains(&d_min),
        "min pair distance {d_min} not between the two hard cores"
    );
    assert!(
        density > da.min(db) && density < da.max(db),
        "density {density} not between {da} and {db}"
    );
    // the interpolated rdf has its hard core between the two
    let first_nonzero = |c: &Color| match &c.pairs[0].interaction {
        Interaction::Rdf { hist } => {
            let k = hist.values.iter().position(|v| *v > 0.0).unwrap();
            hist.start + k as f64 * hist.bin_width
        }
        _ => panic!("expected an rdf"),
    };
    let (ra, rm, rb) = (first_nonzero(&a), first_nonzero(&mid), first_nonzero(&b));
    println!("first non-empty rdf bin: a {ra:.3}, interpolated {rm:.3}, b {rb:.3}");
    assert!(ra < rm && rm < rb);
}

fn assert_histograms_close(x: &Histogram, y: &Histogram, tol: f64, what: &str) {
    let tv = x.total_variation(y);
    assert!(tv <= tol, "{what}: total variation {tv}");
    let (tx, ty) = (x.total(), y.total());
    assert!(
        (tx - ty).abs() <= tol * tx.abs().max(1.0),
        "{what}: totals {tx} vs {ty}"
    );
}

#[test]
fn ends_give_the_colors_back_and_bad_t_is_refused() {
    let opts = AnalysisOptions::default();
    let a = hard_core_color(2.0, 0.04, 3, &opts);
    let b = hard_core_color(6.0, 0.01, 4, &opts);
    let mut at0 = interpolate_colors(&a, &b, 0.0, "zero").unwrap();
    let mut at1 = interpolate_colors(&a, &b, 1.0, "one").unwrap();
    assert_eq!(at0.name, "zero");
    at0.name = a.name.clone();
    at1.name = b.name.clone();
    assert_eq!(at0, a);
    assert_eq!(at1, b);

    // continuity of the transport itself at the ends (same grids: same max_radius)
    let same = AnalysisOptions {
        max_radius: Some(15.0),
        ..Default::default()
    };
    let a = hard_core_color(2.0, 0.04, 3, &same);
    let b = hard_core_color(6.0, 0.01, 4, &same);
    for (t, reference) in [(1e-12, &a), (1.0 - 1e-12, &b)] {
        let c = interpolate_colors(&a, &b, t, "near").unwrap();
        let (cc, rc) = (&c.categories[0], &reference.categories[0]);
        assert!((cc.density - rc.density).abs() <= 1e-9);
        assert!((cc.min_distance - rc.min_distance).abs() <= 1e-9);
        assert_histograms_close(&cc.scale, &rc.scale, 1e-9, "scale");
        assert_histograms_close(&cc.rotation, &rc.rotation, 1e-9, "rotation");
        for (p, q) in c.pairs.iter().zip(&reference.pairs) {
            match (&p.interaction, &q.interaction) {
                (Interaction::Rdf { hist: x }, Interaction::Rdf { hist: y }) => {
                    assert_eq!(x.values.len(), y.values.len());
                    assert_histograms_close(x, y, 1e-9, "rdf");
                    for (u, v) in x.values.iter().zip(&y.values) {
                        assert!((u - v).abs() <= 1e-9, "rdf bin {u} vs {v}");
                    }
                }
                _ => panic!("expected rdfs"),
            }
        }
    }

    for t in [-0.1, 1.1, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(
            matches!(
                interpolate_colors(&a, &b, t, "bad"),
                Err(Error::OutOfRange { .. })
            ),
            "t = {t} accepted"
        );
    }
}

#[test]
fn an_interpolated_color_is_previewed_by_an_arrangement_painted_with_it() {
    let opts = AnalysisOptions::default();
    let (a, b) = (
        hard_core_color(2.0, 0.04, 1, &opts),
        hard_core_color(6.0, 0.01, 2, &opts),
    );
    let mid = interpolate_colors(&a, &b, 0.5, "mid").unwrap();
    let previewed = worldpaint_core::with_painted_preview(mid.clone()).unwrap();
    let points: Vec<DVec2> = previewed
        .preview
        .iter()
        .map(|p| DVec2::new(p[0], p[1]))
        .collect();
    let expected = mid.categories[0].density * mid.region_area;
    println!(
        "preview of the interpolated color: {} points ({expected:.0} expected)",
        points.len()
    );
    assert!((points.len() as f64 - expected).abs() <= 1.0);
    assert!(points
        .iter()
        .all(|p| p.x >= 0.0 && p.y >= 0.0 && p.x <= 100.0 && p.y <= 100.0));
    assert!(
        min_pair_distance(&points) >= 4.0 - 1e-9,
        "the preview keeps the interpolated hard core"
    );
}

/// The quantile function of a histogram read as a piecewise-constant density, at `u`.
fn quantile(h: &Histogram, u: f64) -> f64 {
    let total = h.total();
    let mut acc = 0.0;
    for (k, v) in h.values.iter().enumerate() {
        let m = v / total;
        if m > 0.0 && acc + m >= u {
            return h.start + (k as f64 + (u - acc) / m) * h.bin_width;
        }
        acc += m;
    }
    h.end()
}

proptest::proptest! {
    // a fixed seed: the same 256 random pairs on every run
    #![proptest_config(proptest::test_runner::Config {
        cases: 256,
        rng_seed: proptest::test_runner::RngSeed::Fixed(2015),
        failure_persistence: None,
        ..Default::default()
    })]

    /// Displacement interpolation moves every quantile linearly (Read 1999): `Q_t = (1 − t) Q_a + t Q_b`, up to
    /// the re-binning onto the histogram's bins (a tenth of a bin here); for two Gaussian shapes well inside the
    /// histogram at t = ½ that is one peak at the middle of the two means.
    #[test]
    fn quantiles_interpolate_linearly(
        mean_a in 3.0f64..8.5, std_a in 0.2f64..1.0,
        mean_b in 3.0f64..8.5, std_b in 0.2f64..1.0,
        t in 0.0f64..1.0,
    ) {
        let (a, b) = (gaussian(mean_a, std_a), gaussian(mean_b, std_b));
        let h = displacement_interpolate(&a, &b, t);
        for u in [0.05, 0.25, 0.5, 0.75, 0.95] {
            let want = (1.0 - t) * quantile(&a, u) + t * quantile(&b, u);
            let got = quantile(&h, u);
            proptest::prop_assert!((got - want).abs() <= 0.1 * h.bin_width, "u {u}: {got} vs {want}");
        }
        let mid = displacement_interpolate(&a, &b, 0.5);
        let max = mid.values.iter().copied().fold(0.0, f64::max);
        let m = mid.values.iter().position(|v| *v == max).unwrap();
        let mode = mid.start + (m as f64 + 0.5) * mid.bin_width;
        proptest::prop_assert!((mode - 0.5 * (mean_a + mean_b)).abs() <= 0.15, "mode {mode}");
        proptest::prop_assert!(mid.values[..=m].windows(2).all(|w| w[1] >= w[0] - 1e-12));
        proptest::prop_assert!(mid.values[m..].windows(2).all(|w| w[1] <= w[0] + 1e-12));
    }
}
