//! Lowering: IR → simpler IR, one pass per stage of SPEC §4, applied in
//! the fixed order of [`PASSES`]. A pass is a [`Pass`]: it is fed the
//! statements one at a time and may send zero, one or many statements on
//! for each, keep look-ahead state, and flush it in [`Pass::finish`] at the
//! end of the program. The passes are chained as a stream by [`Pipeline`]:
//! no whole-program vector lies between them, so memory is bounded by the
//! batch and by what the passes hold back. Passes never see the AST and
//! never print.
//!
//! Order: units → polar → offsets → cycles → absolute → comp. Polar runs
//! before offsets (SPEC §4 lists it after): a G90 polar point is relative
//! to the program zero, so it must become a Cartesian program point before
//! the offsets pass folds the program zero away. Cycles run before
//! absolute because their G91 words are not plain increments; comp runs
//! last, on absolute machine coordinates.

mod absolute;
mod cycles;
mod error;
mod offsets;
mod polar;
mod position;
mod units;

pub use error::{LowerError, LowerErrorKind};

use crate::diagnostic::Diagnostic;
use crate::ir::{self, Stmt};

/// A lowering pass: a state machine over the statement stream.
///
/// Architecture invariant: a pass matches [`ir::Op`] without a catch-all
/// arm, and changes nothing but what its stage lowers.
pub trait Pass {
    /// Lower one statement: send what it becomes (nothing, itself, or
    /// several statements) to `out`, now or later.
    fn feed(&mut self, stmt: Stmt, out: &mut Out<'_>);

    /// The program has ended: send what is held back, and report a state
    /// that cannot be closed.
    fn finish(&mut self, out: &mut Out<'_>) {
        let _ = out;
    }
}

/// What a pass is made from.
pub struct Context<'a> {
    pub start: &'a ir::Start,
    pub options: &'a LowerOptions,
}

/// How the passes lower what controllers differ on.
#[derive(Clone, Debug, Default)]
pub struct LowerOptions {
    /// `--cycles keep`: canned cycles stay in the output, normalised.
    pub keep_cycles: bool,
}

/// A pass in the registry: its stage name and how to make it.
pub struct PassInfo {
    pub name: &'static str,
    pub make: fn(&Context<'_>) -> Box<dyn Pass>,
}

/// Every lowering pass, in the order it runs. `--stage NAME` stops after
/// the pass of that name. A new pass is a file and a line here.
pub const PASSES: &[PassInfo] = &[
    units::PASS,
    polar::PASS,
    offsets::PASS,
    cycles::PASS,
    absolute::PASS,
];

/// The index in [`PASSES`] of the pass named `name`.
pub fn pass_index(name: &str) -> Option<usize> {
    PASSES
        .iter()
        .position(|p| p.name.eq_ignore_ascii_case(name))
}

/// Where a pass sends its statements and its problems.
pub struct Out<'a> {
    stmts: &'a mut Vec<Stmt>,
    problems: &'a mut Problems,
}

impl Out<'_> {
    pub fn push(&mut self, stmt: Stmt) {
        self.stmts.push(stmt);
    }

    pub fn report(&mut self, e: LowerError) {
        self.problems.push(e);
    }

    /// Has this pass reported an error? (There will be no output.)
    pub fn failed(&self) -> bool {
        self.problems.errors > 0
    }
}

/// The problems one pass found; it goes on after an error where it can,
/// so one run reports every independent problem.
#[derive(Default)]
struct Problems {
    list: Vec<LowerError>,
    errors: usize,
}

impl Problems {
    fn push(&mut self, e: LowerError) {
        // A statement in a loop fails every time; say it once.
        if self.list.iter().rev().take(8).any(|p| *p == e) {
            return;
        }
        if e.is_error() {
            self.errors += 1;
        }
        if self.list.len() < 50 {
            self.list.push(e);
        }
    }
}

/// The passes up to a stage, chained.
pub struct Pipeline {
    passes: Vec<(Box<dyn Pass>, Problems)>,
    /// Each pass's output, reused between batches.
    buffers: Vec<Vec<Stmt>>,
}

impl Pipeline {
    /// The passes of [`PASSES`] up to and including index `last`.
    pub fn new(context: &Context<'_>, last: usize) -> Pipeline {
        let passes: Vec<(Box<dyn Pass>, Problems)> = PASSES[..=last.min(PASSES.len() - 1)]
            .iter()
            .map(|p| ((p.make)(context), Problems::default()))
            .collect();
        let buffers = passes.iter().map(|_| Vec::new()).collect();
        Pipeline { passes, buffers }
    }

    /// Lower the next statements of the program: `batch` is replaced by
    /// what comes out of the last pass.
    pub fn run(&mut self, batch: &mut Vec<Stmt>) {
        self.flow(batch, false);
    }

    /// The end of the program: the passes flush in order; `batch` gets the
    /// rest of the output.
    pub fn finish(&mut self, batch: &mut Vec<Stmt>) {
        self.flow(batch, true);
    }

    fn flow(&mut self, batch: &mut Vec<Stmt>, last: bool) {
        for ((pass, problems), buffer) in self.passes.iter_mut().zip(&mut self.buffers) {
            let mut out = Out {
                stmts: buffer,
                problems,
            };
            for stmt in batch.drain(..) {
                pass.feed(stmt, &mut out);
            }
            if last {
                pass.finish(&mut out);
            }
            std::mem::swap(batch, buffer);
        }
    }

    /// Has a pass reported an error? Then the output will be thrown away.
    pub fn failed(&self) -> bool {
        self.passes.iter().any(|(_, p)| p.errors > 0)
    }

    /// The passes' diagnostics: warnings, and the errors of the first pass
    /// that had any (a later pass's errors may only follow from them), as
    /// when each pass ran over the whole program before the next.
    pub fn diagnostics(self) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for (_, problems) in self.passes {
            let failed = problems.errors > 0;
            out.extend(problems.list.iter().map(LowerError::to_diagnostic));
            if failed {
                break;
            }
        }
        out
    }
}
