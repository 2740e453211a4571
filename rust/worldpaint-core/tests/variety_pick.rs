//! Picking a variant of each component by hand (seed §4.3: the user "can also pick components"), on the birch of
//! `assets/`: the assembly shows exactly the picked variants, the original's picks rebuild the original, and a pick
//! past a component's variants is refused with a message.

mod common;

use common::birch::{birch, birch_atlas};
use worldpaint_core::{check_assembly, IntersectionLabels};

#[test]
fn the_variants_picked_by_hand_are_the_ones_assembled() {
    let b = birch();
    let (_, atlas, _) = birch_atlas(&b);
    let labels = IntersectionLabels::of_model(&b.model);

    let original = atlas
        .choice_of_variants(&[0; 6])
        .expect("the original's picks");
    let rebuilt = check_assembly(&atlas, &labels, &original)
        .expect("assembles")
        .expect("the original has no new intersection");
    // the assembly numbers its vertices its own way: each stands where one of the birch's does
    let furthest = rebuilt
        .model
        .vertices
        .iter()
        .map(|a| {
            b.model
                .vertices
                .iter()
                .map(|o| a.distance(*o))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    println!(
        "picks [0; 6]: {} faces (the birch has {}), vertices at most {furthest:.2e} m from the birch's",
        rebuilt.model.faces.len(),
        b.model.faces.len()
    );
    assert_eq!(rebuilt.model.faces.len(), b.model.faces.len());
    assert!(furthest < 1e-9, "the original's picks rebuild the birch");

    let picks = [1, 2, 0, 1, 2, 1];
    let choice = atlas.choice_of_variants(&picks).expect("a valid pick");
    let picked = check_assembly(&atlas, &labels, &choice)
        .expect("assembles")
        .expect("no new intersection");
    let shown: Vec<usize> = (0..6)
        .map(|c| {
            let placed = picked
                .instances
                .iter()
                .find(|p| p.component == c)
                .expect("every component placed");
            placed.variant
        })
        .collect();
    println!(
        "picks {picks:?}: variants shown {shown:?}, hash {:x}",
        picked.hash
    );
    assert_eq!(shown, picks);
    assert_ne!(picked.hash, rebuilt.hash);

    let err = atlas
        .choice_of_variants(&[0, 0, 0, 3, 0, 0])
        .expect_err("the crown has 3 variants");
    println!("a pick past the variants: {err}");
    assert!(err
        .to_string()
        .contains("'component 3' has variants 0 (its original) to 2, not 3"));
    assert!(
        atlas.choice_of_variants(&[0; 5]).is_err(),
        "a pick per component"
    );
}
