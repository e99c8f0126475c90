//! `--arcs fit` in the program printer: the run of straight feed moves
//! held back and what was fitted (the printer's side of it is in
//! `program.rs`'s second `impl`). Straight feed moves are held back
//! while they may form a run (one plane, one feed, nothing between them
//! but repeats of that feed), at most [`MOST_HELD`] at a time so memory
//! stays flat; then [`fit`](super::super::fit) chooses which stretches
//! become arcs and the run is printed, lines as they would have been and
//! arcs from exactly the numbers it proved.
//!
//! It must not change anything else: a statement that cannot join a run
//! first prints the run held, then goes its usual way.

use crate::ir;
use crate::source::Span;

/// The most moves held back: a run longer than this is fitted in parts.
pub(super) const MOST_HELD: usize = 4096;

/// The run held back, and what was fitted so far.
#[derive(Default)]
pub(super) struct Fitting {
    pub(super) tolerance: f64,
    /// The moves of the run, as given.
    pub(super) moves: Vec<ir::Stmt>,
    /// Where the run starts and each move ends (plane order: first,
    /// second, normal axis), and the same as printed.
    pub(super) exact: Vec<[f64; 3]>,
    pub(super) printed: Vec<[i64; 3]>,
    /// The feed of the run's moves, on the output grid.
    pub(super) feed: Option<i64>,
    /// G93 or compensation kept for the controller: a run's time or its
    /// offset corners would change, so nothing is fitted.
    pub(super) inverse_time: bool,
    pub(super) compensating: bool,
    /// Lines written as arcs, the arcs, and the first arc's line.
    pub(super) lines_fitted: usize,
    pub(super) arcs: usize,
    /// How much shorter the arcs are than the lines they replace.
    pub(super) bytes_saved: usize,
    pub(super) first: Option<Span>,
    /// `--stage fit`: each arc names the source lines it replaces.
    pub(super) name_runs: bool,
}

impl Fitting {
    /// `tolerance` in the output `units`, if given.
    pub fn new(tolerance: Option<f64>, units: Option<ir::Units>) -> Box<Fitting> {
        let tolerance = tolerance.unwrap_or(match units {
            Some(ir::Units::Mm) => 0.005,
            Some(ir::Units::Inch) | None => 0.0002,
        });
        Box::new(Fitting {
            tolerance,
            ..Fitting::default()
        })
    }
}

pub(super) fn exact_of(position: &ir::Position, i: usize) -> f64 {
    position[i].unwrap_or(0.0)
}
