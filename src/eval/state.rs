//! The evaluator's state in named parts: the machine's modal state
//! ([`Modal`]), what holds for the line being run ([`LineState`]), and
//! what a run of canned cycles keeps ([`CycleState`],
//! [`Sticky`]); the counts the runaway limits read ([`RunCounts`]), what
//! the program reported ([`Reports`]), the start of the output
//! ([`OutputStart`]), and the subprograms and scopes of LinuxCNC's and
//! Fanuc's macro languages ([`Macros`]). Each part keeps its own
//! invariants; none of them runs G-code or knows the IR's meaning or the
//! other parts.

use crate::ast::{Names, OName, Subprogram};
use crate::diagnostic::Diagnostic;
use crate::ir;
use crate::source::Span;
use std::collections::{BTreeSet, HashMap};
use std::rc::Rc;

/// What the runaway limits count (SPEC §2.5): statements made by loops,
/// calls and jumps back, the jumps back, and the changes a loop pass must
/// make for the loop to end some day.
#[derive(Default)]
pub(super) struct RunCounts {
    /// Statements made by loops, subprogram calls and jumps back so far
    /// (`EvalOptions::max_statements`).
    pub(super) made: usize,
    /// Loop passes and subprogram calls under way: their statements are
    /// counted.
    pub(super) repeating: u32,
    /// A `GOTO` went back: every statement from then on is counted.
    pub(super) jumped_back: bool,
    /// The statement limit was reached: the program stops.
    pub(super) over_limit: bool,
    /// The caller stopped the run (`EvalOptions::cancel`).
    pub(super) cancelled: bool,
    /// How many times a variable changed value (or a call's scope was
    /// entered or left): a loop pass that leaves it as it was changed
    /// nothing its condition can read, so it would run forever.
    pub(super) changes: u64,
    /// Backward `GOTO`s taken, and `changes` at the last one from each
    /// place (by file and offset).
    gotos: u64,
    goto_changes: HashMap<(u32, u32), u64>,
}

/// Why a jump back stops the program.
pub(super) enum JumpLimit {
    /// More jumps back than a loop may make passes.
    TooMany,
    /// Nothing changed since the last jump back from the same place.
    NoChange,
}

impl RunCounts {
    /// A statement was kept: counted if a loop, a call or a jump back
    /// made it.
    #[inline]
    pub(super) fn count_made(&mut self) {
        self.made += usize::from(self.repeating > 0 || self.jumped_back);
    }

    /// Whether `max` statements have been made: the program is then over
    /// its limit.
    #[inline]
    pub(super) fn reached(&mut self, max: usize) -> bool {
        if self.made >= max {
            self.over_limit = true;
        }
        self.made >= max
    }

    /// A `GOTO` went back from `from`: counted as a loop's pass.
    pub(super) fn jump_back(&mut self, from: Span, max_passes: u64) -> Result<(), JumpLimit> {
        self.jumped_back = true;
        self.gotos += 1;
        if self.gotos > max_passes {
            return Err(JumpLimit::TooMany);
        }
        let last = self
            .goto_changes
            .insert((from.file, from.start), self.changes);
        match last == Some(self.changes) {
            true => Err(JumpLimit::NoChange),
            false => Ok(()),
        }
    }
}

/// What the program reported: the diagnostics kept (a repeated one once),
/// the errors counted, the DEBUG and PRINT notes given, the warnings said
/// once per program.
#[derive(Default)]
pub(super) struct Reports {
    pub(super) diagnostics: Vec<Diagnostic>,
    pub(super) errors: usize,
    /// `(DEBUG, …)` and `(PRINT, …)` notes given so far.
    pub(super) messages: usize,
    /// The warnings said once per program, by what they are about: a
    /// code (letter and number in tenths), `$` for controller commands.
    pub(super) warned_once: BTreeSet<(u8, u32)>,
}

/// Errors kept; more are counted, not kept.
pub(super) const MAX_REPORTED_ERRORS: usize = 50;

impl Reports {
    /// Keep `d`, unless the same was said just before (a statement in a
    /// loop or a repeated subprogram fails every time) or too many errors
    /// were.
    pub(super) fn add(&mut self, d: Diagnostic) {
        let same = |e: &Diagnostic| e.message == d.message && e.labels == d.labels;
        if self.diagnostics.iter().rev().take(8).any(same) {
            return;
        }
        if crate::diagnostic::is_error(&d) {
            self.errors += 1;
        }
        if self.errors <= MAX_REPORTED_ERRORS {
            self.diagnostics.push(d);
        }
    }

    /// Whether a recent diagnostic has a label that `said` matches.
    pub(super) fn said_recently(&self, said: impl Fn(&Diagnostic) -> bool) -> bool {
        self.diagnostics.iter().rev().take(8).any(said)
    }

    pub(super) fn too_many_errors(&self) -> bool {
        self.errors >= MAX_REPORTED_ERRORS
    }
}

/// The start of the output: the sink gets nothing until the first move
/// (so the setup is complete), then the start and the statements.
pub(super) struct OutputStart<'a> {
    pub(super) sink: &'a mut dyn ir::Sink,
    /// The sink has been told the start ([`ir::Sink::start`]).
    pub(super) started: bool,
    /// The first move: setup directives must come before it.
    pub(super) first_move: Option<Span>,
    /// The first G20/G21, which gives the output units without `SetUnits`.
    pub(super) first_units: Option<ir::Units>,
    /// An F came before the first G20/G21: it is in the machine's units,
    /// so that G20/G21 cannot be moved up to the output's header.
    pub(super) feed_before_units: bool,
}

impl<'a> OutputStart<'a> {
    pub(super) fn new(sink: &'a mut dyn ir::Sink) -> OutputStart<'a> {
        OutputStart {
            sink,
            started: false,
            first_move: None,
            first_units: None,
            feed_before_units: false,
        }
    }

    /// `op` is kept at `span`: the first move and units are noted.
    pub(super) fn note(&mut self, op: &ir::Op, span: Span) {
        match op {
            ir::Op::Move(_) | ir::Op::Spline(_) if self.first_move.is_none() => {
                self.first_move = Some(span)
            }
            ir::Op::Units(u) if self.first_units.is_none() => self.first_units = Some(*u),
            _ => {}
        }
    }
}

/// LinuxCNC's and Fanuc's macro state: subprograms kept from the parts
/// read before, the calls under way and their scopes, and where `GOTO`
/// labels are.
pub(super) struct Macros {
    /// The subprograms of the parts read so far (a program read in parts).
    pub(super) kept: Vec<Rc<Subprogram>>,
    /// The program is read in parts (`eval_chunks`); a call found no
    /// subprogram among those read, so it must be read whole.
    pub(super) in_parts: bool,
    pub(super) needs_whole: bool,
    /// The variables a call's scope sets and saves.
    pub(super) scope: CallScope,
    /// Subprograms being run, innermost last: (name, call span).
    pub(super) calls: Vec<(OName, Span)>,
    /// The modal state M70/M73 saved, by call level (0: the main program).
    pub(super) contexts: Vec<Option<Saved>>,
    /// Where each label a `GOTO` looked for is, by block (its address)
    /// and label: found once, not at every jump.
    pub(super) labels: HashMap<(usize, u32), Option<usize>>,
}

impl Macros {
    pub(super) fn new(names: &Names) -> Macros {
        Macros {
            kept: Vec::new(),
            in_parts: false,
            needs_whole: false,
            scope: CallScope::of(names),
            calls: Vec::new(),
            contexts: Vec::new(),
            labels: HashMap::new(),
        }
    }
}

/// The variables of a call's scope: LinuxCNC's `#1`–`#30` and named
/// parameters that do not start with `_`; Fanuc's locals `#1`–`#33`.
#[derive(Debug)]
pub(super) struct CallScope {
    /// `#k` for k = 1…33, by k − 1: an `o… call` sets the first 30,
    /// Fanuc's `G65` all 33.
    pub(super) numbered: [Option<usize>; 33],
    /// Local named parameters.
    pub(super) named: Vec<usize>,
}

impl CallScope {
    fn of(names: &Names) -> CallScope {
        let mut found = CallScope {
            numbered: [None; 33],
            named: Vec::new(),
        };
        found.add(names, 0);
        found
    }

    /// The names from the symbol `from` on.
    pub(super) fn add(&mut self, names: &Names, from: usize) {
        for (symbol, text) in names.iter().skip(from) {
            let i = symbol.0 as usize;
            if let Some(k) = parameter_number(text) {
                if (1..=33).contains(&k) {
                    self.numbered[k as usize - 1] = Some(i);
                }
            } else if text.starts_with("#<") && !text.starts_with("#<_") {
                self.named.push(i);
            }
        }
    }
}

/// The number of a LinuxCNC numbered parameter's name (`#12` → 12).
pub(crate) fn parameter_number(name: &str) -> Option<u32> {
    name.strip_prefix('#')?.parse().ok()
}

/// What rs274 remembers between cycle blocks (`cycle_r`, `cycle_cc`, …),
/// in the numbers the program wrote.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sticky {
    pub(super) r: f64,
    pub(super) depth: f64,
    pub(super) q: f64,
    pub(super) p: f64,
    pub(super) ijk: [f64; 3],
}

/// The machine's modal state as the program has set it: what the codes
/// and moves of a line change and the lines after read. Plain data: the
/// evaluator sets it as statements are admitted.
pub(super) struct Modal {
    /// Current motion mode, for words written without a G code.
    pub(super) motion: Option<ir::Motion>,
    pub(super) plane: ir::Plane,
    pub(super) units: Option<ir::Units>,
    pub(super) distance: ir::Distance,
    /// G90.1 (absolute arc centres) or G91.1.
    pub(super) arc_centers: ir::Distance,
    pub(super) polar: bool,
    /// G93 is on.
    pub(super) inverse_time: bool,
    /// G7 (LinuxCNC's lathe diameter mode): X words are diameters, halved
    /// as they are read (G8 ends it).
    pub(super) diameter_mode: bool,
    pub(super) spindle: ir::Spindle,
    /// Cutter compensation is on: its side and where it was turned on.
    pub(super) comp: Option<(ir::Side, Span)>,
    /// G40 turned compensation off in this plane and no move has been made
    /// since: a tool change then reads the point back ([`ir::Op::ReadPosition`]).
    pub(super) comp_off: Option<ir::Plane>,
    /// Tool loaded by the last M6, and tool selected by the last T.
    pub(super) tool: u32,
    pub(super) selected: Option<u32>,
    /// Last commanded position in program coordinates (`None` before the
    /// first move that sets the axis).
    pub(super) position: [Option<f64>; 3],
    /// The last F word's value (`None` before one: a feed move without one
    /// is an error; wizards read it for their plunge feed).
    pub(super) feed: Option<f64>,
    /// The work offset selected (G54..G59.3 as 1..=9): G10's P0.
    pub(super) work_offset: u8,
    /// G98 or G99 as the program stated it (`None` before either).
    pub(super) return_level: Option<ir::ReturnLevel>,
    /// Where the normal axis stood when the run of canned cycles began:
    /// G98's level.
    pub(super) cycle_initial: Option<f64>,
    /// G94 after G93, and no F since.
    pub(super) inverse_time_ended: bool,
    /// The motion mode is G5/G5.1 (`motion` is `None`): axis words alone
    /// are refused, as rs274 moves nowhere on them.
    pub(super) spline_mode: bool,
    /// The motion mode is G33 or G33.1 (`motion` is `None`): axis words
    /// alone are another, K on each.
    pub(super) synced: Option<Synced>,
    /// The last move was a G5; and the I J a G5 without them takes
    /// (rs274's `cycle_i`/`cycle_j`: the last G5's P Q turned round, or a
    /// G87's I J).
    pub(super) after_g5: bool,
    pub(super) spline_ij: [f64; 2],
}

/// A motion mode locked to the spindle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Synced {
    /// G33
    Thread,
    /// G33.1
    RigidTap,
    /// LinuxCNC's G76 (its P I J K given again on each line)
    ThreadCycle,
}

impl Modal {
    /// F0 outside G93: a feed move would never end (under G93 each move's
    /// F is its own, the inverse of its time).
    pub(super) fn at_zero_feed(&self) -> bool {
        self.feed == Some(0.0) && !self.inverse_time
    }
}

impl Default for Modal {
    /// The state at power-up, as rs274 starts.
    fn default() -> Self {
        Modal {
            motion: None,
            plane: ir::Plane::XY,
            units: None,
            distance: ir::Distance::Absolute,
            arc_centers: ir::Distance::Incremental,
            polar: false,
            inverse_time: false,
            diameter_mode: false,
            spindle: ir::Spindle::Off,
            comp: None,
            comp_off: None,
            tool: 1,
            selected: None,
            position: [None; 3],
            feed: None,
            work_offset: 1,
            return_level: None,
            cycle_initial: None,
            inverse_time_ended: false,
            spline_mode: false,
            synced: None,
            after_g5: false,
            spline_ij: [0.0; 2],
        }
    }
}

/// What a run of canned cycles keeps between its blocks.
#[derive(Default)]
pub(super) struct CycleState {
    /// The canned cycle axis words repeat (it stands before the motion
    /// mode).
    pub(super) kind: Option<ir::CycleKind>,
    /// A run of cycles is open (its first block set the G98 level).
    pub(super) run_open: bool,
    /// Where G20/G21 changed the units inside the open run of cycles.
    pub(super) units_changed_at: Option<Span>,
    /// The cycle words a repeat may leave out.
    pub(super) sticky: Sticky,
    /// The program has said G98 or G99.
    pub(super) return_level_stated: bool,
    /// The last cycle block's dwell: a repeat of a G81 or G73 that gave
    /// one (Haas's) dwells again.
    pub(super) last_dwell: Option<f64>,
}

/// What holds for the line being run only, set as it starts.
#[derive(Default)]
pub(super) struct LineState {
    /// The line was written after a block-delete `/`.
    pub(super) block_delete: bool,
    /// G53 in the line: its motion is in machine coordinates.
    pub(super) machine_coordinates: bool,
    /// An F under G93 in the line (a feed move needs one on its own line).
    pub(super) inverse_feed: bool,
    /// The line's own N word (`--numbers keep`).
    pub(super) number: Option<u32>,
}

/// The modal state M70 and M73 keep, as rs274 collates it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Modes {
    pub(super) units: Option<ir::Units>,
    pub(super) plane: ir::Plane,
    pub(super) comp: Option<ir::Side>,
    pub(super) distance: ir::Distance,
    pub(super) inverse_time: bool,
    pub(super) work_offset: u8,
    pub(super) tool_offset: Option<bool>,
    pub(super) return_level: ir::ReturnLevel,
    pub(super) arc_centers: ir::Distance,
    pub(super) diameter_mode: bool,
    pub(super) feed: Option<f64>,
    pub(super) speed: f64,
    pub(super) spindle: ir::Spindle,
    pub(super) mist: bool,
    pub(super) flood: bool,
}

/// A saved state at one call level; `on_return` (M73): restored when the
/// subroutine of that level returns.
#[derive(Clone, Debug)]
pub(super) struct Saved {
    pub(super) modes: Modes,
    pub(super) on_return: bool,
}
