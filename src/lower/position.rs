//! Where the tool is, as the passes after offsets see it: absolute
//! coordinates per axis, `None` where the program never set an axis or a
//! machine move (G28, G30, G53) or an offset passed through to the machine
//! left it unknown. The absolute and cycles passes keep one each.

use super::{LowerError, LowerErrorKind};
use crate::ir::{self, Axes, Axis, Distance, Op, Plane, Position};
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

    /// Follow a statement that is not a cycle, without checking it (the
    /// absolute pass checks): an axis whose end is in doubt is unknown.
    pub fn follow(&mut self, op: &Op, span: Span) {
        match op {
            Op::Distance(d) => self.distance = *d,
            Op::Plane(p) => self.plane = *p,
            Op::Move(m) => self.follow_move(&m.to),
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
