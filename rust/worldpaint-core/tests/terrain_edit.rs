//! Terrain that adapts: the diffusion of height differences (thesis 4.4.2, 5.3.3) on a 1025² detailed terrain,
//! and roads embedded into it. Run with `cargo test -p worldpaint-core --release --test terrain_edit --
//! --nocapture` to see the figures.

use worldpaint_core::{
    diffuse, diffuse_horizontal, distance_transform, embed_road, embed_roads, laplace_residual,
    rasterize_corridor, rasterize_gradient_polyline, rasterize_point, rasterize_polyline,
    rough_terrain, Constraints, DVec2, DiffusionOptions, EmbeddedRoad, Error, Heightfield,
    HorizontalConstraints, RoadEmbedding, RoadEmbeddingOptions, RoadProfile,
};

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

/// The default diffusion options with a falloff of `falloff` metres.
fn within(falloff: f64) -> DiffusionOptions {
    DiffusionOptions {
        falloff: Some(falloff),
        ..Default::default()
    }
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
        rasterize_polyline(&mut c, &t, curve).expect("curve on the terrain");
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
    let loose = diffuse(&c, &within(falloff)).expect("diffusion");
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
    let residual = laplace_residual(&d.displacement, nx, ny, |k| !fixed[k]);
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
    rasterize_polyline(
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
    assert!(matches!(
        c.set(3, 3, f64::NAN),
        Err(Error::OutOfRange { .. })
    ));
    assert!(matches!(c.set(999, 3, 1.0), Err(Error::Invalid { .. })));
    assert!(rasterize_polyline(&mut c, &t, &[]).is_err());
    assert!(rasterize_polyline(&mut c, &t, &[DVec3::new(f64::NAN, 1.0, 1.0)]).is_err());
    assert!(rasterize_corridor(&mut c, &t, &[DVec3::new(5.0, 5.0, 1.0)], 0.0).is_err());
    // off the terrain: skipped, not an error
    assert_eq!(
        rasterize_point(&mut c, &t, DVec3::new(-50.0, 5.0, 1.0)).ok(),
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
    let road = |centreline: Vec<DVec2>, width: f64| EmbeddedRoad {
        centreline,
        heights: None,
        width,
        bank_width: 5.0,
    };
    let opts = RoadEmbeddingOptions::default();
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
            Err(e @ Error::Invalid { .. } | e @ Error::OutOfRange { .. }) => {
                let msg = e.reason();
                assert!(msg.starts_with("road 0"), "{msg}");
            }
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
    rasterize_gradient_polyline(&mut c, &t, &ridge, -0.5, -0.5).expect("ridge");
    let d = diffuse(&c, &within(30.0)).expect("diffusion");
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
    let hd = diffuse_horizontal(&hc, &within(20.0)).expect("diffusion");
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
    let roads: Vec<EmbeddedRoad> = [winding, straight]
        .into_iter()
        .map(|centreline| EmbeddedRoad {
            centreline,
            heights: None,
            width,
            bank_width: bank,
        })
        .collect();
    let e =
        embed_roads(&t, &roads, &RoadEmbeddingOptions::default()).expect("roads on the terrain");
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
                    .map(|w| worldpaint_core::segment_distance(p, w[0].truncate(), w[1].truncate()))
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
    let a = EmbeddedRoad {
        centreline: vec![DVec2::new(20.0, 128.0), DVec2::new(236.0, 128.0)],
        heights: Some(vec![40.0, 40.0]),
        width: 6.0,
        bank_width: 8.0,
    };
    // 2 m above the first road where they cross
    let b = EmbeddedRoad {
        centreline: vec![DVec2::new(128.0, 20.0), DVec2::new(128.0, 236.0)],
        heights: Some(vec![32.0, 52.0]),
        ..a.clone()
    };
    let e = embed_roads(&t, &[a, b], &RoadEmbeddingOptions::default()).expect("roads");
    let at = |x: f64, y: f64| e.terrain.height_at(DVec2::new(x, y)).unwrap_or(f64::NAN);
    assert!((at(128.0, 128.0) - 40.0).abs() < 1e-3);
    assert!((at(128.0, 130.0) - 40.0).abs() < 1e-3);
    // the second road meets it: its profile is level with it across the first carriageway, and leaves it gently
    for y in [125.0, 131.0] {
        let (_, z) = nearest_on_profile(&e.profiles[1], DVec2::new(128.0, y));
        assert!((z - 40.0).abs() < 1e-3, "second road at {y} m: {z} m");
    }
    assert!((at(128.0, 124.0) - 40.0).abs() < 0.02);
    assert!((at(128.0, 132.0) - 40.0).abs() < 0.02);
    // and away from the crossing (beyond 6 m + 37.5 m of blend) follows its own heights
    let own = |y: f64| 32.0 + 20.0 * (y - 20.0) / 216.0;
    assert!((at(128.0, 60.0) - own(60.0)).abs() < 1e-3);
    assert!((at(128.0, 200.0) - own(200.0)).abs() < 1e-3);
    let (step, _) = largest_step(&e.terrain, &e.profiles[1], 0.0, &|_| true);
    let grade = e.profiles[1]
        .points
        .windows(2)
        .zip(e.profiles[1].s.windows(2))
        .map(|(p, s)| ((p[1].z - p[0].z) / (s[1] - s[0])).abs())
        .fold(0.0, f64::max);
    println!(
        "user heights 2 m above a crossing road: largest step along the second road {:.2} cm, steepest grade {:.1} % (its own {:.1} %)",
        100.0 * step,
        100.0 * grade,
        100.0 * 20.0 / 216.0
    );
    assert!(step < 0.05);
    // the blend adds at most 8 % to the grade, beyond going from the first road's grade (0) to its own and
    // overshooting that by a third
    let own_grade = 20.0 / 216.0;
    assert!(grade < own_grade * 4.0 / 3.0 + 0.08 + 1e-3, "grade {grade}");
}

/// The slope's frame: `u` along the contour, `v` up the slope (m), centred on the middle of the 256 m terrain and
/// turned 0.4 rad from the grid, so that the roads cross the grid's rows and columns at an angle.
fn on_slope(u: f64, v: f64) -> DVec2 {
    let (sin, cos) = 0.4f64.sin_cos();
    DVec2::new(128.0 + cos * u - sin * v, 128.0 + sin * u + cos * v)
}

/// A 256 m terrain sloping up 12 % along `v`, with spurs and gullies running down it (2 m high, 40 m apart, spur
/// crests on u = 0 and ±40 m) and a little fine relief: a road along the contour smooths the spurs away, a road down
/// a crest keeps it, so their natural profiles differ where they cross.
fn spur_slope() -> Heightfield {
    let n = 257;
    let (sin, cos) = 0.4f64.sin_cos();
    let heights = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            let (u, v) = (
                cos * (x - 128.0) + sin * (y - 128.0),
                -sin * (x - 128.0) + cos * (y - 128.0),
            );
            (20.0
                + 0.12 * v
                + 2.0 * (std::f64::consts::TAU * u / 40.0).cos()
                + 0.15 * (x / 3.1 + 0.7 * y / 2.3).sin()
                + 0.1 * (y / 4.3 - x / 5.7).cos()) as f32
        })
        .collect();
    match Heightfield::new(DVec2::ZERO, 1.0, n, n, heights) {
        Ok(t) => t,
        Err(e) => panic!("spur slope: {e}"),
    }
}

/// A road of the junction tests through points given in the slope's frame: 6 m carriageway, 10 m banks.
fn junction_road(points: &[(f64, f64)]) -> EmbeddedRoad {
    EmbeddedRoad {
        centreline: points.iter().map(|(u, v)| on_slope(*u, *v)).collect(),
        heights: None,
        width: 6.0,
        bank_width: 10.0,
    }
}

/// The distance from `p` to a profile's centreline and the profile's height at the nearest point (in plan).
fn nearest_on_profile(prof: &RoadProfile, p: DVec2) -> (f64, f64) {
    let mut best = (f64::INFINITY, f64::NAN);
    for w in prof.points.windows(2) {
        let (a, b) = (w[0].truncate(), w[1].truncate());
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
        let d = (a + ab * t).distance(p);
        if d < best.0 {
            best = (d, w[0].z + t * (w[1].z - w[0].z));
        }
    }
    best
}

/// Points along a profile's centreline every `spacing` metres, with their distance along the road.
fn along(prof: &RoadProfile, spacing: f64) -> Vec<(f64, DVec2)> {
    let length = prof.s.last().copied().unwrap_or(0.0);
    let mut out = Vec::new();
    let mut k = 0;
    let mut s = 0.0;
    while s <= length {
        while k + 2 < prof.s.len() && prof.s[k + 1] < s {
            k += 1;
        }
        let (a, b) = (prof.points[k].truncate(), prof.points[k + 1].truncate());
        let span = (prof.s[k + 1] - prof.s[k]).max(1e-12);
        out.push((s, a.lerp(b, ((s - prof.s[k]) / span).clamp(0.0, 1.0))));
        s += spacing;
    }
    out
}

/// The largest height step of the terrain between consecutive points 10 cm apart along a road's centreline shifted
/// `offset` metres to its left, and the distance along the road where it is; over the points for which `keep` holds.
fn largest_step(
    h: &Heightfield,
    prof: &RoadProfile,
    offset: f64,
    keep: &dyn Fn(DVec2) -> bool,
) -> (f64, f64) {
    let mut worst = (0.0f64, 0.0);
    let mut prev: Option<f64> = None;
    let points = along(prof, 0.1);
    for (q, (s, p)) in points.iter().enumerate() {
        let (a, b) = (
            points[q.saturating_sub(1)].1,
            points[(q + 1).min(points.len() - 1)].1,
        );
        let p = *p + (b - a).normalize_or_zero().perp() * offset;
        if !keep(p) {
            prev = None;
            continue;
        }
        let z = h.height_at(p).unwrap_or(f64::NAN);
        if let Some(pz) = prev {
            let step = (z - pz).abs();
            if step.is_nan() || step > worst.0 {
                worst = (step, *s);
            }
        }
        prev = Some(z);
    }
    worst
}

/// The largest cross-slope of a road's carriageway, measured as the roads test does (terrain heights half a width
/// less a cell either side of the centreline, at every profile sample a width or more from the road's ends): over
/// the samples outside the junction squares and over those within. A sample is within a junction square when it
/// lies within half a width of another road's centreline, or of its own more than three widths along it, plus the
/// cell that a bilinear sample of the terrain reads beyond.
fn cross_slopes(h: &Heightfield, r: usize, profiles: &[RoadProfile], widths: &[f64]) -> (f64, f64) {
    let (mut outside, mut inside) = (0.0f64, 0.0f64);
    let prof = &profiles[r];
    let pts = &prof.points;
    let length = prof.s.last().copied().unwrap_or(0.0);
    for (k, p) in pts.iter().enumerate() {
        let s = prof.s[k];
        if s < widths[r] || s > length - widths[r] {
            continue;
        }
        let (a, b) = (pts[k.saturating_sub(1)], pts[(k + 1).min(pts.len() - 1)]);
        let n = (b - a).truncate().normalize().perp();
        let half = 0.5 * widths[r] - h.cell;
        let c = p.truncate();
        let left = h.height_at(c + n * half).unwrap_or(f64::NAN);
        let right = h.height_at(c - n * half).unwrap_or(f64::NAN);
        let slope = (left - right).abs() / (2.0 * half);
        let margin = h.cell * std::f64::consts::SQRT_2;
        let in_square = profiles
            .iter()
            .zip(widths)
            .enumerate()
            .any(|(q, (other, w))| q != r && nearest_on_profile(other, c).0 <= 0.5 * w + margin)
            || pts.iter().zip(&prof.s).any(|(o, so)| {
                (so - s).abs() > 3.0 * widths[r]
                    && o.truncate().distance(c) <= 0.5 * widths[r] + margin
            });
        if in_square {
            inside = inside.max(slope);
        } else if slope.is_nan() || slope > outside {
            outside = slope;
        }
    }
    (outside, inside)
}

/// Embeds the roads with the default options.
fn embed(t: &Heightfield, roads: &[EmbeddedRoad]) -> RoadEmbedding {
    match embed_roads(t, roads, &RoadEmbeddingOptions::default()) {
        Ok(e) => e,
        Err(e) => panic!("roads on the terrain: {e}"),
    }
}

/// Prints the steps along every road (all along it and near the other roads), the steps along its carriageway's edges
/// near the other roads, and the cross-slopes outside and within the junction squares; returns the failures.
fn junction_figures(label: &str, t: &Heightfield, roads: &[EmbeddedRoad]) -> Vec<String> {
    let e = embed(t, roads);
    let mut failures = Vec::new();
    if !e.diffusion.converged {
        failures.push(format!("{label}: diffusion did not converge"));
    }
    let widths: Vec<f64> = roads.iter().map(|r| r.width).collect();
    for (r, prof) in e.profiles.iter().enumerate() {
        let near_others = |p: DVec2| {
            e.profiles
                .iter()
                .enumerate()
                .any(|(q, other)| q != r && nearest_on_profile(other, p).0 <= 20.0)
        };
        let (step, at) = largest_step(&e.terrain, prof, 0.0, &|_| true);
        let (near_step, near_at) = largest_step(&e.terrain, prof, 0.0, &near_others);
        let edge = 0.5 * widths[r] - 0.5 * t.cell;
        let (left, _) = largest_step(&e.terrain, prof, edge, &near_others);
        let (right, _) = largest_step(&e.terrain, prof, -edge, &near_others);
        let (cross, in_square) = cross_slopes(&e.terrain, r, &e.profiles, &widths);
        println!(
            "  {label}, road {r} ({:.0} m): largest step between samples 10 cm apart {:.2} cm (at {at:.1} m), within 20 m of another road {:.2} cm (at {near_at:.1} m), along its edges there {:.2} cm; cross-slope {:.2} % outside the junction squares, {:.2} % within them",
            prof.s.last().copied().unwrap_or(0.0),
            100.0 * step,
            100.0 * near_step,
            100.0 * left.max(right),
            100.0 * cross,
            100.0 * in_square
        );
        if step.is_nan() || step >= 0.05 {
            failures.push(format!("{label}, road {r}: step {step} m at {at} m"));
        }
        if cross.is_nan() || cross >= 0.02 {
            failures.push(format!("{label}, road {r}: cross-slope {cross}"));
        }
    }
    failures
}

#[test]
fn roads_that_cross_on_a_slope_meet_without_a_step() {
    let t = spur_slope();
    let crossing = on_slope(0.0, 0.0);
    let contour = junction_road(&[(-100.0, 0.0), (100.0, 0.0)]);
    let down = junction_road(&[(0.0, -100.0), (0.0, 100.0)]);
    let natural = |road: &EmbeddedRoad| {
        nearest_on_profile(&embed(&t, std::slice::from_ref(road)).profiles[0], crossing).1
    };
    let (zc, zd) = (natural(&contour), natural(&down));
    println!(
        "crossing on a 12 % slope with spurs: natural profiles at the crossing {zc:.2} m (along the contour), {zd:.2} m (down the spur), {:.2} m apart",
        zd - zc
    );
    assert!(
        (zd - zc).abs() >= 1.0,
        "natural profiles only {} m apart",
        zd - zc
    );
    let mut failures = Vec::new();
    for (label, roads) in [
        ("contour road first", [contour.clone(), down.clone()]),
        ("road down the slope first", [down.clone(), contour.clone()]),
    ] {
        failures.extend(junction_figures(label, &t, &roads));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn a_road_ending_on_another_meets_it_without_a_step() {
    let t = spur_slope();
    // the through road along the contour; one side road comes up a spur crest and ends on its centreline, another
    // comes down the next crest and ends at its far edge
    let through = junction_road(&[(-100.0, 0.0), (100.0, 0.0)]);
    let from_below = junction_road(&[(-40.0, -100.0), (-40.0, 0.0)]);
    let from_above = junction_road(&[(40.0, 100.0), (40.0, 3.0)]);
    let mut failures = Vec::new();
    for (label, roads) in [
        (
            "T-junctions, through road first",
            [through.clone(), from_below.clone(), from_above.clone()],
        ),
        (
            "T-junctions, side roads first",
            [from_below.clone(), from_above.clone(), through.clone()],
        ),
    ] {
        failures.extend(junction_figures(label, &t, &roads));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn a_road_meeting_several_roads_and_one_crossing_itself_stay_smooth() {
    let t = spur_slope();
    // three roads along the contour, two of them 18 m apart (closer than their blends), crossed by one down a gully
    let ladder = [-60.0, -42.0, 20.0].map(|v| junction_road(&[(0.0, v), (100.0, v)]));
    let across = junction_road(&[(60.0, -90.0), (60.0, 90.0)]);
    // a road that loops back across itself, and a ring that closes on its start
    let lasso = junction_road(&[
        (-95.0, 60.0),
        (-20.0, 60.0),
        (-20.0, 85.0),
        (-50.0, 85.0),
        (-50.0, 40.0),
    ]);
    let ring_points: Vec<(f64, f64)> = (0..=24)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 24.0;
            (-60.0 + 25.0 * a.cos(), -60.0 + 25.0 * a.sin())
        })
        .collect();
    let ring = junction_road(&ring_points);
    let roads: Vec<EmbeddedRoad> = ladder
        .iter()
        .cloned()
        .chain([across, lasso, ring])
        .collect();
    let failures = junction_figures("ladder, lasso and ring", &t, &roads);
    let e = embed(&t, &roads);
    assert!(e
        .profiles
        .iter()
        .all(|p| p.points.iter().all(|q| q.is_finite())));
    // where the lasso crosses itself its two passes are at one height: the sample of the second pass nearest to the
    // first against the first at its nearest point
    let prof = &e.profiles[4];
    let half = prof
        .s
        .partition_point(|s| *s < 0.5 * prof.s.last().copied().unwrap_or(0.0));
    let first_pass = RoadProfile {
        points: prof.points[..half].to_vec(),
        s: prof.s[..half].to_vec(),
    };
    let (gap, first, second) = prof.points[half..]
        .iter()
        .map(|p| {
            let (d, z) = nearest_on_profile(&first_pass, p.truncate());
            (d, z, p.z)
        })
        .fold((f64::INFINITY, f64::NAN, f64::NAN), |a, b| {
            if b.0 < a.0 {
                b
            } else {
                a
            }
        });
    println!(
        "  the lasso's passes where it crosses itself ({gap:.2} m apart in plan): {first:.3} m and {second:.3} m ({:.2} cm apart)",
        100.0 * (first - second).abs()
    );
    assert!((first - second).abs() < 0.01);
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn the_road_given_first_keeps_its_carriageway() {
    let t = spur_slope();
    let contour = junction_road(&[(-100.0, 0.0), (100.0, 0.0)]);
    let down = junction_road(&[(0.0, -100.0), (0.0, 100.0)]);
    let side = junction_road(&[(-40.0, -100.0), (-40.0, 0.0)]);
    let alone = embed(&t, std::slice::from_ref(&contour));
    let together = embed(&t, &[contour, down, side]);
    let profile_change = alone.profiles[0]
        .points
        .iter()
        .zip(&together.profiles[0].points)
        .map(|(a, b)| (a.z - b.z).abs())
        .fold(0.0, f64::max);
    let ground_change = along(&alone.profiles[0], 0.1)
        .iter()
        .map(|(_, p)| {
            let a = alone.terrain.height_at(*p).unwrap_or(f64::NAN);
            let b = together.terrain.height_at(*p).unwrap_or(f64::NAN);
            (a - b).abs()
        })
        .fold(0.0, f64::max);
    println!(
        "the first road with a crossing and a T-junction on it: its profile moves {:.1e} m, the ground along its centreline {:.1e} m",
        profile_change, ground_change
    );
    assert_eq!(
        alone.profiles[0].points.len(),
        together.profiles[0].points.len()
    );
    assert!(profile_change < 1e-3, "profile moved {profile_change} m");
    assert!(ground_change < 1e-3, "ground moved {ground_change} m");
}
