//! The bad-input table of the engine: input a user or a shared file can give, each refused with an error that names
//! it, or handled with the right content, never with a crash, a huge allocation or content crammed where it does not
//! belong.

use std::sync::Arc;
use worldpaint_core::exemplar::{self, scene_from_points};
use worldpaint_core::geom::DVec2;
use worldpaint_core::synthesis::AdaptOptions;
use worldpaint_core::tools::moving::move_region;
use worldpaint_core::tools::stretch::{stretch, Side, StretchOptions};
use worldpaint_core::{
    learn_color, synthesize, AnalysisOptions, Color, Error, Heightfield, Palette, Region, Scene,
    SynthesisOptions,
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
    let scene = scene_from_points("tree", &exemplar::uniform(&region, 0.05, 3));
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
    let forest = scene_from_points("tree", &exemplar::uniform(&square, 0.05, 3));
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
        Side::East,
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

#[path = "common/variety_models.rs"]
mod variety_models;

/// Model variety: copies that are not edits of their part's piece, and counts past the number of models.
mod variety {
    use super::variety_models;
    use std::time::Instant;
    use worldpaint_core::variety::{
        generate, pack_components, pick_texture_variants, Atlas, Decomposition, GenerateOptions,
        IntersectionLabels, Model,
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
        let made = generate(
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
