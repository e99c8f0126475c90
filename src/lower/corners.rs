//! Pass corners: Fanuc's corner words on a G1 made plain moves. `,R r`
//! rounds the corner to the next G1 with an arc of radius r tangent to
//! both moves; `,C c` cuts it with a chamfer from c before the corner
//! along the G1 to c after it along the next move. Both moves shrink by
//! what the corner takes, and a G2/G3 or a G1 is put between them, at
//! the G1's feed and on its line.
//!
//! It runs after absolute (coordinates absolute, in one unit, arc centres
//! relative) and before comp, so that compensation offsets the rounded
//! contour, as on a Fanuc control. It holds the cornered G1 back until the
//! next move decides its end: one move, and the statements of the next
//! move's line (comments between them too). It must not touch a program
//! without corner words: every other statement goes on as it is.

use super::error::{CornerError, LowerError};
use super::pass::{Batch, Context, Out, Pass, PassInfo};
use super::position::Tracker;
use crate::ir::{self, Arc, ArcGeometry, Axis, Corner, Motion, Op, Plane, Stmt};
use crate::source::Span;

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

/// Ends of moves closer than this (relative to their size) are the same
/// point, and a corner's sine under it is no corner.
const EPSILON: f64 = 1e-9;

struct CornersPass {
    at: Tracker,
    held: Option<Held>,
}

/// A G1 with a corner word, waiting for the move after it.
struct Held {
    stmt: Stmt,
    corner: Corner,
    /// Where it starts and ends in the plane's two axes: its start moved on
    /// by the corner before it, if any.
    from: [f64; 2],
    to: [f64; 2],
    /// The statements after it, in order, until the next move.
    after: Vec<Stmt>,
    /// The first of them that is not a comment: on the next move's line,
    /// where it must be.
    first_after: Option<Span>,
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
    /// A statement that is not held: followed, and a cornered G1 held back
    /// (`false`); `from`, where it starts if a corner before it moved its
    /// start on. Anything else goes on.
    fn take(&mut self, stmt: &mut Stmt, from: Option<[f64; 2]>, out: &mut Out<'_>) -> bool {
        let start = from.or_else(|| self.plane_point());
        let Op::Move(m) = &mut stmt.op else {
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        let Some(corner) = m.corner.take() else {
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        let in_plane = self.in_plane(m);
        let Some(start) = start else {
            let (u, v, _) = self.at.plane.axes();
            let axis = if self.at.position[u].is_none() { u } else { v };
            out.report(self.at.unknown(axis, "a corner (`,R`, `,C`)", stmt.span));
            self.at.follow(&stmt.op, stmt.span);
            return true;
        };
        self.at.follow(&stmt.op, stmt.span);
        let end = self.plane_point();
        let (Some(end), true) = (end, in_plane) else {
            let e = CornerError::OutOfPlane { next: None };
            out.report(LowerError::new(e, stmt.span));
            return true;
        };
        self.held = Some(Held {
            stmt: stmt.clone(),
            corner,
            from: start,
            to: end,
            after: Vec::new(),
            first_after: None,
        });
        false
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

    /// A statement after a held G1: held with it, or the next move that
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
        // The next G1: its end, before it is followed.
        let end = self.end_in_plane(m).filter(|_| self.in_plane(m));
        let cut = match end {
            Some(end) => {
                corner_cut(held.from, held.to, end, held.corner).map_err(|e| e.at(stmt.span))
            }
            None => Err(CornerError::OutOfPlane {
                next: Some(stmt.span),
            }),
        };
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

/// The held G1 and what waits behind it, sent as they are (the corner
/// word dropped) after `e` is reported.
fn release(held: Held, e: CornerError, out: &mut Out<'_>) {
    out.report(LowerError::new(e, held.stmt.span));
    out.push(held.stmt);
    for s in held.after {
        out.push(s);
    }
}

/// A corner worked out: the G1 ends at `start`, the corner goes from
/// there to `end` (round: about `centre`, relative to `start`).
#[derive(Debug, PartialEq)]
struct Cut {
    start: [f64; 2],
    end: [f64; 2],
    round: Option<Round>,
}

#[derive(Debug, PartialEq)]
struct Round {
    centre: [f64; 2],
    counter_clockwise: bool,
}

/// Why a corner cannot be cut, before the next move's span is known.
#[derive(Debug, PartialEq)]
enum CutError {
    TooShort { need: f64, room: f64 },
    InLine,
}

impl CutError {
    fn at(self, next: Span) -> CornerError {
        match self {
            CutError::TooShort { need, room } => CornerError::TooShort { need, room, next },
            CutError::InLine => CornerError::InLine { next },
        }
    }
}

/// The corner at `at` between the move from `from` and the move to `to`
/// (points in the plane), cut as `corner` says. The round's arc is tangent
/// to both moves: it starts and ends `r·tan(θ/2)` from the corner, θ the
/// angle the path turns by; the chamfer's legs are `c` along each move.
fn corner_cut(from: [f64; 2], at: [f64; 2], to: [f64; 2], corner: Corner) -> Result<Cut, CutError> {
    let a = [at[0] - from[0], at[1] - from[1]];
    let b = [to[0] - at[0], to[1] - at[1]];
    let (la, lb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
    let room = la.min(lb);
    let size = match corner {
        Corner::Round(r) | Corner::Chamfer(r) => r,
    };
    if room <= EPSILON * la.max(lb) {
        return Err(CutError::TooShort { need: size, room });
    }
    let (d1, d2) = ([a[0] / la, a[1] / la], [b[0] / lb, b[1] / lb]);
    let sine = d1[0] * d2[1] - d1[1] * d2[0];
    let cosine = d1[0] * d2[0] + d1[1] * d2[1];
    if sine.abs() <= EPSILON {
        return Err(CutError::InLine);
    }
    let need = match corner {
        // tan(θ/2) = sin θ / (1 + cos θ)
        Corner::Round(r) => r * sine.abs() / (1.0 + cosine),
        Corner::Chamfer(c) => c,
    };
    if need > room * (1.0 + EPSILON) {
        return Err(CutError::TooShort { need, room });
    }
    let need = need.min(room);
    let start = [at[0] - d1[0] * need, at[1] - d1[1] * need];
    let end = [at[0] + d2[0] * need, at[1] + d2[1] * need];
    let round = match corner {
        Corner::Round(r) => {
            let counter_clockwise = sine > 0.0;
            // The centre is r to the side the path turns to.
            let side = if counter_clockwise { 1.0 } else { -1.0 };
            Some(Round {
                centre: [-d1[1] * r * side, d1[0] * r * side],
                counter_clockwise,
            })
        }
        Corner::Chamfer(_) => None,
    };
    Ok(Cut { start, end, round })
}

/// The held G1 shortened to the cut's start (left out if nothing is left
/// of it), the round or chamfer, then the statements that waited.
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
    if left > EPSILON * scale {
        out.push(g1);
    }
    out.push(corner);
    for s in held.after {
        out.push(s);
    }
}

/// What a statement between a cornered G1 and the next move is, if it
/// may not stand there; `None`: it waits with the G1 (a comment, or a
/// word of the next move's line that changes no position or plane).
fn between(op: &Op) -> Option<&'static str> {
    match op {
        Op::Move(m) => Some(match m.motion {
            Motion::Rapid => "a rapid (G0)",
            Motion::ArcCw | Motion::ArcCcw => "an arc (G2, G3)",
            Motion::Linear => return None,
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

#[cfg(test)]
mod tests {
    use super::{corner_cut, Corner, Cut, CutError, Round};

    /// Worked by hand: a square corner and one turned by 36.87° (the
    /// 3-4-5 triangle: tan of its half is 0.5), each way.
    #[test]
    fn corners_worked_by_hand() {
        let left = corner_cut([0.0, 0.0], [40.0, 0.0], [40.0, 30.0], Corner::Round(5.0));
        let expected = Cut {
            start: [35.0, 0.0],
            end: [40.0, 5.0],
            round: Some(Round {
                centre: [0.0, 5.0],
                counter_clockwise: true,
            }),
        };
        assert_eq!(left, Ok(expected));
        let right = corner_cut([40.0, 30.0], [60.0, 30.0], [60.0, 10.0], Corner::Round(3.0));
        let expected = Cut {
            start: [57.0, 30.0],
            end: [60.0, 27.0],
            round: Some(Round {
                centre: [0.0, -3.0],
                counter_clockwise: false,
            }),
        };
        assert_eq!(right, Ok(expected));
        let Ok(turned) = corner_cut([60.0, 27.0], [60.0, 10.0], [68.0, 4.0], Corner::Round(4.0))
        else {
            panic!("no cut");
        };
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12;
        assert!(near(turned.start, [60.0, 12.0]), "{turned:?}");
        assert!(near(turned.end, [61.6, 8.8]), "{turned:?}");
        let round = turned
            .round
            .as_ref()
            .map(|r| (r.centre, r.counter_clockwise));
        assert!(
            round.is_some_and(|(c, ccw)| near(c, [4.0, 0.0]) && ccw),
            "{turned:?}"
        );
        let chamfer = corner_cut([0.0, 0.0], [40.0, 0.0], [40.0, -30.0], Corner::Chamfer(4.0));
        let expected = Cut {
            start: [36.0, 0.0],
            end: [40.0, -4.0],
            round: None,
        };
        assert_eq!(chamfer, Ok(expected));
    }

    #[test]
    fn corners_that_cannot_be_cut() {
        let in_line = corner_cut([0.0, 0.0], [10.0, 0.0], [20.0, 0.0], Corner::Round(1.0));
        assert_eq!(in_line, Err(CutError::InLine));
        let back = corner_cut([0.0, 0.0], [10.0, 0.0], [5.0, 0.0], Corner::Chamfer(1.0));
        assert_eq!(back, Err(CutError::InLine));
        // A square corner's round takes r of each move.
        let short = corner_cut([0.0, 0.0], [10.0, 0.0], [10.0, 3.0], Corner::Round(4.0));
        assert_eq!(
            short,
            Err(CutError::TooShort {
                need: 4.0,
                room: 3.0
            })
        );
        let exact = corner_cut([0.0, 0.0], [10.0, 0.0], [10.0, 4.0], Corner::Chamfer(4.0));
        assert!(exact.is_ok(), "{exact:?}");
    }

    /// Random corners: the round's arc starts and ends on the two moves,
    /// tangent to each (its radius square to the move), r from its centre,
    /// turning the way the path turns; the chamfer's legs are c long along
    /// each move. Within 1e-9 of the moves' size.
    #[test]
    fn rounds_are_tangent_and_chamfer_legs_equal() {
        let mut random = crate::test_random::Random::new(0x9e37_79b9_7f4a_7c15);
        let mut value = |scale: f64| (random.below(2_000_001) as f64 / 1e6 - 1.0) * scale;
        let (mut rounds, mut chamfers) = (0, 0);
        for i in 0..20_000 {
            let scale = [1.0, 100.0, 2000.0][i % 3];
            let from = [value(scale), value(scale)];
            let at = [value(scale), value(scale)];
            let to = [value(scale), value(scale)];
            let size = value(scale).abs() * 0.3 + 1e-3;
            let corner = if i % 2 == 0 {
                Corner::Round(size)
            } else {
                Corner::Chamfer(size)
            };
            let Ok(cut) = corner_cut(from, at, to, corner) else {
                continue;
            };
            let tolerance = 1e-9 * scale;
            let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
            let len = |a: [f64; 2]| a[0].hypot(a[1]);
            let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
            let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
            let (d1, d2) = (sub(at, from), sub(to, at));
            let (u1, u2) = (
                [d1[0] / len(d1), d1[1] / len(d1)],
                [d2[0] / len(d2), d2[1] / len(d2)],
            );
            // On the moves: in line with each, and inside it.
            let back = sub(at, cut.start);
            let on = sub(cut.end, at);
            assert!(cross(u1, back).abs() < tolerance, "{cut:?}");
            assert!(cross(u2, on).abs() < tolerance, "{cut:?}");
            assert!(dot(u1, back) >= -tolerance && dot(u1, back) <= len(d1) + tolerance);
            assert!(dot(u2, on) >= -tolerance && dot(u2, on) <= len(d2) + tolerance);
            match (corner, &cut.round) {
                (Corner::Round(r), Some(round)) => {
                    let centre = [
                        cut.start[0] + round.centre[0],
                        cut.start[1] + round.centre[1],
                    ];
                    let to_start = sub(cut.start, centre);
                    let to_end = sub(cut.end, centre);
                    assert!((len(to_start) - r).abs() < tolerance, "{cut:?}");
                    assert!((len(to_end) - r).abs() < tolerance, "{cut:?}");
                    assert!(dot(to_start, u1).abs() < tolerance, "{cut:?}");
                    assert!(dot(to_end, u2).abs() < tolerance, "{cut:?}");
                    assert_eq!(round.counter_clockwise, cross(u1, u2) > 0.0);
                    rounds += 1;
                }
                (Corner::Chamfer(c), None) => {
                    assert!((len(back) - c).abs() < tolerance, "{cut:?}");
                    assert!((len(on) - c).abs() < tolerance, "{cut:?}");
                    chamfers += 1;
                }
                _ => panic!("{corner:?} cut as {cut:?}"),
            }
        }
        assert!(
            rounds > 2000 && chamfers > 2000,
            "{rounds} rounds, {chamfers} chamfers"
        );
    }
}
