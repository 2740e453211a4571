//! Terrain that adapts: the diffusion of height differences (thesis 4.4.2, 5.3.3) on a 1025² detailed terrain,
//! and roads embedded into it. Run with `cargo test -p worldpaint-core --release --test terrain_edit --
//! --nocapture` to see the figures.

use worldpaint_core::distance::distance_transform;
use worldpaint_core::exemplar::rough_terrain;
use worldpaint_core::geom::DVec2;
use worldpaint_core::terrain_edit::rasterize::{corridor, gradient_polyline, point, polyline};
use worldpaint_core::terrain_edit::{
    diffuse, diffuse_horizontal, embed_road, embed_roads, Constraints, DiffusionOptions,
    HorizontalConstraints, Road, RoadOptions,
};
use worldpaint_core::{Error, Heightfield};

use glam::DVec3;

/// 1025 × 1025 nodes, 1 m apart, with relief down to 3 m wavelengths.
fn terrain() -> Heightfield {
    let t = rough_terrain(1024.0, 1.0, 11);
    assert_eq!((t.nx, t.ny, t.cell), (1025, 1025, 1.0));
    t
}

/// Three curves over the terrain, each at its own height offset varying along it (raise a ridge, cut a valley,
/// tilt a shelf): a few hundred constrained cells.
fn curves(t: &Heightfield) -> Vec<Vec<DVec3>> {
    let curve = |from: DVec2, to: DVec2, bend: f64, offset: &dyn Fn(f64) -> f64| -> Vec<DVec3> {
        let normal = (to - from).perp().normalize();
        (0..=20)
            .map(|k| {
                let s = k as f64 / 20.0;
                let p = from.lerp(to, s) + normal * bend * (std::f64::consts::PI * s).sin();
                let h = t.height_at(p).unwrap_or(0.0);
                p.extend(h + offset(s))
            })
            .collect()
    };
    vec![
        curve(
            DVec2::new(200.0, 250.0),
            DVec2::new(420.0, 330.0),
            40.0,
            &|s| 8.0 * (std::f64::consts::PI * s).sin(),
        ),
        curve(
            DVec2::new(600.0, 600.0),
            DVec2::new(700.0, 820.0),
            -30.0,
            &|s| -5.0 + 2.0 * s,
        ),
        curve(
            DVec2::new(250.0, 750.0),
            DVec2::new(330.0, 700.0),
            10.0,
            &|_| 3.0,
        ),
    ]
}

/// Largest `|mean of the 4 neighbours − D|` over the free cells, recomputed from the map.
fn laplace_residual(d: &[f64], fixed: &[bool], nx: usize, ny: usize) -> f64 {
    let mut worst = 0.0f64;
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if fixed[k] {
                continue;
            }
            let mut n = Vec::with_capacity(4);
            if i > 0 {
                n.push(d[k - 1]);
            }
            if i + 1 < nx {
                n.push(d[k + 1]);
            }
            if j > 0 {
                n.push(d[k - nx]);
            }
            if j + 1 < ny {
                n.push(d[k + nx]);
            }
            worst = worst.max((n.iter().sum::<f64>() / n.len() as f64 - d[k]).abs());
        }
    }
    worst
}

/// Separable box blur of radius `r` cells (clamped at the border).
fn blur(h: &[f64], nx: usize, ny: usize, r: usize) -> Vec<f64> {
    let pass = |src: &[f64], stride: usize, step: usize, len: usize, lines: usize| {
        let mut out = vec![0.0; src.len()];
        for line in 0..lines {
            for q in 0..len {
                let (a, b) = (q.saturating_sub(r), (q + r).min(len - 1));
                let s: f64 = (a..=b).map(|x| src[line * stride + x * step]).sum();
                out[line * stride + q * step] = s / (b - a + 1) as f64;
            }
        }
        out
    };
    let rows = pass(h, nx, 1, nx, ny);
    pass(&rows, 1, nx, ny, nx)
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    ab / (aa * bb).sqrt()
}

#[test]
fn diffusion_meets_constraints_keeps_detail_and_stays_within_the_falloff() {
    let t = terrain();
    let (nx, ny) = (t.nx, t.ny);
    let mut c = Constraints::for_terrain(&t);
    let mut wanted: Vec<(usize, f64)> = Vec::new();
    let curves = curves(&t);
    for curve in &curves {
        polyline(&mut c, &t, curve).expect("curve on the terrain");
    }
    for k in 0..nx * ny {
        if let Some(v) = c.get(k % nx, k / nx) {
            wanted.push((k, t.heights[k] as f64 + v));
        }
    }
    let count = c.count();
    assert!(
        (200..1000).contains(&count),
        "{count} constrained cells: not a few hundred"
    );
    let falloff = 120.0;
    let options = DiffusionOptions {
        falloff: Some(falloff),
        tolerance: 1e-7,
        max_cycles: 100,
    };
    let d = diffuse(&c, &options).expect("diffusion");
    let edited = d.apply(&t).expect("same grid");
    // the default, looser tolerance against this one: how far a small residual leaves D from the solution
    let loose = diffuse(
        &c,
        &DiffusionOptions {
            falloff: Some(falloff),
            ..Default::default()
        },
    )
    .expect("diffusion");
    let loose_error = loose
        .displacement
        .iter()
        .zip(&d.displacement)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);

    // constrained cells are met
    let constraint_error = wanted
        .iter()
        .map(|(k, z)| (edited.heights[*k] as f64 - z).abs())
        .fold(0.0, f64::max);
    // the discrete Laplace equation holds on the free cells inside the falloff
    let mask = c.mask();
    let distance = distance_transform(nx, ny, t.cell, &mask);
    let fixed: Vec<bool> = mask
        .iter()
        .zip(&distance)
        .map(|(m, dist)| *m || (*dist as f64) > falloff)
        .collect();
    let residual = laplace_residual(&d.displacement, &fixed, nx, ny);
    // nothing moves beyond the falloff
    let beyond = (0..nx * ny)
        .filter(|k| (distance[*k] as f64) > falloff)
        .map(|k| (edited.heights[k] - t.heights[k]).abs() as f64)
        .fold(0.0, f64::max);
    // the detail survives: high-pass (terrain minus its 5×5 blur) before and after, outside the corridors
    let before: Vec<f64> = t.heights.iter().map(|h| *h as f64).collect();
    let after: Vec<f64> = edited.heights.iter().map(|h| *h as f64).collect();
    let (bb, ba) = (blur(&before, nx, ny, 2), blur(&after, nx, ny, 2));
    let corridor_radius = 4.0;
    let moved: Vec<usize> = (0..nx * ny)
        .filter(|k| {
            let dist = distance[*k] as f64;
            dist > corridor_radius && dist <= falloff
        })
        .collect();
    let hp_before: Vec<f64> = moved.iter().map(|k| before[*k] - bb[*k]).collect();
    let hp_after: Vec<f64> = moved.iter().map(|k| after[*k] - ba[*k]).collect();
    let r = correlation(&hp_before, &hp_after);
    // for contrast: how much the terrain itself changed there (so the correlation is not trivially 1)
    let change = moved
        .iter()
        .map(|k| (after[*k] - before[*k]).abs())
        .fold(0.0, f64::max);
    let hp_rms = (hp_before.iter().map(|x| x * x).sum::<f64>() / hp_before.len() as f64).sqrt();

    println!(
        "diffusion 1025²: {count} constrained cells, {} cells solved, {} PCG iterations (V-cycle preconditioned)",
        d.solved_cells, d.cycles
    );
    println!(
        "  residual (max |mean of neighbours − D|): solver {:.2e} m, recomputed {:.2e} m, tolerance {:.2e} m",
        d.residual, residual, d.tolerance
    );
    println!("  max error at constrained cells {constraint_error:.2e} m");
    println!(
        "  default tolerance ({:.2e} m, {} iterations): D within {loose_error:.2e} m of the tight solution",
        loose.tolerance, loose.cycles
    );
    println!("  max change beyond the {falloff} m falloff {beyond:.2e} m");
    println!(
        "  high-pass correlation outside the corridors ({} cells, up to {change:.2} m moved, high-pass rms {hp_rms:.3} m): {r:.5}",
        moved.len()
    );
    assert!(d.converged);
    assert!(constraint_error < 1e-3);
    assert!(
        loose.converged && loose_error < 1e-3,
        "default tolerance leaves D {loose_error} m off"
    );
    assert!(residual <= 1e-6, "Laplace residual {residual}");
    assert!(beyond < 1e-3);
    assert!(change > 1.0, "the edit hardly moved the terrain");
    assert!(r > 0.99, "high-pass correlation {r}");
}

#[test]
fn diffusion_does_not_depend_on_the_thread_count() {
    let t = rough_terrain(256.0, 1.0, 5);
    let mut c = Constraints::for_terrain(&t);
    let z = t.height_at(DVec2::new(100.0, 100.0)).unwrap_or(0.0);
    polyline(
        &mut c,
        &t,
        &[
            DVec3::new(40.0, 60.0, z + 4.0),
            DVec3::new(200.0, 150.0, z - 3.0),
        ],
    )
    .expect("curve");
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        pool.install(|| diffuse(&c, &DiffusionOptions::default()).expect("diffusion"))
    };
    let (one, two, four) = (run(1), run(2), run(4));
    assert_eq!(one.displacement, two.displacement);
    assert_eq!(one.displacement, four.displacement);
    assert_eq!(one.cycles, four.cycles);
}

#[test]
fn bad_input_is_refused_with_a_message() {
    let t = rough_terrain(64.0, 1.0, 1);
    let mut c = Constraints::for_terrain(&t);
    assert!(matches!(c.set(3, 3, f64::NAN), Err(Error::InvalidInput(_))));
    assert!(matches!(c.set(999, 3, 1.0), Err(Error::InvalidInput(_))));
    assert!(polyline(&mut c, &t, &[]).is_err());
    assert!(polyline(&mut c, &t, &[DVec3::new(f64::NAN, 1.0, 1.0)]).is_err());
    assert!(corridor(&mut c, &t, &[DVec3::new(5.0, 5.0, 1.0)], 0.0).is_err());
    // off the terrain: skipped, not an error
    assert_eq!(
        point(&mut c, &t, DVec3::new(-50.0, 5.0, 1.0)).ok(),
        Some(false)
    );
    let bad = DiffusionOptions {
        tolerance: f64::NAN,
        ..Default::default()
    };
    assert!(diffuse(&c, &bad).is_err());
    // nothing to diffuse: nothing moves
    let none = diffuse(&Constraints::for_terrain(&t), &DiffusionOptions::default()).expect("empty");
    assert!(none.displacement.iter().all(|d| *d == 0.0));
    let road = |centreline: Vec<DVec2>, width: f64| Road {
        centreline,
        heights: None,
        width,
        bank_width: 5.0,
    };
    let opts = RoadOptions::default();
    let line = vec![DVec2::new(10.0, 10.0), DVec2::new(50.0, 30.0)];
    for bad in [
        road(line.clone(), 0.0),
        road(line.clone(), f64::NAN),
        road(vec![DVec2::new(10.0, 10.0)], 4.0),
        road(vec![DVec2::new(10.0, 10.0), DVec2::new(10.0, 10.0)], 4.0),
        road(vec![DVec2::new(10.0, 10.0), DVec2::new(90.0, 30.0)], 4.0),
        road(
            vec![DVec2::new(10.0, 10.0), DVec2::new(f64::NAN, 30.0)],
            4.0,
        ),
    ] {
        match embed_road(&t, &bad, &opts) {
            Err(Error::InvalidInput(msg)) => assert!(msg.starts_with("road 0"), "{msg}"),
            other => panic!("accepted a bad road: {:?}", other.map(|e| e.profiles.len())),
        }
    }
    let unchanged = embed_roads(&t, &[], &opts).expect("no road");
    assert_eq!(unchanged.terrain.heights, t.heights);
}

#[test]
fn gradient_and_horizontal_constraints() {
    let t = rough_terrain(128.0, 1.0, 2);
    let mut c = Constraints::for_terrain(&t);
    let z = 30.0;
    let ridge = [DVec3::new(20.0, 64.0, z), DVec3::new(108.0, 64.0, z)];
    gradient_polyline(&mut c, &t, &ridge, -0.5, -0.5).expect("ridge");
    let d = diffuse(
        &c,
        &DiffusionOptions {
            falloff: Some(30.0),
            ..Default::default()
        },
    )
    .expect("diffusion");
    let e = d.apply(&t).expect("grid");
    // along the ridge, and half a metre lower one cell to each side
    for x in [30usize, 64, 100] {
        let at = |j: usize| e.heights[j * t.nx + x] as f64;
        assert!((at(64) - z).abs() < 1e-3, "ridge at {}", at(64));
        assert!((at(65) - (z - 0.5)).abs() < 1e-3, "left side {}", at(65));
        assert!((at(63) - (z - 0.5)).abs() < 1e-3, "right side {}", at(63));
    }

    let mut hc = HorizontalConstraints::for_terrain(&t);
    let shift = DVec2::new(3.0, 0.0);
    hc.polyline(
        t.origin,
        &[DVec2::new(64.0, 20.0), DVec2::new(64.0, 108.0)],
        shift,
    )
    .expect("curve");
    let hd = diffuse_horizontal(
        &hc,
        &DiffusionOptions {
            falloff: Some(20.0),
            ..Default::default()
        },
    )
    .expect("diffusion");
    let k = 64 * t.nx + 64;
    assert!((hd.x.displacement[k] - 3.0).abs() < 1e-12);
    assert!(hd.y.displacement[k].abs() < 1e-12);
    // the relief at the curve now comes from 3 m to its west
    let moved = hd.apply(&t).expect("grid");
    let expected = t.height_at(DVec2::new(61.0, 64.0)).unwrap_or(f64::NAN);
    assert!((moved.heights[k] as f64 - expected).abs() < 1e-3);
    // far from the curve nothing moves
    assert_eq!(moved.heights[64 * t.nx + 10], t.heights[64 * t.nx + 10]);
}

/// Cross-slope, longitudinal steps and the bank fit of embedded roads.
#[test]
fn roads_are_level_across_smooth_along_and_banked_into_the_slope() {
    let t = terrain();
    let (width, bank) = (6.0, 12.0);
    // a winding road over the hill's flank and a straight one across the rolling land, apart from each other
    let winding: Vec<DVec2> = (0..=40)
        .map(|k| {
            let s = k as f64 / 40.0;
            DVec2::new(
                380.0 + 360.0 * s,
                420.0 + 60.0 * (std::f64::consts::TAU * s).sin(),
            )
        })
        .collect();
    let straight = vec![DVec2::new(200.0, 150.0), DVec2::new(900.0, 260.0)];
    let roads: Vec<Road> = [winding, straight]
        .into_iter()
        .map(|centreline| Road {
            centreline,
            heights: None,
            width,
            bank_width: bank,
        })
        .collect();
    let e = embed_roads(&t, &roads, &RoadOptions::default()).expect("roads on the terrain");
    let h = &e.terrain;
    println!(
        "roads on 1025²: {} PCG iterations, residual {:.2e} m (tolerance {:.2e} m), {} cells solved",
        e.diffusion.cycles, e.diffusion.residual, e.diffusion.tolerance, e.diffusion.solved_cells
    );
    assert!(e.diffusion.converged);
    for (r, prof) in e.profiles.iter().enumerate() {
        let pts = &prof.points;
        let mut cross: f64 = 0.0;
        let mut on_profile: f64 = 0.0;
        let mut cut_fill: f64 = 0.0;
        let length = prof.s.last().copied().unwrap_or(0.0);
        for (k, p) in pts.iter().enumerate() {
            let s = prof.s[k];
            if s < width || s > length - width {
                continue; // the road's ends are not across-level by the nearest-point rule
            }
            let (a, b) = (pts[k.saturating_sub(1)], pts[(k + 1).min(pts.len() - 1)]);
            let n = (b - a).truncate().normalize().perp();
            let half = 0.5 * width - t.cell;
            let c = p.truncate();
            let left = h.height_at(c + n * half).expect("on terrain");
            let right = h.height_at(c - n * half).expect("on terrain");
            let centre = h.height_at(c).expect("on terrain");
            cross = cross.max((left - right).abs() / (2.0 * half));
            on_profile = on_profile.max((centre - p.z).abs());
            cut_fill = cut_fill.max((p.z - t.height_at(c).unwrap_or(p.z)).abs());
        }
        // along the centreline, every 10 cm
        let mut step: f64 = 0.0;
        let mut grade_change: f64 = 0.0;
        let mut prev: Option<(f64, Option<f64>)> = None;
        for w in pts.windows(2) {
            for q in 0..5 {
                let c = w[0].truncate().lerp(w[1].truncate(), q as f64 / 5.0);
                let z = h.height_at(c).expect("on terrain");
                if let Some((pz, pg)) = prev {
                    let dz = z - pz;
                    step = step.max(dz.abs());
                    let g = dz / (0.2 * w[0].truncate().distance(w[1].truncate()));
                    if let Some(pg) = pg {
                        grade_change = grade_change.max((g - pg).abs());
                    }
                    prev = Some((z, Some(g)));
                } else {
                    prev = Some((z, None));
                }
            }
        }
        println!(
            "  road {r}: {length:.0} m, cut/fill up to {cut_fill:.2} m; max cross-slope {:.3} %, max step between samples 10 cm apart {:.2} cm, max grade change between them {:.3} %, max centre off profile {:.1e} m",
            100.0 * cross,
            100.0 * step,
            100.0 * grade_change,
            on_profile
        );
        assert!(cut_fill > 0.5, "road {r} barely needed cut or fill");
        assert!(cross < 0.02, "road {r}: cross-slope {cross}");
        assert!(step < 0.05, "road {r}: step {step} m");
        assert!(
            on_profile < 0.01,
            "road {r}: centre {on_profile} m off its profile"
        );
    }
    // banks: beyond half the width plus the bank width the terrain is natural; inside, the change fades out
    let (nx, ny) = (t.nx, t.ny);
    let dist_to = |p: DVec2| {
        e.profiles
            .iter()
            .map(|prof| {
                prof.points
                    .windows(2)
                    .map(|w| {
                        worldpaint_core::geom::segment_distance(p, w[0].truncate(), w[1].truncate())
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (mut beyond, mut outer_ring, mut max_d): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let (mut bank_slope, mut bank_cells) = (0.0f64, 0usize);
    for j in 100..500 {
        for i in 150..950 {
            let k = j * nx + i;
            let p = DVec2::new(i as f64, j as f64);
            let dist = dist_to(p);
            if dist > 0.5 * width + bank + 4.0 * t.cell {
                continue;
            }
            let change = (h.heights[k] - t.heights[k]) as f64;
            max_d = max_d.max(change.abs());
            if dist > 0.5 * width + bank {
                beyond = beyond.max(change.abs());
            } else if dist > 0.5 * width + bank - t.cell {
                outer_ring = outer_ring.max(change.abs());
            }
            if dist > 0.5 * width + t.cell && dist < 0.5 * width + bank && i + 1 < nx && j + 1 < ny
            {
                let dx = (h.heights[k + 1] - t.heights[k + 1]) as f64 - change;
                let dy = (h.heights[k + nx] - t.heights[k + nx]) as f64 - change;
                bank_slope = bank_slope.max((dx * dx + dy * dy).sqrt() / t.cell);
                bank_cells += 1;
            }
        }
    }
    println!(
        "  banks ({bank_cells} cells): max change beyond the banks {beyond:.1e} m, in their outer metre {outer_ring:.3} m (largest change {max_d:.2} m), steepest added slope {:.1} %",
        100.0 * bank_slope
    );
    assert!(beyond < 1e-3);
    // over the bank width the change fades: its last metre holds at most a few cells' share of it
    assert!(
        outer_ring < max_d * 3.0 * t.cell / bank,
        "bank edge {outer_ring}"
    );
    assert!(bank_slope < 3.0 * max_d / bank, "bank slope {bank_slope}");
    let _ = ny;
}

#[test]
fn where_roads_cross_the_first_keeps_its_heights() {
    let t = rough_terrain(256.0, 1.0, 4);
    let a = Road {
        centreline: vec![DVec2::new(20.0, 128.0), DVec2::new(236.0, 128.0)],
        heights: Some(vec![40.0, 40.0]),
        width: 6.0,
        bank_width: 8.0,
    };
    let b = Road {
        centreline: vec![DVec2::new(128.0, 20.0), DVec2::new(128.0, 236.0)],
        heights: Some(vec![30.0, 50.0]),
        ..a.clone()
    };
    let e = embed_roads(&t, &[a, b], &RoadOptions::default()).expect("roads");
    let at = |x: f64, y: f64| e.terrain.height_at(DVec2::new(x, y)).unwrap_or(f64::NAN);
    assert!((at(128.0, 128.0) - 40.0).abs() < 1e-3);
    assert!((at(128.0, 130.0) - 40.0).abs() < 1e-3);
    // away from the crossing the second road follows its own profile
    assert!((at(128.0, 60.0) - (30.0 + 20.0 * 40.0 / 216.0)).abs() < 1e-3);
}
