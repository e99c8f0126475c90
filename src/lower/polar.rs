//! Pass polar (SPEC §4.3): G16/G15 with Fanuc semantics. In the active
//! plane the first axis word is the radius and the second the angle in
//! degrees, counter-clockwise from the first axis. Under G90 the pole is
//! the program zero (the result is an absolute program point); under G91
//! it is the current position (the result is an incremental move). A word
//! left out keeps the last radius or angle of this G16 block; the first
//! polar move must give both. Canned-cycle hole positions are polar too.
//! Changing offsets or the plane, or a machine move, under G16 is an error.

use super::error::{LowerError, LowerErrorKind};
use super::pass::{feed_in_turn, follows_only, Batch, Context, Out, Pass, PassInfo};
use crate::ir::{Axes, Axis, Op, Plane, Stmt};
use crate::source::Span;

pub const PASS: PassInfo = PassInfo {
    name: "polar",
    make: |_: &Context<'_>| Box::new(PolarPass::default()),
};

#[derive(Default)]
struct PolarPass {
    plane: Option<Plane>,
    /// Some((radius, angle)) while G16 is on; the values are the last given.
    polar: Option<(Option<f64>, Option<f64>)>,
    entered: Option<Span>,
}

impl PolarPass {
    /// Make the plane words of `to` Cartesian; false if they are incomplete.
    fn cartesian(&mut self, to: &mut Axes) -> bool {
        let Some((radius, angle)) = &mut self.polar else {
            return true;
        };
        let (a, b, _) = self.plane.unwrap_or(Plane::XY).axes();
        let (a, b) = (Axis::ALL[a], Axis::ALL[b]);
        if let Some(r) = to.get(a) {
            *radius = Some(r);
        }
        if let Some(t) = to.get(b) {
            *angle = Some(t);
        }
        if !to.has(a) && !to.has(b) {
            return true;
        }
        match (*radius, *angle) {
            (Some(r), Some(t)) => {
                let t = t.to_radians();
                to.set(a, r * t.cos());
                to.set(b, r * t.sin());
                true
            }
            _ => false,
        }
    }
}

impl Pass for PolarPass {
    /// Polar coordinates off: a run of moves stays as it is.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        if self.polar.is_none() && follows_only(input) {
            return 0;
        }
        feed_in_turn(self, input, to)
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let span = stmt.span;
        let on = self.polar.is_some();
        let mut report = |kind| out.report(LowerError::new(kind, span));
        match &mut stmt.op {
            Op::Polar(turn_on) => {
                if *turn_on {
                    if !on {
                        self.entered = Some(span);
                    }
                    self.polar.get_or_insert((None, None));
                } else {
                    self.polar = None;
                }
                return false;
            }
            Op::Plane(p) => {
                if on && Some(*p) != self.plane.or(Some(Plane::XY)) {
                    report(LowerErrorKind::PlaneChangeUnderPolar);
                }
                self.plane = Some(*p);
            }
            Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::CancelPosition
            | Op::ToolLength { .. }
            | Op::CancelToolLength => {
                if on {
                    report(LowerErrorKind::OffsetsUnderPolar {
                        since: self.entered,
                    });
                }
            }
            Op::MachineMove(_) | Op::Home { .. } => {
                if on {
                    report(LowerErrorKind::MachineMoveUnderPolar);
                }
            }
            Op::Move(m) => {
                if !self.cartesian(&mut m.to) {
                    report(LowerErrorKind::PolarIncomplete {
                        plane: self.plane.unwrap_or(Plane::XY),
                    });
                }
            }
            Op::Cycle(c) => {
                if !self.cartesian(&mut c.at) {
                    report(LowerErrorKind::PolarIncomplete {
                        plane: self.plane.unwrap_or(Plane::XY),
                    });
                }
            }
            Op::RigidTap(t) => {
                if !self.cartesian(&mut t.to) {
                    report(LowerErrorKind::PolarIncomplete {
                        plane: self.plane.unwrap_or(Plane::XY),
                    });
                }
            }
            // (The evaluator refuses a spline under G16.)
            Op::Spline(_)
            | Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::ReadPosition(_)
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::End
            | Op::Units(_)
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::InverseTime(_)
            | Op::InverseTimeFloor(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            | Op::PathControl(_)
            | Op::Comment(_)
            | Op::SetToolData(_)
            | Op::Passthrough(_)
            // (Made by the absolute pass, after this one.)
            | Op::IncrementalMove(_) => {}
        }
        true
    }
}
