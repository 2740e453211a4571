//! Element arrangement by example (Ijiri et al. 2008), the patterns it keeps: two symbols in rows keep their
//! adjacencies, an irregular reference keeps its spacing, and a lattice is kept better than by WorldBrush's point
//! synthesis. Run with `--nocapture` to see the figures.

mod common;

use common::arrangement::*;
use glam::DVec2;
use worldpaint_core::{
    grow_arrangement, hard_core_points, learn_color, relax_arrangement, scene_from_points,
    synthesize, ReferenceArrangement, RotationMode, SynthesisOptions,
};

#[test]
fn two_symbols_in_rows_keep_their_adjacencies() {
    // stones in rows (seed Fig. 8 d): rows of big stones (0) and small stones (1) alternate
    let reference =
        ReferenceArrangement::new(lattice(true, 9, |row, _| (row % 2) as u32)).expect("valid");
    let region = rect((-12.0, -12.0), (12.0, 12.0));
    let grown = grown_from_centre(&reference, &region);
    // adjacency frequencies: the share of a symbol-s element's neighbours that have symbol t, over interior elements
    let frequencies =
        |which: &[usize], ring: &dyn Fn(usize) -> Vec<usize>, symbol: &dyn Fn(usize) -> u32| {
            let mut counts = [[0.0f64; 2]; 2];
            for &i in which {
                for j in ring(i) {
                    counts[symbol(i) as usize][symbol(j) as usize] += 1.0;
                }
            }
            counts.map(|row| {
                let total = row[0] + row[1];
                row.map(|c| c / total)
            })
        };
    let ref_interior: Vec<usize> = (0..reference.elements().len())
        .filter(|&i| !reference.is_boundary(i))
        .collect();
    let expected = frequencies(&ref_interior, &|i| reference.ring(i).to_vec(), &|i| {
        reference.elements()[i].symbol
    });
    let neighbours = grown.neighbours();
    let interior: Vec<usize> = (0..grown.elements.len())
        .filter(|&i| {
            let p = grown.elements[i].position;
            p.x.abs() < 10.0 && p.y.abs() < 10.0
        })
        .collect();
    let found = frequencies(&interior, &|i| neighbours[i].clone(), &|i| {
        grown.elements[i].symbol
    });
    let closest = closest_pair(&positions(&grown), 1.0);
    println!(
        "stones in rows: {} elements ({} interior); share of a big stone's neighbours that are big / small \
         {:.3} / {:.3} (reference {:.3} / {:.3}), of a small stone's {:.3} / {:.3} (reference {:.3} / {:.3}); \
         closest pair {closest:.3} (r_short {:.3})",
        grown.elements.len(),
        interior.len(),
        found[0][0],
        found[0][1],
        expected[0][0],
        expected[0][1],
        found[1][0],
        found[1][1],
        expected[1][0],
        expected[1][1],
        reference.r_short()
    );
    assert!(grown.elements.len() > 500, "the region fills");
    for s in 0..2 {
        for t in 0..2 {
            assert!(
                (found[s][t] - expected[s][t]).abs() <= 0.1 * expected[s][t],
                "adjacency frequency {s}–{t} within 10 % of the reference's"
            );
        }
    }
    assert!(closest >= reference.r_short());
}

/// The nearest-neighbour distance histogram: 5 bins of 0.2 × `mean` from 0.6 × `mean` (the ends open).
fn spacing_histogram(d: &[f64], mean: f64) -> Vec<f64> {
    let bins = 5;
    let mut h = vec![0.0; bins];
    for &x in d {
        let k = ((x / mean - 0.6) / 0.2)
            .floor()
            .clamp(0.0, (bins - 1) as f64) as usize;
        h[k] += 1.0 / d.len() as f64;
    }
    h
}

#[test]
fn an_irregular_reference_keeps_its_spacing() {
    let square = rect((0.0, 0.0), (8.0, 8.0));
    let region = rect((-10.0, -10.0), (10.0, 10.0));
    let seeds = [3u64, 5, 9, 11];
    let (mut tvs, mut baselines, mut close) = (Vec::new(), Vec::new(), Vec::new());
    // the histograms of the four runs pooled, each scaled by its reference's mean spacing
    let (mut pooled_ref, mut pooled_grown) = (vec![0.0; 5], vec![0.0; 5]);
    for (k, &seed) in seeds.iter().enumerate() {
        // a Poisson-disk reference of 64 points, 0.75 m apart at least
        let points = hard_core_points(&square, 1.0, 0.75, seed);
        let reference = ReferenceArrangement::new(points.iter().map(|p| element(*p, 0)).collect())
            .expect("valid reference");
        let mut grown = grow_arrangement(
            &reference,
            &region,
            DVec2::ZERO,
            &options(RotationMode::BestFit),
        )
        .expect("grows");
        relax_arrangement(&mut grown).expect("relaxes");
        let all = positions(&grown);
        let nn_all = nearest_distances(&all);
        let nn_grown: Vec<f64> = all
            .iter()
            .zip(&nn_all)
            .filter(|(p, _)| p.x.abs() < 8.0 && p.y.abs() < 8.0)
            .map(|(_, d)| *d)
            .collect();
        let nn_ref = nearest_distances(&points);
        let mean_ref = nn_ref.iter().sum::<f64>() / nn_ref.len() as f64;
        let (h_ref, h_grown) = (
            spacing_histogram(&nn_ref, mean_ref),
            spacing_histogram(&nn_grown, mean_ref),
        );
        let tv = total_variation(&h_ref, &h_grown);
        // the same process's own spread: another Poisson-disk set of 64 points against this one
        let other = hard_core_points(&square, 1.0, 0.75, seeds[(k + 1) % seeds.len()]);
        let baseline = total_variation(
            &h_ref,
            &spacing_histogram(&nearest_distances(&other), mean_ref),
        );
        let mean_grown = nn_grown.iter().sum::<f64>() / nn_grown.len() as f64;
        println!(
            "Poisson-disk reference {seed} ({} points): grown {} elements ({} interior); nearest-neighbour distance \
             mean {mean_grown:.3} m (reference {mean_ref:.3} m); histogram {h_grown:.3?} vs {h_ref:.3?}: TV \
             {tv:.3} (another reference of the same process: {baseline:.3})",
            points.len(),
            grown.elements.len(),
            nn_grown.len()
        );
        assert!(grown.elements.len() > 300);
        tvs.push(tv);
        baselines.push(baseline);
        close.push(h_grown[0]);
        for k in 0..pooled_ref.len() {
            pooled_ref[k] += h_ref[k] / seeds.len() as f64;
            pooled_grown[k] += h_grown[k] / seeds.len() as f64;
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let pooled = total_variation(&pooled_ref, &pooled_grown);
    println!(
        "nearest-neighbour distance TV to the reference: mean {:.3} over {} references (two references of the \
         process differ by {:.3}), {pooled:.3} between the pooled histograms {pooled_grown:.3?} and \
         {pooled_ref:.3?}; elements closer than 0.8 × the reference's mean spacing {:.1} % (reference 0 %)",
        mean(&tvs),
        tvs.len(),
        mean(&baselines),
        100.0 * mean(&close)
    );
    assert!(
        pooled <= 0.1,
        "the nearest-neighbour distance distribution kept"
    );
    assert!(
        mean(&tvs) <= 0.1,
        "each reference's nearest-neighbour distances kept"
    );
    assert!(
        tvs.iter().all(|&tv| tv <= 0.12),
        "no reference's nearest-neighbour distances lost"
    );
    assert!(
        mean(&close) <= 0.05,
        "few pairs closer than the reference's"
    );
}

/// Ring-size share, mean edge length error and edge-angle TV of points with the Delaunay connectivity that
/// [`Reference::new`] builds (skewed triangles dropped), over its interior points.
fn delaunay_figures(
    points: &[DVec2],
    reference: &ReferenceArrangement,
    ring: usize,
) -> (f64, f64, f64) {
    let analysed = ReferenceArrangement::new(points.iter().map(|p| element(*p, 0)).collect())
        .expect("a triangulation");
    let interior: Vec<usize> = (0..points.len())
        .filter(|&i| !analysed.is_boundary(i))
        .collect();
    let share = interior
        .iter()
        .filter(|&&i| analysed.ring(i).len() == ring)
        .count() as f64
        / interior.len().max(1) as f64;
    let edges = analysed.edges();
    let length_error = (analysed.mean_edge() / reference.mean_edge() - 1.0).abs();
    let tv = total_variation(
        &angle_histogram(&edges, |i| points[i]),
        &angle_histogram(&reference.edges(), |i| reference.elements()[i].position),
    );
    (share, length_error, tv)
}

#[test]
fn the_arrangement_keeps_a_lattice_better_than_point_synthesis() {
    for hexagonal in [true, false] {
        let name = if hexagonal { "hexagonal" } else { "square" };
        let mut reference =
            ReferenceArrangement::new(lattice(hexagonal, 7, |_, _| 0)).expect("valid");
        if !hexagonal {
            // every diagonal the same way (seed Fig. 3), as a user leaves a square lattice
            let backward: Vec<(usize, usize)> = reference
                .edges()
                .into_iter()
                .filter(|&(a, b)| b - a == 6 && a % 7 != 0)
                .collect();
            for (a, b) in backward {
                reference.flip(a, b).expect("a diagonal flips");
            }
        }
        let ring = reference.ring(24).len();
        let region = rect((-10.0, -10.0), (10.0, 10.0));
        let grown = grown_from_centre(&reference, &region);
        let interior: Vec<usize> = (0..grown.elements.len())
            .filter(|&i| {
                let p = grown.elements[i].position;
                p.x.abs() < 8.0 && p.y.abs() < 8.0
            })
            .collect();
        let arr_share = ring_share(&reference, &grown, &interior);
        let mean_length = |edges: &[(usize, usize)], at: &dyn Fn(usize) -> DVec2| {
            edges
                .iter()
                .map(|&(a, b)| at(a).distance(at(b)))
                .sum::<f64>()
                / edges.len() as f64
        };
        let arr_length = (mean_length(&grown.edges, &|i| grown.elements[i].position)
            / reference.mean_edge()
            - 1.0)
            .abs();
        let arr_tv = total_variation(
            &angle_histogram(&grown.edges, |i| grown.elements[i].position),
            &angle_histogram(&reference.edges(), |i| reference.elements()[i].position),
        );

        let points: Vec<DVec2> = reference.elements().iter().map(|e| e.position).collect();
        let exemplar = rect((-0.5, -0.5), (7.0, if hexagonal { 5.7 } else { 6.5 }));
        let color = learn_color(
            &scene_from_points("stone", &points),
            &exemplar,
            "lattice",
            &Default::default(),
        )
        .expect("learns");
        let synthesized = synthesize(
            &Default::default(),
            &color,
            &region,
            &SynthesisOptions {
                seed: 3,
                ..Default::default()
            },
        )
        .expect("synthesizes");
        let wb: Vec<DVec2> = synthesized.instances.iter().map(|i| i.position).collect();
        let (wb_share, wb_length, wb_tv) = delaunay_figures(&wb, &reference, ring);
        println!(
            "{name} lattice exemplar: arrangement {} elements, ring size {ring} kept by {:.1} %, mean edge length \
             error {:.1} %, edge-angle TV {:.3}; WorldBrush point synthesis {} points (Delaunay), ring size {ring} \
             {:.1} %, mean edge length error {:.1} %, edge-angle TV {:.3}",
            grown.elements.len(),
            100.0 * arr_share,
            100.0 * arr_length,
            arr_tv,
            wb.len(),
            100.0 * wb_share,
            100.0 * wb_length,
            wb_tv
        );
        assert!(arr_share > wb_share, "{name}: rings kept better");
        assert!(arr_tv < wb_tv, "{name}: edge directions kept better");
    }
}
