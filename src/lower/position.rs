//! Where the tool is, as the passes after offsets see it: absolute
//! coordinates per axis, `None` where the program never set an axis or a
//! machine move (G28, G30, G53) or an offset passed through to the machine
//! left it unknown. The cycles, absolute and comp passes keep one each.

use super::error::{LowerError, LowerErrorKind};
use crate::ir::{self, Axes, Axis, Distance, Op, Plane, Position, Stmt};
use crate::source::Span;

#[derive(Clone, Debug)]
pub struct Tracker {
    pub distance: Distance,
    pub plane: Plane,
    pub position: Position,
    /// Where each unknown axis became unknown (a machine move), if it was
    /// ever known.
    lost_at: [Option<Span>; 9],
}

impl Tracker {
    pub fn new() -> Tracker {
        Tracker {
            distance: Distance::Absolute,
            plane: Plane::XY,
            position: [None; 9],
            lost_at: [None; 9],
        }
    }

    /// Forget the axes `op` leaves unknown ([`Op::unknown_after`]).
    pub fn forget_after(&mut self, op: &Op, at: Span) {
        let unknown = op.unknown_after();
        for axis in Axis::ALL {
            if unknown(axis) {
                self.position[axis.index()] = None;
                self.lost_at[axis.index()] = Some(at);
            }
        }
    }

    /// A G92 passed through to the machine: the point it names is where
    /// the tool is in the output's coordinates from here.
    pub fn set_position(&mut self, a: &Axes) {
        a.place(&mut self.position, Some);
    }

    /// The first axis `to` writes whose position is unknown.
    pub fn unknown_axis(&self, to: &Axes) -> Option<usize> {
        to.iter()
            .map(|(axis, _)| axis.index())
            .find(|&i| self.position[i].is_none())
    }

    /// An [`Op::IncrementalMove`]: the axes known move by their steps
    /// (the error: one out of range), the others stay unknown.
    pub fn step(&mut self, to: &Axes, span: Span) -> Result<(), LowerError> {
        let mut end = self.position;
        for (axis, v) in to.iter() {
            let i = axis.index();
            end[i] = self.position[i].map(|p| p + v);
            let e = end[i].unwrap_or(v);
            if !ir::is_position(e) {
                return Err(LowerError::new(
                    LowerErrorKind::PositionOutOfRange { axis, value: e },
                    span,
                ));
            }
        }
        self.position = end;
        Ok(())
    }

    /// The error for something that needs `axis` where it is unknown.
    pub fn unknown(&self, axis: usize, what: &'static str, span: Span) -> LowerError {
        LowerError::new(
            LowerErrorKind::UnknownPosition {
                axis: Axis::ALL[axis],
                what,
                since: self.lost_at[axis],
            },
            span,
        )
    }

    /// The end point of axis words under the distance mode, or the error.
    pub fn end_of(
        &self,
        to: &Axes,
        what: &'static str,
        span: Span,
    ) -> Result<Position, LowerError> {
        let mut end = self.position;
        for (axis, v) in to.iter() {
            let i = axis.index();
            let e = match self.distance {
                Distance::Absolute => v,
                Distance::Incremental => match self.position[i] {
                    Some(p) => p + v,
                    None => return Err(self.unknown(i, what, span)),
                },
            };
            if !ir::is_position(e) {
                return Err(LowerError::new(
                    LowerErrorKind::PositionOutOfRange { axis, value: e },
                    span,
                ));
            }
            end[i] = Some(e);
        }
        Ok(end)
    }

    /// [`Tracker::end_of`] under G90, made the position: the same error,
    /// or the axes' values are where the tool is.
    pub fn move_absolute(&mut self, to: &Axes, span: Span) -> Result<(), LowerError> {
        // Nothing moves on an error.
        self.check_absolute(to, span)?;
        to.place(&mut self.position, Some);
        Ok(())
    }

    /// The error [`Tracker::end_of`] gives under G90, if any: an axis out
    /// of range.
    #[inline]
    pub fn check_absolute(&self, to: &Axes, span: Span) -> Result<(), LowerError> {
        debug_assert!(self.distance == Distance::Absolute);
        match to.all_values(ir::is_position) {
            true => Ok(()),
            false => Err(out_of_range(to, span)),
        }
    }

    /// [`Tracker::end_of`] without its error, in place: an axis whose end
    /// is in doubt makes every axis of the move unknown.
    fn follow_move(&mut self, to: &Axes) {
        let position = &mut self.position;
        match self.distance {
            Distance::Absolute => {
                if to.all_values(ir::is_position) {
                    to.place(position, Some);
                } else {
                    to.place(position, |_| None);
                }
            }
            Distance::Incremental => {
                let end = |p: Option<f64>, v: f64| p.map(|p| p + v);
                let known = to
                    .iter()
                    .all(|(a, v)| end(position[a.index()], v).is_some_and(ir::is_position));
                for (axis, v) in to.iter() {
                    let i = axis.index();
                    position[i] = end(position[i], v).filter(|_| known);
                }
            }
        }
    }

    /// [`Tracker::follow`] of each statement of `stmts` in turn, when they
    /// are moves and statements that move nothing
    /// ([`super::pass::follows_only`]) under G90: each axis from the last move
    /// that writes it. `false`, and nothing followed, for any other run.
    pub fn follow_run(&mut self, stmts: &[Stmt]) -> bool {
        if self.distance != Distance::Absolute || !super::pass::follows_only(stmts) {
            return false;
        }
        // The axes no later move writes, a bit each.
        let mut left: u16 = (1 << Axis::ALL.len()) - 1;
        for stmt in stmts.iter().rev() {
            let Op::Move(m) = &stmt.op else { continue };
            let written = m.to.bits() & left;
            if written == 0 {
                continue;
            }
            // As `follow_move`: a move with an axis out of range leaves
            // its axes unknown.
            let known = m.to.all_values(ir::is_position);
            for (i, axis) in Axis::ALL.into_iter().enumerate() {
                if written & (1 << i) != 0 {
                    self.position[i] = m.to.get(axis).filter(|_| known);
                }
            }
            left &= !written;
            if left == 0 {
                break;
            }
        }
        true
    }

    /// Follow a statement that is not a cycle, without checking it (the
    /// absolute pass checks): an axis whose end is in doubt is unknown.
    pub fn follow(&mut self, op: &Op, span: Span) {
        match op {
            Op::Distance(d) => self.distance = *d,
            Op::Plane(p) => self.plane = *p,
            Op::Move(m) => self.follow_move(&m.to),
            Op::IncrementalMove(m) => {
                for (axis, v) in m.to.iter() {
                    let p = &mut self.position[axis.index()];
                    *p = p.map(|p| p + v).filter(|&e| ir::is_position(e));
                }
            }
            Op::SetPosition(a) => self.set_position(a),
            Op::Spline(s) => self.follow_move(&s.to),
            _ => self.forget_after(op, span),
        }
    }
}

/// The error of a move with an axis out of range: the first such axis.
#[cold]
fn out_of_range(to: &Axes, span: Span) -> LowerError {
    let (axis, value) = to
        .iter()
        .find(|&(_, v)| !ir::is_position(v))
        .unwrap_or((Axis::X, f64::NAN));
    LowerError::new(LowerErrorKind::PositionOutOfRange { axis, value }, span)
}

#[cfg(test)]
mod tests {
    use super::Tracker;
    use crate::ir::{self, Axes, Axis, Distance, Motion, Op, Stmt};
    use crate::source::Span;

    /// `follow_run` leaves a tracker as `follow` of each statement in turn
    /// would (every axis from its last move, unknown after a move out of
    /// range), and as it was where the statements are not a run.
    #[test]
    fn a_run_is_followed_as_each_statement_in_turn() {
        let mut random = crate::test_random::Random::new(0x2545_f491_4f6c_dd1d);
        let mut next = |n: u64| random.below(n);
        let (mut runs, mut others) = (0, 0);
        for _ in 0..5000 {
            let mut stmts = Vec::new();
            for _ in 0..1 + next(12) {
                let mut to = Axes::default();
                for axis in [Axis::X, Axis::Y, Axis::Z, Axis::A] {
                    if next(3) == 0 {
                        to.set(axis, [2e9, -0.0, 1.5, -7.25, 3.0][next(5) as usize]);
                    }
                }
                let m = ir::Move {
                    motion: Motion::Linear,
                    to,
                    arc: None,
                    corner: None,
                    lead: None,
                };
                let op = match next(40) {
                    0 => Op::Feed(100.0),
                    1 => Op::Comment(String::new()),
                    2 => Op::Distance(Distance::Absolute),
                    3 => Op::MachineMove(m),
                    _ => Op::Move(m),
                };
                stmts.push(Stmt::new(op, Span::default()));
            }
            let mut start = Tracker::new();
            for slot in start.position.iter_mut() {
                *slot = [None, Some(4.0), Some(-0.0)][next(3) as usize];
            }
            if next(6) == 0 {
                start.distance = Distance::Incremental;
            }
            let mut in_turn = start.clone();
            for stmt in &stmts {
                in_turn.follow(&stmt.op, stmt.span);
            }
            let mut at_once = start.clone();
            let followed = at_once.follow_run(&stmts);
            let run =
                start.distance == Distance::Absolute && super::super::pass::follows_only(&stmts);
            assert_eq!(followed, run, "{stmts:?}");
            let expected = if followed { &in_turn } else { &start };
            assert_eq!(format!("{at_once:?}"), format!("{expected:?}"), "{stmts:?}");
            (runs, others) = (runs + usize::from(run), others + usize::from(!run));
        }
        assert!(runs > 1000 && others > 1000, "{runs} runs, {others} others");
    }
}
