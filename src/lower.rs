//! Lowering: IR → simpler IR, one pass per stage of SPEC §4, applied in a
//! fixed order by [`Lowering`]. Each pass is a state machine in its own
//! file: `State::run` lowers a batch of statements in place (it may drop
//! statements, and never reorders them), keeping between batches only what
//! the program has made modal so far. The statements stream through the
//! passes in program order, so a pass sees the same sequence whatever the
//! batch size. A pass can be stopped after (`--stage NAME`). Passes never
//! see the AST and never print.
//!
//! Order: units → polar → offsets → absolute. Polar runs before offsets
//! (SPEC §4 lists it after): a G90 polar point is relative to the program
//! zero, so it must become a Cartesian program point before the offsets
//! pass folds the program zero away. The result is the same tool path.

mod absolute;
mod offsets;
mod polar;
mod units;

use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::ir;
use crate::source::Span;

/// The lowering passes, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Pass {
    Units,
    Polar,
    Offsets,
    Absolute,
}

impl Pass {
    pub const ALL: [Pass; 4] = [Pass::Units, Pass::Polar, Pass::Offsets, Pass::Absolute];

    pub fn name(self) -> &'static str {
        match self {
            Pass::Units => "units",
            Pass::Polar => "polar",
            Pass::Offsets => "offsets",
            Pass::Absolute => "absolute",
        }
    }
}

/// The passes up to a stage, with each one's state between batches.
pub struct Lowering {
    last: Pass,
    units: units::State,
    polar: polar::State,
    offsets: offsets::State,
    absolute: absolute::State,
}

impl Lowering {
    /// Passes `Pass::ALL` up to and including `last`, for a program with
    /// this setup, written in `output_units`.
    pub fn new(setup: &ir::Setup, output_units: ir::Units, last: Pass) -> Lowering {
        Lowering {
            last,
            units: units::State::new(output_units),
            polar: polar::State::new(),
            offsets: offsets::State::new(setup),
            absolute: absolute::State::new(),
        }
    }

    /// Lower the next statements of the program, in place.
    pub fn run(&mut self, stmts: &mut Vec<ir::Stmt>) {
        for pass in Pass::ALL {
            match pass {
                Pass::Units => self.units.run(stmts),
                Pass::Polar => self.polar.run(stmts),
                Pass::Offsets => self.offsets.run(stmts),
                Pass::Absolute => self.absolute.run(stmts),
            }
            if pass == self.last {
                break;
            }
        }
    }

    /// Has a pass reported an error? Then the output will be thrown away.
    pub fn failed(&self) -> bool {
        [
            &self.polar.errors,
            &self.offsets.errors,
            &self.absolute.errors,
        ]
        .iter()
        .any(|e| !e.0.is_empty())
    }

    /// The end of the program: the errors of the first pass that had any
    /// (a later pass's errors may only follow from them), as when each
    /// pass ran over the whole program before the next.
    pub fn finish(self) -> Result<(), Vec<Diagnostic>> {
        for errors in [self.polar.errors, self.offsets.errors, self.absolute.errors] {
            if !errors.0.is_empty() {
                return Err(errors.0);
            }
        }
        Ok(())
    }
}

/// Collects the diagnostics of one pass; the pass goes on after an error
/// where it can, so one run reports every independent problem.
#[derive(Default)]
pub(crate) struct Errors(Vec<Diagnostic>);

impl Errors {
    fn push(&mut self, d: Diagnostic) {
        // A statement in a loop fails every time; say it once.
        let same = |e: &Diagnostic| e.message == d.message && e.labels == d.labels;
        if self.0.len() < 50 && !self.0.iter().rev().take(8).any(same) {
            self.0.push(d);
        }
    }
}

/// `what` (a move, G92, …) needs the position of an axis no move has set.
fn unknown_position(span: Span, axis: usize, what: &str) -> Diagnostic {
    let letter = ['X', 'Y', 'Z'][axis];
    error(
        format!("{what} needs the current {letter} position, which is not known"),
        span,
        format!("no move has set {letter} yet"),
    )
    .with_help(format!("move to an absolute {letter} position first"))
}
