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
mod comp;
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
/// arm, and changes nothing but what its stage lowers. A pass is `Send`:
/// the back end runs on a thread of its own (`compile::on_two_threads`).
pub trait Pass: Send {
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
    /// `--comp keep`: G41/G42/G40 stay in the output, for the controller.
    pub keep_comp: bool,
    /// `--comp-entry lookahead`: the entry move goes straight to the
    /// offset start of the move after it (Ger's entry), not rs274's.
    pub comp_entry_lookahead: bool,
    /// The path of the tool's tip (`ger render`): G43/G44 change nothing,
    /// whether the length is known or not. Off, a known length is folded
    /// into Z as the machine would apply it (rs274's controlled point).
    pub tip_path: bool,
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
    comp::PASS,
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
    /// Takes the statements on when there are [`CHUNK`] of them.
    full: &'a mut dyn FnMut(&mut Vec<Stmt>),
}

impl Out<'_> {
    pub fn push(&mut self, stmt: Stmt) {
        self.stmts.push(stmt);
        if self.stmts.len() >= CHUNK {
            if self.problems.errors > 0 {
                // The output is thrown away.
                self.stmts.clear();
            } else {
                (self.full)(self.stmts);
            }
        }
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

    /// Lower the next statements of the program (`batch` is emptied): what
    /// comes out of the last pass goes to `sink`, in pieces of at most
    /// [`CHUNK`] statements or so, and only while no pass has failed. A
    /// pass that makes many statements of one (a cycle with many pecks)
    /// is passed on as it goes, so memory stays bounded.
    pub fn run(&mut self, batch: &mut Vec<Stmt>, sink: &mut dyn FnMut(&mut Vec<Stmt>)) {
        flow(&mut self.passes, &mut self.buffers, batch, false, sink);
    }

    /// The end of the program: the passes flush in order, the rest goes to
    /// `sink`.
    pub fn finish(&mut self, sink: &mut dyn FnMut(&mut Vec<Stmt>)) {
        flow(
            &mut self.passes,
            &mut self.buffers,
            &mut Vec::new(),
            true,
            sink,
        );
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

/// A pass's output is handed on once it holds this many statements.
pub const CHUNK: usize = 4096;

/// Run `input` through `passes` (and flush them if `last`), depth first:
/// a pass's output goes on to the next pass whenever it reaches [`CHUNK`]
/// statements (even in the middle of one statement's expansion), and the
/// last pass's to `sink`. After a pass has failed nothing more comes out
/// of it: the later passes' problems would only follow from its own, and
/// are not reported.
fn flow(
    passes: &mut [(Box<dyn Pass>, Problems)],
    buffers: &mut [Vec<Stmt>],
    input: &mut Vec<Stmt>,
    last: bool,
    sink: &mut dyn FnMut(&mut Vec<Stmt>),
) {
    let (Some(((pass, problems), later)), Some((buffer, later_buffers))) =
        (passes.split_first_mut(), buffers.split_first_mut())
    else {
        if !input.is_empty() {
            sink(input);
        }
        input.clear();
        return;
    };
    let mut output = std::mem::take(buffer);
    {
        let mut next = |o: &mut Vec<Stmt>| flow(later, later_buffers, o, false, sink);
        let mut out = Out {
            stmts: &mut output,
            problems,
            full: &mut next,
        };
        for stmt in input.drain(..) {
            pass.feed(stmt, &mut out);
        }
        if last {
            pass.finish(&mut out);
        }
    }
    if problems.errors > 0 {
        output.clear();
    } else if last || !output.is_empty() {
        flow(later, later_buffers, &mut output, last, sink);
    }
    *buffer = output;
}
