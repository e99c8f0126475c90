//! The pass contract: what a lowering pass is ([`Pass`]), what it is made
//! from ([`Context`], [`LowerOptions`]) and where it sends its statements
//! and problems ([`Out`], [`Batch`]). The passes and the pipeline that
//! chains them (`lower.rs`) both import this module; it imports no pass
//! and knows nothing of their order.

use super::error::LowerError;
use crate::ir::{self, Op, Stmt};

/// A lowering pass: a state machine over the statement stream.
///
/// Architecture invariant: a pass matches [`ir::Op`] without a catch-all
/// arm, and changes nothing but what its stage lowers. A pass is `Send`:
/// the back end runs on a thread of its own (`compile::on_two_threads`).
pub trait Pass: Send {
    /// Lower one statement where it lies, and say whether it goes on.
    /// `true`: it goes on, changed or not, after whatever the pass sent
    /// to `out` while lowering it (the common case, which copies nothing).
    /// `false`: it goes no further; what it becomes, if anything, the pass
    /// sends to `out`, now or later (a copy it holds back). A statement
    /// followed by others it makes is sent by the pass too (a copy, then
    /// the others) and answered `false`: what `out` is sent comes before a
    /// statement that goes on.
    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool;

    /// The program has ended: send what is held back, and report a state
    /// that cannot be closed.
    fn finish(&mut self, out: &mut Out<'_>) {
        let _ = out;
    }

    /// Feed the statements of `input` in order, as `flow` does; the
    /// index from which they went on where they lie (the others are in
    /// the output). Made for each pass, so that its `feed` is called
    /// directly, not through the `dyn Pass` of the pipeline once a
    /// statement. A pass may take a batch at once where [`feed_in_turn`]
    /// would only follow its moves (see [`follows_only`]).
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        feed_in_turn(self, input, to)
    }
}

/// [`Pass::feed_each`] one statement at a time, by [`Pass::feed`].
pub fn feed_in_turn<P: Pass + ?Sized>(
    pass: &mut P,
    input: &mut [Stmt],
    to: &mut Batch<'_, '_>,
) -> usize {
    feed_in_turn_quick(pass, input, to, |_, _| false)
}

/// [`feed_in_turn`], where `quick` takes each statement first: `true`
/// where it took it as [`Pass::feed`] would have, the statement going on
/// where it lies with nothing sent or reported (a pass's common case,
/// without making the output `feed` is handed); `false`, untouched, for
/// `feed`.
#[inline(always)]
pub fn feed_in_turn_quick<P: Pass + ?Sized>(
    pass: &mut P,
    input: &mut [Stmt],
    to: &mut Batch<'_, '_>,
    quick: impl Fn(&mut P, &mut Stmt) -> bool,
) -> usize {
    // input[waiting..] went on where they lie, and are not in the
    // output yet.
    let mut waiting = 0;
    for i in 0..input.len() {
        if quick(pass, &mut input[i]) {
            continue;
        }
        let (before, rest) = input.split_at_mut(i);
        let mut out = Out::new(to.output, to.problems, to.next, &mut before[waiting..]);
        let goes_on = pass.feed(&mut rest[0], &mut out);
        if !goes_on {
            out.send_waiting();
            waiting = i + 1;
        } else if out.sent_waiting {
            waiting = i;
        }
    }
    waiting
}

/// Whether `stmts` are moves, feeds, speeds and comments only: the
/// statements of nearly every batch of a program from CAM. A pass that
/// only follows the moves of such a run (the units pass at a factor of
/// one, polar off, cycles, compensation off, offsets under G90) takes
/// the batch at once, in its `feed_each`, without `feed` once a statement.
pub fn follows_only(stmts: &[Stmt]) -> bool {
    stmts.iter().all(|s| {
        matches!(
            s.op,
            Op::Move(_) | Op::Feed(_) | Op::Speed(_) | Op::Comment(_)
        )
    })
}

/// Where [`Pass::feed_each`] sends statements: a pass's output, its
/// problems and the rest of the pipeline.
pub struct Batch<'a, 'n> {
    pub(super) output: &'a mut Vec<Stmt>,
    pub(super) problems: &'a mut Problems,
    pub(super) next: &'a mut (dyn FnMut(&mut Vec<Stmt>) + 'n),
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

/// Where a pass sends its statements and its problems.
pub struct Out<'a> {
    stmts: &'a mut Vec<Stmt>,
    problems: &'a mut Problems,
    /// Takes the statements on when there are [`CHUNK`] of them.
    full: &'a mut dyn FnMut(&mut Vec<Stmt>),
    /// The statements before this one that went on where they lie: they
    /// come before anything the pass sends now.
    waiting: &'a mut [Stmt],
    /// `waiting` has been moved to `stmts`.
    pub(super) sent_waiting: bool,
}

impl<'a> Out<'a> {
    pub(super) fn new(
        stmts: &'a mut Vec<Stmt>,
        problems: &'a mut Problems,
        full: &'a mut dyn FnMut(&mut Vec<Stmt>),
        waiting: &'a mut [Stmt],
    ) -> Out<'a> {
        Out {
            stmts,
            problems,
            full,
            waiting,
            sent_waiting: false,
        }
    }

    pub fn push(&mut self, stmt: Stmt) {
        self.send_waiting();
        self.push_one(stmt);
    }

    fn push_one(&mut self, stmt: Stmt) {
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

    /// Move the waiting statements to the output, before what comes next.
    fn send_waiting(&mut self) {
        if self.sent_waiting {
            return;
        }
        self.sent_waiting = true;
        let waiting = std::mem::take(&mut self.waiting);
        for slot in waiting {
            // The slot is never read again (`flow` goes on after it). What
            // is left there is an empty comment, harmless even if a slip
            // ever printed it (an `End` would end the program).
            let vacated = Stmt::new(ir::Op::Comment(String::new()), slot.span);
            self.push_one(std::mem::replace(slot, vacated));
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
pub(super) struct Problems {
    pub(super) list: Vec<LowerError>,
    pub(super) errors: usize,
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

/// A pass's output is handed on once it holds this many statements.
pub const CHUNK: usize = 4096;
