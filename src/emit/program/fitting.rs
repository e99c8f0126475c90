//! `--arcs fit` in the program printer: straight feed moves are held back
//! while they may form a run (one plane, one feed, nothing between them
//! but repeats of that feed), at most [`MOST_HELD`] at a time so memory
//! stays flat; then [`fit`](super::super::fit) chooses which stretches
//! become arcs and the run is printed, lines as they would have been and
//! arcs from exactly the numbers it proved.
//!
//! It must not change anything else: a statement that cannot join a run
//! first prints the run held, then goes its usual way.

use super::{ProgramPrinter, CENTER};
use crate::diagnostic::{note, Diagnostic};
use crate::emit::fit::{self, Piece};
use crate::ir::{self, Axis, Motion, Op};
use crate::source::Span;

/// The most moves held back: a run longer than this is fitted in parts.
const MOST_HELD: usize = 4096;

/// The run held back, and what was fitted so far.
#[derive(Default)]
pub(super) struct Fitting {
    pub tolerance: f64,
    /// The moves of the run, as given.
    moves: Vec<ir::Stmt>,
    /// Where the run starts and each move ends (plane order: first,
    /// second, normal axis), and the same as printed.
    exact: Vec<[f64; 3]>,
    printed: Vec<[i64; 3]>,
    /// The feed of the run's moves, on the output grid.
    feed: Option<i64>,
    /// G93 or compensation kept for the controller: a run's time or its
    /// offset corners would change, so nothing is fitted.
    inverse_time: bool,
    compensating: bool,
    /// Lines written as arcs, the arcs, and the first arc's line.
    lines_fitted: usize,
    arcs: usize,
    /// How much shorter the arcs are than the lines they replace.
    bytes_saved: usize,
    first: Option<Span>,
}

impl Fitting {
    /// `tolerance` in the output `units`, if given.
    pub fn new(tolerance: Option<f64>, units: Option<ir::Units>) -> Box<Fitting> {
        let tolerance = tolerance.unwrap_or(match units {
            Some(ir::Units::Mm) => 0.005,
            Some(ir::Units::Inch) | None => 0.0002,
        });
        Box::new(Fitting {
            tolerance,
            ..Fitting::default()
        })
    }
}

impl ProgramPrinter {
    /// `--arcs fit`: hold the statement back if it joins the run (or
    /// repeats its feed); otherwise print the run held and say no.
    pub(super) fn held(&mut self, stmt: &ir::Stmt) -> bool {
        let Some(fitting) = self.fitting.as_deref() else {
            return false;
        };
        match &stmt.op {
            Op::Feed(f) if !fitting.moves.is_empty() && Some(self.p.scaled(*f)) == fitting.feed => {
                return true;
            }
            Op::Move(m) if self.joins(stmt, m) => {
                self.hold(stmt, m);
                return true;
            }
            _ => {}
        }
        self.print_held();
        if let Some(fitting) = self.fitting.as_deref_mut() {
            match stmt.op {
                Op::InverseTime(on) => fitting.inverse_time = on,
                Op::Comp { .. } => fitting.compensating = true,
                Op::CompOff => fitting.compensating = false,
                _ => {}
            }
        }
        false
    }

    /// Whether a move may join a run: a straight feed in the plane's axes
    /// from a known point, on a line of its own.
    fn joins(&self, stmt: &ir::Stmt, m: &ir::Move) -> bool {
        let Some(fitting) = self.fitting.as_deref() else {
            return false;
        };
        let (a, b, n) = self.p.plane.axes();
        let plane_axes = (1 << a) | (1 << b) | (1 << n);
        m.motion == Motion::Linear
            && m.arc.is_none()
            && !stmt.block_delete
            && !fitting.inverse_time
            && !fitting.compensating
            && m.to.bits() & !plane_axes == 0
            && [a, b, n].iter().all(|&i| self.position[i].is_some())
    }

    fn hold(&mut self, stmt: &ir::Stmt, m: &ir::Move) {
        let (a, b, n) = self.p.plane.axes();
        if self.fitting.as_ref().is_some_and(|f| f.moves.is_empty()) {
            let exact = [a, b, n].map(|i| self.position[i].unwrap_or(0.0));
            let printed = [a, b, n].map(|i| {
                self.printed[i].unwrap_or_else(|| self.p.scaled(exact_of(&self.position, i)))
            });
            let feed = self
                .pending_feed
                .map(|f| self.p.scaled(f))
                .or(self.printed_feed);
            let Some(fitting) = self.fitting.as_deref_mut() else {
                return;
            };
            fitting.exact.push(exact);
            fitting.printed.push(printed);
            fitting.feed = feed;
        }
        m.to.place(&mut self.position, Some);
        let exact = [a, b, n].map(|i| exact_of(&self.position, i));
        let Some(fitting) = self.fitting.as_deref_mut() else {
            return;
        };
        let before = fitting.printed[fitting.printed.len() - 1];
        let mut printed = before;
        for (k, &i) in [a, b, n].iter().enumerate() {
            if let Some(v) = m.to.get(Axis::ALL[i]) {
                printed[k] = self.p.scaled(v);
            }
        }
        fitting.exact.push(exact);
        fitting.printed.push(printed);
        fitting.moves.push(stmt.clone());
        if fitting.moves.len() >= MOST_HELD {
            self.print_held();
        }
    }

    /// Print the run held: its arcs, and its other moves as they are.
    pub(super) fn print_held(&mut self) {
        let Some(fitting) = self.fitting.as_deref_mut() else {
            return;
        };
        if fitting.moves.is_empty() {
            return;
        }
        let moves = std::mem::take(&mut fitting.moves);
        let exact = std::mem::take(&mut fitting.exact);
        let printed = std::mem::take(&mut fitting.printed);
        let pieces = if moves.len() < fit::MIN_SEGMENTS {
            Vec::new()
        } else {
            fit::Run {
                exact: &exact,
                printed: &printed,
                scale: 1.0 / self.p.unscaled(1),
                tolerance: fitting.tolerance,
            }
            .fit()
        };
        // The position is the run's end already; lines are printed as
        // `final_move` prints them, which reads only the printed state.
        if pieces.iter().any(|p| matches!(p, Piece::Arc { .. })) {
            // The lines first, to count what the arcs save; then the run
            // again, from the same state, with its arcs.
            let from = self.p.out.len();
            let state = (
                self.printed,
                self.pending_feed,
                self.printed_feed,
                self.p.seq,
            );
            self.print_pieces(&moves, &printed, &[]);
            let lines = self.p.out.len() - from;
            self.p.out.truncate(from);
            (
                self.printed,
                self.pending_feed,
                self.printed_feed,
                self.p.seq,
            ) = state;
            self.print_pieces(&moves, &printed, &pieces);
            let arcs = self.p.out.len() - from;
            if let Some(fitting) = self.fitting.as_deref_mut() {
                fitting.bytes_saved += lines - arcs.min(lines);
            }
        } else {
            self.print_pieces(&moves, &printed, &[]);
        }
        if let Some(fitting) = self.fitting.as_deref_mut() {
            // The vectors' room is kept for the next run.
            fitting.moves = moves;
            fitting.moves.clear();
            fitting.exact = exact;
            fitting.exact.clear();
            fitting.printed = printed;
            fitting.printed.clear();
        }
    }

    /// The held `moves` as `pieces` say (lines where they say nothing).
    fn print_pieces(&mut self, moves: &[ir::Stmt], printed: &[[i64; 3]], pieces: &[Piece]) {
        let mut k = 0;
        let mut pieces = pieces.iter();
        while k < moves.len() {
            match pieces.next() {
                Some(&Piece::Arc {
                    segments,
                    center,
                    clockwise,
                }) => {
                    let (start, end) = (printed[k], printed[k + segments]);
                    self.fitted_arc(moves[k].span, start, end, center, clockwise);
                    if let Some(fitting) = self.fitting.as_deref_mut() {
                        fitting.lines_fitted += segments;
                        fitting.arcs += 1;
                        fitting.first.get_or_insert(moves[k].span);
                    }
                    k += segments;
                }
                Some(Piece::Line) | None => {
                    if let Op::Move(m) = &moves[k].op {
                        self.final_move(&moves[k], m);
                    }
                    k += 1;
                }
            }
        }
    }

    /// An arc as [`fit`] proved it: from `start` to `end` about `center`
    /// (the grid numbers, in plane order), numbered by the run's first line.
    fn fitted_arc(
        &mut self,
        span: Span,
        start: [i64; 3],
        end: [i64; 3],
        center: [i64; 2],
        clockwise: bool,
    ) {
        let (a, b, n) = self.p.plane.axes();
        self.p.begin(span, false);
        self.p.code(if clockwise { "G2" } else { "G3" });
        for axis in Axis::ALL {
            let i = axis.index();
            let q = match i {
                _ if i == a => end[0],
                _ if i == b => end[1],
                _ if i == n && self.printed[n] != Some(end[2]) => end[2],
                _ => continue,
            };
            self.p.word_q(axis.letter(), q);
            self.printed[i] = Some(q);
        }
        self.p.word_q(CENTER[a], center[0] - start[0]);
        self.p.word_q(CENTER[b], center[1] - start[1]);
        self.feed_word();
        self.p.end();
    }

    /// `--arcs fit`: a note of how many lines were written as how many arcs.
    pub fn arcs_fitted(&self) -> Option<Diagnostic> {
        let fitting = self.fitting.as_deref()?;
        let first = fitting.first?;
        Some(note(
            format!(
                "{} lines written as {} arcs, {} bytes shorter (`--arcs fit`, within {})",
                fitting.lines_fitted, fitting.arcs, fitting.bytes_saved, fitting.tolerance
            ),
            first,
            "the first of them",
        ))
    }
}

fn exact_of(position: &ir::Position, i: usize) -> f64 {
    position[i].unwrap_or(0.0)
}
