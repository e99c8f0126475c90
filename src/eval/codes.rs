//! G and M codes: one statement of a line (a code and its argument words)
//! becomes IR. This is where the meaning of each code is decided — which
//! words it takes, what is modal, what is refused. Subprogram calls
//! (`M98`/`M99`) are run here too.

use super::corner;
use super::evaluator::{Evaluator, Flow};
use super::options::{Chosen, Flavour};
use super::state::Synced;
use super::value::Slot;
use super::words::WordValues;
use crate::ast::{self, LineStmt, OName, WordValue};
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Arc, ArcGeometry, Axes, Axis, Motion, Op};
use crate::source::Span;
use std::rc::Rc;

pub(super) mod error;

use error::{CodeError, CodeErrorKind as K};

/// A code for messages: its letter and number in tenths.
type Code = Option<(u8, u32)>;

/// Why the G code `t` (in tenths) is not one ger reads.
fn unsupported_g(t: u32) -> &'static str {
    match t {
        120 | 130 => "circle milling (G12/G13) is a Fanuc option; use G2/G3 or a CirclePocket wizard",
        541 => "extended work offsets (G54.1 P…) are not supported; use G54–G59.3",
        680 | 690 => "coordinate rotation is not supported",
        500 | 510 => "scaling is not supported",
        650 => "G65 is Fanuc's macro call, read in plain G-code (not in .egc)",
        950 => "feed per revolution (G95) is not supported: use G94 or G93",
        52 | 53 => "NURBS (G5.2/G5.3) are not supported; G5 and G5.1 splines are",
        700 | 710..=712 | 720..=722 => "lathe cycles (G70-G72) are outside what ger, a milling compiler, lowers",
        310 | 382..=385 => "a probing move stops where its switch trips, which only the machine knows; what follows it cannot be worked out",
        _ => "ger does not know this code",
    }
}

/// A G code in tenths: G1 is 10, G54.1 is 541.
fn tenths(value: f64) -> Option<u32> {
    // Rounded without a libm call (`round_to_int` is `round` here).
    let t = crate::emit::number::round_to_int(value * 10.0) as f64;
    ((value * 10.0 - t).abs() < 1e-6 && (0.0..100_000.0).contains(&t)).then_some(t as u32)
}

fn code_name(letter: u8, t: u32) -> String {
    if t.is_multiple_of(10) {
        format!("{}{}", letter as char, t / 10)
    } else {
        format!("{}{}.{}", letter as char, t / 10, t % 10)
    }
}

/// A word [`Evaluator::plain_move`] reads: an [`ast::Word`] of a line the
/// parser made, or a [`ast::PlainWord`] of [`ast::Lines`].
pub(super) trait MoveWord {
    fn letter(&self) -> u8;
    /// Its value, when it is written as a number.
    fn number(&self) -> Option<f64>;
}

impl MoveWord for ast::Word {
    #[inline]
    fn letter(&self) -> u8 {
        self.letter
    }

    #[inline]
    fn number(&self) -> Option<f64> {
        match &self.value {
            WordValue::Number(n) => Some(n.value),
            WordValue::Expr(_) => None,
        }
    }
}

impl MoveWord for ast::PlainWord {
    #[inline]
    fn letter(&self) -> u8 {
        self.letter
    }

    #[inline]
    fn number(&self) -> Option<f64> {
        Some(self.value)
    }
}

impl Evaluator<'_> {
    pub(super) fn exec_line_stmt(&mut self, stmt: LineStmt<'_>) -> Flow {
        if let Some(flow) = self.plain_move(stmt.code, stmt.args, |w| w.span) {
            return flow;
        }
        let table = self.word_table.take().unwrap_or_default();
        let mut words = WordValues::new(stmt.args, table);
        let flow = self.exec_stmt_words(stmt, &mut words);
        self.word_table = Some(words.table);
        flow
    }

    /// [`Self::exec_line_stmt`] with the table for its words.
    fn exec_stmt_words(&mut self, stmt: LineStmt<'_>, words: &mut WordValues) -> Flow {
        // G7 and G8 hold for the X words of their own line (rs274 reads X
        // by the mode, then rescales it when the line changes the mode).
        if let Some(code) = stmt.code.filter(|c| c.letter == b'G') {
            if let WordValue::Number(n) = &code.value {
                if n.value == 7.0 || n.value == 8.0 {
                    self.modal.diameter_mode = n.value == 7.0;
                }
            }
        }
        let span = stmt
            .code
            .map(|c| c.span)
            .or_else(|| stmt.args.first().map(|w| w.span))
            .unwrap_or_default();
        let Some(span) = self.read_words(stmt.args, words, span) else {
            return Flow::Next;
        };
        let result = match stmt.code {
            None => self.plain_words(words, span),
            Some(code) => {
                let Some(value) = self.word_value(code) else {
                    return Flow::Next;
                };
                match tenths(value) {
                    Some(t) if code.letter == b'G' => self.g_code(t, code.span, words, span),
                    Some(t) => self.m_code(t, code.span, words, span),
                    None => {
                        let letter = code.letter as char;
                        Err(CodeError::new(K::NotACode { letter, value }, code.span).into())
                    }
                }
            }
        };
        result.unwrap_or_else(|d| self.reported(d))
    }

    /// The values of a statement's words `args` (but its `N` words and
    /// those given a vacant variable) into `words`; `span` grown to the
    /// last. `None` when a word's value is an error, reported.
    fn read_words(
        &mut self,
        args: &[ast::Word],
        words: &mut WordValues,
        span: Span,
    ) -> Option<Span> {
        let mut span = span;
        for (i, w) in args.iter().enumerate() {
            span = span.to(w.span);
            if w.letter == b'N' {
                continue;
            }
            // A word given a vacant variable is left out (Fanuc).
            if matches!(&w.value, WordValue::Expr(e) if super::value::vacant(e, &self.vars)) {
                continue;
            }
            let mut value = self.word_value(w)?;
            if w.letter == b'X' && self.modal.diameter_mode {
                value /= 2.0;
            }
            if let Some(first) = words.given(w.letter) {
                let letter = ast::Word::spelling(w.letter);
                self.report(CodeError::new(K::WordTwice { letter, first }, w.span));
                return None;
            }
            words.set(w.letter, value, i);
        }
        Some(span)
    }

    /// A line with Fanuc's `G65` ([`ast::MacroCall`]): the statements
    /// before it, then the call ([`Self::macro_call`]) in any plain file,
    /// whatever `--from` says (G65 means nothing else to any controller
    /// ger reads); in `.egc` a G code like any other, which says so.
    pub(super) fn exec_macro_call(&mut self, call: &ast::MacroCall) -> Flow {
        self.this_line.machine_coordinates = false;
        self.this_line.inverse_feed = false;
        self.this_line.block_delete = call.block_delete;
        self.this_line.number = ast::line_number(&call.before);
        let mut flow = Flow::Next;
        for s in ast::statements(&call.before) {
            flow = self.exec_line_stmt(s);
            if flow != Flow::Next {
                break;
            }
        }
        if flow == Flow::Next {
            flow = match self.options.plain {
                true => self.run_macro_call(call),
                false => self.exec_line_stmt(LineStmt {
                    code: Some(&call.code),
                    args: &call.args,
                }),
            };
        }
        self.this_line.block_delete = false;
        self.this_line.number = None;
        flow
    }

    /// The call of a [`ast::MacroCall`], its words' values worked out.
    fn run_macro_call(&mut self, call: &ast::MacroCall) -> Flow {
        let table = self.word_table.take().unwrap_or_default();
        let mut words = WordValues::new(&call.args, table);
        let flow = match self.read_words(&call.args, &mut words, call.code.span) {
            Some(_) => self
                .macro_call(&mut words, call.code.span)
                .unwrap_or_else(|d| self.reported(d)),
            None => Flow::Next,
        };
        self.word_table = Some(words.table);
        flow
    }

    /// Report a statement's error; the program goes on after it, unless it
    /// is the statement limit (going on, every statement after it would be
    /// the same error). (Seldom called: kept out of the paths that call it.)
    #[cold]
    fn reported(&mut self, d: Diagnostic) -> Flow {
        self.report(d);
        match self.run.over_limit {
            true => Flow::Abort,
            false => Flow::Next,
        }
    }

    /// The commonest statements of a CAM program, a move of numbers (`G1
    /// X10.5 Y2 F300`, `G2 X1 Y1 I1 J0`, or the same without its code in
    /// that mode), made as [`Self::exec_stmt_words`] makes them (the same
    /// checks and statements, in the same order), without its table of
    /// words. `None`, having done nothing, for any other statement (an arc
    /// by R or of turns among them), and in a state that path must see (a
    /// cycle, G7, G53): that path runs it.
    /// `code` and `args` are a statement's ([`LineStmt`]), of either kind of
    /// word, `span` a word's span.
    #[inline]
    pub(super) fn plain_move<W: MoveWord>(
        &mut self,
        code: Option<&W>,
        args: &[W],
        span: impl Fn(&W) -> Span,
    ) -> Option<Flow> {
        #[cfg(test)]
        if GENERAL_PATH_ONLY.with(std::cell::Cell::get) {
            return None;
        }
        if self.cycles.kind.is_some()
            || self.modal.diameter_mode
            || self.this_line.machine_coordinates
        {
            return None;
        }
        let motion = match code {
            None => self.modal.motion?,
            Some(code) => match (code.letter(), code.number()) {
                (b'G', Some(0.0)) => Motion::Rapid,
                (b'G', Some(1.0)) => Motion::Linear,
                (b'G', Some(2.0)) => Motion::ArcCw,
                (b'G', Some(3.0)) => Motion::ArcCcw,
                _ => return None,
            },
        };
        let span = span(code.or(args.first())?).to(span(args.last()?));
        // X, Y, Z, F, I, J and K, a bit and a value each: numbers in range,
        // each given once.
        let (mut given, mut values) = (0u8, [0.0; 7]);
        for w in args {
            let slot = match MOVE_SLOTS[usize::from(w.letter())] {
                SKIP => continue,
                OTHER => return None,
                slot => slot,
            };
            match w.number() {
                Some(n) if ir::is_length(n) && given & (1 << slot) == 0 => {
                    given |= 1 << slot;
                    values[usize::from(slot)] = n;
                }
                _ => return None,
            }
        }
        let value = |slot: usize| (given & (1 << slot) != 0).then_some(values[slot]);
        let feed = value(3);
        // No axis (no move, or a full circle), a negative feed (an error),
        // an arc without its centre or a centre without an arc: that path.
        let centre = given & 0b111_0000 != 0;
        if given & 0b111 == 0 || feed.is_some_and(|f| f < 0.0) || centre != motion.is_arc() {
            return None;
        }
        // F first, then the mode, then the move (`feed_speed_tool`, `g_code`,
        // `leftover_move`).
        let mut made = Ok(());
        if let Some(f) = feed {
            made = self.emit(Op::Feed(f), span);
        }
        if made.is_ok() {
            if code.is_some() {
                self.modal.motion = Some(motion);
                self.cycles.run_open = false;
            }
            #[cfg(test)]
            PLAIN_MOVES.with(|n| n.set(n.get() + 1));
            made = self.emit_move_with(motion, span, |m| {
                for (slot, axis) in [Axis::X, Axis::Y, Axis::Z].into_iter().enumerate() {
                    if let Some(v) = value(slot) {
                        m.to.set(axis, v);
                    }
                }
                if motion.is_arc() {
                    m.arc = Some(Arc {
                        geometry: ArcGeometry::Center([value(4), value(5), value(6)]),
                        turns: 1,
                    });
                }
                Ok(())
            });
        }
        Some(match made {
            Ok(()) => Flow::Next,
            Err(d) => self.reported(d),
        })
    }

    /// The number a word stands for; symbolic words are evaluated.
    #[inline]
    fn word_value(&mut self, w: &ast::Word) -> Option<f64> {
        match &w.value {
            // Most words: a number in range for any letter.
            WordValue::Number(n) if ir::is_length(n.value) => Some(n.value),
            _ => self.word_value_checked(w),
        }
    }

    /// [`Self::word_value`] of any word.
    #[cold]
    fn word_value_checked(&mut self, w: &ast::Word) -> Option<f64> {
        let value = match &w.value {
            WordValue::Number(n) => n.value,
            WordValue::Expr(e) => {
                let what = || format!("the `{}` word", ast::Word::spelling(w.letter));
                match super::value::number(e, &self.vars, &what) {
                    Ok(v) => v,
                    Err(err) => {
                        self.report_expr(err);
                        return None;
                    }
                }
            }
        };
        // A length, feed or speed no machine has is a typo.
        let length = matches!(
            w.letter,
            b'X' | b'Y'
                | b'Z'
                | b'I'
                | b'J'
                | b'K'
                | b'R'
                | b'F'
                | b'S'
                | ast::Word::ROUND
                | ast::Word::CHAMFER
        );
        if length && !ir::is_length(value) {
            self.report(super::error::out_of_range(
                format!("`{}` is out of range", w.letter as char),
                "lengths, feeds and speeds",
                value,
                w.span,
            ));
            return None;
        }
        Some(value)
    }

    /// F, S and T come first in any statement: `G1 X10 F100` feeds at 100.
    fn feed_speed_tool(&mut self, w: &mut WordValues, span: Span) -> Result<(), Diagnostic> {
        if !w.has_any(b"FST") {
            return Ok(());
        }
        if let Some((f, fspan)) = w.take(b'F') {
            if f < 0.0 {
                return Err(CodeError::new(K::NegativeFeed, fspan).into());
            }
            self.emit(Op::Feed(f), span)?;
        }
        if let Some((s, sspan)) = w.take(b'S') {
            if s < 0.0 {
                return Err(CodeError::new(K::NegativeSpeed, sspan).into());
            }
            self.emit(Op::Speed(s), span)?;
        }
        if let Some((t, tspan)) = w.take(b'T') {
            let tool = whole(t, tspan, "a tool number")?;
            self.modal.selected = Some(tool);
            self.emit(Op::SelectTool(tool), span)?;
        }
        Ok(())
    }

    /// Words with no G/M code before them: F, S, T, and a move in the
    /// current motion mode.
    fn plain_words(&mut self, w: &mut WordValues, span: Span) -> Result<Flow, Diagnostic> {
        if let Some(synced) = self.modal.synced.filter(|_| w.has_any(b"XYZABCUVW@^")) {
            match synced {
                Synced::Thread => self.thread_feed_word(w, "G33")?,
                Synced::RigidTap => self.thread_feed_word(w, "G33.1")?,
                Synced::ThreadCycle => {}
            }
        }
        self.feed_speed_tool(w, span)?;
        self.leftover_move(w, span, None)?;
        Ok(Flow::Next)
    }

    /// Axis words left after a code took its own: a move in the current
    /// motion mode. Any other word left over is an error.
    fn leftover_move(
        &mut self,
        w: &mut WordValues,
        span: Span,
        code: Code,
    ) -> Result<(), Diagnostic> {
        let has_axes = w.has_any(b"XYZABCUVW@^");
        let corner = match w.has_any(&[ast::Word::ROUND, ast::Word::CHAMFER]) {
            true => corner::take_corner(w)?,
            false => None,
        };
        if let Some(kind) = self
            .cycles
            .kind
            .filter(|_| has_axes && !self.this_line.machine_coordinates)
        {
            if let Some((_, at)) = corner {
                return Err(CodeError::new(K::CornerNotOnG1("a canned cycle's block"), at).into());
            }
            self.cycle_block(kind, None, w, span)?;
            return self.unused_words(w, code);
        }
        let arc_words = w.has_any(b"IJKR");
        if let Some(synced) = self
            .modal
            .synced
            .filter(|_| has_axes && self.modal.motion.is_none())
        {
            match synced {
                Synced::Thread => self.thread(span, w, span)?,
                Synced::RigidTap => self.rigid_tap(span, w, span)?,
                Synced::ThreadCycle => self.threading_cycle(span, w, span)?,
            }
            return self.unused_words(w, code);
        }
        if has_axes || (arc_words && self.modal.motion.is_some_and(Motion::is_arc)) {
            let Some(motion) = self.modal.motion else {
                let (_, at) = w.remaining().next().unwrap_or((b'X', span));
                let kind = match self.modal.spline_mode {
                    true => K::Spline(error::SplineProblem::Again),
                    false => K::MoveWithoutMotion,
                };
                return Err(CodeError::new(kind, at).into());
            };
            if let Some((_, at)) = corner {
                corner::check_motion(motion, self.this_line.machine_coordinates, at)?;
            }
            self.polar_words(w)?;
            if self.this_line.machine_coordinates {
                let m = self.motion_move(motion, w, span)?;
                if m.motion.is_arc() {
                    return Err(CodeError::new(K::ArcInMachineCoordinates, span).into());
                }
                self.emit(Op::MachineMove(m), span)?;
            } else {
                self.emit_move(motion, w, span, corner.map(|(c, _)| c))?;
            }
        } else if let Some((_, at)) = corner {
            return Err(CodeError::new(K::CornerNotOnG1("a line without a move"), at).into());
        }
        self.unused_words(w, code)
    }

    /// Words no code of the statement took: an error at the first.
    fn unused_words(&self, w: &WordValues, code: Code) -> Result<(), Diagnostic> {
        if let Some((letter, at)) = w.remaining().next() {
            let kind = K::UnusedWord {
                letter: ast::Word::spelling(letter),
                code: code.map(|(l, t)| code_name(l, t)),
            };
            return Err(CodeError::new(kind, at).into());
        }
        Ok(())
    }

    fn motion_move(
        &mut self,
        motion: Motion,
        w: &mut WordValues,
        span: Span,
    ) -> Result<ir::Move, Diagnostic> {
        let to = axis_words(w);
        let arc = match motion.is_arc() {
            true => {
                let mut arc = Arc::BLANK;
                arc_words(w, span, &mut arc)?;
                Some(arc)
            }
            false => None,
        };
        Ok(ir::Move {
            motion,
            to,
            arc,
            corner: None,
            lead: None,
        })
    }

    /// A move of `motion` to the axis words of `w` (and its arc words), as
    /// [`Self::emit`] of it, but built where it is kept, in the batch. (Built
    /// apart and copied, a move is read back wide right after it was
    /// written a word at a time, and the processor waits for the writes.)
    fn emit_move(
        &mut self,
        motion: Motion,
        w: &mut WordValues,
        span: Span,
        corner: Option<ir::Corner>,
    ) -> Result<(), Diagnostic> {
        self.emit_move_with(motion, span, |m| {
            // Its words first: an error in them comes before any other.
            if motion.is_arc() {
                arc_words(w, span, m.arc.insert(Arc::BLANK))?;
            }
            axis_words_into(w, &mut m.to);
            m.corner = corner;
            Ok(())
        })
    }

    /// [`Self::emit_move`] of the move `fill` writes (its motion set).
    #[inline(always)]
    fn emit_move_with(
        &mut self,
        motion: Motion,
        span: Span,
        fill: impl FnOnce(&mut ir::Move) -> Result<(), Diagnostic>,
    ) -> Result<(), Diagnostic> {
        /// A statement to fill in: a constant, so that nothing just written
        /// is copied into the batch.
        const BLANK: ir::Stmt = ir::Stmt {
            op: Op::Move(ir::Move {
                motion: Motion::Rapid,
                to: Axes::NONE,
                arc: None,
                corner: None,
                lead: None,
            }),
            span: Span {
                file: 0,
                line: 0,
                start: 0,
                end: 0,
            },
            block_delete: false,
            number: None,
        };
        let mut out = std::mem::take(&mut self.out);
        out.push(BLANK);
        let mut filled = Ok(());
        if let Some(stmt) = out.last_mut() {
            stmt.span = span;
            stmt.block_delete = self.this_line.block_delete;
            stmt.number = self.kept_number();
            if let Op::Move(m) = &mut stmt.op {
                m.motion = motion;
                filled = fill(m);
            }
        }
        let admitted = match (filled, out.last()) {
            (Ok(()), Some(stmt)) => self.admit(&stmt.op, span),
            (Ok(()), None) => Ok(()),
            (Err(e), _) => Err(e),
        };
        if admitted.is_err() {
            out.pop();
        }
        // What `take` left holds nothing and allocated nothing (the checks
        // make no statement): forgotten, not dropped, which is a call.
        let placeholder = std::mem::replace(&mut self.out, out);
        debug_assert_eq!(placeholder.capacity(), 0);
        std::mem::forget(placeholder);
        admitted?;
        self.kept();
        Ok(())
    }

    fn g_code(
        &mut self,
        t: u32,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<Flow, Diagnostic> {
        let code = Some((b'G', t));
        // A computed `G#1` that is 65 ([`Self::exec_macro_call`] runs a
        // written one): its F, S and T are arguments.
        if t == 650 && self.options.plain {
            return self.macro_call(w, at);
        }
        if matches!(t, 960 | 970) {
            // Before the line's S, which it gives its meaning.
            let op = spindle_mode(t, at, w)?;
            self.emit(op, span)?;
        }
        if t == 330 || t == 331 {
            self.thread_feed_word(w, if t == 330 { "G33" } else { "G33.1" })?;
        }
        self.feed_speed_tool(w, span)?;
        let kind = match (t, self.options.from) {
            (760, Flavour::Fanuc) => Some(ir::CycleKind::G76),
            (870, Flavour::Fanuc) => Some(ir::CycleKind::G87Fanuc),
            _ => super::cycle::kind_of(t),
        };
        if let Some(kind) = kind {
            self.cycle_block(kind, Some(at), w, span)?;
            return self.unused_words(w, code).map(|_| Flow::Next);
        }
        match t {
            0 | 10 | 20 | 30 => self.select_motion(t),
            330 => {
                self.thread(at, w, span)?;
                return self.unused_words(w, code).map(|_| Flow::Next);
            }
            331 => {
                self.rigid_tap(at, w, span)?;
                return self.unused_words(w, code).map(|_| Flow::Next);
            }
            760 if self.options.from == Flavour::LinuxCnc => {
                self.threading_cycle(at, w, span)?;
                return self.unused_words(w, code).map(|_| Flow::Next);
            }
            50 | 51 => {
                self.spline(t, at, w, span)?;
                return self.unused_words(w, code).map(|_| Flow::Next);
            }
            960 | 970 => {}
            _ if self.g_mode(t, at, span)? => {}
            _ => {
                let op = self.g_statement(t, at, w)?;
                self.emit(op, span)?;
            }
        }
        self.leftover_move(w, span, code)?;
        Ok(Flow::Next)
    }

    /// G0, G1, G2 or G3 (`t` is 0, 10, 20 or 30): the motion mode, which
    /// ends a canned cycle's run.
    #[inline]
    fn select_motion(&mut self, t: u32) {
        self.modal.synced = None;
        self.modal.motion = Some(match t {
            0 => Motion::Rapid,
            10 => Motion::Linear,
            20 => Motion::ArcCw,
            _ => Motion::ArcCcw,
        });
        self.cycles.kind = None;
        self.cycles.run_open = false;
    }

    /// A G code other than the motion codes that sets a mode of the
    /// evaluator, and makes a statement at most where the mode changes:
    /// whether `t` is one.
    fn g_mode(&mut self, t: u32, at: Span, span: Span) -> Result<bool, Diagnostic> {
        match t {
            70 | 80 => {
                // Folded into the X words as they are read.
                if t == 70 {
                    self.warn_once((b'G', 70), || CodeError::new(K::DiameterMode, at));
                }
            }
            530 => {
                // The motion of this line is in machine coordinates.
                self.this_line.machine_coordinates = true;
            }
            // G90.1/G91.1: made only where the mode changes (G91.1, the
            // mode every program starts in, is most often a post's
            // header, and leaves the IR as it was).
            901 | 911 => {
                let mode = if t == 901 {
                    ir::Distance::Absolute
                } else {
                    ir::Distance::Incremental
                };
                if mode != self.modal.arc_centers {
                    self.emit(Op::ArcCenters(mode), span)?;
                }
            }
            // G93/G94: made only where the mode changes (G94 is most often
            // a post's header).
            930 | 940 => {
                let on = t == 930;
                if on != self.modal.inverse_time {
                    self.emit(Op::InverseTime(on), span)?;
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// A G code that is one IR statement: that statement.
    fn g_statement(&mut self, t: u32, at: Span, w: &mut WordValues) -> Result<Op, Diagnostic> {
        // Only for messages: built when one is needed.
        let name = || code_name(b'G', t);
        Ok(match t {
            40 => self.dwell(w, at)?,
            610 => Op::PathControl(ir::PathControl::ExactPath),
            611 => Op::PathControl(ir::PathControl::ExactStop),
            640 => blend(w)?,
            100 => self.g10(w, at)?,
            150 => Op::Polar(false),
            160 => Op::Polar(true),
            170 => Op::Plane(ir::Plane::XY),
            180 => Op::Plane(ir::Plane::ZX),
            190 => Op::Plane(ir::Plane::YZ),
            200 => Op::Units(ir::Units::Inch),
            210 => Op::Units(ir::Units::Mm),
            280 | 300 => {
                let via = axis_words(w);
                self.warn_once((b'G', t), || {
                    CodeError::new(K::HomePassedThrough(name()), at)
                });
                Op::Home {
                    home: if t == 280 {
                        ir::Home::G28
                    } else {
                        ir::Home::G30
                    },
                    via,
                    incremental: false,
                }
            }
            400 => Op::CompOff,
            410 | 420 | 411 | 421 => self.comp_on(t, at, w)?,
            430 | 440 => {
                let tool = match w.take(b'H') {
                    Some((h, hspan)) => whole(h, hspan, "a tool number")?,
                    None => self.modal.tool,
                };
                Op::ToolLength {
                    tool: Some(tool),
                    negative: t == 440,
                }
            }
            490 => Op::CancelToolLength,
            520 => Op::LocalOffset(self.take_axes(w, at, "G52", false)?),
            540..=590 if t.is_multiple_of(10) => Op::SelectWorkOffset((t / 10 - 53) as u8),
            // G59.1 … G59.3: the systems after G59 (LinuxCNC's P7 … P9).
            591..=593 => Op::SelectWorkOffset((t - 584) as u8),
            760 => return Err(CodeError::new(K::G76, at).into()),
            800 => {
                self.modal.synced = None;
                self.cycles.kind = None;
                self.cycles.run_open = false;
                Op::CycleOff
            }
            900 => Op::Distance(ir::Distance::Absolute),
            910 => Op::Distance(ir::Distance::Incremental),
            920 => {
                let axes = self.take_axes(w, at, "G92", true)?;
                Op::SetPosition(if axes.is_empty() {
                    Axes::xyz(0.0, 0.0, 0.0)
                } else {
                    axes
                })
            }
            921 | 922 => Op::CancelPosition,
            980 | 990 => {
                self.cycles.return_level_stated = true;
                Op::ReturnLevel(if t == 980 {
                    ir::ReturnLevel::Initial
                } else {
                    ir::ReturnLevel::R
                })
            }
            _ => {
                let why = unsupported_g(t);
                let kind = K::Unsupported { code: name(), why };
                return Err(CodeError::new(kind, at).into());
            }
        })
    }

    fn m_code(
        &mut self,
        t: u32,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<Flow, Diagnostic> {
        let code = Some((b'M', t));
        let name = || code_name(b'M', t);
        if t == 980 {
            return self.subprogram_call(w, at, span);
        }
        self.feed_speed_tool(w, span)?;
        let (op, flow) = match t {
            0 => (Op::Stop(ir::Stop::Program), Flow::Next),
            10 => (Op::Stop(ir::Stop::Optional), Flow::Next),
            20 | 300 => (Op::End, Flow::End),
            30 => (Op::Spindle(ir::Spindle::Clockwise), Flow::Next),
            40 => (Op::Spindle(ir::Spindle::CounterClockwise), Flow::Next),
            50 => (Op::Spindle(ir::Spindle::Off), Flow::Next),
            60 => {
                if let Some(tool) = self.modal.selected {
                    self.modal.tool = tool;
                }
                (Op::ChangeTool, Flow::Next)
            }
            70 => (Op::Coolant(ir::Coolant::Mist), Flow::Next),
            80 => (Op::Coolant(ir::Coolant::Flood), Flow::Next),
            90 => (Op::Coolant(ir::Coolant::Off), Flow::Next),
            990 => {
                self.leftover_move(w, span, code)?;
                return Ok(Flow::Return);
            }
            470 => {
                let kind = K::Unsupported {
                    code: name(),
                    why: "M47 repeats the program from the top; the output cannot express it",
                };
                return Err(CodeError::new(kind, at).into());
            }
            700 | 730 => {
                if t == 730 && self.macros.calls.is_empty() {
                    self.report(CodeError::new(K::M73AtTopLevel, at));
                }
                self.save_modes(t == 730);
                self.leftover_move(w, span, code)?;
                return Ok(Flow::Next);
            }
            710 => {
                self.forget_modes();
                self.leftover_move(w, span, code)?;
                return Ok(Flow::Next);
            }
            720 => {
                let Some(saved) = self.saved_modes() else {
                    return Err(CodeError::new(K::NoSavedModes, at).into());
                };
                self.leftover_move(w, span, code)?;
                return Ok(self.restore_modes(&saved, span));
            }
            // Any other whole M code is the machine's: passed through.
            _ if t.is_multiple_of(10) => {
                let number = t / 10;
                let mut words = Vec::new();
                for letter in [b'P', b'Q', b'E', b'L'] {
                    if let Some((v, _)) = w.take(letter) {
                        words.push((letter, v));
                    }
                }
                self.warn_once((b'M', t), || {
                    CodeError::new(K::MCodePassedThrough(number), at)
                });
                (
                    Op::Passthrough(ir::Passthrough::MCode { number, words }),
                    Flow::Next,
                )
            }
            _ => {
                let kind = K::Unsupported {
                    code: name(),
                    why: "the output cannot express this code",
                };
                return Err(CodeError::new(kind, at).into());
            }
        };
        self.emit(op, span)?;
        // LinuxCNC reads the point back at a tool change (M6, M61): after
        // G40 with no move since, it is the tool's last offset point.
        if t == 60 || t == 610 {
            if let Some(plane) = self.modal.comp_off.take() {
                self.emit(Op::ReadPosition(plane), span)?;
            }
        }
        self.leftover_move(w, span, code)?;
        Ok(flow)
    }

    fn dwell(&mut self, w: &mut WordValues, at: Span) -> Result<Op, Diagnostic> {
        let seconds = match (w.take_number(b'P'), w.take(b'X')) {
            (Some((p, pspan, _)), None) => self.seconds(p, pspan)?,
            (None, Some((x, _))) => x,
            (Some(_), Some((_, xspan))) => return Err(CodeError::new(K::DwellTwice, xspan).into()),
            (None, None) => return Err(CodeError::new(K::DwellWithoutTime, at).into()),
        };
        if seconds < 0.0 {
            return Err(CodeError::new(K::NegativeDwell, at).into());
        }
        Ok(Op::Dwell(seconds))
    }

    /// A dwell's P in seconds: milliseconds on Fanuc, seconds on the
    /// others. The first P of a plain program whose controller no flag
    /// named gets a note saying whose meaning was taken, and why.
    pub(super) fn seconds(&mut self, p: f64, pspan: Span) -> Result<f64, Diagnostic> {
        let from = self.options.from;
        let seconds = match from {
            Flavour::Generic | Flavour::LinuxCnc | Flavour::Grbl | Flavour::Mach3 => p,
            Flavour::Fanuc => p / 1000.0,
        };
        let chosen = self.options.chosen;
        if self.options.plain && chosen != Chosen::Flag {
            self.warn_once((b'G', 40), || {
                CodeError::new(K::DwellMeaning { p, from, chosen }, pspan)
            });
        }
        if seconds < 0.0 {
            return Err(CodeError::new(K::NegativeDwell, pspan).into());
        }
        Ok(seconds)
    }

    fn g10(&mut self, w: &mut WordValues, at: Span) -> Result<Op, Diagnostic> {
        let Some((l, lspan)) = w.take(b'L') else {
            return Err(CodeError::new(K::G10WithoutL, at).into());
        };
        // The form first: P and R mean other things in the others (L1's
        // P is a tool, its R the tool's radius).
        let here = match l as i64 {
            1 if l == 1.0 => return tool_data(w, at, ir::Measured::Given),
            2 if l == 2.0 => false,
            20 if l == 20.0 => true,
            10 | 11 if l.fract() == 0.0 && self.options.from == Flavour::Fanuc => {
                return Err(CodeError::new(K::FanucOffsetMemory, lspan).into());
            }
            10 if l == 10.0 => return tool_data(w, at, ir::Measured::Here),
            11 if l == 11.0 => return tool_data(w, at, ir::Measured::InFixture),
            _ => return Err(CodeError::new(K::G10Form, lspan).into()),
        };
        let Some((p, pspan)) = w.take(b'P') else {
            return Err(CodeError::new(K::G10WithoutP, at).into());
        };
        let mut index = whole(p, pspan, "a work offset number")?;
        // P0: the system in use on LinuxCNC (Fanuc's is its external
        // offset, which shifts every system: refused below).
        if index == 0 && self.options.from != Flavour::Fanuc {
            index = u32::from(self.modal.work_offset);
        }
        if !(1..=9).contains(&index) {
            return Err(CodeError::new(K::WorkOffsetNumber, pspan).into());
        }
        if let Some((_, rspan)) = w.take(b'R') {
            return Err(CodeError::new(K::RotatedWorkOffset, rspan).into());
        }
        let axes = self.take_axes(w, at, "G10", true)?;
        Ok(match here {
            false => Op::SetWorkOffset {
                index: index as u8,
                origin: axes,
            },
            true => Op::SetWorkOffsetHere {
                index: index as u8,
                at: axes,
            },
        })
    }

    /// X/Y/Z of a code that takes axes itself (G52, G92, G10 L2/L20).
    fn take_axes(
        &mut self,
        w: &mut WordValues,
        at: Span,
        name: &'static str,
        may_be_empty: bool,
    ) -> Result<Axes, Diagnostic> {
        let axes = axis_words(w);
        if axes.is_empty() && !may_be_empty {
            return Err(CodeError::new(K::WithoutAxes(name), at).into());
        }
        Ok(axes)
    }

    /// `M98 P… L…`: run a subprogram inline, L times (or the Fanuc form
    /// `P31000`: the digits before the last four are the count).
    fn subprogram_call(
        &mut self,
        w: &mut WordValues,
        at: Span,
        span: Span,
    ) -> Result<Flow, Diagnostic> {
        let Some((p, pspan, written)) = w.take_number(b'P') else {
            return Err(CodeError::new(K::M98WithoutP, at).into());
        };
        let p = whole(p, pspan, "a program number")?;
        let (number, mut count) = written.m98_split(p);
        if let Some((l, lspan)) = w.take(b'L') {
            if count != 1 {
                return Err(CodeError::new(K::M98CountTwice, lspan).into());
            }
            count = whole(l, lspan, "a repeat count")?;
        }
        self.feed_speed_tool(w, span)?;
        self.leftover_move(w, span, Some((b'M', 980)))?;
        self.run_subprogram(OName::Number(number), count, pspan, at, |_| Vec::new())
    }

    /// Fanuc's `G65 P… L… A… B…`: a macro call. Every other word is an
    /// argument (argument specification I: A → #1, B → #2, C → #3, I → #4
    /// … Z → #26), set in a new level of locals `#1`–`#33` where the rest
    /// start vacant; the caller's come back after it.
    fn macro_call(&mut self, w: &mut WordValues, at: Span) -> Result<Flow, Diagnostic> {
        let Some((p, pspan)) = w.take(b'P') else {
            return Err(CodeError::new(K::G65WithoutP, at).into());
        };
        let number = whole(p, pspan, "a program number")?;
        let count = match w.take(b'L') {
            Some((l, lspan)) => whole(l, lspan, "a repeat count")?,
            None => 1,
        };
        let mut args = Vec::new();
        for (letter, local) in MACRO_ARGUMENTS {
            if let Some((value, _)) = w.take(letter) {
                args.push((local, value));
            }
        }
        self.unused_words(w, Some((b'G', 650)))?;
        self.run_subprogram(OName::Number(number), count, pspan, at, |ev| {
            ev.fanuc_scope(&args)
        })
    }

    /// LinuxCNC's `o… call [a] [b] …`: the subprogram runs once with `#1`,
    /// `#2`, … set to the arguments, in a scope of its own
    /// ([`Self::linuxcnc_scope`]). An argument that cannot be worked out
    /// is reported and passed as 0.
    pub(super) fn sub_call(&mut self, call: &ast::SubCall) -> Flow {
        let args: Vec<Slot> = call.args.iter().map(|a| self.value_slot(a)).collect();
        self.run_subprogram(call.name, 1, call.at, call.at, |ev| {
            ev.linuxcnc_scope(&args)
        })
        .unwrap_or_else(|d| self.reported(d))
    }

    /// LinuxCNC's `oN sub` inside a block, where no subprogram starts: its
    /// o-word is a word no code uses.
    pub(super) fn misplaced_sub(&mut self, at: Span) -> Flow {
        let kind = K::UnusedWord {
            letter: "O".into(),
            code: None,
        };
        self.reported(CodeError::new(kind, at).into())
    }

    /// Run subprogram `name` `count` times, in the scope `enter` makes
    /// (it returns the values to put back after).
    fn run_subprogram(
        &mut self,
        name: OName,
        count: u32,
        pspan: Span,
        at: Span,
        enter: impl FnOnce(&mut Self) -> Vec<(usize, Slot)>,
    ) -> Result<Flow, Diagnostic> {
        let program = self.program;
        // The program's, or one a part read before kept.
        let kept = || self.macros.kept.iter().find(|s| s.name == name).cloned();
        let sub = match program.subprograms.iter().find(|s| s.name == name) {
            Some(sub) => Sub::Program(sub),
            None => match kept() {
                Some(sub) => Sub::Kept(sub),
                // It may be written further on, in a part not read yet.
                None if self.macros.in_parts => {
                    self.macros.needs_whole = true;
                    return Ok(Flow::Abort);
                }
                None => return Err(self.no_subprogram(name, pspan)),
            },
        };
        let body: &[ast::Stmt] = match &sub {
            Sub::Program(sub) => &sub.body,
            Sub::Kept(sub) => &sub.body,
        };
        if self.macros.calls.len() >= self.options.max_call_depth {
            // It stops the program: going on, each level would run the
            // rest of its body and its repeats (`L3` at 64 levels: 3^64).
            self.report_call_depth(name, at);
            return Ok(Flow::Abort);
        }
        self.macros.calls.push((name, at));
        let level = self.macros.calls.len();
        self.leave_level(level);
        let saved = enter(self);
        let mut flow = Flow::Next;
        for _ in 0..count {
            self.run.repeating += 1;
            let ran = self.exec_block(body);
            self.run.repeating -= 1;
            flow = match ran {
                Flow::Return | Flow::Next => Flow::Next,
                other => self.no_label(other),
            };
            if flow != Flow::Next {
                break;
            }
        }
        if !saved.is_empty() {
            self.run.changes += 1;
        }
        for (i, slot) in saved {
            self.vars[i] = slot;
        }
        let restore = self.leave_level(level);
        self.macros.calls.pop();
        match restore {
            Some(modes) if flow == Flow::Next => Ok(self.restore_modes(&modes, at)),
            _ => Ok(flow),
        }
    }

    /// A call of a subprogram neither the program nor a part read before
    /// has; the error names those it has.
    fn no_subprogram(&self, name: OName, pspan: Span) -> Diagnostic {
        let names = &self.names;
        let file = match name {
            OName::Named(s) => names
                .text(s)
                .strip_prefix("o<")
                .and_then(|n| n.strip_suffix('>'))
                .map(str::to_string),
            OName::Number(_) => None,
        };
        let numbers = self.program.subprograms.iter().map(|s| s.name);
        let kept = self.macros.kept.iter().map(|s| s.name);
        let known = numbers.chain(kept).map(|n| n.describe(names)).collect();
        let name = name.describe(names);
        let kind = K::NoSubprogram { name, file, known };
        CodeError::new(kind, pspan).into()
    }

    /// Calls nested deeper than the limit. Runaway recursion is the usual
    /// cause: the error says where it started.
    fn report_call_depth(&mut self, name: OName, at: Span) {
        let recursion = self
            .macros
            .calls
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, first)| (name.describe(&self.names), first));
        let kind = K::CallDepth {
            limit: self.options.max_call_depth,
            recursion,
        };
        self.report(CodeError::new(kind, at));
    }
}

/// A subprogram found for a call: the program's, or one kept from a part
/// read before ([`super::eval_chunks`]).
enum Sub<'a> {
    Program(&'a ast::Subprogram),
    Kept(Rc<ast::Subprogram>),
}

/// Fanuc's argument specification I: the local each letter of a `G65`
/// sets.
const MACRO_ARGUMENTS: [(u8, u32); 21] = [
    (b'A', 1),
    (b'B', 2),
    (b'C', 3),
    (b'I', 4),
    (b'J', 5),
    (b'K', 6),
    (b'D', 7),
    (b'E', 8),
    (b'F', 9),
    (b'H', 11),
    (b'M', 13),
    (b'Q', 17),
    (b'R', 18),
    (b'S', 19),
    (b'T', 20),
    (b'U', 21),
    (b'V', 22),
    (b'W', 23),
    (b'X', 24),
    (b'Y', 25),
    (b'Z', 26),
];

/// The axis words of a statement: X Y Z, A B C (degrees), U V W.
#[inline(always)]
fn axis_words(w: &mut WordValues) -> Axes {
    let mut axes = Axes::default();
    axis_words_into(w, &mut axes);
    axes
}

/// The arc words (I J K, R, P) of an arc move, taken from `w` into `arc`,
/// in place (a result moved out of a call is read back wide right after
/// it was written: the processor waits for the writes).
fn arc_words(w: &mut WordValues, span: Span, arc: &mut Arc) -> Result<(), Diagnostic> {
    let center: ir::Center = [b'I', b'J', b'K'].map(|l| w.take_value(l));
    let radius = w.take(b'R');
    arc.turns = match w.take(b'P') {
        Some((p, pspan)) => {
            let n = whole(p, pspan, "a number of turns")?;
            if n == 0 {
                return Err(CodeError::new(K::ZeroTurns, pspan).into());
            }
            n
        }
        None => 1,
    };
    arc.geometry = match (radius, center.iter().all(Option::is_none)) {
        (Some((_, rspan)), false) => return Err(CodeError::new(K::RadiusAndCentre, rspan).into()),
        (Some((0.0, rspan)), true) => return Err(CodeError::new(K::ZeroRadius, rspan).into()),
        (Some((r, _)), true) => ArcGeometry::Radius(r),
        (None, false) => ArcGeometry::Center(center),
        (None, true) => return Err(CodeError::new(K::ArcWithoutCentre, span).into()),
    };
    Ok(())
}

/// [`axis_words`] into `axes` (empty).
#[inline(always)]
pub(super) fn axis_words_into(w: &mut WordValues, axes: &mut Axes) {
    for axis in Axis::ALL {
        if let Some(v) = w.take_value(axis.letter()) {
            axes.set(axis, v);
        }
    }
}

/// [`Evaluator::plain_move`]'s slot of each letter: X, Y, Z, F, I, J and
/// K are 0 to 6, `N` is [`SKIP`]ped, any other is [`OTHER`] (looked up,
/// not matched: a match on the letter is a jump the processor guesses
/// wrong as often as the letters change).
const MOVE_SLOTS: [u8; 256] = {
    let mut slots = [OTHER; 256];
    let letters = *b"XYZFIJK";
    let mut i = 0;
    while i < letters.len() {
        slots[letters[i] as usize] = i as u8;
        i += 1;
    }
    slots[b'N' as usize] = SKIP;
    slots
};
const SKIP: u8 = 254;
const OTHER: u8 = 255;

#[cfg(test)]
thread_local! {
    /// Tests: every statement by the general path (`exec_stmt_words`), to
    /// compare [`Evaluator::plain_move`] with it.
    static GENERAL_PATH_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// Tests: the moves [`Evaluator::plain_move`] made.
    static PLAIN_MOVES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// A word that must hold a whole, non-negative number.
/// G64 and its tolerances: P how far from a corner the blend may pass,
/// Q LinuxCNC's naive-CAM tolerance. A negative one is none given
/// (rs274: the default tolerance, and Q as P).
fn blend(w: &mut WordValues) -> Result<Op, Diagnostic> {
    let mut tolerance = |letter: u8| -> Result<Option<f64>, Diagnostic> {
        match w.take(letter) {
            Some((v, span)) if !ir::is_length(v) => Err(super::error::out_of_range(
                format!("G64 `{}` is out of range", letter as char),
                "tolerances",
                v,
                span,
            )),
            Some((v, _)) => Ok((v >= 0.0).then_some(v)),
            None => Ok(None),
        }
    };
    Ok(Op::PathControl(ir::PathControl::Blend {
        tolerance: tolerance(b'P')?,
        naive: tolerance(b'Q')?,
    }))
}

/// G96 (S its surface speed, D its limit in rpm, positive) or G97.
fn spindle_mode(t: u32, at: Span, w: &mut WordValues) -> Result<Op, Diagnostic> {
    if t == 970 {
        return Ok(Op::SpindleMode(ir::SpindleMode::Rpm));
    }
    let speed = match w.take(b'S') {
        None => return Err(CodeError::new(K::SurfaceSpeedWithoutS, at).into()),
        Some((s, span)) if s < 0.0 => return Err(CodeError::new(K::NegativeSpeed, span).into()),
        Some((s, _)) => s,
    };
    let max_rpm = match w.take(b'D') {
        Some((d, span)) if !(d > 0.0 && ir::is_length(d)) => {
            return Err(super::error::out_of_range(
                "G96 `D` is out of range".to_string(),
                "spindle speeds",
                d,
                span,
            ))
        }
        Some((d, _)) => Some(d),
        None => None,
    };
    Ok(Op::SpindleMode(ir::SpindleMode::SurfaceSpeed {
        speed,
        max_rpm,
    }))
}

/// `G10 L1 P<tool> R<radius> Z<length>` (rs274's convert_setup_tool),
/// or L10/L11 with the Z the current point is to read (`measured`): only
/// the values given change. Q, I and J (a lathe tool's orientation
/// and angles) do not change a mill's path and are passed on as written;
/// an offset on another axis is refused, as ger keeps a tool's radius and
/// Z length only.
fn tool_data(w: &mut WordValues, at: Span, measured: ir::Measured) -> Result<Op, Diagnostic> {
    let Some((p, pspan)) = w.take(b'P') else {
        return Err(CodeError::new(K::ToolDataWithoutP(measured.l_number()), at).into());
    };
    let lathe = [b'Q', b'I', b'J'].map(|letter| w.take(letter).map(|(v, _)| v));
    for letter in *b"XYABCUVW" {
        if let Some((_, span)) = w.take(letter) {
            return Err(CodeError::new(K::ToolDataAxis(letter as char), span).into());
        }
    }
    let tool = whole(p, pspan, "a tool number")?;
    let radius = w.take(b'R');
    if let Some((r, rspan)) = radius {
        if r < 0.0 {
            return Err(CodeError::new(K::NegativeToolRadius, rspan).into());
        }
    }
    Ok(Op::SetToolData(ir::ToolData {
        tool,
        radius: radius.map(|(r, _)| r),
        length: w.take(b'Z').map(|(z, _)| z),
        measured,
        lathe,
    }))
}

fn whole(value: f64, span: Span, what: &'static str) -> Result<u32, Diagnostic> {
    ast::whole_number(value).ok_or_else(|| CodeError::new(K::NotWhole(what), span).into())
}

/// Run one line of extended G-code that a wizard produced (parsed, without
/// errors, where the script gave it); its statements take the wizard
/// call's span.
pub(super) fn run_wizard_line(
    ev: &mut Evaluator<'_>,
    program: &ast::Program,
    span: Span,
) -> Result<(), Vec<Diagnostic>> {
    for stmt in &program.main {
        let ast::StmtKind::Line(line) = &stmt.kind else {
            return Err(vec![CodeError::new(K::WizardLineNotPlain, span).into()]);
        };
        let mut line = line.clone();
        for w in &mut line.words {
            if matches!(w.value, WordValue::Expr(_)) {
                return Err(vec![CodeError::new(K::WizardLineVariables, span).into()]);
            }
            w.span = span;
        }
        let before = ev.reports.errors;
        ev.exec_line(&line);
        if ev.reports.errors > before {
            return Err(Vec::new());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::{GENERAL_PATH_ONLY, PLAIN_MOVES};
    use crate::driver::{compile, CompileOptions};
    use crate::source::Sources;

    /// A made-up program of moves of numbers (the statements
    /// `Evaluator::plain_move` takes) and of what it must leave to the
    /// general path: other words and codes, words twice, lengths out of
    /// range, negative feeds, arcs by R or of turns, full circles, moves
    /// without a mode, and the states a move of numbers means something
    /// else in (G91, G20, a cycle, G7, G53, compensation).
    fn made_up_program(seed: u64) -> String {
        let mut random = crate::test_random::Random::new(seed);
        let mut next = |n: u64| random.below(n);
        // A third of the programs have only what is right; the others
        // (most of which fail) also what is not.
        let wild = next(3) != 0;
        let mut text = String::from(match wild {
            false => "G21 G90 G17 F100\n",
            true => ["G20 G17 F10\n", "G17\n"][next(2) as usize],
        });
        text.push_str(["G0 X0 Y0 Z5\n", ""][usize::from(wild && next(4) == 0)]);
        // Where the tool is (in absolute lines), so that most arcs are arcs.
        let (mut x, mut y) = (0.0f64, 0.0f64);
        // G7: X words are diameters.
        let mut diameters = false;
        for _ in 0..60 {
            let mut line = String::new();
            if next(10) == 0 {
                line.push_str("N10 ");
            }
            let code = match wild {
                true => next(40),
                // (Each with its code: after an arc, a move of axes alone is one.)
                false => [10, 12, 12, 18, 18, 30, 31][next(7) as usize],
            };
            match code {
                0 => line.push_str("G91 "),
                1 => line.push_str("G90 "),
                2 => line.push_str("G81 R1 Z-1 "),
                3 => line.push_str("G80 "),
                4 | 5 => {
                    diameters = code == 4;
                    line.push_str(["G8 ", "G7 "][usize::from(diameters)]);
                }
                6 => line.push_str("G53 "),
                7 => line.push_str("G41.1 D2 "),
                8 => line.push_str("G40 "),
                9 => line.push_str("M3 S1000 "),
                10 => line.push_str("G01 "),
                11 => line.push_str("G0.5 "),
                30 => {
                    diameters = next(2) == 0;
                    line.push_str(["G8 G1 ", "G7 G1 "][usize::from(diameters)]);
                }
                31 => {
                    // (Z alone: X and Y stay known.)
                    text.push_str(&format!("G53 G0 Z{}\n", next(50)));
                    continue;
                }
                32 => line.push_str("G91 G1 "),
                33 => line.push_str("G90 G1 "),
                12..=17 => line.push_str(["G0 ", "G1 "][next(2) as usize]),
                18..=25 => {
                    (x, y) = push_arc(&mut line, &mut next, wild, diameters, (x, y));
                    text.push_str(&line);
                    text.push('\n');
                    continue;
                }
                _ => {}
            }
            // The last X is a second one.
            for (k, letter) in ["X", "Y", "Z", "F", "A", "S", "I", "X"]
                .into_iter()
                .enumerate()
            {
                let value = match next(if wild { 30 } else { 1000 }) {
                    0 => 2e7,
                    1 if letter == "F" => -5.0,
                    _ => (next(2000) as f64 + 1.0) / 100.0,
                };
                let wanted = match letter {
                    "X" | "Y" | "Z" if k < 7 => next(2) == 0,
                    "F" => next(6) == 0,
                    _ => wild && next(40) == 0,
                };
                if wanted {
                    line.push_str(&format!("{letter}{value} "));
                    match letter {
                        "X" if diameters => x = value / 2.0,
                        "X" => x = value,
                        "Y" => y = value,
                        _ => {}
                    }
                }
            }
            text.push_str(&line);
            text.push('\n');
        }
        text.push_str("M30\n");
        text
    }

    /// An arc from `from` about a centre a random step away, pushed to
    /// `line` (in a wild program now and then with a word such an arc must
    /// not have); where it ends, as written.
    fn push_arc(
        line: &mut String,
        next: &mut impl FnMut(u64) -> u64,
        wild: bool,
        diameters: bool,
        (x, y): (f64, f64),
    ) -> (f64, f64) {
        let i = (next(9) as f64 - 4.0) / 2.0;
        let j = (next(8) as f64 + 1.0) / 2.0 * [1.0, -1.0][next(2) as usize];
        let (cx, cy, turn) = (x + i, y + j, next(628) as f64 / 100.0);
        let (ex, ey) = (
            cx + (x - cx) * turn.cos() - (y - cy) * turn.sin(),
            cy + (x - cx) * turn.sin() + (y - cy) * turn.cos(),
        );
        let g = ["G2", "G3"][next(2) as usize];
        // (Under G7 the X word is twice the coordinate.)
        let xw = if diameters { 2.0 * ex } else { ex };
        line.push_str(&format!("{g} X{xw:.3} Y{ey:.3} I{i} J{j} "));
        match next(if wild { 12 } else { 1000 }) {
            0 => line.push_str("R2 "),
            1 => line.push_str("P2 "),
            2 => line.push_str("K1 "),
            3 => line.push_str("J1 "),
            _ => {}
        }
        (
            (ex * 1000.0).round() / 1000.0,
            (ey * 1000.0).round() / 1000.0,
        )
    }

    /// `plain_move` makes what the general path makes of every statement:
    /// the same output, the same diagnostics, on made-up programs (as
    /// LinuxCNC's and as ger's language).
    #[test]
    fn moves_of_numbers_are_made_as_the_general_path_makes_them() {
        let (mut with_output, mut taken) = (0, 0);
        for seed in 1..=300u64 {
            let text = made_up_program(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let name = ["made_up.ngc", "made_up.egc"][seed as usize % 2];
            let mut sources = Sources::new();
            let file = sources.add(name, text.clone());
            let options = CompileOptions::default();
            let mut compiled = Vec::new();
            for general in [true, false] {
                GENERAL_PATH_ONLY.with(|g| g.set(general));
                let before = PLAIN_MOVES.with(std::cell::Cell::get);
                let c = compile(&sources, file, &options, None);
                taken += PLAIN_MOVES.with(std::cell::Cell::get) - before;
                compiled.push((c.output, format!("{:?}", c.diagnostics)));
            }
            GENERAL_PATH_ONLY.with(|g| g.set(false));
            assert_eq!(compiled[0], compiled[1], "{name}:\n{text}");
            with_output += usize::from(compiled[0].0.is_some());
        }
        // The comparison means something: programs come out, and moves were
        // made by `plain_move`.
        assert!(with_output > 50, "{with_output} programs with output");
        assert!(taken > 3000, "{taken} moves");
    }
}

#[cfg(test)]
mod read_back {
    #![allow(clippy::unwrap_used)]

    use crate::driver::{tool_path, CompileOptions};
    use crate::source::Sources;

    /// Where the last move of `between` (put after a G41 profile's G40
    /// with no move) leaves the tool.
    fn last_end(between: &str) -> [f64; 3] {
        let text = format!(
            "G21 G90 G17\nSetTool 1 6\nT1 M6\nG0 X-10 Y-10 Z5\nG41 G1 X0 Y-5 F500\n\
             G1 Y20\nG40\n{between}\nG0 Z20\nM30\n"
        );
        let mut sources = Sources::new();
        let file = sources.add("read_back.egc", text.clone());
        let (path, diagnostics) = tool_path(&sources, file, &CompileOptions::default(), None);
        let path = path.unwrap_or_else(|| panic!("{text}\n{diagnostics:?}"));
        path.moves.last().unwrap().end
    }

    /// M6 and M61 (LinuxCNC's tool number, no change) read the tool's
    /// point back: the Z move after them keeps X at the offset point
    /// (-3, the tool's radius left of X0). Other codes between do not: the
    /// Z move goes back to the programmed X and Y.
    #[test]
    fn a_tool_change_after_g40_reads_the_tools_point_back() {
        for between in ["T1 M6", "M61 Q1"] {
            let end = last_end(between);
            assert!((end[0] + 3.0).abs() < 1e-9, "{between}: {end:?}");
            assert!((end[1] - 20.0).abs() < 1e-9, "{between}: {end:?}");
        }
        for between in ["M5", "G4 P1", "T1"] {
            let end = last_end(between);
            assert!(end[0].abs() < 1e-9, "{between}: {end:?}");
        }
    }
}
