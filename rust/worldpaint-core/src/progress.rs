//! Progress of work done item by item on several threads: each finished item reports the fraction done so far, in
//! order (the reports never go back), and a report answered with `false` stops the items that have not started
//! yet.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Counts the finished items of a parallel loop of `total` items and reports each to `report`.
pub(crate) struct Counted<F: Fn(f64) -> bool + Sync> {
    total: usize,
    /// Items finished; held while reporting, so that the reports come in order.
    done: Mutex<usize>,
    stopped: AtomicBool,
    report: F,
}

impl<F: Fn(f64) -> bool + Sync> Counted<F> {
    pub(crate) fn new(total: usize, report: F) -> Self {
        Counted {
            total,
            done: Mutex::new(0),
            stopped: AtomicBool::new(false),
            report,
        }
    }

    /// Whether the next item should start (no report has asked to stop).
    pub(crate) fn go_on(&self) -> bool {
        !self.stopped.load(Ordering::Relaxed)
    }

    /// One more item is finished.
    pub(crate) fn done_one(&self) {
        let Ok(mut done) = self.done.lock() else {
            return;
        };
        *done += 1;
        if !(self.report)(*done as f64 / self.total.max(1) as f64) {
            self.stopped.store(true, Ordering::Relaxed);
        }
    }

    /// [`Error::Cancelled`] when a report asked to stop: the loop's result is then incomplete.
    pub(crate) fn finish(self) -> Result<()> {
        if self.stopped.into_inner() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}
