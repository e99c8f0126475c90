//! The evaluator itself: how a block finished ([`Flow`]) and the
//! [`Evaluator`] struct whose `impl` blocks live in the modules above it
//! (`eval.rs` and its children). The struct and its parts only: it must
//! not hold code that runs statements.

use super::known::Predefined;
use super::options::EvalOptions;
use super::seen::Watched;
use super::setup::SetupBuilder;
use super::state::{CycleState, LineState, Macros, Modal, OutputStart, Reports, RunCounts};
use super::value::Vars;
use super::wizard_api::WizardHost;
use super::words::WordTable;
use crate::ast::{self, Names, OName};
use crate::ir;
use crate::source::Span;
use std::rc::Rc;

/// How a block finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Flow {
    Next,
    /// M99: back to the caller.
    Return,
    /// M2/M30: the program is over.
    End,
    /// Fanuc's `GOTO`: on at the line labelled N, from where it was.
    Goto(u32, Span),
    /// LinuxCNC's `oN break` and `oN continue`, from where they were.
    Break(OName, Span),
    Continue(OName, Span),
    /// An error made it impossible to go on (a limit, a broken condition).
    Abort,
}

pub(super) struct Evaluator<'a> {
    pub(super) program: &'a ast::Program,
    /// The program's names; those of a program read in parts grow with
    /// each part ([`Evaluator::names_added`]).
    pub(super) names: Rc<Names>,
    /// The word table of the statement run last, for the next
    /// ([`WordValues`]).
    pub(super) word_table: Option<Box<WordTable>>,
    /// A line of [`ast::Lines`] made [`ast::Word`]s, for the statements
    /// [`Evaluator::plain_line`] does not run itself.
    pub(super) line_words: Vec<ast::Word>,
    pub(super) options: &'a EvalOptions,
    /// What the runaway limits count.
    pub(super) run: RunCounts,
    /// Diagnostics, errors and notes reported so far.
    pub(super) reports: Reports,
    /// The sink, and what it is told at the start.
    pub(super) output: OutputStart<'a>,
    /// Subprograms, calls and scopes of the macro languages.
    pub(super) macros: Macros,
    pub(super) wizards: Option<&'a mut dyn WizardHost>,
    pub(super) vars: Vars,
    /// Statements not yet sent to the sink.
    pub(super) out: Vec<ir::Stmt>,
    /// How many make a batch now: the options' first, doubling up to
    /// their batch.
    pub(super) batch_now: usize,
    pub(super) setup: SetupBuilder,
    /// What holds for the line being run only.
    pub(super) this_line: LineState,
    /// The machine's modal state: what the codes of a line set.
    pub(super) modal: Modal,
    /// What a run of canned cycles remembers between blocks.
    pub(super) cycles: CycleState,
    /// rs274's predefined parameters the program names, and the state
    /// they read that `modal` does not keep.
    pub(super) predefined: Predefined,
    /// The values seen where variables are read and set, when a caller
    /// asked ([`super::watch_program`]).
    pub(super) watch: Option<Box<Watched>>,
}
