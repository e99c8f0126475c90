//! What the editor's hover shows of a variable: every value seen at each
//! place the program reads or sets one ([`Watched`], filled by
//! `watch.rs`). Data only: it knows nothing of the evaluator.

use crate::source::Span;
use std::collections::{HashMap, HashSet};

/// More different values than this at one place are counted no further.
const MAX_DISTINCT: usize = 1_000;

/// Every value seen at each place (a variable read, or the name an
/// assignment sets), by file and byte offset of the place's start.
#[derive(Debug, Default)]
pub struct Watched {
    pub seen: HashMap<(u32, u32), Seen>,
}

/// The numbers seen at one place.
#[derive(Debug, Clone, PartialEq)]
pub struct Seen {
    pub first: f64,
    pub min: f64,
    pub max: f64,
    /// Different values seen (counted up to [`MAX_DISTINCT`]).
    pub distinct: usize,
    bits: HashSet<u64>,
}

impl Seen {
    fn new(v: f64) -> Seen {
        Seen {
            first: v,
            min: v,
            max: v,
            distinct: 1,
            bits: HashSet::from([v.to_bits()]),
        }
    }

    fn add(&mut self, v: f64) {
        self.min = self.min.min(v);
        self.max = self.max.max(v);
        if self.bits.len() < MAX_DISTINCT && self.bits.insert(v.to_bits()) {
            self.distinct = self.bits.len();
        }
    }
}

impl Watched {
    pub(super) fn note(&mut self, span: Span, v: f64) {
        self.seen
            .entry((span.file, span.start))
            .and_modify(|s| s.add(v))
            .or_insert_with(|| Seen::new(v));
    }
}
