//! Real forest: a color learned from the western half of the Luquillo hectare, painted into the eastern half,
//! against the real eastern trees (see `support/forest.rs`). Prints the report (`--nocapture`) and checks loose
//! sanity only: the painted density is within 15% of the real one, and the painted trees follow the slopes at
//! least about as well as a Poisson-disk scatter that ignores the terrain.

#[path = "common/forest_report.rs"]
mod forest;
#[path = "common/real_data.rs"]
mod real_data;

#[test]
#[ignore = "needs shared/data/real (make test-rust runs it where present)"]
fn luquillo_east_from_west() {
    let report = match forest::run() {
        Ok(r) => r,
        Err(e) => panic!("forest report failed: {e}"),
    };
    println!("{}", report.table());
    let s = &report.synthesized;
    assert!(
        (s.density_ratio - 1.0).abs() <= 0.15,
        "synthesized density is {:.3} x the real eastern density (allowed 0.85..1.15)",
        s.density_ratio
    );
    let limit = 1.5 * report.poisson_disk.slope_tv + 0.05;
    assert!(
        s.slope_tv <= limit,
        "synthesized slope TV {:.4} exceeds 1.5 x the Poisson-disk's {:.4} + 0.05 = {limit:.4}",
        s.slope_tv,
        report.poisson_disk.slope_tv
    );
}
