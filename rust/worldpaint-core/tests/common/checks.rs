//! Acceptance checks of the reports against real data: what is measured, the bound, and
//! whether it holds; the test fails naming every check that does not.

/// One acceptance check.
pub struct Check {
    pub what: String,
    pub measured: String,
    pub bound: String,
    pub holds: bool,
}

/// Fails the test with every check that does not hold.
pub fn assert_all_hold(checks: &[Check]) {
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.holds)
        .map(|c| format!("{}: {} (bound {})", c.what, c.measured, c.bound))
        .collect();
    assert!(
        failed.is_empty(),
        "real-village checks failed: {}",
        failed.join("; ")
    );
}
