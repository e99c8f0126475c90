//! Stage 0, expand: AST → IR (SPEC §4.0). Runs the program: variables,
//! expressions, `if`/`while`, subprogram calls (`M98`/`M99`, inlined),
//! setup directives and wizard calls, and turns every G-code statement into
//! IR statements that carry the span of the source that produced them.
//! The result is still modal (G91, G20, G16 stay); lowering is not done
//! here. This module must not know how IR is printed or lowered.

mod block;
mod codes;
mod comp;
mod context;
mod corner;
mod cycle;
mod degrees;
mod error;
mod evaluator;
mod known;
mod options;
mod polar;
mod predefined;
mod seen;
mod setup;
mod spline;
mod state;
mod thread;
mod thread_cycle;
pub mod value;
mod watch;
mod wizard_api;
mod words;

pub use cycle::{count_pecks, MAX_PECKS};
pub(crate) use options::LAST_USER_PARAMETER;
pub use options::{Chosen, EvalOptions, Flavour};
pub use seen::{Seen, Watched};
pub use wizard_api::{MachineState, WizardCall, WizardContext, WizardHost};

use crate::ast::{self, Names, StmtKind, Symbol};
use crate::diagnostic::Diagnostic;
use crate::ir;
use crate::source::Span;
use evaluator::{Evaluator, Flow};
use known::Predefined;
pub(crate) use state::parameter_number;
use state::{CycleState, JumpLimit, LineState, Macros, Modal, OutputStart, Reports, RunCounts};
use std::rc::Rc;
use std::sync::atomic::Ordering;
use value::{ExprError, Slot, Value, Vars};

/// Stage 0: evaluate a parsed program into IR, which goes to `sink` as it
/// is made. Returns the diagnostics; after an error nothing more is sent.
pub fn eval_program<'a>(
    program: &'a ast::Program,
    options: &'a EvalOptions,
    wizards: Option<&'a mut (dyn WizardHost + 'a)>,
    sink: &'a mut dyn ir::Sink,
) -> Vec<Diagnostic> {
    let mut ev = Evaluator::new(program, options, wizards, sink);
    ev.run();
    ev.finish();
    ev.reports.diagnostics
}

/// Stage 0 run only to see the values variables have where the program
/// reads and sets them (the editor's hover): no output is made.
pub fn watch_program(
    program: &ast::Program,
    options: &EvalOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> Watched {
    let mut nowhere = watch::Nowhere;
    let wizards = wizards.map(|w| w as &mut dyn WizardHost);
    let mut ev = Evaluator::new(program, options, wizards, &mut nowhere);
    ev.watch = Some(Box::default());
    ev.run();
    ev.watch.map(|w| *w).unwrap_or_default()
}

/// A part of a program read in parts: its statements and subprograms.
pub type Part = (Vec<ast::Stmt>, Vec<ast::Subprogram>);

/// What [`eval_chunks`] found.
pub struct Chunked {
    pub diagnostics: Vec<Diagnostic>,
    /// The program's names, as the parts left them (the parts after the
    /// program's end are read into them, for their syntax errors).
    pub names: Names,
    /// A call found no subprogram among those read so far (a wizard's
    /// `M98` line, which the parts' check cannot see): the program must be
    /// read whole, and nothing of this run kept.
    pub needs_whole: bool,
}

/// Stage 0 for a program read a part at a time
/// ([`crate::syntax::chunk`]): `next` gives each part's statements and
/// subprograms in order (and is given back the statements of the part
/// before, run), interning into the names it is handed (the
/// program's, which the parts share; the last part's comments are dropped
/// first), and `None` at the end. A part ends outside every block, has no
/// `GOTO`, and calls only subprograms of its own or of the parts before
/// it, which are kept. `next` is not asked again after the program ends
/// (M2/M30) or after an error that stops it. Returns the diagnostics, as
/// [`eval_program`].
pub fn eval_chunks(
    options: &EvalOptions,
    wizards: Option<&mut dyn WizardHost>,
    sink: &mut dyn ir::Sink,
    next: &mut dyn FnMut(&mut Names, Vec<ast::Stmt>) -> Option<Part>,
) -> Chunked {
    let empty = ast::Program {
        main: Vec::new(),
        main_number: None,
        subprograms: Vec::new(),
        names: Names::default(),
    };
    let wizards = wizards.map(|w| w as &mut dyn WizardHost);
    let mut ev = Evaluator::new(&empty, options, wizards, sink);
    ev.macros.in_parts = true;
    // The statements of the part that ran last, handed back with the call
    // for the next (their vectors can be used again).
    let mut ran = Vec::new();
    loop {
        // No statement of an earlier part is run again: its notes can go.
        let names = Rc::make_mut(&mut ev.names);
        names.forget_notes();
        let Some((stmts, subprograms)) = next(names, std::mem::take(&mut ran)) else {
            break;
        };
        ev.names_added();
        // A subprogram outlives its part, and so do its comments.
        let names = Rc::make_mut(&mut ev.names);
        for mut sub in subprograms {
            for stmt in &mut sub.body {
                stmt.map_notes(&mut |s| names.keep_note(s));
            }
            ev.macros.kept.push(Rc::new(sub));
        }
        let flow = ev.exec_block(&stmts);
        ran = stmts;
        if ev.no_label(flow) != Flow::Next || ev.run.cancelled {
            break;
        }
    }
    ev.finish();
    Chunked {
        diagnostics: ev.reports.diagnostics,
        names: Rc::try_unwrap(ev.names).unwrap_or_else(|shared| (*shared).clone()),
        needs_whole: ev.macros.needs_whole,
    }
}

use error::{EvalError, EvalErrorKind};

impl<'a> Evaluator<'a> {
    fn new(
        program: &'a ast::Program,
        options: &'a EvalOptions,
        wizards: Option<&'a mut dyn WizardHost>,
        sink: &'a mut dyn ir::Sink,
    ) -> Self {
        let mut names = program.names.clone();
        if options.plain {
            names.name_call_parameters();
        }
        let mut ev = Evaluator {
            program,
            word_table: None,
            line_words: Vec::new(),
            options,
            run: RunCounts::default(),
            reports: Reports::default(),
            output: OutputStart::new(sink),
            macros: Macros::new(&names),
            wizards,
            vars: Vars::new(
                numbered_parameters(&names, options.from),
                &names,
                options.from == Flavour::Fanuc,
                options.rs274(),
            ),
            names: Rc::new(names),
            out: Vec::with_capacity(options.batch.clamp(1, 1 << 16)),
            batch_now: options.first_batch.clamp(1, options.batch.max(1)),
            setup: setup::SetupBuilder::with_tools(&options.tools, options.tool_units),
            modal: Modal::default(),
            this_line: LineState::default(),
            cycles: CycleState::default(),
            predefined: Predefined::default(),
            watch: None,
        };
        ev.predefined.add_names(&ev.names, 0, options.from);
        ev
    }

    /// The next part of a program read in parts has added names: their
    /// variables, as the whole program's would have started.
    fn names_added(&mut self) {
        let (names, known) = (Rc::clone(&self.names), self.vars.len());
        if names.len() > known {
            let from = self.options.from;
            self.vars.grow(&names, known, |text| first_slot(text, from));
            self.macros.scope.add(&names, known);
            self.predefined.add_names(&names, known, from);
        }
    }

    fn run(&mut self) {
        let main = &self.program.main;
        let flow = self.exec_block(main);
        self.no_label(flow);
    }

    /// A `GOTO` whose label no block of its program has, or a `break` or
    /// `continue` whose loop is not around it: an error.
    fn no_label(&mut self, flow: Flow) -> Flow {
        let (kind, from) = match flow {
            Flow::Goto(label, from) => (EvalErrorKind::NoLabel(label), from),
            Flow::Break(label, from) => {
                let (label, is_break) = (label.written(&self.names), true);
                (EvalErrorKind::NoLoop { label, is_break }, from)
            }
            Flow::Continue(label, from) => {
                let (label, is_break) = (label.written(&self.names), false);
                (EvalErrorKind::NoLoop { label, is_break }, from)
            }
            Flow::Next | Flow::Return | Flow::End | Flow::Abort => return flow,
        };
        self.report(EvalError::new(kind, from));
        Flow::Abort
    }

    /// A statement in a loop or a repeated subprogram fails every time:
    /// it is said once ([`Reports::add`]).
    fn report(&mut self, d: impl Into<Diagnostic>) {
        self.reports.add(d.into());
    }

    fn report_expr(&mut self, e: ExprError) {
        // An expression in a loop fails at every pass: an error already
        // said at the same place is not worded again (its "did you mean"
        // looks through every name).
        let said = |d: &Diagnostic| {
            e.span().is_some_and(|span| {
                d.labels
                    .iter()
                    .any(|l| l.file_id == span.file_id() && l.range == span.range())
            })
        };
        if self.reports.said_recently(said) {
            return;
        }
        if let Some(d) = e.to_diagnostic(&self.names, &self.vars, self.options.from) {
            self.report(d);
        }
    }

    fn too_many_errors(&self) -> bool {
        self.reports.too_many_errors()
    }

    fn emit(&mut self, op: ir::Op, span: Span) -> Result<(), Diagnostic> {
        self.admit(&op, span)?;
        self.out.push(ir::Stmt {
            op,
            span,
            block_delete: self.this_line.block_delete,
            number: self.kept_number(),
        });
        self.kept();
        Ok(())
    }

    /// The source line's N word for the statements it makes, unless a
    /// called subprogram makes them (its N words would repeat at every
    /// call, and clash with the caller's).
    pub(super) fn kept_number(&self) -> Option<u32> {
        self.this_line
            .number
            .filter(|_| self.macros.calls.is_empty())
    }

    /// The checks and the state of [`Self::emit`] for `op`, before it is
    /// kept.
    fn admit(&mut self, op: &ir::Op, span: Span) -> Result<(), Diagnostic> {
        if self.run.reached(self.options.max_statements) {
            let kind = EvalErrorKind::TooManyStatements(self.options.max_statements);
            return Err(EvalError::new(kind, span).into());
        }
        self.check_under_comp(op, span)?;
        match op {
            ir::Op::Comp { side, .. } => self.modal.comp = Some((*side, span)),
            ir::Op::CompOff if self.modal.comp.is_some() => {
                self.modal.comp = None;
                self.modal.comp_off = Some(self.modal.plane);
            }
            ir::Op::End => self.modal.comp = None,
            ir::Op::Feed(f) => {
                self.modal.feed = Some(*f);
                self.modal.inverse_time_ended = false;
                self.output.feed_before_units |= self.output.first_units.is_none();
                self.this_line.inverse_feed = self.modal.inverse_time;
            }
            ir::Op::Spline(_) if self.modal.feed.is_none() => {
                return Err(EvalError::new(EvalErrorKind::FeedBeforeRate, span).into());
            }
            ir::Op::Spline(_) if self.modal.at_zero_feed() => {
                return Err(EvalError::new(EvalErrorKind::ZeroFeed, span).into());
            }
            // A G33's speed is the spindle's: it needs no F (and takes none).
            ir::Op::Move(ir::Move { lead: Some(_), .. }) => {}
            ir::Op::Move(m) if m.motion != ir::Motion::Rapid && self.modal.feed.is_none() => {
                let kind = if self.modal.inverse_time_ended {
                    EvalErrorKind::FeedAfterInverseTime
                } else {
                    EvalErrorKind::FeedBeforeRate
                };
                return Err(EvalError::new(kind, span).into());
            }
            ir::Op::Move(m) if m.motion != ir::Motion::Rapid && self.modal.at_zero_feed() => {
                return Err(EvalError::new(EvalErrorKind::ZeroFeed, span).into());
            }
            ir::Op::Move(m) if m.motion != ir::Motion::Rapid && self.modal.inverse_time => {
                // rs274: each G1/G2/G3 under G93 has its own F.
                if !std::mem::take(&mut self.this_line.inverse_feed) {
                    return Err(EvalError::new(EvalErrorKind::InverseTimeWithoutF, span).into());
                }
                if m.arc.is_some() && self.modal.comp.is_some() {
                    let kind = EvalErrorKind::InverseTimeArcUnderComp;
                    return Err(EvalError::new(kind, span).into());
                }
            }
            // G94 after G93: rs274 sets the feed to 0.
            ir::Op::InverseTime(false) => {
                self.modal.feed = None;
                self.modal.inverse_time_ended = true;
            }
            ir::Op::Units(u) if self.cycles.run_open && self.modal.units != Some(*u) => {
                self.cycles.units_changed_at = Some(span);
            }
            ir::Op::SetToolData(data) => {
                let units = self.modal.units.or(self.options.units);
                self.setup.set_tool_data(data, units);
            }
            _ => {}
        }
        self.track(op);
        self.output.note(op, span);
        if !self.output.started && self.output.first_move.is_some() {
            self.start(span);
        }
        Ok(())
    }

    /// A statement was kept: counted, and the batch sent once full.
    #[inline]
    fn kept(&mut self) {
        self.run.count_made();
        if self.out.len() >= self.batch_now {
            self.send_full();
        }
    }

    /// A full batch sent; the next twice as large, up to the options'.
    #[inline(never)]
    fn send_full(&mut self) {
        self.send();
        self.batch_now = self
            .batch_now
            .saturating_mul(2)
            .min(self.options.batch.max(1));
    }

    /// A statement of its own (not from a G-code line): a limit reached
    /// here stops the program.
    fn emit_or_abort(&mut self, op: ir::Op, span: Span) -> Flow {
        match self.emit(op, span) {
            Ok(()) => Flow::Next,
            Err(d) => {
                self.report(d);
                Flow::Abort
            }
        }
    }

    /// Report the warning `make` builds, unless one about `key` was
    /// already given.
    fn warn_once<D: Into<Diagnostic>>(&mut self, key: (u8, u32), make: impl FnOnce() -> D) {
        if self.reports.warned_once.insert(key) {
            self.report(make());
        }
    }

    /// The setup is complete (the first move, or the end of a program
    /// without moves): tell the sink what it starts from. The output units
    /// are `SetUnits`, else the first G20/G21 before the first move (unless
    /// an F came before it: that F is in the machine's units, and the
    /// G20/G21 stays where it is, after it), else `--units`; else the
    /// machine's own, with a warning (SPEC §3).
    fn start(&mut self, at: Span) {
        self.output.started = true;
        // With `--units` the F is in those units, and the G20/G21 may fix
        // the output's as usual.
        let first_units = self
            .output
            .first_units
            .filter(|_| !self.output.feed_before_units || self.options.units.is_some());
        let output_units = self
            .setup
            .get()
            .units
            .or(first_units)
            .or(self.options.units);
        let setup = self.setup.in_units(output_units);
        if output_units.is_none() && self.output.first_units.is_none() && at != Span::default() {
            self.report(EvalError::new(EvalErrorKind::UnitsUnstated, at));
        }
        let start = ir::Start {
            program_units: self.options.units.or(setup.units),
            output_units,
            setup,
            return_level: self.options.from.power_up_return_level(),
        };
        self.output.sink.start(&start);
    }

    /// Send the statements made so far to the sink, once it has started
    /// (after the first move: the setup is complete). Until then they wait
    /// here. After an error nothing is sent: there will be no output.
    fn send(&mut self) {
        let cancel = self.options.cancel.as_ref();
        if !self.run.cancelled && cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            self.run.cancelled = true;
            let at = self.out.last().map_or(Span::default(), |s| s.span);
            self.report(EvalError::new(EvalErrorKind::Cancelled, at));
        }
        if self.reports.errors > 0 {
            self.out.clear();
            return;
        }
        if self.output.started {
            self.output.sink.batch(&mut self.out);
        }
    }

    /// The end of the program: send what is left.
    fn finish(&mut self) {
        if self.reports.errors > 0 {
            return;
        }
        if !self.output.started && self.out.is_empty() {
            self.only_subprograms();
        }
        if !self.output.started {
            self.start(Span::default());
        }
        self.output.sink.batch(&mut self.out);
    }

    /// A program that made no statement but defines subprograms (a file
    /// of subroutines): the empty program rs274 runs, its end at the first.
    fn only_subprograms(&mut self) {
        let kept = self.macros.kept.first().map(|s| s.span);
        let Some(first) = self.program.subprograms.first().map(|s| s.span).or(kept) else {
            return;
        };
        self.report(EvalError::new(EvalErrorKind::OnlySubprograms, first));
        self.out.push(ir::Stmt::new(ir::Op::End, first));
    }

    /// Keep the little state wizards can read (SPEC §5).
    fn track(&mut self, op: &ir::Op) {
        self.follow_predefined(op);
        match op {
            ir::Op::Spline(s) => {
                self.modal.comp_off = None;
                self.track_spline(s);
            }
            ir::Op::Move(m) => {
                self.modal.comp_off = None;
                self.modal.after_g5 = false;
                self.modal.motion = Some(m.motion);
                for axis in [ir::Axis::X, ir::Axis::Y, ir::Axis::Z] {
                    if let Some(v) = m.to.get(axis) {
                        let axis = axis.index();
                        self.modal.position[axis] = match self.modal.distance {
                            ir::Distance::Absolute => Some(v),
                            ir::Distance::Incremental => self.modal.position[axis].map(|p| p + v),
                        };
                    }
                }
            }
            ir::Op::Units(u) => self.modal.units = Some(*u),
            ir::Op::Plane(p) => self.modal.plane = *p,
            ir::Op::Spindle(s) => self.modal.spindle = *s,
            ir::Op::Distance(d) => self.modal.distance = *d,
            ir::Op::ArcCenters(d) => self.modal.arc_centers = *d,
            ir::Op::InverseTime(on) => self.modal.inverse_time = *on,
            ir::Op::Polar(on) => self.modal.polar = *on,
            ir::Op::SelectWorkOffset(index) => self.modal.work_offset = *index,
            ir::Op::SetPosition(a) => {
                for axis in [ir::Axis::X, ir::Axis::Y, ir::Axis::Z] {
                    if let Some(v) = a.get(axis) {
                        self.modal.position[axis.index()] = Some(v);
                    }
                }
            }
            ir::Op::ReturnLevel(level) => self.modal.return_level = Some(*level),
            ir::Op::Cycle(c) => {
                self.modal.comp_off = None;
                self.modal.after_g5 = false;
                if c.kind == ir::CycleKind::G87 {
                    let [i, j, _] = c.ijk;
                    self.modal.spline_ij = [i.unwrap_or(0.0), j.unwrap_or(0.0)];
                }
                self.track_cycle(c);
            }
            ir::Op::ReadPosition(plane) => {
                // The tool's offset point: not known here.
                let (u, v, _) = plane.axes();
                self.modal.position[u] = None;
                self.modal.position[v] = None;
            }
            _ => {}
        }
    }

    /// Where a spline leaves the tool, and what a G5 after it without I J
    /// takes.
    fn track_spline(&mut self, s: &ir::Spline) {
        for axis in [ir::Axis::X, ir::Axis::Y] {
            if let Some(v) = s.to.get(axis) {
                let i = axis.index();
                self.modal.position[i] = match self.modal.distance {
                    ir::Distance::Absolute => Some(v),
                    ir::Distance::Incremental => self.modal.position[i].map(|p| p + v),
                };
            }
        }
        self.modal.after_g5 = matches!(s.kind, ir::SplineKind::Cubic { .. });
        if let ir::SplineKind::Cubic { end, .. } = s.kind {
            // (0 - v: no -0 in a message.)
            self.modal.spline_ij = [0.0 - end[0], 0.0 - end[1]];
        }
    }

    /// Where a canned cycle block leaves the tool, for wizards: over its
    /// hole, at the R level (G99) or the run's initial level (G98: the
    /// higher of the two). Unknown under G91, where repeats step on, or
    /// where the return level was never stated (controllers differ).
    fn track_cycle(&mut self, c: &ir::Cycle) {
        let (u, v, w) = self.modal.plane.axes();
        let position = &mut self.modal.position;
        if self.modal.distance == ir::Distance::Incremental {
            *position = [None; 3];
            return;
        }
        if c.starts_run {
            self.modal.cycle_initial = position[w];
        }
        for i in [u, v] {
            if let Some(at) = c.at.get(ir::Axis::ALL[i]) {
                position[i] = Some(at);
            }
        }
        position[w] = match self.modal.return_level {
            Some(ir::ReturnLevel::R) => Some(c.r),
            Some(ir::ReturnLevel::Initial) => self.modal.cycle_initial.map(|z| z.max(c.r)),
            None => None,
        };
    }

    fn exec_block(&mut self, stmts: &[ast::Stmt]) -> Flow {
        let mut next = 0;
        while let Some(stmt) = stmts.get(next) {
            next += 1;
            let system = match &stmt.kind {
                StmtKind::Assign(a) => self.system_target(&a.target).map(|name| (name, &a.value)),
                _ => None,
            };
            let flow = match system {
                Some((name, value)) => {
                    let names = Rc::clone(&self.names);
                    // Its message is the comment after it on its line.
                    let message = match stmts.get(next) {
                        Some(c)
                            if c.span.line == stmt.span.line && c.span.file == stmt.span.file =>
                        {
                            match &c.kind {
                                StmtKind::Comment(text) => Some(names.text(*text).trim()),
                                _ => None,
                            }
                        }
                        _ => None,
                    };
                    next += usize::from(message.is_some());
                    self.system_assign(name, value, stmt.span, message)
                }
                None => self.exec(stmt),
            };
            match flow {
                Flow::Next => {}
                // A jump to a label of this block; else the block around
                // it looks (Fanuc jumps out of a loop, never into one).
                Flow::Goto(label, from) => match self.label_in(stmts, label) {
                    Some(at) => {
                        if !self.jumped(at < next, from) {
                            return Flow::Abort;
                        }
                        next = at;
                    }
                    None => return flow,
                },
                _ => return flow,
            }
            if self.too_many_errors() || self.run.cancelled {
                return Flow::Abort;
            }
        }
        Flow::Next
    }

    /// Where the line labelled `N<label>` is in the block `stmts`.
    fn label_in(&mut self, stmts: &[ast::Stmt], label: u32) -> Option<usize> {
        *self
            .macros
            .labels
            .entry((stmts.as_ptr() as usize, label))
            .or_insert_with(|| labelled(stmts, label))
    }

    /// The number of a Fanuc `#` variable, when the program is Fanuc's.
    fn fanuc_parameter(&self, name: Symbol) -> Option<u32> {
        (self.options.from == Flavour::Fanuc)
            .then(|| parameter_number(self.names.text(name)))
            .flatten()
    }

    /// Fanuc's `#3000` (an alarm) and `#3006` (a stop with a message).
    fn is_system_variable(&self, name: Symbol) -> bool {
        matches!(self.fanuc_parameter(name), Some(3000 | 3006))
    }

    /// The system variable an assignment sets, if it sets one: by name, or
    /// through `#[…]` (whose number's errors the assignment reports).
    fn system_target(&self, target: &ast::Target) -> Option<Symbol> {
        if self.options.from != Flavour::Fanuc {
            return None;
        }
        let name = match target {
            ast::Target::Name(name) => *name,
            ast::Target::Indirect(number) => self.vars.resolve(number, number.span).ok()?,
        };
        self.is_system_variable(name).then_some(name)
    }

    /// `#3000 = n (MESSAGE)` stops the compile with the alarm, as the
    /// machine would stop; `#3006 = n (MESSAGE)` is the message and M0.
    fn system_assign(
        &mut self,
        name: Symbol,
        value: &ast::Expr,
        span: Span,
        message: Option<&str>,
    ) -> Flow {
        let number = match value::number(value, &self.vars, &|| "the alarm number".into()) {
            Ok(n) => n,
            Err(e) => {
                self.report_expr(e);
                return Flow::Abort;
            }
        };
        let message = message.unwrap_or("").to_string();
        if self.fanuc_parameter(name) == Some(3000) {
            let kind = EvalErrorKind::Alarm { number, message };
            self.report(EvalError::new(kind, span));
            return Flow::Abort;
        }
        if !message.is_empty() {
            let op = ir::Op::Comment(format!("MSG, {message}"));
            if self.emit_or_abort(op, span) == Flow::Abort {
                return Flow::Abort;
            }
        }
        self.emit_or_abort(ir::Op::Stop(ir::Stop::Program), span)
    }

    /// A `GOTO` taken; a backward one is a loop, with a loop's limits.
    /// False when a limit stops the program.
    fn jumped(&mut self, backward: bool, from: Span) -> bool {
        if !backward {
            return true;
        }
        let kind = match self.run.jump_back(from, self.options.max_iterations) {
            Ok(()) => return true,
            Err(JumpLimit::TooMany) => EvalErrorKind::LoopLimit(self.options.max_iterations),
            // Between two jumps back from one place nothing changed: the
            // program goes round for ever.
            Err(JumpLimit::NoChange) => EvalErrorKind::LoopNeverEnds,
        };
        self.report(EvalError::new(kind, from));
        false
    }

    /// One line, in rs274's order of execution when it has several codes.
    fn exec_line(&mut self, line: &ast::Line) -> Flow {
        self.exec_words(&line.words, line.block_delete)
    }

    /// Run plain lines in a row, each as [`Self::exec_line`] would; the
    /// first flow that is not [`Flow::Next`] ends them.
    fn exec_lines(&mut self, lines: &ast::Lines) -> Flow {
        for (words, line) in lines.each() {
            self.this_line.number = ast::plain_line_number(words);
            let flow = self.plain_line(words, lines.file, line);
            self.this_line.number = None;
            if flow != Flow::Next {
                return flow;
            }
        }
        Flow::Next
    }

    /// A line of [`ast::Lines`], as [`Self::exec_words`] runs it: a move of
    /// numbers ([`Self::plain_move`], the commonest line of a CAM program)
    /// read from its words as they are; any other line made [`ast::Word`]s
    /// and run so.
    fn plain_line(&mut self, words: &[ast::PlainWord], file: u32, line: u32) -> Flow {
        // The statements `ast::few_statements` cuts it into: the words
        // before its one code (unless only `N` words), or the code's.
        let mut codes = words.iter().enumerate().filter(|(_, w)| w.is_code());
        let (first, more) = (codes.next(), codes.next().is_some());
        let before = &words[..first.map_or(words.len(), |(at, _)| at)];
        let uncoded = !before.iter().all(|w| w.letter == b'N');
        self.this_line.machine_coordinates = false;
        self.this_line.inverse_feed = false;
        let stmt = match first {
            _ if more => None,
            Some(_) if uncoded => None,
            None if !uncoded => return Flow::Next,
            None => Some((None, before)),
            Some((at, code)) => Some((Some(code), &words[at + 1..])),
        };
        let span = |w: &ast::PlainWord| w.span(file, line);
        if let Some(flow) = stmt.and_then(|(code, args)| self.plain_move(code, args, span)) {
            return flow;
        }
        let mut made = std::mem::take(&mut self.line_words);
        made.clear();
        made.extend(words.iter().map(|w| w.word(file, line)));
        let flow = self.exec_words(&made, false);
        self.line_words = made;
        flow
    }

    /// Run a line of `words`, written after a `/` if `block_delete`.
    fn exec_words(&mut self, words: &[ast::Word], block_delete: bool) -> Flow {
        self.this_line.machine_coordinates = false;
        self.this_line.inverse_feed = false;
        self.this_line.block_delete = block_delete;
        self.this_line.number = ast::line_number(words);
        let flow = self.exec_line_in_order(words);
        self.this_line.block_delete = false;
        self.this_line.number = None;
        flow
    }

    fn exec_line_in_order(&mut self, words: &[ast::Word]) -> Flow {
        // Most lines: one code or none, with nothing before the code but
        // N words, whose order is the line's. Words before the one code
        // (`Z5 G0`, `X5 G91`, `Y40 M8`) go in rs274's order below, as
        // with several codes: the code acts first, on all of them.
        // (Not an iterator over the two: moving them into one stalls on
        // the stores that made them.)
        if let Some([uncoded, coded]) = ast::few_statements(words) {
            match (uncoded, coded) {
                (Some(_), Some(_)) => {}
                (Some(s), None) | (None, Some(s)) => return self.exec_line_stmt(s),
                (None, None) => return Flow::Next,
            }
        }
        if let Some(stmts) = block::in_order(words) {
            for s in &stmts {
                let flow = self.exec_line_stmt(s.as_stmt());
                if flow != Flow::Next {
                    return flow;
                }
            }
            return Flow::Next;
        }
        for s in ast::statements(words) {
            let flow = self.exec_line_stmt(s);
            if flow != Flow::Next {
                return flow;
            }
        }
        Flow::Next
    }

    fn exec(&mut self, stmt: &ast::Stmt) -> Flow {
        if self.predefined.named_any() {
            self.refresh_predefined(Some(stmt.span));
            self.warn_task(stmt);
        }
        if self.watch.is_some() {
            self.watch_reads(stmt);
        }
        match &stmt.kind {
            StmtKind::Line(line) => self.exec_line(line),
            StmtKind::Lines(lines) => self.exec_lines(lines),
            StmtKind::MacroCall(call) => self.exec_macro_call(call),
            StmtKind::Assign(a) => {
                if let Some(name) = self.target(&a.target, a.name_span) {
                    self.assign(name, a.name_span, &a.value);
                    if self.watch.is_some() {
                        self.watch_set(name, a.name_span);
                    }
                }
                Flow::Next
            }
            StmtKind::Assigns(all) => self.exec_assigns(all),
            StmtKind::Call {
                name,
                name_span,
                args,
            } => self.call(*name, *name_span, args, stmt.span),
            StmtKind::If(if_) => {
                let ast::If {
                    branches,
                    otherwise,
                } = &**if_;
                for (cond, body) in branches {
                    match self.condition(cond, "the `if` condition") {
                        Ok(true) => return self.exec_block(body),
                        Ok(false) => {}
                        Err(e) => {
                            self.report_expr(e);
                            return Flow::Abort;
                        }
                    }
                }
                match otherwise {
                    Some(body) => self.exec_block(body),
                    None => Flow::Next,
                }
            }
            StmtKind::While(w) => self.exec_while(w, stmt.span),
            StmtKind::SubCall(call) => self.sub_call(call),
            StmtKind::Return(r) => {
                let value = match &r.value {
                    Some(v) => self.value_slot(v),
                    None => Slot::Set(Value::Number(0.0)),
                };
                self.set_return_value(value, r.value.is_some());
                Flow::Return
            }
            StmtKind::DefinitionRead { returns_value } => {
                let value = match returns_value {
                    true => Slot::Unset,
                    false => Slot::Set(Value::Number(0.0)),
                };
                self.set_return_value(value, *returns_value);
                Flow::Next
            }
            StmtKind::Repeat(r) => self.exec_repeat(r),
            // Left in a block by the parser: no subprogram starts there.
            StmtKind::Sub(_) => self.misplaced_sub(stmt.span),
            StmtKind::Break(label) => Flow::Break(*label, stmt.span),
            StmtKind::Continue(label) => Flow::Continue(*label, stmt.span),
            StmtKind::Goto(target) => {
                match value::number(target, &self.vars, &|| "the `GOTO` target".into()) {
                    Ok(n) if (0.0..1e8).contains(&n) && n.fract() == 0.0 => {
                        Flow::Goto(n as u32, stmt.span)
                    }
                    Ok(n) => {
                        let kind = EvalErrorKind::BadLabel(n);
                        self.report(EvalError::new(kind, target.span));
                        Flow::Abort
                    }
                    Err(e) => {
                        self.report_expr(e);
                        Flow::Abort
                    }
                }
            }
            StmtKind::Error => Flow::Next,
            StmtKind::Comment(c) => self.comment(Rc::clone(&self.names).text(*c), stmt.span),
            StmtKind::Command(c) => self.command(Rc::clone(&self.names).text(*c), stmt.span),
        }
    }

    /// A comment of plain G-code: a note if it is LinuxCNC's DEBUG or
    /// PRINT, and kept for the output unless `--comments drop`.
    fn comment(&mut self, text: &str, span: Span) -> Flow {
        if self.options.plain {
            self.debug_message(text, span);
        }
        if !self.options.keep_comments {
            return Flow::Next;
        }
        self.emit_or_abort(ir::Op::Comment(text.to_string()), span)
    }

    /// A controller command line (grbl's `$H`), passed through.
    fn command(&mut self, text: &str, span: Span) -> Flow {
        let text = text.to_string();
        self.warn_once((b'$', 0), || {
            EvalError::new(EvalErrorKind::CommandPassedThrough(text.clone()), span)
        });
        let op = ir::Op::Passthrough(ir::Passthrough::Line(text));
        self.emit_or_abort(op, span)
    }

    /// LinuxCNC's `(DEBUG, …)` and `(PRINT, …)`: a note at the line, with
    /// each `#<name>` and `#123` replaced by its value as rs274 prints it
    /// (six decimals, `######` for a parameter with none).
    fn debug_message(&mut self, comment: &str, span: Span) {
        let inner = comment.trim().trim_start_matches('(').trim_end_matches(')');
        let Some((kind, text)) = inner.split_once(',') else {
            return;
        };
        let kind = kind.trim().to_ascii_uppercase();
        if kind != "DEBUG" && kind != "PRINT" {
            return;
        }
        // A message in a loop must not fill the memory with notes.
        self.reports.messages += 1;
        if self.reports.messages > MAX_MESSAGES {
            if self.reports.messages == MAX_MESSAGES + 1 {
                let kind = EvalErrorKind::MessagesCut(MAX_MESSAGES);
                self.report(EvalError::new(kind, span));
            }
            return;
        }
        let mut out = String::new();
        let mut rest = text;
        while let Some(at) = rest.find('#') {
            out.push_str(&rest[..at]);
            let after = &rest[at + 1..];
            match crate::syntax::linuxcnc::parameter_name(after) {
                Ok((name, used)) => {
                    // A numbered parameter the program never names has
                    // its first value (rs274: 0 for #1–#5000).
                    let predefined = known::Param::of_name(&name)
                        .filter(|_| self.options.from != Flavour::Fanuc);
                    let slot = match (self.names.find(&name), predefined) {
                        (Some(s), _) => self.vars.get(s.0 as usize).copied(),
                        (None, Some(p)) => Some(match self.predefined_value(p, Some(span)) {
                            Some(v) => Slot::Set(Value::Number(v)),
                            None => Slot::Machine,
                        }),
                        (None, None) => {
                            parameter_number(&name).map(|n| first_value(n, self.options.from))
                        }
                    };
                    let value = slot.and_then(|slot| match slot {
                        Slot::Set(Value::Number(n)) => Some(n),
                        Slot::Set(Value::Bool(b)) => Some(f64::from(u8::from(b))),
                        _ => None,
                    });
                    match value {
                        Some(v) => out.push_str(&format!("{v:.6}")),
                        None => out.push_str("######"),
                    }
                    rest = &after[used..];
                }
                Err(_) => {
                    out.push('#');
                    rest = after;
                }
            }
        }
        out.push_str(rest);
        let kind = EvalErrorKind::Message {
            kind,
            text: out.trim().to_string(),
        };
        self.report(EvalError::new(kind, span));
    }

    /// A condition: true or false, or in plain G-code (LinuxCNC's o-word
    /// `if` and `while`) also a number, true when it is not 0.
    fn condition(&self, cond: &ast::Expr, what: &str) -> Result<bool, value::ExprError> {
        if self.options.plain {
            if let Some(n) = value::fast_number(cond, &self.vars) {
                return Ok(n != 0.0);
            }
            if let Value::Number(n) = value::eval(cond, &self.vars)? {
                return Ok(n != 0.0);
            }
        }
        value::boolean(cond, &self.vars, &|| what.into())
    }

    /// A `while` loop, or LinuxCNC's `do … while` (tested after each pass).
    /// `break` and `continue` naming the loop end it or its pass.
    fn exec_while(&mut self, w: &ast::While, span: Span) -> Flow {
        // Errors about the whole loop point at its head (a `do` loop's
        // head is its condition, at the end).
        let head = if w.test_after {
            Span {
                end: w.cond.span.end + 1,
                ..w.cond.span
            }
        } else {
            Span {
                end: w.cond.span.end + 1,
                ..span
            }
        };
        let mut count: u64 = 0;
        // The condition held before this pass (a `do` loop's first pass
        // runs untested).
        let mut tested = !w.test_after;
        loop {
            if tested && self.watch.is_some() {
                self.watch_expr(&w.cond);
            }
            if tested {
                match self.condition(&w.cond, "the `while` condition") {
                    Ok(true) => {}
                    Ok(false) => return Flow::Next,
                    Err(e) => {
                        self.report_expr(e);
                        return Flow::Abort;
                    }
                }
            }
            count += 1;
            if count > self.options.max_iterations {
                let kind = EvalErrorKind::LoopLimit(self.options.max_iterations);
                self.report(EvalError::new(kind, head));
                return Flow::Abort;
            }
            let changes = self.run.changes;
            self.run.repeating += 1;
            let flow = self.exec_block(&w.body);
            self.run.repeating -= 1;
            if self.predefined.named_any() {
                // What the last statement of the pass changed, for the
                // test below and the condition.
                self.refresh_predefined(None);
            }
            match flow {
                Flow::Next => {}
                Flow::Break(label, _) if w.label == Some(label) => return Flow::Next,
                Flow::Continue(label, _) if w.label == Some(label) => {}
                other => return other,
            }
            // The condition reads only variables: if a pass after it held
            // changed none, every pass after it does the same, for ever.
            if tested && self.run.changes == changes {
                self.report(EvalError::new(EvalErrorKind::LoopNeverEnds, head));
                return Flow::Abort;
            }
            tested = true;
        }
    }

    /// LinuxCNC's `repeat`: the body as many times as the count is 1 or
    /// more after each pass takes 1 from it. The count is worked out once.
    fn exec_repeat(&mut self, r: &ast::Repeat) -> Flow {
        let mut left = match value::number(&r.count, &self.vars, &|| "the `repeat` count".into()) {
            Ok(n) => n,
            Err(e) => {
                self.report_expr(e);
                return Flow::Abort;
            }
        };
        // Errors about the whole loop point at its head.
        let head = Span {
            end: r.at.end + 1,
            ..r.at
        };
        let mut count: u64 = 0;
        while left >= 1.0 {
            count += 1;
            if count > self.options.max_iterations {
                let kind = EvalErrorKind::LoopLimit(self.options.max_iterations);
                self.report(EvalError::new(kind, head));
                return Flow::Abort;
            }
            // Each pass changes the count: a loop around it goes on.
            left -= 1.0;
            self.run.changes += 1;
            self.run.repeating += 1;
            let flow = self.exec_block(&r.body);
            self.run.repeating -= 1;
            if flow != Flow::Next {
                // A `break` or `continue` cannot name a `repeat` loop.
                return flow;
            }
        }
        Flow::Next
    }

    /// LinuxCNC's `#<_value>` and `#<_value_returned>`, as a `return` or
    /// an `endsub` sets them.
    fn set_return_value(&mut self, value: Slot, returned: bool) {
        use crate::syntax::linuxcnc::{RETURN_VALUE, VALUE_RETURNED};
        let names = Rc::clone(&self.names);
        if let Some(name) = names.find(RETURN_VALUE) {
            self.store(name, value);
        }
        if let Some(name) = names.find(VALUE_RETURNED) {
            let returned = f64::from(u8::from(returned));
            self.store(name, Slot::Set(Value::Number(returned)));
        }
    }

    /// The variable an assignment sets: its name, or the parameter an
    /// indirect target's value names (`None`: an error, reported).
    /// Several assignments on one line: every target and value from the
    /// variables as they were before the line, then every store.
    fn exec_assigns(&mut self, all: &[ast::Assignment]) -> Flow {
        let stores: Vec<Option<(Symbol, Slot)>> = all
            .iter()
            .map(|a| {
                let name = self.target(&a.target, a.name_span)?;
                Some((name, self.assigned(name, a.name_span, &a.value)?))
            })
            .collect();
        for (name, slot) in stores.into_iter().flatten() {
            self.store(name, slot);
        }
        if self.watch.is_some() {
            for a in all {
                if let ast::Target::Name(name) = a.target {
                    self.watch_set(name, a.name_span);
                }
            }
        }
        Flow::Next
    }

    fn target(&mut self, target: &ast::Target, span: Span) -> Option<Symbol> {
        let number = match target {
            ast::Target::Name(name) if self.read_only(*name) => {
                let text = self.names.text(*name).to_string();
                let kind = EvalErrorKind::ReadOnlyParameter(text);
                self.report(EvalError::new(kind, span));
                return None;
            }
            ast::Target::Name(name) => {
                // rs274 makes a named parameter (0) as it reads its
                // assignment: the rest of the line reads it as 0 if it had
                // no value (`#<n> = [#<n> + 1]` sets 1).
                if self.options.rs274()
                    && self.vars[name.0 as usize] == Slot::Unset
                    && self.names.text(*name).starts_with("#<")
                {
                    self.store(*name, Slot::Set(Value::Number(0.0)));
                }
                return Some(*name);
            }
            ast::Target::Indirect(number) => number,
        };
        match self.vars.resolve(number, span) {
            Ok(name) => Some(name),
            Err(e) => {
                self.report_expr(e);
                None
            }
        }
    }

    fn assign(&mut self, name: Symbol, name_span: Span, value: &ast::Expr) {
        if let Some(slot) = self.assigned(name, name_span, value) {
            self.store(name, slot);
        }
    }

    /// What `name = value` would set `name` to (`None`: nothing, as
    /// reported).
    fn assigned(&mut self, name: Symbol, name_span: Span, value: &ast::Expr) -> Option<Slot> {
        if self.names.text(name) == "PI" {
            self.report(EvalError::new(EvalErrorKind::AssignToPi, name_span));
            return None;
        }
        if self
            .fanuc_parameter(name)
            .is_some_and(|n| n == 0 || n >= 1000)
        {
            let kind = EvalErrorKind::ReadOnlyVariable(self.names.text(name).to_string());
            self.report(EvalError::new(kind, name_span));
            return None;
        }
        Some(self.value_slot(value))
    }

    /// What a variable set to `value` holds: its value, or poisoned when
    /// it cannot be worked out (reported).
    fn value_slot(&mut self, value: &ast::Expr) -> Slot {
        // A copy of a vacant variable is vacant (Fanuc).
        if value::vacant(value, &self.vars) {
            return Slot::Vacant;
        }
        let result = match value::fast_number(value, &self.vars) {
            Some(n) => Ok(Value::Number(n)),
            None => value::eval(value, &self.vars),
        };
        match result {
            Ok(v) => Slot::Set(v),
            Err(e) => {
                self.report_expr(e);
                Slot::Poisoned
            }
        }
    }

    fn store(&mut self, name: Symbol, slot: Slot) {
        let var = &mut self.vars[name.0 as usize];
        if *var != slot {
            self.run.changes += 1;
        }
        *var = slot;
    }

    fn call(&mut self, name: Symbol, name_span: Span, args: &[ast::Expr], span: Span) -> Flow {
        let names = Rc::clone(&self.names);
        let text = names.text(name);
        let directive = setup::Directive::from_name(text);
        if directive.is_none() && !self.wizards.as_ref().is_some_and(|h| h.has(text)) {
            let known = self.wizards.as_ref().map(|h| h.names()).unwrap_or_default();
            self.unknown_wizard(text, name_span, &known);
            return Flow::Next;
        }
        let mut values = Vec::with_capacity(args.len());
        for a in args {
            match value::eval(a, &self.vars) {
                Ok(v) => values.push(v),
                Err(e) => {
                    self.report_expr(e);
                    return Flow::Next;
                }
            }
        }
        let arg_spans: Vec<Span> = args.iter().map(|a| a.span).collect();
        if let Some(directive) = directive {
            if let Some(first) = self.output.first_move {
                let directive = setup::Directive::NAMES[directive as usize];
                let kind = EvalErrorKind::SetupAfterFirstMove { directive, first };
                self.report(EvalError::new(kind, name_span));
                return Flow::Next;
            }
            if let Err(d) = self
                .setup
                .apply(directive, &values, name_span, &arg_spans, &self.names)
            {
                self.report(d);
            }
            return Flow::Next;
        }
        let Some(host) = self.wizards.take() else {
            return Flow::Next;
        };
        let call = WizardCall {
            span,
            arg_spans: &arg_spans,
            names: &names,
        };
        let result = {
            let mut ctx = Context { ev: self, span };
            host.call(text, &values, &call, &mut ctx)
        };
        match result {
            None => {
                let known = host.names();
                self.wizards = Some(host);
                self.unknown_wizard(text, name_span, &known);
                return Flow::Next;
            }
            Some(Ok(())) => {}
            Some(Err(ds)) => {
                for d in ds {
                    self.report(d);
                }
            }
        }
        self.wizards = Some(host);
        Flow::Next
    }

    fn unknown_wizard(&mut self, text: &str, span: Span, known: &[String]) {
        let mut candidates: Vec<&str> = setup::Directive::NAMES.to_vec();
        candidates.extend(known.iter().map(String::as_str));
        let nearest = candidates
            .iter()
            .map(|c| {
                (
                    value::edit_distance(&text.to_lowercase(), &c.to_lowercase()),
                    c,
                )
            })
            .filter(|(d, _)| *d <= 2)
            .min_by_key(|(d, _)| *d)
            .map(|(_, c)| c.to_string());
        let kind = EvalErrorKind::UnknownWizard {
            name: text.to_string(),
            nearest,
        };
        self.report(EvalError::new(kind, span));
    }
}

/// The evaluator as a wizard sees it: emitted statements get the call's
/// span.
struct Context<'e, 'a> {
    ev: &'e mut Evaluator<'a>,
    span: Span,
}

impl WizardContext for Context<'_, '_> {
    fn run_line(&mut self, line: &ast::Program) -> Result<(), Vec<Diagnostic>> {
        codes::run_wizard_line(self.ev, line, self.span)
    }

    fn emit(&mut self, op: ir::Op) -> Result<(), Diagnostic> {
        self.ev.emit(op, self.span)
    }

    fn state(&self) -> MachineState {
        let tool = self.ev.modal.tool;
        MachineState {
            position: self.ev.modal.position,
            incremental: self.ev.modal.distance == ir::Distance::Incremental,
            absolute_centers: self.ev.modal.arc_centers == ir::Distance::Absolute,
            inverse_time: self.ev.modal.inverse_time,
            polar: self.ev.modal.polar,
            units: self.ev.modal.units,
            tool,
            tool_diameter: self.ev.setup.tool_diameter(tool, self.ev.modal.units),
            tool_angle: self.ev.setup.tool_angle(tool),
            // under G93 an F is a time, not a feed per minute
            feed: self.ev.modal.feed.filter(|_| !self.ev.modal.inverse_time),
        }
    }
}

/// The variables' first values: LinuxCNC's numbered parameters `#1`–`#5000`
/// start at 0 (a fresh parameter file); every other name is unset.
/// `(DEBUG, …)` and `(PRINT, …)` notes shown at most.
const MAX_MESSAGES: usize = 100;

/// On Fanuc, `#0`, the locals `#1`–`#33` and the commons `#100`–`#199`
/// start vacant; `#500`–`#999` keep their values on the machine and the
/// rest are system variables, so they are unset (an error when read).
fn numbered_parameters(names: &Names, from: Flavour) -> Vec<Slot> {
    names
        .iter()
        .map(|(_, text)| first_slot(text, from))
        .collect()
}

/// The value the variable named `text` starts with.
fn first_slot(text: &str, from: Flavour) -> Slot {
    use crate::syntax::linuxcnc::{RETURN_VALUE, VALUE_RETURNED};
    match parameter_number(text) {
        Some(n) => first_value(n, from),
        // LinuxCNC's: 0 until a subroutine returns.
        None if from != Flavour::Fanuc && (text == RETURN_VALUE || text == VALUE_RETURNED) => {
            Slot::Set(Value::Number(0.0))
        }
        None => Slot::Unset,
    }
}

/// The value the numbered parameter `#n` starts with.
fn first_value(n: u32, from: Flavour) -> Slot {
    match (from, n) {
        (Flavour::Fanuc, 0..=33 | 100..=199) => Slot::Vacant,
        (Flavour::Fanuc, _) => Slot::Unset,
        (_, 1..=LAST_USER_PARAMETER) => Slot::Set(Value::Number(0.0)),
        _ => Slot::Unset,
    }
}

/// Where the line labelled `N<label>` is among `stmts`. (Not in a run of
/// [`ast::Lines`]: those are in parts of plain programs, which have no
/// `GOTO`.)
fn labelled(stmts: &[ast::Stmt], label: u32) -> Option<usize> {
    fn first(s: &ast::Stmt) -> Option<&ast::Word> {
        match &s.kind {
            StmtKind::Line(line) => line.words.first(),
            StmtKind::MacroCall(call) => call.words().next(),
            _ => None,
        }
    }
    stmts.iter().position(|s| {
        first(s).is_some_and(|w| {
            w.letter == b'N'
                && matches!(&w.value, ast::WordValue::Number(n) if n.value == f64::from(label))
        })
    })
}

impl Evaluator<'_> {
    /// Entering a Fanuc `G65` macro: a new level of locals `#1`–`#33`,
    /// the arguments set and the rest vacant. Returns the caller's values.
    fn fanuc_scope(&mut self, args: &[(u32, f64)]) -> Vec<(usize, Slot)> {
        let mut saved = Vec::new();
        for (k, local) in self.macros.scope.numbered.iter().enumerate() {
            if let Some(i) = *local {
                let value = args
                    .iter()
                    .find(|(n, _)| *n as usize == k + 1)
                    .map_or(Slot::Vacant, |(_, v)| Slot::Set(Value::Number(*v)));
                saved.push((i, std::mem::replace(&mut self.vars[i], value)));
            }
        }
        self.run.changes += 1;
        saved
    }

    /// Entering a subprogram from a LinuxCNC `o… call`: `#1`–`#30`
    /// take the call's arguments (0 where none is given or it could not
    /// be worked out) and the local named parameters start unset, as on
    /// LinuxCNC. Returns the caller's values, to be put back when the call
    /// returns.
    fn linuxcnc_scope(&mut self, args: &[Slot]) -> Vec<(usize, Slot)> {
        let scope = &self.macros.scope;
        let mut saved = Vec::new();
        for k in 0..30 {
            if let Some(i) = scope.numbered[k] {
                let value = match args.get(k) {
                    Some(slot @ Slot::Set(_)) => *slot,
                    _ => Slot::Set(Value::Number(0.0)),
                };
                saved.push((i, std::mem::replace(&mut self.vars[i], value)));
            }
        }
        for &i in &scope.named {
            saved.push((i, std::mem::replace(&mut self.vars[i], Slot::Unset)));
        }
        self.run.changes += 1;
        saved
    }
}

#[cfg(test)]
mod tests {
    use crate::driver::{compile, CompileOptions};
    use crate::source::Sources;
    use crate::syntax::Language;

    #[test]
    fn debug_messages_in_a_loop_are_capped() {
        let program = "G21 G90\n#2 = 0\no1 while [#2 LT 150]\n(DEBUG, pass #2)\n#2 = [#2 + 1]\no1 endwhile\nM2\n";
        let mut sources = Sources::new();
        let file = sources.add("p.ngc", program.to_string());
        let options = CompileOptions {
            input: Some(Language::Gcode),
            ..CompileOptions::default()
        };
        let compiled = compile(&sources, file, &options, None);
        assert!(compiled.output.is_some());
        let notes: Vec<String> = compiled
            .diagnostics
            .iter()
            .map(|d| d.message.clone())
            .collect();
        assert_eq!(notes.len(), super::MAX_MESSAGES + 1);
        assert_eq!(notes[0], "DEBUG: pass 0.000000");
        assert_eq!(notes[99], "DEBUG: pass 99.000000");
        assert!(notes[100].starts_with("more DEBUG and PRINT messages"));
    }
}
