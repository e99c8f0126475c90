//! The figures of a tool path gathered move by move as the back end makes
//! it (`ger stats` never holds the path): lengths, length / feed, tools
//! and operations, and each move's planned time as the planner's bounded
//! window lets its blocks go. Where the machine stops to sync (the first
//! move, after an event, at a change of spindle or coolant) is found here.
//!
//! Architecture Invariant: holds only what the figures and the planner's
//! window need, never the moves behind them (the moves' times when asked,
//! for the studio's clock).

use super::block::{rapid_rate, Limits};
use super::chords::Piece;
use super::{
    chords, ends_box, linuxcnc, unit, widen, widen_by, widen_to, Figures, OperationFigures,
    Planner, ToolFigures,
};
use crate::driver::machine::Controller;
use crate::toolpath::{Along, Event, EventKind, Move, MoveKind, PathSink};
use std::collections::VecDeque;

/// A tool path's [`Figures`], fed a move and an event at a time.
pub struct Tally<'l> {
    limits: Option<&'l Limits>,
    figures: Figures,
    planner: Option<Planner<'l>>,
    ledger: Ledger,
    moves: usize,
    /// An event came since the last block: the next starts from rest
    /// (every event is a sync: a tool change, a dwell, a stop, the
    /// spindle or the coolant changed).
    event_since: bool,
    /// The feed moves' box since the operation or the tool last changed,
    /// with their places in the figures: added to both boxes when either
    /// changes and at the end (one box widened a move, not two).
    run_box: Option<(usize, usize, [[f64; 3]; 2])>,
    /// Lines on the machine's steps (grbl).
    line_steps: Option<chords::LineSteps>,
    /// Tool lengths are known: the path may be the controlled point's.
    lengths_known: bool,
}

/// Where the planned times go: the planner hands each move's time on
/// once its blocks are timed, some blocks after it took them, in the
/// program's order; the ledger knows each move's tool and operation
/// from where they change, and adds the dwells between moves where they
/// stand (so the sums are those of the figures summed in order).
struct Ledger {
    /// From which move on the tool and the operation are these (their
    /// places in the figures); the first is the oldest move's not settled.
    runs: VecDeque<Run>,
    /// Dwells not yet added: the move they come before, their
    /// operation's and their tool's places, the seconds the controller
    /// dwells.
    dwells: VecDeque<(usize, usize, usize, f64)>,
    total_s: f64,
    /// Per tool, as in [`Figures::tools`].
    tool_s: Vec<f64>,
    /// Each move's planned time, when kept.
    move_s: Option<Vec<f64>>,
    /// The dwells as the controller dwells them.
    dwell_s: f64,
}

/// Moves from `from` on, of the tool and the operation at these places
/// in the figures.
#[derive(Clone, Copy, PartialEq)]
struct Run {
    from: usize,
    tool: usize,
    op: usize,
}

impl Ledger {
    /// The moves from `run.from` on of its tool and operation.
    fn run_from(&mut self, run: Run) {
        let same = |last: &Run| (last.tool, last.op) == (run.tool, run.op);
        if !self.runs.back().is_some_and(same) {
            self.runs.push_back(run);
        }
    }

    /// Move `index` planned at `seconds`: the moves and dwells before it
    /// are done (a move of no block took none).
    #[inline(always)]
    fn timed(&mut self, index: usize, seconds: f64, ops: &mut [OperationFigures]) {
        self.settle_before(index, ops);
        while self.runs.get(1).is_some_and(|r| r.from <= index) {
            self.runs.pop_front();
        }
        let Some(&Run { tool, op, .. }) = self.runs.front() else {
            return;
        };
        self.total_s += seconds;
        if let Some(t) = self.tool_s.get_mut(tool) {
            *t += seconds;
        }
        if let Some(t) = ops.get_mut(op).and_then(|o| o.time_s.as_mut()) {
            *t += seconds;
        }
        if let Some(each) = self.move_s.as_mut() {
            each.push(seconds);
        }
    }

    /// The dwells before move `index`, and a time of 0 for each move
    /// before it not yet timed.
    fn settle_before(&mut self, index: usize, ops: &mut [OperationFigures]) {
        while let Some(&(before, op, tool, seconds)) = self.dwells.front() {
            if before > index {
                break;
            }
            if let Some(t) = ops.get_mut(op).and_then(|o| o.time_s.as_mut()) {
                *t += seconds;
            }
            if let Some(t) = self.tool_s.get_mut(tool) {
                *t += seconds;
            }
            self.dwells.pop_front();
        }
        if let Some(each) = self.move_s.as_mut() {
            each.resize(each.len().max(index), 0.0);
        }
    }
}

impl<'l> Tally<'l> {
    /// Figures on the machine `limits` describes (length / feed only,
    /// without one); `each_move`: keep each move's planned time.
    pub fn new(limits: Option<&'l Limits>, each_move: bool) -> Tally<'l> {
        Tally {
            limits,
            figures: Figures::default(),
            planner: limits.map(Planner::new),
            ledger: Ledger {
                runs: VecDeque::new(),
                dwells: VecDeque::new(),
                total_s: 0.0,
                tool_s: Vec::new(),
                move_s: (each_move && limits.is_some()).then(Vec::new),
                dwell_s: 0.0,
            },
            moves: 0,
            event_since: false,
            run_box: None,
            line_steps: limits.map(chords::LineSteps::of),
            lengths_known: false,
        }
    }

    /// The run's box added to its operation's and its tool's.
    fn settle_box(&mut self) {
        if let Some((op, tool, ends)) = self.run_box.take() {
            let figures = &mut self.figures;
            if let Some(op) = figures.operations.get_mut(op) {
                widen(&mut op.bounds, ends);
            }
            if let Some(tool) = figures.tools.get_mut(tool) {
                widen(&mut tool.bounds, ends);
            }
        }
    }

    /// Whether tool lengths were known, so that `G43` may have folded one
    /// into the path: its bounds are then the controlled point's, not the
    /// tip's ([`PathSink::tool_lengths_known`]).
    pub fn lengths_known(&self) -> bool {
        self.lengths_known
    }

    /// The figures, the planner's window emptied.
    pub fn finish(mut self) -> Figures {
        self.settle_box();
        let Tally {
            planner,
            ledger,
            figures,
            limits,
            moves,
            ..
        } = &mut self;
        figures.feed_time_s += figures.dwell_s;
        let (Some(planner), Some(limits)) = (planner.as_mut(), limits) else {
            return std::mem::take(figures);
        };
        planner.finish(&mut |index, s| ledger.timed(index, s, &mut figures.operations));
        // The dwells after the last move, and a time for each move of no
        // block at the end.
        ledger.settle_before(*moves, &mut figures.operations);
        let stops = ledger.dwell_s
            + figures.tool_changes as f64 * limits.tool_change_s
            + figures.spindle_starts as f64 * limits.spindle_start_s;
        figures.time_s = Some(ledger.total_s + stops);
        for (tool, s) in figures.tools.iter_mut().zip(&ledger.tool_s) {
            tool.time_s = Some(*s);
        }
        figures.move_s = ledger.move_s.take().unwrap_or_default();
        std::mem::take(figures)
    }

    /// The place of `m`'s tool in the figures, added if new.
    fn tool_slot(&mut self, tool: u32) -> usize {
        if let Some(at) = self.figures.tools.iter().position(|t| t.tool == tool) {
            return at;
        }
        self.figures.tools.push(ToolFigures {
            tool,
            ..ToolFigures::default()
        });
        self.ledger.tool_s.push(0.0);
        self.figures.tools.len() - 1
    }

    /// Lengths and length / feed of `m`, into the whole's, its tool's and
    /// its operation's figures.
    fn measure(&mut self, m: &Move, (along, length): (&Along, f64), tool: usize) {
        let figures = &mut self.figures;
        let planned = self.limits.is_some();
        if figures.operations.is_empty() {
            figures.operations.push(OperationFigures {
                tool: m.state.tool,
                line: m.span.line,
                time_s: planned.then_some(0.0),
                ..OperationFigures::default()
            });
        }
        let Some(op) = figures.operations.last_mut() else {
            return;
        };
        if m.kind == MoveKind::Rapid {
            figures.rapid_mm += length;
            op.rapid_mm += length;
            if let Some(limits) = self.limits {
                let seconds = length / rapid_rate(limits, unit(m), 1.0);
                figures.feed_time_s += seconds;
                op.feed_time_s += seconds;
                figures.tools[tool].feed_time_s += seconds;
            }
            return;
        }
        let seconds = match m.state.feed_rate() > 0.0 {
            true => length / (m.state.feed_rate() / 60.0),
            false => 0.0,
        };
        figures.cut_mm += length;
        figures.feed_time_s += seconds;
        op.cut_mm += length;
        if m.state.feed_rate() > 0.0 {
            op.feed_time_s += seconds;
        }
        let each = &mut figures.tools[tool];
        each.cut_mm += length;
        each.feed_time_s += seconds;
        let op = figures.operations.len() - 1;
        match &mut self.run_box {
            Some((o, t, run)) if (*o, *t) == (op, tool) => widen_by(run, m),
            _ => {
                self.settle_box();
                self.run_box = Some((op, tool, ends_box(m)));
            }
        }
        // An arc reaches beyond its ends where it passes an axis.
        if let Some((_, _, run)) = &mut self.run_box {
            along.bulges(|p| widen_to(run, p));
        }
    }

    /// `m`, the `index`th move (its points and its length in `shape`), to
    /// the planner as its pieces, the first block after a sync marked as
    /// starting from rest.
    fn plan_move(&mut self, m: &Move, shape: (&Along, f64), index: usize, tool: usize) {
        let stopped = index == 0 || self.event_since;
        // A move of no block (no length, or no step) leaves the machine
        // stopped for the next.
        self.event_since = stopped;
        let Tally {
            planner,
            ledger,
            figures,
            limits,
            event_since: still,
            line_steps,
            ..
        } = self;
        let (Some(planner), Some(limits), Some(lines)) =
            (planner.as_mut(), limits, line_steps.as_mut())
        else {
            return;
        };
        ledger.run_from(Run {
            from: index,
            tool,
            op: figures.operations.len().saturating_sub(1),
        });
        let mut to = ToPlanner {
            planner,
            ledger,
            ops: &mut figures.operations,
            still,
        };
        pieces_of(m, shape, index, (limits, lines), &mut to);
    }
}

/// The planner taking a move's pieces, the first block after a sync
/// marked as starting from rest, each move timed to the ledger (a type,
/// not a closure, so that the planner's work is inlined where each piece
/// is made, and a block goes to it in registers).
struct ToPlanner<'a, 'l> {
    planner: &'a mut Planner<'l>,
    ledger: &'a mut Ledger,
    ops: &'a mut Vec<OperationFigures>,
    still: &'a mut bool,
}

impl chords::Take for ToPlanner<'_, '_> {
    #[inline(always)]
    fn take(&mut self, mut piece: Piece) {
        if let Piece::Block(b) = &mut piece {
            b.stopped_before = *self.still;
            *self.still = false;
        }
        let (ledger, ops) = (&mut *self.ledger, &mut *self.ops);
        self.planner
            .take(piece, &mut |i, s| ledger.timed(i, s, ops));
    }
}

/// The pieces the planner takes for move `m`, the `index`th (its points
/// `along`), on `limits`: grbl's chords, LinuxCNC's segment; none marked
/// as after a sync (the tally marks them).
fn pieces_of(
    m: &Move,
    shape: (&Along, f64),
    index: usize,
    (limits, lines): (&Limits, &mut chords::LineSteps),
    out: &mut impl chords::Take,
) {
    match limits.controller {
        Controller::Grbl => chords::pieces(m, shape, index, (limits, lines), out),
        Controller::LinuxCnc => {
            if let Some(b) = linuxcnc::block(m, shape, index, limits) {
                out.take(Piece::Block(b));
            }
        }
    }
}

impl PathSink for Tally<'_> {
    fn feed_move(&mut self, m: &Move) {
        let index = self.moves;
        self.moves += 1;
        let tool = self.tool_slot(m.state.tool);
        // An arc's sweep and radii found once for its length and its chords.
        let along = m.along();
        let length = along.length();
        self.measure(m, (&along, length), tool);
        self.plan_move(m, (&along, length), index, tool);
    }

    /// A tool change starts an operation; a dwell adds to the one running.
    fn feed_event(&mut self, e: &Event) {
        self.event_since = true;
        let planned = self.limits.is_some();
        let ops = &mut self.figures.operations;
        match e.kind {
            EventKind::ToolChange(tool) => {
                self.figures.tool_changes += 1;
                ops.push(OperationFigures {
                    tool,
                    line: e.span.line,
                    time_s: planned.then_some(0.0),
                    ..OperationFigures::default()
                });
            }
            EventKind::Dwell(seconds) => {
                self.figures.dwell_s += seconds;
                let dwelt = self.limits.map_or(seconds, |l| l.dwell_s(seconds));
                self.ledger.dwell_s += dwelt;
                let Some(op) = ops.last_mut() else {
                    return;
                };
                op.dwell_s += seconds;
                op.feed_time_s += seconds;
                // The operation's tool's, as its moves are.
                let tool = op.tool;
                let (op, tool) = (ops.len() - 1, self.tool_slot(tool));
                self.figures.tools[tool].feed_time_s += seconds;
                if planned {
                    let before = self.moves;
                    self.ledger.dwells.push_back((before, op, tool, dwelt));
                }
            }
            EventKind::Sync { spindle_start } => {
                self.figures.spindle_starts += usize::from(spindle_start);
            }
            EventKind::Stop(_) | EventKind::End => {}
        }
    }

    /// grbl's planner (chords, steps) outweighs the last passes;
    /// LinuxCNC's (a segment a move) does not.
    fn heavy(&self) -> bool {
        self.limits
            .is_some_and(|l| l.controller == Controller::Grbl)
    }

    fn tool_lengths_known(&mut self) {
        self.lengths_known = true;
    }

    fn restart(&mut self) {
        let each_move = self.ledger.move_s.is_some();
        *self = Tally::new(self.limits, each_move);
    }
}
