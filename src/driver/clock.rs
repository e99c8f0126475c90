//! The time each stage of one compile took (`ger compile --timings`).

use std::time::{Duration, Instant};

/// Times the stages of one compile.
pub(super) struct Clock {
    pub(super) last: Instant,
    pub(super) timings: Vec<(&'static str, Duration)>,
    /// Time the next lap spent on a stage reported apart.
    pub(super) inside: Duration,
}

impl Clock {
    pub(super) fn new() -> Clock {
        Clock {
            last: Instant::now(),
            timings: Vec::new(),
            inside: Duration::ZERO,
        }
    }

    pub(super) fn lap(&mut self, stage: &'static str) {
        self.split(stage, &[]);
    }

    /// A lap that ran `parts` inside it: they are reported after it, and
    /// its own time without them.
    pub(super) fn split(&mut self, stage: &'static str, parts: &[(&'static str, Duration)]) {
        let now = Instant::now();
        let inner =
            parts.iter().map(|(_, d)| *d).sum::<Duration>() + std::mem::take(&mut self.inside);
        self.timings
            .push((stage, (now - self.last).saturating_sub(inner)));
        self.timings.extend_from_slice(parts);
        self.last = now;
    }

    /// Time the next lap spends on a stage reported apart (the passes the
    /// evaluator's thread runs, reported with the lowering).
    pub(super) fn ran_inside(&mut self, took: Duration) {
        self.inside += took;
    }

    /// Stages timed on another thread, at the same time as the last lap:
    /// reported, not taken from it.
    pub(super) fn add(&mut self, stages: &[(&'static str, Duration)]) {
        self.timings.extend_from_slice(stages);
    }
}
