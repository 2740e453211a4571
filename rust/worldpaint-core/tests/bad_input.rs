//! The bad-input table of the engine: input a user or a shared file can give, each refused with an error that names
//! it, or handled with the right content, never with a crash, a huge allocation or content crammed where it does not
//! belong.

use std::sync::Arc;
use worldpaint_core::{
    learn_color, move_region, scene_from_points, stretch, synthesize, uniform_points, AdaptOptions,
    AnalysisOptions, Color, DVec2, Error, Heightfield, Palette, Region, Scene, StretchOptions,
    StretchSide, SynthesisOptions,
};

fn rect(min: (f64, f64), max: (f64, f64)) -> Region {
    Region::Rect {
        min: DVec2::new(min.0, min.1),
        max: DVec2::new(max.0, max.1),
    }
}

/// A flat 200 m terrain from (0, 0), 2 m cells.
fn flat_terrain() -> Arc<Heightfield> {
    let n = 101;
    Arc::new(Heightfield::new(DVec2::ZERO, 2.0, n, n, vec![0.0; n * n]).unwrap())
}

/// A uniform forest of 0.05 trees per m², learned on a 50 m square without maps.
fn forest_color() -> Color {
    let region = rect((0.0, 0.0), (50.0, 50.0));
    let scene = scene_from_points("tree", &uniform_points(&region, 0.05, 3));
    learn_color(&scene, &region, "forest", &AnalysisOptions::default()).unwrap()
}

fn on_flat_terrain() -> Scene {
    Scene::on(flat_terrain())
}

/// The flat terrain with `color` painted in `region`.
fn forest_on_flat_terrain(color: &Color, region: &Region) -> Scene {
    let mut scene = on_flat_terrain();
    let painted = synthesize(&scene, color, region, &Default::default()).unwrap();
    scene.categories = painted.categories;
    scene.instances = painted.instances;
    scene
}

/// The color's file with one field replaced, read back.
fn read_with(
    color: &Color,
    edit: impl Fn(&mut serde_json::Value),
) -> worldpaint_core::Result<Color> {
    let mut value: serde_json::Value = serde_json::from_str(&color.to_json().unwrap()).unwrap();
    edit(&mut value["color"]);
    Color::from_json(&value.to_string())
}

fn refused_naming(result: worldpaint_core::Result<Color>, words: &[&str]) {
    let e = result
        .err()
        .unwrap_or_else(|| panic!("a file with {words:?} was accepted"));
    assert!(matches!(e, Error::Parse { .. }), "refused, but as {e:?}");
    let m = e.to_string();
    assert!(m.starts_with("not a valid color file"), "{m}");
    for w in words {
        assert!(m.contains(w), "'{m}' should name '{w}'");
    }
}

#[test]
fn a_color_file_with_one_absurd_number_is_refused_at_import_naming_the_field() {
    let color = forest_color();
    refused_naming(
        read_with(&color, |c| c["bin_width"] = 1e-9.into()),
        &["max_radius / bin_width", "histogram bins"],
    );
    refused_naming(
        read_with(&color, |c| c["categories"][0]["density"] = 1e6.into()),
        &["categories[0].density"],
    );
    refused_naming(
        read_with(&color, |c| {
            c["pairs"][0]["interaction"]["hist"]["values"][0] = 1e11.into()
        }),
        &["pairs[0].hist.values[0]"],
    );
    refused_naming(
        read_with(&color, |c| {
            let first = c["categories"][0].clone();
            c["categories"].as_array_mut().unwrap().push(first);
        }),
        &["is named twice"],
    );
    // the same checks for a palette, with the color's place in it
    let palette = Palette {
        colors: vec![color.clone()],
    };
    let json = palette
        .to_json()
        .unwrap()
        .replacen("\"density\": ", "\"density\": 1e6, \"x\": ", 1);
    match Palette::from_json(&json) {
        Err(e @ Error::Parse { .. }) => {
            let m = e.to_string();
            assert!(m.contains("not a valid palette file: colors[0]"), "{m}");
        }
        other => panic!("accepted: {:?}", other.map(|p| p.colors.len())),
    }
}

#[test]
fn a_paste_is_counted_on_the_part_of_the_region_on_the_terrain() {
    let color = forest_color();
    let scene = on_flat_terrain();
    let opts = SynthesisOptions {
        seed: 4,
        ..Default::default()
    };
    let count = |region: &Region| {
        synthesize(&scene, &color, region, &opts)
            .unwrap()
            .instances
            .len() as f64
    };
    // 50 x 50 m on the terrain, the rest of the 100 x 100 m square off it
    let spilling = count(&rect((150.0, 150.0), (250.0, 250.0)));
    let inside = count(&rect((150.0, 150.0), (200.0, 200.0)));
    let expected = color.categories[0].density * 2500.0;
    assert!(
        (spilling - expected).abs() < 0.25 * expected,
        "{spilling} for {expected}"
    );
    assert!(
        (spilling - inside).abs() < 0.25 * expected,
        "{spilling} vs {inside}"
    );
    // a circle of 5 km over a 200 m terrain: the terrain's area, not the circle's
    let huge = Region::Circle {
        center: DVec2::splat(100.0),
        radius: 5000.0,
    };
    let all = count(&huge);
    let expected = color.categories[0].density * 200.0 * 200.0;
    assert!(
        (all - expected).abs() < 0.2 * expected,
        "{all} for {expected}"
    );
    // far off the terrain: refused
    let off = synthesize(
        &scene,
        &color,
        &rect((1000.0, 1000.0), (1100.0, 1100.0)),
        &opts,
    );
    assert!(
        matches!(off, Err(Error::RegionOffTerrain { .. })),
        "{off:?}"
    );
    // the message shows both boxes in metres; one ten thousand light years away in scientific notation
    let far = synthesize(&scene, &color, &rect((1e20, 0.0), (2e20, 10.0)), &opts);
    let message = far.map(|_| ()).expect_err("refused").to_string();
    assert!(
        message.contains("x 1.000e20..2.000e20, y 0.0..10.0") && !message.contains("DVec2"),
        "{message}"
    );
}

#[test]
fn work_past_the_limits_is_refused_before_it_is_allocated() {
    // 1e10 instances: a dense color over a large terrain
    let mut color = forest_color();
    color.categories[0].density = 1e4;
    let n = 1001;
    let big = Arc::new(Heightfield::new(DVec2::ZERO, 10.0, n, n, vec![0.0; n * n]).unwrap());
    let scene = Scene {
        terrain: Some(big),
        ..Default::default()
    };
    match synthesize(
        &scene,
        &color,
        &rect((0.0, 0.0), (10_000.0, 10_000.0)),
        &Default::default(),
    ) {
        Err(Error::TooLarge { unit, needed, .. }) => {
            assert_eq!(unit, "instances");
            assert!(needed >= 1e12, "{needed}");
        }
        other => panic!("not refused: {:?}", other.map(|r| r.instances.len())),
    }
    // a terrain of 1e12 cells
    assert!(matches!(
        Heightfield::new(DVec2::ZERO, 1.0, 1_000_000, 1_000_000, Vec::new()),
        Err(Error::TooLarge { .. })
    ));
    // a learning region 1e7 m long and 1e-7 m wide samples a bounded lattice
    let sliver = rect((0.0, 0.0), (1e7, 1e-7));
    let scene = scene_from_points("tree", &[DVec2::new(1.0, 0.5e-7), DVec2::new(2.0, 0.5e-7)]);
    let learned = learn_color(&scene, &sliver, "sliver", &AnalysisOptions::default()).unwrap();
    assert_eq!(learned.categories[0].count, 2);
    // a bin width of a nanometre
    let square = rect((0.0, 0.0), (50.0, 50.0));
    let forest = scene_from_points("tree", &uniform_points(&square, 0.05, 3));
    let fine = AnalysisOptions {
        bin_width: Some(1e-9),
        ..Default::default()
    };
    assert!(matches!(
        learn_color(&forest, &square, "fine", &fine),
        Err(Error::TooLarge { .. })
    ));
    // an oriented pair naming a category the scene does not have
    let oriented = AnalysisOptions {
        oriented: vec![("tree".into(), "house".into())],
        ..Default::default()
    };
    match learn_color(&forest, &square, "oriented", &oriented) {
        Err(e) => assert!(e.to_string().contains("'house'"), "{e}"),
        Ok(_) => panic!("an unknown oriented pair was accepted"),
    }
    // a mirrored example instance
    let mut mirrored = forest.clone();
    mirrored.instances[0].scale = -1.0;
    match learn_color(&mirrored, &square, "mirrored", &AnalysisOptions::default()) {
        Err(e) => assert!(e.to_string().contains("scales must be positive"), "{e}"),
        Ok(_) => panic!("a negative scale was learned"),
    }
    // a region nested past the depth limit
    let mut nested = rect((0.0, 0.0), (10.0, 10.0));
    for _ in 0..100 {
        nested = Region::Clipped {
            within: vec![nested],
            without: Vec::new(),
        };
    }
    assert!(matches!(nested.validate(), Err(Error::TooLarge { .. })));
}

#[test]
fn a_move_off_the_terrain_keeps_what_it_cannot_place() {
    let color = forest_color();
    let source = rect((20.0, 20.0), (70.0, 70.0));
    let scene = forest_on_flat_terrain(&color, &source);
    let before = scene.instances.len();
    assert!(before > 50, "{before}");
    let move_by = |dx: f64| {
        move_region(
            &scene,
            Some(&color),
            &source,
            DVec2::new(dx, 0.0),
            &AdaptOptions::default(),
        )
        .unwrap()
    };
    let moved = move_by(1000.0);
    assert_eq!(moved.stayed, before);
    assert_eq!(moved.moved, 0);
    assert!(moved.edit.removed.is_empty() && moved.edit.added.is_empty());
    // half on, half off: what lands on the terrain moves, the rest stays
    let moved = move_by(155.0);
    assert!(
        moved.stayed > 0 && moved.moved > 0,
        "{} stayed, {} moved",
        moved.stayed,
        moved.moved
    );
    assert_eq!(moved.stayed + moved.moved, before);
    assert!(moved.edit.added.iter().all(|i| i.position.x <= 200.0));
}

#[test]
fn a_scaled_plane_is_read_with_its_own_extent() {
    // the default plane scaled to 1000 x 500 m: four vertices, two triangles
    let v = [
        [-500.0, -250.0, 0.0],
        [500.0, -250.0, 0.0],
        [-500.0, 250.0, 0.0],
        [500.0, 250.0, 0.0],
    ];
    let t = Heightfield::from_mesh(&v, &[[0, 1, 3], [0, 3, 2]], None).unwrap();
    let (lo, hi) = t.bbox();
    assert_eq!(lo, DVec2::new(-500.0, -250.0));
    assert!(
        (hi.x - 500.0).abs() < 1e-6 && (hi.y - 250.0).abs() < 1e-6,
        "{hi}"
    );
}

#[test]
fn a_stretch_far_past_the_terrain_does_not_cram_what_it_moves() {
    let color = forest_color();
    let scene = forest_on_flat_terrain(&color, &rect((0.0, 0.0), (200.0, 200.0)));
    let stretched = stretch(
        &scene,
        &rect((20.0, 20.0), (180.0, 180.0)),
        StretchSide::East,
        10_000.0,
        Some(&color),
        &StretchOptions::default(),
        &|_| true,
    )
    .unwrap();
    let edit = &stretched.edit;
    let kept = (0..scene.instances.len())
        .filter(|k| !edit.removed.contains(k))
        .count();
    let after = kept + edit.added.iter().filter(|i| i.position.x <= 200.0).count();
    let full = color.categories[0].density * 200.0 * 200.0;
    assert!(
        after as f64 <= 1.3 * full,
        "{after} instances on a terrain that holds {full:.0}"
    );
}

mod common;
use common::variety_models;

/// Model variety: copies that are not edits of their part's piece, and counts past the number of models.
mod variety {
    use super::variety_models;
    use std::time::Instant;
    use worldpaint_core::{
        generate_variants, pack_components, pick_texture_variants, Atlas, Decomposition,
        GenerateOptions, IntersectionLabels, Model,
    };

    /// The variety test tree decomposed (root: the lower trunk) into an atlas of its original pieces, its parts named
    /// as Blender names their collections.
    fn named_tree_atlas() -> (variety_models::Tree, Decomposition, Atlas) {
        let tree = variety_models::tree(4);
        let d = Decomposition::from_labels(&tree.model, &tree.labels, Some(0)).expect("decomposed");
        let mut atlas = Atlas::new(&tree.model, d.clone()).expect("atlas");
        let names = (0..d.components.len())
            .map(|c| format!("Tree Parts/Tree part {c}"))
            .collect();
        atlas.set_names(names).expect("names");
        (tree, d, atlas)
    }

    #[test]
    fn a_copy_that_is_not_an_edit_of_its_parts_piece_is_refused_naming_it_and_nothing_changes() {
        let (tree, d, atlas) = named_tree_atlas();
        let piece = |c: usize| d.component_model(&tree.model, c).expect("piece");
        let crown_as_trunk = piece(5);
        let mut thrown = piece(5);
        for v in &mut thrown.vertices {
            v.x += 1e30;
        }
        let mut emptied = piece(5);
        emptied.faces.clear();
        emptied.uvs = None;
        emptied.materials = None;
        let mut not_a_number = piece(5);
        not_a_number.vertices[3].x = f64::NAN;
        let cases: Vec<(usize, &str, Model, Vec<&str>)> = vec![
            (
                0,
                "Crown copy",
                crown_as_trunk,
                vec![
                    "copy 'Crown copy' in 'Tree Parts/Tree part 0'",
                    "do not match the piece of 'Tree Parts/Tree part 0'",
                ],
            ),
            (
                5,
                "Crown far",
                thrown,
                vec![
                    "copy 'Crown far' in 'Tree Parts/Tree part 5'",
                    "m from the model, more than 100 times the model's size",
                ],
            ),
            (
                5,
                "Crown empty",
                emptied,
                vec![
                    "copy 'Crown empty' in 'Tree Parts/Tree part 5'",
                    "it has no faces",
                ],
            ),
            (
                5,
                "Crown nan",
                not_a_number,
                vec![
                    "copy 'Crown nan' in 'Tree Parts/Tree part 5': vertex 3",
                    "coordinates must be finite numbers",
                ],
            ),
        ];
        for (c, name, copy, words) in cases {
            let mut tried = atlas.clone();
            let start = Instant::now();
            let e = tried
                .add_named_variant(c, name, copy)
                .expect_err(name)
                .to_string();
            println!("  {name}: {e} ({:.3} s)", start.elapsed().as_secs_f64());
            assert!(
                start.elapsed().as_secs_f64() < 10.0,
                "{name}: answered in time"
            );
            for w in words {
                assert!(e.contains(w), "'{e}' should say '{w}'");
            }
            assert_eq!(
                (tried.count(), tried.variants(c).len()),
                (1, 1),
                "{name}: the atlas as it was"
            );
        }
    }

    #[test]
    fn a_count_past_the_number_of_models_makes_every_model_once() {
        let (tree, d, mut atlas) = named_tree_atlas();
        let mut taller = d.component_model(&tree.model, 5).expect("crown");
        let top = taller.vertices.iter().map(|v| v.z).fold(f64::MIN, f64::max);
        for v in &mut taller.vertices {
            if v.z > top - 1e-9 {
                v.z += 0.5;
            }
        }
        atlas
            .add_named_variant(5, "Crown tall", taller)
            .expect("a taller crown");
        let labels = IntersectionLabels::of_model(&tree.model);
        let start = Instant::now();
        let made = generate_variants(
            &atlas,
            &labels,
            &GenerateOptions {
                count: 1_000_000_000,
                seed: 1,
                max_attempts: 0,
            },
        )
        .expect("a count of #V or more makes every model");
        println!(
            "  a billion asked of {}: {} made, {} rejected in {:.3} s",
            atlas.count(),
            made.accepted.len(),
            made.rejected.len(),
            start.elapsed().as_secs_f64()
        );
        assert!(start.elapsed().as_secs_f64() < 10.0, "answered in time");
        assert_eq!(atlas.count(), 2);
        assert_eq!(made.accepted.len() + made.rejected.len(), 2);
        assert!(made.exhausted, "every model tried");
        // with texture edits each of the count asked is made (a shape repeats with other details): a billion is
        // refused, naming the count, before anything is allocated
        let faces = tree.model.faces.len();
        let start = Instant::now();
        let e = pick_texture_variants(&[], &pack_components(&[]), faces, 0.5, 1_000_000_000, 1)
            .expect_err("a billion textured variants")
            .to_string();
        println!("  {e}");
        assert!(start.elapsed().as_secs_f64() < 10.0, "answered in time");
        assert!(
            e.contains(&format!(
                "the texture choices of 1000000000 variants of {faces} faces"
            )),
            "{e}"
        );
    }
}

// ---- Apply Sketch: what no camera can show, and sketches too large to match -----------------------------------

mod sketch {
    use worldpaint_core::{
        apply_sketch, random_strokes, rough_terrain, Camera, DVec2, DVec3, Sight, SketchEdit,
        SketchOptions, SketchStroke, MAX_ASSIGNMENT_NODES, MAX_MATCHING_WORK,
    };
    use worldpaint_core::{Error, Heightfield};

    /// The sketch benchmark's view on a 256 m rough terrain: 15 m above its ground at (0.15, 0.15) of it, looking
    /// at (0.7, 0.7), 60° wide.
    fn view() -> (Heightfield, Camera) {
        view_of(128)
    }

    /// That view on an `n` × `n` terrain.
    fn view_of(n: usize) -> (Heightfield, Camera) {
        let side = 2.0 * (n - 1) as f64;
        let terrain = rough_terrain(side, 2.0, 3);
        let at = |x: f64, y: f64| {
            let p = DVec2::new(x, y) * side;
            p.extend(terrain.height_at(p).unwrap_or(0.0))
        };
        let camera =
            Camera::looking_at(at(0.15, 0.15) + DVec3::Z * 15.0, at(0.7, 0.7), 60.0, 1.5).unwrap();
        (terrain, camera)
    }

    /// A stroke 3 % of the image above the visible skyline over the middle of the view.
    fn above_skyline(terrain: &Heightfield, camera: &Camera) -> SketchStroke {
        let sight = Sight::new(terrain);
        SketchStroke {
            points: (0..=20)
                .filter_map(|k| {
                    let x = 0.3 + 0.4 * k as f64 / 20.0;
                    let (y, _) = sight.column_silhouette(camera, x, 0.0, 1.0)?;
                    Some(DVec2::new(x, y + 0.03))
                })
                .collect(),
        }
    }

    fn stroke(points: &[(f64, f64)]) -> SketchStroke {
        SketchStroke {
            points: points.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
        }
    }

    fn apply(
        terrain: &Heightfield,
        camera: &Camera,
        strokes: &[SketchStroke],
        options: &SketchOptions,
    ) -> worldpaint_core::Result<SketchEdit> {
        apply_sketch(terrain, camera, strokes, options, &|_| true)
    }

    #[test]
    fn a_sketch_no_camera_can_show_is_refused_with_the_figure() {
        let (terrain, camera) = view();
        let good = above_skyline(&terrain, &camera);
        let frame = camera.frame_max;
        let moved = |eye: DVec3| Camera::new(eye, camera.forward, DVec3::Z, -frame, frame).unwrap();
        let ground = terrain.height_at(camera.eye.truncate()).unwrap();
        let far = camera.eye - camera.forward * 1e7;
        // 175° across the frame's width: tan(87.5°) at the frame's edges
        let wide = {
            let half = 87.5f64.to_radians().tan();
            Camera::new(
                camera.eye,
                camera.forward,
                DVec3::Z,
                DVec2::new(-half, -half / 1.5),
                DVec2::new(half, half / 1.5),
            )
            .unwrap()
        };
        let sky = Camera::new(
            camera.eye,
            DVec3::new(0.3, 0.3, 1.0),
            DVec3::X,
            -frame,
            frame,
        )
        .unwrap();
        let sketch_of = |s: SketchStroke| vec![s];
        #[allow(clippy::type_complexity)]
        let cases: Vec<(&str, Camera, Vec<SketchStroke>, &[&str])> = vec![
            (
                "a stroke at y = 50-60",
                camera,
                sketch_of(stroke(&[(0.3, 50.0), (0.6, 60.0)])),
                &["stroke 0, point 0", "out of the camera frame"],
            ),
            (
                "strokes in pixels",
                camera,
                vec![good.clone(), stroke(&[(300.0, 200.0), (600.0, 250.0)])],
                &[
                    "stroke 1, point 0",
                    "(300.0000, 200.0000)",
                    "out of the camera frame",
                    "not in pixels",
                ],
            ),
            (
                "a point at 1e300",
                camera,
                sketch_of(stroke(&[(0.3, 0.5), (1e300, 0.5)])),
                &["stroke 0, point 1", "out of the camera frame"],
            ),
            (
                "a point not a number",
                camera,
                sketch_of(stroke(&[(0.3, 0.5), (f64::NAN, 0.5)])),
                &["stroke 0, point 1", "not finite"],
            ),
            (
                "a camera 1e7 m away",
                moved(far),
                sketch_of(good.clone()),
                &[
                    "the camera",
                    "its eye is 99999",
                    "m from the terrain, farther than the bound of 359 m",
                ],
            ),
            (
                "a 175° field of view",
                wide,
                sketch_of(good.clone()),
                &[
                    "field of view",
                    "175.000°",
                    "Blender camera's range",
                    "172.847°",
                ],
            ),
            (
                "a camera 60 m under the ground",
                moved(camera.eye.truncate().extend(ground - 60.0)),
                sketch_of(good.clone()),
                &["the camera", "60.0 m under the ground"],
            ),
            (
                "a camera looking at the sky",
                sky,
                sketch_of(good.clone()),
                &["the camera", "sees no terrain"],
            ),
            (
                "a stroke at the top of the frame",
                camera,
                sketch_of(stroke(&[(0.3, 0.97), (0.7, 0.98)])),
                &[
                    "the sketch",
                    "would change the terrain by",
                    "more than the terrain's relief of",
                ],
            ),
        ];
        for (name, camera, strokes, words) in cases {
            let before = terrain.heights.clone();
            let e = match apply(&terrain, &camera, &strokes, &SketchOptions::default()) {
                Ok(edit) => panic!(
                    "{name}: applied (raised {:.1} m)",
                    edit.deformation
                        .displacement
                        .iter()
                        .fold(0.0f64, |a, d| a.max(*d))
                ),
                Err(e) => e.to_string(),
            };
            for w in words {
                assert!(e.contains(w), "{name}: '{e}' does not say '{w}'");
            }
            assert!(!e.contains("needs no change"), "{name}: {e}");
            assert_eq!(terrain.heights, before, "{name}: the terrain changed");
        }
    }

    #[test]
    fn the_change_bound_is_the_terrains_relief_unless_set() {
        let (terrain, camera) = view();
        let high = vec![stroke(&[(0.3, 0.97), (0.7, 0.98)])];
        let e = apply(&terrain, &camera, &high, &SketchOptions::default())
            .unwrap_err()
            .to_string();
        // the figure asked for, and the bound: the 256 m terrain's relief, unless a quarter of its side is more
        let (lo, hi) = terrain
            .heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), &z| (l.min(z), h.max(z)));
        let bound = ((hi - lo) as f64).max(0.25 * 254.0);
        let relief = format!("{bound:.1} m");
        assert!(
            e.contains(&relief),
            "'{e}' does not name the relief {relief}"
        );
        let mut options = SketchOptions::default();
        options.limits.max_change = Some(1e4);
        let edit = apply(&terrain, &camera, &high, &options).expect("allowed with a larger bound");
        let raised = edit
            .deformation
            .displacement
            .iter()
            .fold(0.0f64, |a, d| a.max(*d));
        assert!(raised > bound, "raised {raised:.1} m");
        // and a bound set smaller than a sensible sketch's change refuses it, naming the bound
        let good = vec![above_skyline(&terrain, &camera)];
        options.limits.max_change = Some(0.5);
        let e = apply(&terrain, &camera, &good, &options)
            .unwrap_err()
            .to_string();
        assert!(e.contains("more than the bound set of 0.5 m"), "{e}");
    }

    #[test]
    fn a_sketch_too_large_to_match_is_refused_before_the_work() {
        // the benchmark's 512² terrain, with its 1,000-odd feature pieces
        let (terrain, camera) = view_of(512);
        let strokes = random_strokes(1_000, 1);
        let e = apply(&terrain, &camera, &strokes, &SketchOptions::default()).unwrap_err();
        match &e {
            Error::TooLarge {
                what,
                needed,
                limit,
                ..
            } => {
                assert_eq!(what, "the sketch's matching");
                assert_eq!(*limit, MAX_MATCHING_WORK);
                assert!(*needed > MAX_MATCHING_WORK as f64);
            }
            other => panic!("not refused as too large: {other}"),
        }
        assert!(e.to_string().contains("candidate columns"), "{e}");
    }

    #[test]
    fn many_strokes_are_matched_within_the_node_budget_and_the_search_stops_when_asked() {
        let (terrain, camera) = view();
        let strokes = random_strokes(20, 3);
        let mut options = SketchOptions::default();
        options.limits.max_change = Some(1e6);
        let edit =
            apply(&terrain, &camera, &strokes, &options).expect("20 random strokes are matched");
        let a = &edit.targets.assignment;
        assert!(a.nodes <= MAX_ASSIGNMENT_NODES + 1, "{} nodes", a.nodes);
        assert_eq!(a.chosen.len(), 20);
        // asked to stop from inside the matching (the callback hears 0.2 there, again and again): it stops there
        let asked = std::sync::atomic::AtomicUsize::new(0);
        let e = apply_sketch(&terrain, &camera, &strokes, &options, &|f| {
            if f == 0.2 {
                asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < 5
            } else {
                true
            }
        })
        .unwrap_err();
        assert!(matches!(e, Error::Cancelled), "{e}");
        assert_eq!(asked.load(std::sync::atomic::Ordering::Relaxed), 6);
    }
}
