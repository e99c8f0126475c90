//! LinuxCNC's polar words, `@` (radius) and `^` (angle in degrees,
//! counter-clockwise from X), made the X and Y words rs274 makes of them
//! in the G17 plane: under G90 a point about the program zero (a word left
//! out is the current point's radius or angle); under G91 a step of the
//! current point's radius and angle, written as the X and Y increments it
//! makes. A G91 cycle block repeated by L steps again before each hole.
//! It must not emit anything: the move or the cycle that takes the words
//! does, and it alone knows what they mean.

use super::codes::error::{CodeError, CodeErrorKind as K};
use super::evaluator::Evaluator;
use super::words::WordValues;
use crate::diagnostic::Diagnostic;
use crate::ir;

/// What the polar words of a G91 block add at each step: the radius and
/// the angle (radians), from where the tool stood before the block.
#[derive(Clone, Copy)]
pub(super) struct PolarStep {
    radius: Option<f64>,
    angle: Option<f64>,
    pub(super) from: (f64, f64),
}

impl PolarStep {
    /// The point one step on from `(x, y)`, as rs274 turns it: the radius
    /// first, then the angle; either is undefined at the origin.
    pub(super) fn next(&self, (x, y): (f64, f64)) -> Option<(f64, f64)> {
        let (mut x, mut y) = (x, y);
        for (grow, turn) in [(self.radius, None), (None, self.angle)] {
            if grow.is_none() && turn.is_none() {
                continue;
            }
            if x == 0.0 && y == 0.0 {
                return None;
            }
            let radius = x.hypot(y) + grow.unwrap_or(0.0);
            let angle = y.atan2(x) + turn.unwrap_or(0.0);
            (x, y) = (radius * angle.cos(), radius * angle.sin());
        }
        Some((x, y))
    }
}

impl Evaluator<'_> {
    /// The `@` and `^` of `w` made its X and Y words (spanned at the polar
    /// words); under G91, the step they make, for a cycle's repeats.
    pub(super) fn polar_words(
        &mut self,
        w: &mut WordValues,
    ) -> Result<Option<PolarStep>, Diagnostic> {
        let (Some(at), radius, angle) = (
            w.given(b'@').or(w.given(b'^')),
            w.given(b'@').map(|_| w.table_value(b'@')),
            w.given(b'^').map(|_| w.table_value(b'^')),
        ) else {
            return Ok(None);
        };
        let fail = |kind| -> Diagnostic { CodeError::new(kind, at).into() };
        if self.modal.plane != ir::Plane::XY {
            return Err(fail(K::PolarPlane));
        }
        for letter in [b'X', b'Y'] {
            if let Some(axis) = w.given(letter) {
                return Err(CodeError::new(K::PolarAndAxis(letter as char), axis).into());
            }
        }
        if self.this_line.machine_coordinates {
            return Err(fail(K::PolarMachine));
        }
        let known = |i: usize| self.modal.position[i];
        let current = match (known(0), known(1)) {
            (Some(x), Some(y)) => Some((x, y)),
            _ => None,
        };
        let incremental = self.modal.distance == ir::Distance::Incremental;
        let need_current = || current.ok_or_else(|| fail(K::PolarPosition));
        let (x, y, step) = if incremental {
            let from = need_current()?;
            let step = PolarStep {
                radius,
                angle: angle.map(f64::to_radians),
                from,
            };
            let (x, y) = step
                .next(from)
                .ok_or_else(|| fail(K::PolarAtOrigin { incremental }))?;
            (x - from.0, y - from.1, Some(step))
        } else {
            let (r, t) = match (radius, angle) {
                (Some(r), Some(t)) => (r, t.to_radians()),
                _ => {
                    let (cx, cy) = need_current()?;
                    if radius.is_some() && cx == 0.0 && cy == 0.0 {
                        return Err(fail(K::PolarAtOrigin { incremental }));
                    }
                    let t = angle.map_or(cy.atan2(cx), f64::to_radians);
                    (radius.unwrap_or(cx.hypot(cy)), t)
                }
            };
            (r * t.cos(), r * t.sin(), None)
        };
        w.polar_to_xy(x, y);
        Ok(step)
    }
}
