//! Pass corners: Fanuc's corner words on a G1, G2 or G3 made plain moves.
//! `,R r` rounds the corner to the next G1, G2 or G3 with an arc of radius
//! r tangent to both moves; `,C c` cuts it with a chamfer from c before the
//! corner to c after it (along a line; the chord, on an arc). Both moves
//! shrink by what the corner takes, and a G2/G3 or a G1 is put between
//! them, at the cornered move's feed and on its line. The geometry is
//! `corners/cut.rs`.
//!
//! It runs after absolute (coordinates absolute, in one unit, arc centres
//! relative) and before comp, so that compensation offsets the rounded
//! contour, as on a Fanuc control. It holds the cornered move back until
//! the next move decides its end: one move, and the statements of the next
//! move's line (comments between them too). It must not touch a program
//! without corner words: every other statement goes on as it is.

mod cut;

use super::error::{CornerError, LowerError};
use super::pass::{Batch, Context, Out, Pass, PassInfo};
use super::position::Tracker;
use crate::ir::{self, Arc, ArcGeometry, Axis, Corner, Motion, Op, Plane, Stmt};
use crate::source::Span;
use cut::{corner_cut, Cut, CutError, Element, EPSILON, P2};

pub const PASS: PassInfo = PassInfo {
    name: "corners",
    make: |_: &Context<'_>| {
        Box::new(CornersPass {
            at: Tracker::new(),
            held: None,
        })
    },
};

/// Statements held between a cornered G1 and the next move, at most: a
/// line makes a few; more is a program that never moves again.
const MAX_HELD: usize = 1000;

struct CornersPass {
    at: Tracker,
    held: Option<Held>,
}

/// A G1, G2 or G3 with a corner word, waiting for the move after it.
struct Held {
    stmt: Stmt,
    corner: Corner,
    /// Where it starts and ends in the plane's two axes: its start moved on
    /// by the corner before it, if any.
    from: P2,
    to: P2,
    /// An arc's centre (absolute) and whether it turns counter-clockwise.
    centre: Option<(P2, bool)>,
    /// The statements after it, in order, until the next move.
    after: Vec<Stmt>,
    /// The first of them that is not a comment: on the next move's line,
    /// where it must be.
    first_after: Option<Span>,
}

impl Held {
    fn element(&self) -> Element {
        let (from, to) = (self.from, self.to);
        match self.centre {
            Some((centre, ccw)) => Element::Arc {
                from,
                to,
                centre,
                ccw,
            },
            None => Element::Line { from, to },
        }
    }
}

impl Pass for CornersPass {
    /// Nothing held and no corner word in the batch: it only follows the
    /// moves.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        let cornered = |s: &Stmt| matches!(&s.op, Op::Move(m) if m.corner.is_some());
        if self.held.is_some() || input.iter().any(cornered) {
            return super::pass::feed_in_turn(self, input, to);
        }
        if !self.at.follow_run(input) {
            for s in input.iter() {
                self.at.follow(&s.op, s.span);
            }
        }
        0
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        match self.held.take() {
            Some(held) => self.after_corner(held, stmt, out),
            None => self.take(stmt, None, out),
        }
    }

    fn finish(&mut self, out: &mut Out<'_>) {
        if let Some(held) = self.held.take() {
            let e = CornerError::NextNotG1 {
                what: "the end of the program",
                next: None,
            };
            release(held, e, out);
        }
    }
}

impl CornersPass {
    /// A statement that is not held: followed, and a cornered move held
    /// back (`false`); `from`, where it starts if a corner before it moved
    /// its start on (an arc's centre is then made relative to it). Anything
    /// else goes on.
    fn take(&mut self, stmt: &mut Stmt, from: Option<P2>, out: &mut Out<'_>) -> bool {
        let Op::Move(m) = &mut stmt.op else {
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        let centre = self.arc_centre(m, from);
        let start = from.or_else(|| self.plane_point());
        let Some(corner) = m.corner.take() else {
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        // An arc whose centre is not known is not in the plane's terms.
        let in_plane = self.in_plane(m) && (m.arc.is_none() || centre.is_some());
        let turns = m.arc.map_or(1, |arc| arc.turns);
        let Some(start) = start else {
            let (u, v, _) = self.at.plane.axes();
            let axis = if self.at.position[u].is_none() { u } else { v };
            out.report(self.at.unknown(axis, "a corner (`,R`, `,C`)", stmt.span));
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        self.at.follow(&stmt.op, stmt.span);
        let end = self.plane_point();
        let e = match (end, in_plane) {
            _ if turns != 1 => CornerError::MultiTurn { next: None },
            (Some(end), true) => {
                self.held = Some(Held {
                    stmt: stmt.clone(),
                    corner,
                    from: start,
                    to: end,
                    centre,
                    after: Vec::new(),
                    first_after: None,
                });
                return false;
            }
            _ => CornerError::OutOfPlane { next: None },
        };
        out.report(LowerError::new(e, stmt.span));
        true
    }

    /// The centre in the plane (absolute) of `m` if it is an arc from
    /// where the tool is, and whether it turns counter-clockwise; its
    /// centre made relative to `from` when a corner moved its start there.
    fn arc_centre(&self, m: &mut ir::Move, from: Option<P2>) -> Option<(P2, bool)> {
        let ccw = m.motion == Motion::ArcCcw;
        let ArcGeometry::Center(c) = &mut m.arc.as_mut()?.geometry else {
            return None;
        };
        let (u, v, _) = self.at.plane.axes();
        let at = self.plane_point()?;
        let centre = [at[0] + c[u]?, at[1] + c[v]?];
        if let Some(from) = from {
            c[u] = Some(centre[0] - from[0]);
            c[v] = Some(centre[1] - from[1]);
        }
        Some((centre, ccw))
    }

    /// The move `m` after a corner as the corner sees it: from the tool's
    /// point (the corner) to its end, in the plane.
    fn next_element(&self, m: &mut ir::Move, next: Span) -> Result<Element, CornerError> {
        let out_of_plane = CornerError::OutOfPlane { next: Some(next) };
        let (Some(from), Some(to), true) =
            (self.plane_point(), self.end_in_plane(m), self.in_plane(m))
        else {
            return Err(out_of_plane);
        };
        match m.arc {
            None => Ok(Element::Line { from, to }),
            Some(arc) if arc.turns != 1 => Err(CornerError::MultiTurn { next: Some(next) }),
            Some(_) => match self.arc_centre(m, None) {
                Some((centre, ccw)) => Ok(Element::Arc {
                    from,
                    to,
                    centre,
                    ccw,
                }),
                None => Err(out_of_plane),
            },
        }
    }

    /// The tool's point in the plane, if both its axes are known.
    fn plane_point(&self) -> Option<[f64; 2]> {
        let (u, v, _) = self.at.plane.axes();
        Some([self.at.position[u]?, self.at.position[v]?])
    }

    /// Whether `m`, from where the tool is, moves along no axis but the
    /// plane's two.
    fn in_plane(&self, m: &ir::Move) -> bool {
        let (u, v, _) = self.at.plane.axes();
        m.to.iter().all(|(axis, value)| {
            let i = axis.index();
            i == u || i == v || self.at.position[i].is_some_and(|p| same(p, value))
        })
    }

    /// A statement after a held move: held with it, or the next move that
    /// decides the corner.
    fn after_corner(&mut self, mut held: Held, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let another_line = held
            .first_after
            .is_some_and(|first| (first.file, first.line) != (stmt.span.file, stmt.span.line));
        let refused = match between(&stmt.op) {
            Some(what) => Some(what),
            None if another_line || held.after.len() >= MAX_HELD => Some("a line without a move"),
            None => None,
        };
        if let Some(what) = refused {
            let next = Some(held.first_after.unwrap_or(stmt.span));
            release(held, CornerError::NextNotG1 { what, next }, out);
            return self.take(stmt, None, out);
        }
        let Op::Move(m) = &mut stmt.op else {
            if !matches!(stmt.op, Op::Comment(_)) {
                held.first_after.get_or_insert(stmt.span);
            }
            held.after.push(stmt.clone());
            self.at.follow(&stmt.op, stmt.span);
            self.held = Some(held);
            return false;
        };
        // The next move, before it is followed.
        let cut = self.next_element(m, stmt.span).and_then(|next| {
            corner_cut(held.element(), next, held.corner).map_err(|e| e.at(held.corner, stmt.span))
        });
        match cut {
            Ok(cut) => {
                let t2 = cut.end;
                send_cut(held, &cut, self.at.plane, out);
                self.take(stmt, Some(t2), out)
            }
            Err(e) => {
                release(held, e, out);
                m.corner = None;
                self.at.follow(&stmt.op, stmt.span);
                true
            }
        }
    }

    /// Where `m` ends in the plane's two axes, if known.
    fn end_in_plane(&self, m: &ir::Move) -> Option<[f64; 2]> {
        let (u, v, _) = self.at.plane.axes();
        let at = |i: usize| m.to.get(Axis::ALL[i]).or(self.at.position[i]);
        Some([at(u)?, at(v)?])
    }
}

/// The held move and what waits behind it, sent as they are (the corner
/// word dropped) after `e` is reported.
fn release(held: Held, e: CornerError, out: &mut Out<'_>) {
    out.report(LowerError::new(e, held.stmt.span));
    out.push(held.stmt);
    for s in held.after {
        out.push(s);
    }
}

impl CutError {
    fn at(self, corner: Corner, next: Span) -> CornerError {
        match self {
            CutError::TooShort { need, room } => CornerError::TooShort { need, room, next },
            CutError::InLine => CornerError::InLine { next },
            CutError::Tangent => CornerError::Tangent { next },
            CutError::NoCut => CornerError::NoCut { corner, next },
        }
    }
}

/// The held move shortened to the cut's start (a G1 left out if nothing
/// is left of it; an arc always keeps some), the round or chamfer, then
/// the statements that waited.
fn send_cut(held: Held, cut: &Cut, plane: Plane, out: &mut Out<'_>) {
    let (u, v, _) = plane.axes();
    let mut g1 = held.stmt;
    let Op::Move(m) = &mut g1.op else {
        return;
    };
    let moved = [cut.start[0] - held.from[0], cut.start[1] - held.from[1]];
    let left = moved[0].hypot(moved[1]);
    let scale = held.from[0].abs().max(held.from[1].abs()).max(1.0);
    m.to.set(Axis::ALL[u], cut.start[0]);
    m.to.set(Axis::ALL[v], cut.start[1]);
    let mut to = ir::Axes::default();
    to.set(Axis::ALL[u], cut.end[0]);
    to.set(Axis::ALL[v], cut.end[1]);
    let corner = match &cut.round {
        Some(round) => {
            let mut centre = [None; 3];
            centre[u] = Some(round.centre[0]);
            centre[v] = Some(round.centre[1]);
            ir::Move {
                motion: if round.counter_clockwise {
                    Motion::ArcCcw
                } else {
                    Motion::ArcCw
                },
                to,
                arc: Some(Arc {
                    geometry: ArcGeometry::Center(centre),
                    turns: 1,
                }),
                corner: None,
                lead: None,
            }
        }
        None => ir::Move {
            motion: Motion::Linear,
            to,
            arc: None,
            corner: None,
            lead: None,
        },
    };
    let corner = g1.with_op(Op::Move(corner));
    if left > EPSILON * scale || held.centre.is_some() {
        out.push(g1);
    }
    out.push(corner);
    for s in held.after {
        out.push(s);
    }
}

/// What a statement between a cornered move and the next move is, if it
/// may not stand there; `None`: it waits with the cornered move (a comment, or a
/// word of the next move's line that changes no position or plane).
fn between(op: &Op) -> Option<&'static str> {
    match op {
        Op::Move(m) => Some(match m.motion {
            Motion::Rapid => "a rapid (G0)",
            Motion::Linear | Motion::ArcCw | Motion::ArcCcw => return None,
        }),
        Op::Comment(_)
        | Op::Feed(_)
        | Op::Speed(_)
        | Op::SpindleMode(_)
        | Op::SelectTool(_)
        | Op::Spindle(_)
        | Op::Coolant(_)
        | Op::Dwell(_)
        | Op::Comp { .. }
        | Op::CompOff
        | Op::PathControl(_)
        | Op::SetToolData(_)
        | Op::Passthrough(_) => None,
        Op::MachineMove(_) => Some("a G53 move"),
        Op::IncrementalMove(_) => Some("a step on an axis only the machine knows"),
        Op::Spline(_) => Some("a spline (G5, G5.1)"),
        Op::RigidTap(_) => Some("a rigid tap (G33.1)"),
        Op::Home { .. } => Some("a G28 or G30 move"),
        Op::Cycle(_) | Op::CycleOff => Some("a canned cycle"),
        Op::End => Some("the end of the program"),
        Op::Stop(_) => Some("a program stop"),
        Op::ChangeTool | Op::ReadPosition(_) => Some("a tool change"),
        Op::Plane(_) => Some("a change of plane"),
        Op::Units(_)
        | Op::Distance(_)
        | Op::ArcCenters(_)
        | Op::InverseTime(_)
        | Op::InverseTimeFloor(_)
        | Op::SelectWorkOffset(_)
        | Op::SetWorkOffset { .. }
        | Op::SetWorkOffsetHere { .. }
        | Op::LocalOffset(_)
        | Op::SetPosition(_)
        | Op::CancelPosition
        | Op::ToolLength { .. }
        | Op::CancelToolLength
        | Op::Polar(_)
        | Op::DiameterMode(_)
        | Op::ReturnLevel(_) => Some("a change of mode or offset"),
    }
}

/// Whether two coordinates are the same point on their axis.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= EPSILON * a.abs().max(b.abs()).max(1.0)
}
