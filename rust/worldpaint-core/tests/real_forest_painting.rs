//! Real forest: a color learned from the western half of the Luquillo hectare, painted into the eastern half with
//! five seeds, against the real eastern trees (see `common/forest_report.rs`). Prints the report (`--nocapture`)
//! and checks what a user would: the painted density is within 15% of the real one; the painted trees' pcf
//! (translation-corrected, 0–50 m) is at most 1.25× as far from the real eastern trees' as the real western trees'
//! is (the natural difference between the halves), and nearer than a uniform scatter's and than a Poisson process
//! that follows the western trees' slope preference; their slope histogram, their counts over 10 m cells and their
//! counts over 50 m squares are at least as close to the real eastern trees' as that Poisson process's, and as the
//! mean of five of its draws.

mod common;
use common::forest_report;

use common::forest_report::mean;

#[test]
#[ignore = "needs shared/data/real (make test-rust runs it where present)"]
fn luquillo_east_from_west() {
    let report = match forest_report::run() {
        Ok(r) => r,
        Err(e) => panic!("forest report failed: {e}"),
    };
    println!("{}", report.table());
    let s = &report.synthesized;
    for r in s {
        assert!(
            (r.density_ratio - 1.0).abs() <= 0.15,
            "{}: density is {:.3} x the real eastern density (allowed 0.85..1.15)",
            r.label,
            r.density_ratio
        );
    }
    let pcf_l2 = mean(s, |r| r.pcf_l2);
    let natural = report.real_west.pcf_l2;
    assert!(
        pcf_l2 <= 1.25 * natural,
        "pcf L2 {pcf_l2:.4} over 1.25 x the natural difference {natural:.4}"
    );
    let (uniform, poisson) = (&report.uniform, &report.slope_poisson);
    assert!(
        pcf_l2 < uniform.pcf_l2,
        "pcf L2 {pcf_l2:.4}, uniform {:.4}",
        uniform.pcf_l2
    );
    assert!(
        pcf_l2 < poisson.pcf_l2,
        "pcf L2 {pcf_l2:.4}, slope Poisson {:.4}",
        poisson.pcf_l2
    );
    let slope_tv = mean(s, |r| r.slope_tv);
    assert!(
        slope_tv <= poisson.slope_tv,
        "slope TV {slope_tv:.4}, slope Poisson {:.4}",
        poisson.slope_tv
    );
    let counts = mean(s, |r| r.count_correlation);
    assert!(
        counts >= poisson.count_correlation,
        "count correlation {counts:.3}, slope Poisson {:.3}",
        poisson.count_correlation
    );
    // over 50 m squares, and against the mean of five Poisson draws as well as the first
    let windows = mean(s, |r| r.window_correlation);
    let poisson_mean = report.slope_poisson_mean();
    for p in [poisson, &poisson_mean] {
        assert!(
            windows >= p.window_correlation,
            "50 m count correlation {windows:.3}, {} {:.3}",
            p.label,
            p.window_correlation
        );
    }
    assert!(
        slope_tv <= poisson_mean.slope_tv,
        "slope TV {slope_tv:.4}, {} {:.4}",
        poisson_mean.label,
        poisson_mean.slope_tv
    );
    assert!(
        counts >= poisson_mean.count_correlation,
        "count correlation {counts:.3}, {} {:.3}",
        poisson_mean.label,
        poisson_mean.count_correlation
    );
}
