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
    chords, ends_box, linuxcnc, unit, widen, Figures, OperationFigures, Planner, ToolFigures,
};
use crate::driver::machine::Controller;
use crate::toolpath::{Along, Event, EventKind, Move, MoveKind, PathSink, State};
use std::collections::VecDeque;

/// A tool path's [`Figures`], fed a move and an event at a time.
pub struct Tally<'l> {
    limits: Option<&'l Limits>,
    figures: Figures,
    planner: Option<Planner<'l>>,
    ledger: Ledger,
    moves: usize,
    spindle_on: bool,
    /// The state of the move before, for the syncs at a change.
    previous: Option<State>,
    /// An event came since the last block: the next starts from rest.
    event_since: bool,
}

/// Moves and dwells whose planned time is not known yet, oldest first:
/// the planner times a move's blocks some blocks after it took them.
struct Ledger {
    pending: VecDeque<Pending>,
    total_s: f64,
    /// Per tool, as in [`Figures::tools`].
    tool_s: Vec<f64>,
    /// Each move's planned time, when kept.
    move_s: Option<Vec<f64>>,
    /// The dwells as the controller dwells them.
    dwell_s: f64,
}

enum Pending {
    /// The `index`th move, of the tool in `tool` and the operation in `op`
    /// (their places in the figures), and its blocks' time so far.
    Move {
        index: usize,
        tool: usize,
        op: usize,
        seconds: f64,
    },
    /// A dwell in operation `op`.
    Dwell { op: usize, seconds: f64 },
}

impl Ledger {
    /// A block of move `index` timed at `seconds`: the moves and dwells
    /// before it are done.
    fn timed(&mut self, index: usize, seconds: f64, ops: &mut [OperationFigures]) {
        while let Some(front) = self.pending.front_mut() {
            match front {
                Pending::Move {
                    index: i,
                    seconds: s,
                    ..
                } if *i == index => {
                    *s += seconds;
                    return;
                }
                _ => self.settle_first(ops),
            }
        }
    }

    /// The oldest pending move or dwell added to its tool's, its
    /// operation's and the total time (in the program's order, so the sums
    /// are those of the figures summed at the end).
    fn settle_first(&mut self, ops: &mut [OperationFigures]) {
        let Some(first) = self.pending.pop_front() else {
            return;
        };
        let (op, seconds) = match first {
            Pending::Move {
                tool, op, seconds, ..
            } => {
                self.total_s += seconds;
                if let Some(t) = self.tool_s.get_mut(tool) {
                    *t += seconds;
                }
                if let Some(each) = self.move_s.as_mut() {
                    each.push(seconds);
                }
                (op, seconds)
            }
            Pending::Dwell { op, seconds } => (op, seconds),
        };
        if let Some(t) = ops.get_mut(op).and_then(|o| o.time_s.as_mut()) {
            *t += seconds;
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
                pending: VecDeque::new(),
                total_s: 0.0,
                tool_s: Vec::new(),
                move_s: (each_move && limits.is_some()).then(Vec::new),
                dwell_s: 0.0,
            },
            moves: 0,
            spindle_on: false,
            previous: None,
            event_since: false,
        }
    }

    /// The figures, the planner's window emptied.
    pub fn finish(mut self) -> Figures {
        let Tally {
            planner,
            ledger,
            figures,
            limits,
            ..
        } = &mut self;
        figures.feed_time_s += figures.dwell_s;
        let (Some(planner), Some(limits)) = (planner.as_mut(), limits) else {
            return std::mem::take(figures);
        };
        planner.finish(&mut |index, s| ledger.timed(index, s, &mut figures.operations));
        while !ledger.pending.is_empty() {
            ledger.settle_first(&mut figures.operations);
        }
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
    fn measure(&mut self, m: &Move, length: f64, tool: usize) {
        let figures = &mut self.figures;
        let on = m.state.spindle.is_some();
        figures.spindle_starts += usize::from(on && !self.spindle_on);
        self.spindle_on = on;
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
                let seconds = length / rapid_rate(limits, unit(m));
                figures.feed_time_s += seconds;
                op.feed_time_s += seconds;
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
        let ends = ends_box(m);
        widen(&mut op.bounds, ends);
        let tool = &mut figures.tools[tool];
        tool.cut_mm += length;
        tool.feed_time_s += seconds;
        widen(&mut tool.bounds, ends);
    }

    /// `m`, the `index`th move (its points `along`), to the planner as
    /// its pieces, the first block after a sync marked as starting from
    /// rest.
    fn plan_move(&mut self, m: &Move, along: &Along, index: usize, tool: usize) {
        let state = (m.state.spindle, m.state.rpm, m.state.flood, m.state.mist);
        let changed = self
            .previous
            .is_some_and(|a| (a.spindle, a.rpm, a.flood, a.mist) != state);
        let stopped = index == 0 || self.event_since || changed;
        self.previous = Some(m.state);
        // A move of no block (no length, or no step) leaves the machine
        // stopped for the next.
        self.event_since = stopped;
        let Tally {
            planner,
            ledger,
            figures,
            limits,
            event_since: still,
            ..
        } = self;
        let (Some(planner), Some(limits)) = (planner.as_mut(), limits) else {
            return;
        };
        ledger.pending.push_back(Pending::Move {
            index,
            tool,
            op: figures.operations.len().saturating_sub(1),
            seconds: 0.0,
        });
        let ops = &mut figures.operations;
        let timed = &mut |i, s| ledger.timed(i, s, ops);
        pieces_of(m, along, index, limits, &mut |mut piece| {
            if let Piece::Block(b) = &mut piece {
                b.stopped_before = *still;
                *still = false;
            }
            planner.take(piece, timed)
        });
    }
}

/// The pieces the planner takes for move `m`, the `index`th (its points
/// `along`), on `limits`: grbl's chords, LinuxCNC's segment; none marked
/// as after a sync (the tally marks them).
fn pieces_of(m: &Move, along: &Along, index: usize, limits: &Limits, out: &mut impl FnMut(Piece)) {
    match limits.controller {
        Controller::Grbl => chords::pieces(m, along, index, limits, out),
        Controller::LinuxCnc => {
            if let Some(b) = linuxcnc::block(m, along, index, limits) {
                out(Piece::Block(b));
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
        self.measure(m, along.length(), tool);
        self.plan_move(m, &along, index, tool);
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
                if let Some(op) = ops.last_mut() {
                    op.dwell_s += seconds;
                    op.feed_time_s += seconds;
                    if planned {
                        let op = ops.len() - 1;
                        let seconds = dwelt;
                        self.ledger
                            .pending
                            .push_back(Pending::Dwell { op, seconds });
                    }
                }
            }
            EventKind::Stop(_) | EventKind::End => {}
        }
    }

    fn restart(&mut self) {
        let each_move = self.ledger.move_s.is_some();
        *self = Tally::new(self.limits, each_move);
    }
}
