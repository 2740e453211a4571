//! Model variety (Maréchal et al.) as a user would check it: a tree of six components with three variants each
//! gives 729 different, crack-free, watertight trees; a deliberate new self-intersection is rejected while the
//! original's own are kept; the memory overhead reads like the seed's Table 2; a fully cyclic rock refuses a solid
//! transform; local cycles repeat at most as allowed; conflicting texture components never share an atlas; the same
//! seed gives the same variants at any thread count; bad input is refused with a message.
//!
//! `cargo test -p worldpaint-core --release --test variety -- --nocapture` prints the figures.

mod common;
use common::variety_models;

use common::birch::{birch, birch_atlas};
use common::variety_models::{
    cactus, column, edit, moved_piece, ring, rock, tree, tree_atlas, CactusPart, DVec3, Role,
};
use std::collections::HashSet;
use worldpaint_core::{
    atlas_images, check_assemblies, generate_variants, memory_report, pack_components,
    pick_textures, Atlas, Choice, DVec2, Decomposition, GenerateOptions, Image, IntersectionLabels,
    Model, Rejection, TextureComponent, VariantClass,
};

fn all_choices(atlas: &Atlas) -> Vec<Choice> {
    (0..atlas.count())
        .map(|k| {
            atlas
                .choice(k)
                .expect("every number below the count names an assembly")
        })
        .collect()
}

#[test]
fn the_birch_from_assets_gives_729_different_sound_trees() {
    let b = birch();
    let faces = b.model.faces.len();
    println!(
        "assets/birch.obj: {} vertices, {faces} faces, components {:?}",
        b.model.vertices.len(),
        b.names
    );
    assert!((600..=1000).contains(&faces), "{faces} faces");
    assert!(b.model.is_watertight(), "the original birch is closed");
    let (d, atlas, classes) = birch_atlas(&b);
    assert_eq!(d.components.len(), 6);
    assert_eq!(
        d.regions.len(),
        5,
        "a tree-like graph of 6 nodes has 5 arcs"
    );
    assert!(d.is_tree_like());
    for r in &d.regions {
        println!(
            "  {}–{}: a ring of {} vertices, closed: {}",
            b.names[r.components.0],
            b.names[r.components.1],
            r.vertices.len(),
            r.chains.len() == 1 && r.chains[0].closed
        );
        assert!(
            r.chains.len() == 1 && r.chains[0].closed,
            "one boundary loop"
        );
    }
    for (c, cl) in classes.iter().enumerate() {
        println!(
            "  {}: {} faces, variants {cl:?}",
            b.names[c],
            d.components[c].faces.len()
        );
        let solid = c == 1 || c == 2; // a branch tilted from its first ring moves its leaf mass as a solid
        assert_eq!(cl[1] == VariantClass::SolidTransform, solid, "{cl:?}");
        assert!(cl.iter().all(|&k| k != VariantClass::RegionChange));
    }
    assert_eq!(atlas.count(), 729, "#V = 3^6");
    let labels = IntersectionLabels::of_model(&b.model);
    println!(
        "  intersecting face pairs in the original (clumps set into their leaf masses, allowed): {}",
        labels.pairs().len()
    );
    assert!(!labels.pairs().is_empty());
    let choices = all_choices(&atlas);
    let results = check_assemblies(&atlas, &labels, &choices).expect("assembly");
    let mut hashes = HashSet::new();
    let mut worst_gap: f64 = 0.0;
    let mut sizes = (usize::MAX, 0);
    for (choice, r) in choices.iter().zip(&results) {
        let a = r
            .as_ref()
            .unwrap_or_else(|why| panic!("assembly {choice:?} rejected: {why:?}"));
        worst_gap = worst_gap.max(a.max_gap);
        assert!(a.max_gap <= 1e-6, "crack of {} m", a.max_gap);
        assert!(
            a.model.is_watertight(),
            "assembly {choice:?} has an open edge"
        );
        assert!(a.model.validate().is_ok());
        let uvs = a.model.uvs.as_ref().expect("the original's UVs");
        assert_eq!(uvs.len(), a.model.faces.len());
        sizes = (
            sizes.0.min(a.model.faces.len()),
            sizes.1.max(a.model.faces.len()),
        );
        hashes.insert(a.hash);
    }
    println!(
        "  729 assemblies: {} distinct geometry hashes, all accepted, all closed, largest weld gap {worst_gap:.2e} m, \
         {} to {} faces",
        hashes.len(),
        sizes.0,
        sizes.1
    );
    assert_eq!(hashes.len(), 729, "no two assemblies are the same tree");
}

#[test]
fn bending_the_upper_trunk_carries_the_crown() {
    let t = tree(15);
    let (_, atlas, _) = tree_atlas(&t);
    // The bent upper trunk carries the crown with it: the crown turns by the bend's 12° about the axis at z = 5 m.
    let straight = atlas
        .assemble(&atlas.choice(0).expect("choice"))
        .expect("assembly");
    let bent_choice = Choice {
        graph: 0,
        picks: vec![vec![0], vec![1], vec![0], vec![0], vec![0], vec![0]],
    };
    let bent = atlas.assemble(&bent_choice).expect("assembly");
    let (before, after) = (component_centre(&straight, 5), component_centre(&bent, 5));
    let bend = glam::DAffine3::from_translation(DVec3::Z * 5.0)
        * glam::DAffine3::from_rotation_x(12f64.to_radians())
        * glam::DAffine3::from_translation(-DVec3::Z * 5.0);
    println!("  bent upper trunk: crown centre {before:.3} → {after:.3}");
    assert!(
        after.distance(bend.transform_point3(before)) < 1e-9,
        "the frame moves the crown with the bend"
    );
    assert!(after.distance(before) > 0.5);
}

#[test]
fn a_new_self_intersection_is_rejected_and_the_originals_own_are_kept() {
    let t = tree(15);
    let (d, mut atlas, _) = tree_atlas(&t);
    let labels = IntersectionLabels::of_model(&t.model);
    // Branch 1 (component 2) with one leaf pushed into the middle of its own branch tube.
    let comp = &d.components[2];
    let first_leaf = comp
        .vertices
        .iter()
        .find_map(|&v| match t.roles[v as usize] {
            Role::Leaf(id) => Some(id),
            _ => None,
        })
        .expect("the branch has leaves");
    let tube_mid: Vec<DVec3> = comp
        .vertices
        .iter()
        .filter(|&&v| t.roles[v as usize] == Role::Tube(2))
        .map(|&v| t.model.vertices[v as usize])
        .collect();
    let mid = tube_mid.iter().copied().sum::<DVec3>() / tube_mid.len() as f64;
    let leaf_centre = {
        let pts: Vec<DVec3> = comp
            .vertices
            .iter()
            .filter(|&&v| t.roles[v as usize] == Role::Leaf(first_leaf))
            .map(|&v| t.model.vertices[v as usize])
            .collect();
        pts.iter().copied().sum::<DVec3>() / pts.len() as f64
    };
    let poked = edit(
        &t,
        &d,
        2,
        |r, p| {
            if r == Role::Leaf(first_leaf) {
                p - leaf_centre + mid
            } else {
                p
            }
        },
        |_| true,
    );
    assert_eq!(
        atlas.add_variant(2, poked).expect("a local edit"),
        VariantClass::Local
    );
    assert_eq!(atlas.count(), 4 * 243);
    let choices = all_choices(&atlas);
    let results = check_assemblies(&atlas, &labels, &choices).expect("assembly");
    let (mut kept, mut rejected) = (0, 0);
    for (choice, r) in choices.iter().zip(&results) {
        let poking = choice.picks[2][0] == 3;
        match r {
            Ok(_) => {
                assert!(!poking, "a tree with the leaf through its branch was kept");
                kept += 1;
            }
            Err(Rejection::SelfIntersection(..)) => {
                assert!(
                    poking,
                    "assembly {choice:?} rejected without the new intersection"
                );
                rejected += 1;
            }
            Err(other) => panic!("unexpected rejection {other:?}"),
        }
    }
    println!(
        "  with a leaf poked through branch 1: {kept} kept, {rejected} rejected (of {})",
        choices.len()
    );
    assert_eq!((kept, rejected), (729, 243));
}

#[test]
fn reshaping_a_branch_base_adapts_the_trunk_in_a_duplicated_graph() {
    let t = tree(15);
    let (d, mut atlas, _) = tree_atlas(&t);
    // Branch 1's base (its connecting region with the lower trunk) loses its square shape: one corner pulled out.
    let r02 = d
        .regions
        .iter()
        .position(|r| r.components == (0, 2))
        .expect("R02");
    let corner = d.regions[r02].vertices[0];
    let pulled = t.model.vertices[corner as usize] * DVec3::new(1.15, 1.15, 1.0);
    let reshaped = edit(
        &t,
        &d,
        2,
        |_, p| {
            if p == t.model.vertices[corner as usize] {
                pulled
            } else {
                p
            }
        },
        |_| true,
    );
    assert_eq!(
        atlas.add_variant(2, reshaped).expect("reshaped"),
        VariantClass::RegionChange
    );
    assert_eq!(atlas.graphs().len(), 2, "the graph is duplicated (§4.2.3)");
    assert_eq!(
        atlas.count(),
        729 + 243,
        "G keeps 3^6; G' holds the reshaped branch with 3^5 others"
    );
    let labels = IntersectionLabels::of_model(&t.model);
    let duplicated: Vec<Choice> = all_choices(&atlas)
        .into_iter()
        .filter(|c| c.graph == 1)
        .collect();
    assert_eq!(duplicated.len(), 243);
    let results = check_assemblies(&atlas, &labels, &duplicated).expect("assembly");
    for (choice, r) in duplicated.iter().zip(results) {
        let a = r.unwrap_or_else(|why| panic!("{choice:?} rejected: {why:?}"));
        assert!(
            a.max_gap <= 1e-6,
            "the adapted trunk meets the reshaped base"
        );
        assert!(a.model.is_watertight());
        let placed = a
            .instances
            .iter()
            .find(|p| p.component == 0)
            .expect("the trunk");
        let on_trunk = placed.placement.transform_point3(pulled);
        assert!(a.model.vertices.iter().any(|v| v.distance(on_trunk) < 1e-9));
    }
    println!(
        "  reshaped branch base: 243 assemblies in the duplicated graph, all closed and crack-free"
    );
}

#[test]
fn turning_a_branch_base_as_a_solid_tilts_the_branch() {
    let t = tree(15);
    let (d, mut atlas, _) = tree_atlas(&t);
    // Branch 2's base quad turned 10° about its own centre (a solid move of its region with the trunk): the trunk
    // cannot follow, so the branch is brought back by the inverse turn — it leaves the trunk tilted.
    let r03 = d
        .regions
        .iter()
        .position(|r| r.components == (0, 3))
        .expect("R03");
    let base: Vec<DVec3> = d.regions[r03]
        .vertices
        .iter()
        .map(|&v| t.model.vertices[v as usize])
        .collect();
    let centre = base.iter().copied().sum::<DVec3>() / base.len() as f64;
    let turn = glam::DAffine3::from_translation(centre)
        * glam::DAffine3::from_rotation_z(10f64.to_radians())
        * glam::DAffine3::from_translation(-centre);
    let turned = edit(
        &t,
        &d,
        3,
        |_, p| {
            if base.iter().any(|b| b.distance(p) < 1e-12) {
                turn.transform_point3(p)
            } else {
                p
            }
        },
        |_| true,
    );
    assert_eq!(
        atlas.add_variant(3, turned).expect("solid"),
        VariantClass::SolidTransform
    );
    let v = &atlas.variants(3)[3];
    assert!(
        v.normalised_by != glam::DAffine3::IDENTITY,
        "brought back by the inverse turn"
    );
    let labels = IntersectionLabels::of_model(&t.model);
    let mut picks = vec![vec![0]; 6];
    picks[3] = vec![3];
    let choice = Choice { graph: 0, picks };
    let a = worldpaint_core::check_assembly(&atlas, &labels, &choice)
        .expect("assembly")
        .expect("kept");
    assert!(a.max_gap <= 1e-6 && a.model.is_watertight());
    let plain = atlas
        .assemble(&atlas.choice(0).expect("choice"))
        .expect("assembly");
    let moved = component_centre(&a, 3).distance(component_centre(&plain, 3));
    println!(
        "  turned branch base: kept, closed, crack-free; the branch's centre moved {moved:.3} m"
    );
    assert!(moved > 0.1, "the branch tilts");
    assert_ne!(a.hash, plain.hash);
}

#[test]
fn memory_overhead_reads_like_the_seeds_table_2() {
    let b = birch();
    let (d, atlas, _) = birch_atlas(&b);
    let choices = all_choices(&atlas);
    let m = memory_report(&atlas, &choices).expect("memory");
    println!(
        "  Model      Components  Variations  Objects  Memory   (seed: Birch 6, 3, 729, +54 %)"
    );
    println!(
        "  birch      {:>10}  {:>10}  {:>7}  {:+.0} %",
        m.components, m.variations, m.objects, m.overhead_percent
    );
    println!(
        "  original {} B; atlas {} B; 729 trees as components + placements {} B, as full meshes {} B ({:.0}× more)",
        m.original_bytes,
        m.atlas_bytes,
        m.shared_bytes,
        m.full_bytes,
        m.full_bytes as f64 / m.shared_bytes as f64
    );
    assert_eq!(
        (m.components, m.variations, m.objects),
        (d.components.len(), 3, 729)
    );
    assert!(
        m.overhead_percent > 0.0 && m.overhead_percent < 150.0,
        "{}",
        m.overhead_percent
    );
    assert!(
        m.full_bytes > 20 * m.shared_bytes,
        "sharing components must save most of the memory"
    );
}

#[test]
fn a_fully_cyclic_rock_refuses_a_solid_transform_of_a_connecting_region() {
    let (model, labels) = rock();
    let d = Decomposition::from_labels(&model, &labels, None).expect("decomposition");
    assert_eq!(d.components.len(), 4);
    assert!(
        d.is_fully_cyclic(),
        "each piece touches the others in a cycle"
    );
    let mut atlas = Atlas::new(&model, d.clone()).expect("atlas");
    // The meridian between pieces 1 and 2 turned 8° about the vertical axis: a rigid move of that region only.
    let r12 = d
        .regions
        .iter()
        .position(|r| r.components == (1, 2))
        .expect("pieces 1 and 2 touch");
    let on_meridian: HashSet<u32> = d.regions[r12].vertices.iter().copied().collect();
    let turn = glam::DQuat::from_rotation_z(8f64.to_radians());
    let mut turned = d.component_model(&model, 1).expect("sub-mesh");
    for (k, &v) in d.components[1].vertices.iter().enumerate() {
        if on_meridian.contains(&v) {
            turned.vertices[k] = turn * turned.vertices[k];
        }
    }
    let err = atlas
        .add_variant(1, turned)
        .expect_err("a solid transform on a cycle must be refused");
    println!("  refused: {err}");
    let msg = err.to_string();
    assert!(
        msg.contains("fully cyclic") && msg.contains("§4.2.3"),
        "{msg}"
    );
    assert_eq!(atlas.count(), 1, "the refused variant is not in the atlas");
    // A local bump is fine, and so is reshaping the meridian (the neighbour is adapted in a duplicated graph).
    let mut bump = d.component_model(&model, 1).expect("sub-mesh");
    let free = d.components[1]
        .vertices
        .iter()
        .position(|v| !d.regions.iter().any(|r| r.vertices.contains(v)))
        .expect("a vertex inside the piece");
    bump.vertices[free] *= 1.2;
    assert_eq!(
        atlas.add_variant(1, bump).expect("local"),
        VariantClass::Local
    );
    let mut reshaped = d.component_model(&model, 1).expect("sub-mesh");
    for (k, &v) in d.components[1].vertices.iter().enumerate() {
        if on_meridian.contains(&v) {
            let p = reshaped.vertices[k];
            reshaped.vertices[k] = DVec3::new(p.x * 1.15, p.y * 1.15, p.z);
        }
    }
    assert_eq!(
        atlas.add_variant(1, reshaped).expect("reshaped"),
        VariantClass::RegionChange
    );
    assert_eq!(atlas.graphs().len(), 2, "the graph was duplicated");
    assert_eq!(
        atlas.count(),
        3,
        "2 in the main graph, 1 in the duplicated one"
    );
    let labels = IntersectionLabels::of_model(&model);
    let choices = all_choices(&atlas);
    for (choice, r) in choices
        .iter()
        .zip(check_assemblies(&atlas, &labels, &choices).expect("assembly"))
    {
        let a = r.unwrap_or_else(|why| panic!("{choice:?} rejected: {why:?}"));
        assert!(a.max_gap <= 1e-6 && a.model.is_watertight(), "{choice:?}");
    }
    let e = atlas
        .add_local_cycle(1, 3)
        .expect_err("no local cycle on a cyclic graph");
    println!("  refused: {e}");
    assert!(e.to_string().contains("tree-like"));
}

#[test]
fn a_local_cycle_repeats_a_piece_at_most_the_allowed_number_of_times() {
    let (model, labels) = column();
    let d = Decomposition::from_labels(&model, &labels, Some(0)).expect("decomposition");
    let mut atlas = Atlas::new(&model, d.clone()).expect("atlas");
    let e = atlas
        .add_local_cycle(0, 3)
        .expect_err("the base is a terminal node");
    println!("  refused: {e}");
    assert!(e.to_string().contains("terminal"));
    let mut bulge = d.component_model(&model, 1).expect("sub-mesh");
    for p in bulge
        .vertices
        .iter_mut()
        .filter(|p| (p.z - 1.5).abs() < 1e-9)
    {
        *p = DVec3::new(p.x * 1.3, p.y * 1.3, p.z);
    }
    assert_eq!(
        atlas.add_variant(1, bulge).expect("local"),
        VariantClass::Local
    );
    assert_eq!(
        atlas.local_cycle_candidates(),
        vec![1],
        "only the middle piece has identical ends"
    );
    atlas
        .add_local_cycle(1, 3)
        .expect("the middle piece has identical ends");
    assert_eq!(atlas.count(), 2 + 4 + 8, "Σ_{{r=1..3}} 2^r");
    let labels = IntersectionLabels::of_model(&model);
    let choices = all_choices(&atlas);
    let mut heights = Vec::new();
    for (choice, r) in choices
        .iter()
        .zip(check_assemblies(&atlas, &labels, &choices).expect("assembly"))
    {
        let a = r.unwrap_or_else(|why| panic!("{choice:?} rejected: {why:?}"));
        assert!(a.max_gap <= 1e-6 && a.model.is_watertight(), "{choice:?}");
        let h = a.model.bounds().1.z;
        assert!(
            (h - (2.0 + choice.picks[1].len() as f64)).abs() < 1e-9,
            "height {h}"
        );
        heights.push(h);
    }
    heights.sort_by(f64::total_cmp);
    heights.dedup();
    println!("  column heights with 1 to 3 middle pieces: {heights:?}");
    assert_eq!(heights, vec![3.0, 4.0, 5.0]);
    let g = generate_variants(
        &atlas,
        &labels,
        &GenerateOptions {
            count: 14,
            seed: 3,
            max_attempts: 400,
        },
    )
    .expect("generate");
    assert_eq!(
        g.accepted.len(),
        14,
        "every assembly is reachable at random"
    );
    assert!(g
        .accepted
        .iter()
        .all(|(c, _)| (1..=3).contains(&c.picks[1].len())));
    let too_many = Choice {
        graph: 0,
        picks: vec![vec![0], vec![0; 4], vec![0]],
    };
    let e = atlas
        .assemble(&too_many)
        .expect_err("4 copies where 3 are allowed");
    assert!(e.to_string().contains("1 to 3"), "{e}");
}

/// A strip of five quads; faces 3 and 4 share one UV island (they overlap in the texture domain).
fn textured_strip() -> Model {
    let mut v = Vec::new();
    for x in 0..6 {
        v.push(DVec3::new(x as f64, 0.0, 0.0));
        v.push(DVec3::new(x as f64, 1.0, 0.0));
    }
    let faces: Vec<Vec<u32>> = (0..5u32)
        .map(|q| vec![2 * q, 2 * q + 2, 2 * q + 3, 2 * q + 1])
        .collect();
    let island = |i: usize| {
        let (u0, v0) = ((i % 2) as f64 * 0.5, (i / 2) as f64 * 0.5);
        vec![
            DVec2::new(u0 + 0.05, v0 + 0.05),
            DVec2::new(u0 + 0.45, v0 + 0.05),
            DVec2::new(u0 + 0.45, v0 + 0.45),
            DVec2::new(u0 + 0.05, v0 + 0.45),
        ]
    };
    let uvs = vec![island(0), island(1), island(2), island(3), island(3)];
    Model::new(v, faces)
        .and_then(|m| m.with_uvs(uvs))
        .expect("strip")
}

fn paint(base: &Image, texels: &[(u32, u32)], colour: [u8; 4]) -> Image {
    let mut out = base.clone();
    for &(x, y) in texels {
        let i = ((y * base.width + x) * 4) as usize;
        out.rgba[i..i + 4].copy_from_slice(&colour);
    }
    out
}

#[test]
fn conflicting_texture_components_never_share_an_atlas_and_uvs_do_not_change() {
    let model = textured_strip();
    let before = model.clone();
    let base = Image::new(32, 32, vec![128; 32 * 32 * 4]).expect("image");
    let edits = [
        paint(&base, &[(4, 4), (5, 4)], [200, 30, 30, 255]), // island 0 (face 0)
        paint(&base, &[(10, 10)], [30, 200, 30, 255]), // island 0 again: conflicts with the first
        paint(&base, &[(20, 5)], [30, 30, 200, 255]),  // island 1 (face 1)
        paint(&base, &[(6, 20)], [200, 200, 30, 255]), // island 2 (face 2)
        paint(&base, &[(22, 22)], [30, 200, 200, 255]), // island 3: faces 3 and 4 both
    ];
    let comps: Vec<TextureComponent> = edits
        .iter()
        .map(|e| TextureComponent::from_edit(&model, &base, e).expect("component"))
        .collect();
    assert_eq!(comps[0].faces, vec![0]);
    assert_eq!(
        comps[4].faces,
        vec![3, 4],
        "a painted texel shared by two faces takes both"
    );
    assert!(comps[0].conflicts(&comps[1]));
    assert!(!comps[0].conflicts(&comps[2]));
    let packing = pack_components(&comps);
    println!(
        "  5 texture components packed into {} atlases {:?} (exact: {})",
        packing.atlases, packing.atlas_of, packing.exact
    );
    for i in 0..comps.len() {
        for j in i + 1..comps.len() {
            if comps[i].conflicts(&comps[j]) {
                assert_ne!(
                    packing.atlas_of[i], packing.atlas_of[j],
                    "components {i} and {j} conflict"
                );
            }
        }
    }
    assert_eq!(
        packing.atlases, 2,
        "one conflict needs two atlases, no more"
    );
    assert!(packing.exact);
    let images = atlas_images(&base, &comps, &packing);
    assert_eq!(images.len(), 2);
    assert_eq!(
        images[packing.atlas_of[0]].texel(4 * 32 + 4),
        Some([200, 30, 30, 255])
    );
    assert_eq!(
        images[packing.atlas_of[1]].texel(4 * 32 + 4),
        Some([128; 4]),
        "component 0 is not in atlas of 1"
    );
    let mut shown = vec![0usize; comps.len()];
    for seed in 0..200 {
        let pick = pick_textures(&comps, &packing, model.faces.len(), 0.6, seed).expect("pick");
        let mut owner = vec![None; model.faces.len()];
        for &k in &pick.chosen {
            shown[k] += 1;
            for &f in &comps[k].faces {
                assert!(
                    owner[f as usize].is_none(),
                    "face {f} locked by two components"
                );
                owner[f as usize] = Some(k);
                assert_eq!(pick.face_atlas[f as usize], Some(packing.atlas_of[k]));
            }
        }
        assert!(
            !(pick.chosen.contains(&0) && pick.chosen.contains(&1)),
            "0 and 1 share face 0"
        );
        assert_eq!(
            pick,
            pick_textures(&comps, &packing, model.faces.len(), 0.6, seed).expect("pick")
        );
    }
    println!("  times each component was shown over 200 variants: {shown:?}");
    assert!(shown.iter().all(|&n| n > 0));
    let bits = |m: &Model| -> Vec<u64> {
        m.uvs
            .iter()
            .flatten()
            .flatten()
            .flat_map(|uv| [uv.x.to_bits(), uv.y.to_bits()])
            .collect()
    };
    assert_eq!(
        bits(&model),
        bits(&before),
        "texture coordinates unchanged, bit for bit"
    );
}

#[test]
fn the_same_seed_gives_the_same_variants_at_any_thread_count() {
    let t = tree(15);
    let (_, atlas, _) = tree_atlas(&t);
    let labels = IntersectionLabels::of_model(&t.model);
    let options = GenerateOptions {
        count: 300,
        seed: 42,
        max_attempts: 0,
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| generate_variants(&atlas, &labels, &options).expect("generate"))
    };
    let (one, four) = (run(1), run(4));
    let hashes = |g: &worldpaint_core::Generation| -> Vec<u64> {
        g.accepted.iter().map(|(_, a)| a.hash).collect()
    };
    assert_eq!(one.accepted.len(), 300);
    assert_eq!(hashes(&one), hashes(&four));
    assert_eq!(
        one.accepted.iter().map(|a| &a.0).collect::<Vec<_>>(),
        four.accepted.iter().map(|a| &a.0).collect::<Vec<_>>()
    );
    let distinct: HashSet<u64> = hashes(&one).into_iter().collect();
    assert_eq!(distinct.len(), 300, "the variants are distinct");
    let other = generate_variants(
        &atlas,
        &labels,
        &GenerateOptions {
            seed: 43,
            ..options.clone()
        },
    )
    .expect("generate");
    assert_ne!(hashes(&one), hashes(&other), "another seed, other variants");
    println!("  300 variants, seed 42: identical on 1 and 4 threads; seed 43 differs");
}

#[test]
fn asking_for_every_possible_birch_gives_every_one_once() {
    let b = birch();
    let (_, atlas, _) = birch_atlas(&b);
    let labels = IntersectionLabels::of_model(&b.model);
    // 700 in at most 700 draws: the draws stall on repeats, and the assemblies never drawn are enumerated
    for (count, max_attempts) in [(729usize, 0usize), (1000, 0), (700, 0), (700, 700)] {
        let (seed, options) = (
            1,
            GenerateOptions {
                count,
                seed: 1,
                max_attempts,
            },
        );
        let g = generate_variants(&atlas, &labels, &options).expect("generate");
        let distinct: HashSet<u64> = g.accepted.iter().map(|(_, a)| a.hash).collect();
        println!(
            "  {count} asked of 729 possible (seed {seed}, attempts {max_attempts}): {} made, {} distinct, \
             {} rejected, every one tried: {}",
            g.accepted.len(),
            distinct.len(),
            g.rejected.len(),
            g.exhausted
        );
        assert_eq!(g.accepted.len(), count.min(729));
        assert_eq!(distinct.len(), count.min(729));
        assert!(g.rejected.is_empty());
        assert_eq!(
            g.exhausted,
            count >= 729,
            "the report says when no other variant exists"
        );
    }
    // with a rejected branch (a leaf poked into it, 243 of its 972 assemblies): all asked gives the others, once
    let t = tree(15);
    let (d, mut poked_atlas, _) = tree_atlas(&t);
    let poked = edit(
        &t,
        &d,
        2,
        |r, p| if r == Role::Tube(2) { p * 0.2 } else { p },
        |_| true,
    );
    poked_atlas.add_variant(2, poked).expect("a local edit");
    let labels = IntersectionLabels::of_model(&t.model);
    let options = GenerateOptions {
        count: 972,
        seed: 5,
        max_attempts: 0,
    };
    let g = generate_variants(&poked_atlas, &labels, &options).expect("generate");
    let distinct: HashSet<u64> = g.accepted.iter().map(|(_, a)| a.hash).collect();
    println!(
        "  972 asked of 972 possible with one bad branch: {} made ({} distinct), {} rejected",
        g.accepted.len(),
        distinct.len(),
        g.rejected.len()
    );
    assert_eq!((g.accepted.len(), g.rejected.len()), (729, 243));
    assert_eq!(distinct.len(), 729);
    assert!(g.exhausted);
}

#[test]
fn bad_input_is_refused_with_a_message() {
    let ok_vertices = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let cases: Vec<(&str, worldpaint_core::Result<Model>, &str)> = vec![
        (
            "index out of range",
            Model::new(ok_vertices.clone(), vec![vec![0, 1, 9]]),
            "vertex 9",
        ),
        (
            "NaN vertex",
            Model::new(
                vec![DVec3::new(f64::NAN, 0.0, 0.0), DVec3::X, DVec3::Y],
                vec![vec![0, 1, 2]],
            ),
            "finite",
        ),
        (
            "two corners",
            Model::new(ok_vertices.clone(), vec![vec![0, 1]]),
            "3 corners",
        ),
        (
            "repeated corner",
            Model::new(ok_vertices.clone(), vec![vec![0, 1, 1]]),
            "twice",
        ),
    ];
    for (name, result, needle) in cases {
        let e = result.expect_err(name);
        println!("  {name}: {e}");
        assert!(e.to_string().contains(needle), "{name}: {e}");
    }
    let t = tree(15);
    let e = Decomposition::from_labels(&t.model, &[], None).expect_err("empty labels");
    println!("  empty labels: {e}");
    assert!(e.to_string().contains("label"));
    let e = Decomposition::from_labels(&t.model, &t.labels[1..], None).expect_err("short labels");
    assert!(e.to_string().contains("items where"), "{e}");
    let (d, mut atlas, _) = tree_atlas(&t);
    let mut short = d.component_model(&t.model, 2).expect("sub-mesh");
    short.vertices.truncate(3);
    short.faces.retain(|f| f.iter().all(|&v| v < 3));
    short.uvs = None;
    short.materials = None;
    let e = atlas
        .add_variant(2, short)
        .expect_err("a variant that lost vertices");
    println!("  variant without the component's vertices: {e}");
    assert!(e.to_string().contains("delete faces, not vertices"), "{e}");
    let e = atlas
        .add_variant(9, t.model.clone())
        .expect_err("no component 9");
    assert!(e.to_string().contains("component"), "{e}");
    let e = atlas.choice(atlas.count()).expect_err("past the count");
    assert!(e.to_string().contains("past"), "{e}");
    let e = atlas
        .assemble(&Choice {
            graph: 0,
            picks: vec![vec![7]; 6],
        })
        .expect_err("no variant 7");
    assert!(e.to_string().contains("entry 7"), "{e}");
    let e = worldpaint_core::new_intersection(&t.model, &[None; 3], &IntersectionLabels::default())
        .expect_err("face origins of the wrong length");
    assert!(e.to_string().contains("face origins"), "{e}");
    let mut broken = t.model.clone();
    broken.faces[0][0] = 99_999;
    assert!(broken.validate().is_err());
    let _ = IntersectionLabels::of_model(&broken); // no panic: the bad face's triangles are left out
    let mut moved_root = d.clone();
    moved_root.root = 99;
    let e = Atlas::new(&t.model, moved_root).expect_err("a root that does not exist");
    assert!(e.to_string().contains("root 99"), "{e}");
    let e = Atlas::new(&column().0, d.clone()).expect_err("another model");
    assert!(
        e.to_string().contains("decomposition was made of one"),
        "{e}"
    );
    let e = Image::new(4, 4, vec![0; 10]).expect_err("short image");
    assert!(e.to_string().contains("image"), "{e}");
    let e = TextureComponent::from_edit(
        &t.model,
        &Image::new(2, 2, vec![0; 16]).expect("image"),
        &Image::new(2, 2, vec![0; 16]).expect("image"),
    )
    .expect_err("nothing painted");
    assert!(e.to_string().contains("nothing was painted"), "{e}");
}

/// The mean of the vertices of component `c`'s faces in an assembly.
fn component_centre(a: &worldpaint_core::Assembled, c: u32) -> DVec3 {
    let mut used: Vec<u32> = a
        .model
        .faces
        .iter()
        .zip(&a.face_component)
        .filter(|(_, &k)| k == c)
        .flat_map(|(f, _)| f.iter().copied())
        .collect();
    used.sort_unstable();
    used.dedup();
    used.iter()
        .map(|&v| a.model.vertices[v as usize])
        .sum::<DVec3>()
        / used.len() as f64
}

/// An order-free key of a model's geometry: each face's corners quantised to 1e-5 m (as `Assembled::hash`), started
/// at its least corner, the faces sorted. Two models with the same faces at the same places have the same key.
fn shape_key(m: &Model) -> Vec<Vec<[i64; 3]>> {
    let mut faces: Vec<Vec<[i64; 3]>> = m
        .faces
        .iter()
        .map(|f| {
            let q: Vec<[i64; 3]> = f
                .iter()
                .map(|&v| {
                    let p = m.vertices[v as usize] * 1e5;
                    [p.x.round() as i64, p.y.round() as i64, p.z.round() as i64]
                })
                .collect();
            let first = (0..q.len()).min_by_key(|&k| q[k]).unwrap_or(0);
            q[first..].iter().chain(&q[..first]).copied().collect()
        })
        .collect();
    faces.sort();
    faces
}

/// Asks for every assembly of the atlas: (made, distinct shapes among them, rejected).
fn made_and_distinct(atlas: &Atlas, model: &Model) -> (usize, usize, usize) {
    let labels = IntersectionLabels::of_model(model);
    let options = GenerateOptions {
        count: atlas.count() as usize,
        seed: 1,
        max_attempts: 0,
    };
    let g = generate_variants(atlas, &labels, &options).expect("generate");
    let shapes: HashSet<Vec<Vec<[i64; 3]>>> = g
        .accepted
        .iter()
        .map(|(_, a)| shape_key(&a.model))
        .collect();
    for (choice, a) in &g.accepted {
        assert!(a.max_gap <= 1e-6 && a.model.is_watertight(), "{choice:?}");
    }
    (g.accepted.len(), shapes.len(), g.rejected.len())
}

/// Whether model vertex `v` lies on a connecting region.
fn on_region(d: &Decomposition, v: usize) -> bool {
    d.regions.iter().any(|r| r.vertices.contains(&(v as u32)))
}

/// The ring of four parts with two local edits of each (its middle section pushed out from the ring's axis, its
/// three inner sections flattened): 3^4 = 81 different rings.
fn ring_atlas() -> (Model, Decomposition, Atlas) {
    let (model, labels, place) = ring();
    let d = Decomposition::from_labels(&model, &labels, None).expect("decomposition");
    assert!(d.components.len() == 4 && d.is_fully_cyclic());
    let mut atlas = Atlas::new(&model, d.clone()).expect("atlas");
    for c in 0..4 {
        let first = 4 * d.components[c].label as usize;
        let bulged = moved_piece(&model, &d, c, |v, p| {
            if place[v].0 == first + 2 {
                p + DVec3::new(p.x, p.y, 0.0).normalize() * 0.2
            } else {
                p
            }
        });
        let flat = moved_piece(&model, &d, c, |v, p| {
            if (first + 1..=first + 3).contains(&place[v].0) {
                DVec3::new(p.x, p.y, p.z * 0.6)
            } else {
                p
            }
        });
        for edit in [bulged, flat] {
            assert_eq!(
                atlas.add_variant(c, edit).expect("a local edit"),
                VariantClass::Local
            );
        }
    }
    (model, d, atlas)
}

#[test]
fn a_ring_of_four_parts_counts_only_different_models() {
    let (model, d, mut atlas) = ring_atlas();
    let names: Vec<String> = (0..4)
        .map(|c| format!("Ring Parts/Ring part {}", d.components[c].label))
        .collect();
    atlas.set_names(names.clone()).expect("names");
    assert_eq!(atlas.count(), 81);
    // A third copy of a part next to the root, turned whole 10° about the ring's axis (its two sections with it):
    // the assembly keeps the sections where the neighbours have them, so it would be the original again (counted
    // before as a 4th piece: 108 possible, 81 different). It is refused by name.
    let c = (0..4)
        .find(|&c| d.parent(c).is_some_and(|(p, _)| p == d.root))
        .expect("a part next to the root");
    let parent = d.parent(c).map(|(p, _)| p).unwrap_or(d.root);
    let turn = glam::DQuat::from_rotation_z(10f64.to_radians());
    let turned = moved_piece(&model, &d, c, |_, p| turn * p);
    let e = atlas
        .add_named_variant(c, "Part turned", turned)
        .expect_err("a part of a ring turned whole is refused");
    println!("  refused: {e}");
    let msg = e.to_string();
    for needle in [
        format!("copy 'Part turned' in '{}'", names[c]),
        format!("connecting region with '{}'", names[parent]),
        "the whole piece".to_string(),
        "ring".to_string(),
    ] {
        assert!(msg.contains(&needle), "{needle:?} in {msg}");
    }
    // the root turned whole moves every part with it: no new ring either
    let root_turned = moved_piece(&model, &d, d.root, |_, p| turn * p);
    let e = atlas
        .add_named_variant(d.root, "Root turned", root_turned)
        .expect_err("the root turned whole is refused");
    println!("  refused: {e}");
    assert!(e
        .to_string()
        .contains(&format!("copy 'Root turned' in '{}'", names[d.root])));
    // a copy left as it was, and a copy of a copy, would only repeat models
    let same = d.component_model(&model, c).expect("piece");
    let e = atlas
        .add_named_variant(c, "Part.001", same)
        .expect_err("an unedited copy");
    println!("  refused: {e}");
    assert!(e.to_string().contains("copy 'Part.001'") && e.to_string().contains("original piece"));
    let again = atlas.variants(c)[1].model.clone();
    let e = atlas
        .add_named_variant(c, "Part.002", again)
        .expect_err("a copy of a copy");
    println!("  refused: {e}");
    assert!(e.to_string().contains("same shape as copy 'copy 1'"), "{e}");
    assert_eq!(atlas.count(), 81, "none of them counted");
    let (made, distinct, rejected) = made_and_distinct(&atlas, &model);
    println!("  ring of four parts, three pieces each: 81 possible, {made} made, {distinct} different, {rejected} rejected");
    assert_eq!((made, distinct, rejected), (81, 81, 0));
}

/// How an edit moves a vertex: (vertex of the model, position) to its new position.
type MoveVertex<'a> = dyn Fn(usize, DVec3) -> DVec3 + 'a;

/// The cactus's atlas: two or three pieces per part, 3^4 × 2^3 = 648 different cacti. Arm B's copy is turned from
/// its elbow (its ring to the tip turned as a solid: the tip follows).
fn cactus_atlas() -> (variety_models::Cactus, Decomposition, Atlas) {
    let cactus = cactus();
    let (model, parts) = (&cactus.model, &cactus.parts);
    let d = Decomposition::from_labels(model, &cactus.labels, Some(0)).expect("decomposition");
    assert!(d.components.len() == 7 && d.is_tree_like());
    let mut atlas = Atlas::new(model, d.clone()).expect("atlas");
    let radial = |p: DVec3, f: f64| DVec3::new(p.x * f, p.y * f, p.z);
    let centre = |a: usize, k: usize| {
        let ring: Vec<DVec3> = (0..parts.len())
            .filter(|&v| parts[v] == CactusPart::Arm(a, k))
            .map(|v| model.vertices[v])
            .collect();
        ring.iter().copied().sum::<DVec3>() / ring.len() as f64
    };
    let free = |v: usize, part: CactusPart| parts[v] == part && !on_region(&d, v);
    let bend = {
        let (elbow, out) = (centre(1, 2), centre(1, 2) - centre(1, 1));
        let axis = DVec3::Z.cross(out).normalize();
        glam::DAffine3::from_translation(elbow)
            * glam::DAffine3::from_axis_angle(axis, 15f64.to_radians())
            * glam::DAffine3::from_translation(-elbow)
    };
    let edits: Vec<(u32, Box<MoveVertex>)> = vec![
        (
            0,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Trunk(0) {
                    radial(p, 1.3)
                } else {
                    p
                }
            }),
        ),
        (
            0,
            Box::new(|v, p| {
                if free(v, CactusPart::Trunk(2)) {
                    radial(p, 1.15)
                } else {
                    p
                }
            }),
        ),
        (
            1,
            Box::new(|v, p| {
                if free(v, CactusPart::Trunk(4)) {
                    radial(p, 1.15)
                } else {
                    p
                }
            }),
        ),
        (
            1,
            Box::new(|v, p| {
                if free(v, CactusPart::Trunk(5)) {
                    radial(p, 0.88)
                } else {
                    p
                }
            }),
        ),
        (
            2,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Trunk(9) {
                    p + DVec3::Z * 0.5
                } else {
                    p
                }
            }),
        ),
        (
            2,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Trunk(7) {
                    radial(p, 1.15)
                } else {
                    p
                }
            }),
        ),
        (
            3,
            Box::new(|v, p| {
                let c = centre(0, 2);
                if parts[v] == CactusPart::Arm(0, 2) {
                    c + (p - c) * 1.3
                } else {
                    p
                }
            }),
        ),
        (
            3,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Arm(0, 3) {
                    p + DVec3::Z * 0.15
                } else {
                    p
                }
            }),
        ),
        (
            4,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Arm(0, 6) {
                    p + DVec3::Z * 0.3
                } else {
                    p
                }
            }),
        ),
        (
            5,
            Box::new(|v, p| match parts[v] {
                CactusPart::Arm(1, k) if k >= 3 => bend.transform_point3(p),
                _ => p,
            }),
        ),
        (
            6,
            Box::new(|v, p| {
                if parts[v] == CactusPart::Arm(1, 6) {
                    p + DVec3::Z * 0.3
                } else {
                    p
                }
            }),
        ),
    ];
    for (label, edit) in edits {
        let c = d
            .components
            .iter()
            .position(|k| k.label == label)
            .expect("part");
        let class = atlas
            .add_variant(c, moved_piece(model, &d, c, edit))
            .expect("a variant");
        let solid = label == 5;
        assert_eq!(
            class == VariantClass::SolidTransform,
            solid,
            "part {label}: {class:?}"
        );
    }
    (cactus, d, atlas)
}

#[test]
fn a_cactus_with_an_arm_turned_whole_counts_only_different_models() {
    let (cactus, d, mut atlas) = cactus_atlas();
    let (model, parts) = (&cactus.model, &cactus.parts);
    let names: Vec<String> = (0..7)
        .map(|c| format!("Cactus Parts/Cactus part {}", d.components[c].label))
        .collect();
    atlas.set_names(names.clone()).expect("names");
    let part = |label: u32| {
        d.components
            .iter()
            .position(|k| k.label == label)
            .expect("part")
    };
    let (arm, tip) = (part(3), part(4));
    assert_eq!(atlas.count(), 648);
    let (made, distinct, rejected) = made_and_distinct(&atlas, model);
    println!("  cactus, arm B's copy turned from its elbow: 648 possible, {made} made, {distinct} different, {rejected} rejected");
    assert_eq!((made, distinct, rejected), (648, 648, 0));

    // Arm A's piece turned whole 20° about the trunk's axis, its rings on the trunk and to the tip with it: counted
    // before as a 4th piece (864 possible, 648 different), refused now by name.
    let turn = glam::DQuat::from_rotation_z(20f64.to_radians());
    let turned = moved_piece(model, &d, arm, |_, p| turn * p);
    let e = atlas
        .add_named_variant(arm, "Arm turned", turned)
        .expect_err("an arm turned whole is refused");
    println!("  refused: {e}");
    let msg = e.to_string();
    for needle in [
        "copy 'Arm turned' in 'Cactus Parts/Cactus part 3'",
        "turns or moves its connecting region with 'Cactus Parts/Cactus part 0'",
        "the whole piece",
        "turn the rest of the piece about it",
    ] {
        assert!(msg.contains(needle), "{needle:?} in {msg}");
    }
    // turned whole after its elbow was raised: most of the piece moves with the ring, refused the same way
    let raised_and_turned = moved_piece(model, &d, arm, |v, p| {
        turn * if parts[v] == CactusPart::Arm(0, 3) {
            p + DVec3::Z * 0.3
        } else {
            p
        }
    });
    let e = atlas
        .add_named_variant(arm, "Arm raised and turned", raised_and_turned)
        .expect_err("an arm turned with its ring is refused");
    println!("  refused: {e}");
    assert!(e.to_string().contains("12 of its 16 other vertices"), "{e}");
    assert_eq!(atlas.count(), 648);

    // Arm A's tip with its ring to the arm stretched along x (§4.2.3: the arm is adapted in a duplicated graph):
    // 648 + 324 models, all different. The same ring stretched from the arm's side would repeat some of them (1,188
    // possible, 1,080 different) and is refused.
    let ring4: Vec<usize> = (0..parts.len())
        .filter(|&v| parts[v] == CactusPart::Arm(0, 4))
        .collect();
    let centre = ring4.iter().map(|&v| model.vertices[v]).sum::<DVec3>() / 4.0;
    let widen = |v: usize, p: DVec3| {
        if ring4.contains(&v) {
            DVec3::new(centre.x + (p.x - centre.x) * 1.3, p.y, p.z)
        } else {
            p
        }
    };
    let wide_tip = moved_piece(model, &d, tip, widen);
    assert_eq!(
        atlas
            .add_named_variant(tip, "Tip wide", wide_tip)
            .expect("a reshaped ring"),
        VariantClass::RegionChange
    );
    assert_eq!(atlas.count(), 972);
    let wide_arm = moved_piece(model, &d, arm, widen);
    let e = atlas
        .add_named_variant(arm, "Arm wide", wide_arm)
        .expect_err("the same ring reshaped from both sides");
    println!("  refused: {e}");
    assert!(
        e.to_string()
            .contains("exactly as copy 'Tip wide' in 'Cactus Parts/Cactus part 4'"),
        "{e}"
    );
    let (made, distinct, rejected) = made_and_distinct(&atlas, model);
    println!("  cactus with a reshaped ring: 972 possible, {made} made, {distinct} different, {rejected} rejected");
    assert_eq!((made, distinct, rejected), (972, 972, 0));
    // two copies that each reshape a ring cannot be picked together, and the message names them
    let top = part(2);
    let ring6: Vec<usize> = (0..parts.len())
        .filter(|&v| parts[v] == CactusPart::Trunk(6))
        .collect();
    let oval = moved_piece(model, &d, top, |v, p| {
        if ring6.contains(&v) {
            DVec3::new(p.x * 1.2, p.y, p.z)
        } else {
            p
        }
    });
    assert_eq!(
        atlas
            .add_named_variant(top, "Top oval", oval)
            .expect("a reshaped ring"),
        VariantClass::RegionChange
    );
    let mut picks = vec![0; 7];
    picks[top] = atlas.variants(top).len() - 1;
    picks[tip] = atlas.variants(tip).len() - 1;
    let e = atlas
        .choice_of_variants(&picks)
        .expect_err("two reshaped rings");
    println!("  refused: {e}");
    assert!(
        e.to_string().contains(
            "copy 'Top oval' in 'Cactus Parts/Cactus part 2' and copy 'Tip wide' in 'Cactus Parts/Cactus part 4' \
             each reshape a connecting region"
        ),
        "{e}"
    );
}
