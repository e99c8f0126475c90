//! LinuxCNC's G5 (cubic spline: X Y, I J from the start, P Q from the
//! end) and G5.1 (quadratic: X Y, I J) read into an [`ir::Op::Spline`]
//! with rs274's checks, each an error at the line. The absolute pass makes
//! the curve arcs; nothing here knows where the tool is.
//!
//! A G5 without I and J takes its first control point where rs274 takes
//! it: the last G5's P Q turned round (a smooth join), or a G87's I J,
//! else the start itself; when the move before was not a G5, that is a
//! leftover, and a warning says so.

use super::codes::error::{CodeError, CodeErrorKind as K, SplineProblem as P};
use super::evaluator::Evaluator;
use super::words::WordValues;
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Axes, Axis};
use crate::source::Span;

impl Evaluator<'_> {
    /// A G5 (`t` 50) or G5.1 (51) line's curve, its words taken.
    pub(super) fn spline(
        &mut self,
        t: u32,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let fail =
            |problem, span| -> Diagnostic { CodeError::new(K::Spline(problem), span).into() };
        if self.modal.plane != ir::Plane::XY {
            return Err(fail(P::Plane, at));
        }
        if self.modal.polar {
            return Err(fail(P::Polar, at));
        }
        if self.modal.inverse_time {
            return Err(fail(P::InverseTime, at));
        }
        if self.modal.diameter_mode {
            return Err(fail(P::Diameter, at));
        }
        self.polar_words(w)?;
        if let Some((letter, span)) = w.remaining().find(|(l, _)| b"ZABCUVW".contains(l)) {
            return Err(fail(P::Axis(letter as char), span));
        }
        let mut to = Axes::default();
        for axis in [Axis::X, Axis::Y] {
            if let Some(v) = w.take_value(axis.letter()) {
                to.set(axis, v);
            }
        }
        if to.is_empty() {
            return Err(fail(P::NoEnd, at));
        }
        let (i, j) = (w.take(b'I'), w.take(b'J'));
        let kind = if t == 51 {
            let (Some((i, _)), Some((j, _))) = (i, j) else {
                return Err(fail(P::NoIJ, at));
            };
            if i == 0.0 && j == 0.0 {
                return Err(fail(P::Straight, at));
            }
            ir::SplineKind::Quadratic { control: [i, j] }
        } else {
            let start = match (i, j) {
                (Some((i, _)), Some((j, _))) => [i, j],
                (None, None) => {
                    if !self.modal.after_g5 {
                        self.report(CodeError::new(K::SplineLeftover(self.modal.spline_ij), at));
                    }
                    self.modal.spline_ij
                }
                (Some((_, s)), None) | (None, Some((_, s))) => return Err(fail(P::IOrJ, s)),
            };
            let (Some((p, _)), Some((q, _))) = (w.take(b'P'), w.take(b'Q')) else {
                return Err(fail(P::NoPQ, at));
            };
            ir::SplineKind::Cubic { start, end: [p, q] }
        };
        self.emit(ir::Op::Spline(Box::new(ir::Spline { to, kind })), span)?;
        // rs274's motion mode is now the spline's, under which axis words
        // alone move nowhere: refused ([`SplineProblem::Again`]).
        self.modal.motion = None;
        self.modal.spline_mode = true;
        self.modal.synced = None;
        self.cycles.kind = None;
        self.cycles.run_open = false;
        Ok(())
    }
}
