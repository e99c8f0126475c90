//! Pass units (SPEC §4.1): every length in the output units; G20/G21 are
//! removed. Feeds are converted when they are given, so a feed set before a
//! unit switch keeps its machine value, as on LinuxCNC; a feed given before
//! the program's first G20/G21 is in the machine's units, and that G20/G21
//! stays in the output after it (the printer writes the F on a line
//! before it). Tool and offset tables are already in the output units
//! (§3). Under G16 the angle word is left alone: it is in degrees; so
//! are A, B and C.
//!
//! A program that never states its units is in the machine's: nothing is
//! converted. If it states them only after its first move, the first G20 or
//! G21 stays where it is (the moves before it run in the machine's units)
//! and fixes the output units from there on.

use super::error::{LowerError, LowerErrorKind};
use super::pass::{feed_in_turn, follows_only, Batch, Context, Out, Pass, PassInfo};
use crate::ir::{self, ArcGeometry, Axis, CompRadius, Op, Stmt, Units};

pub const PASS: PassInfo = PassInfo {
    name: "units",
    make: |cx| Box::new(UnitsPass::new(cx)),
};

struct UnitsPass {
    /// The units lengths are converted to; `None` until known.
    output: Option<Units>,
    /// The units the program is in now; `None`: the machine's.
    current: Option<Units>,
    /// Under G16 the plane's second axis word is an angle, not a length.
    polar: bool,
    plane: ir::Plane,
    /// A feed given in the machine's units, before the program's first
    /// G20/G21: warned about when that G20/G21 comes.
    machine_feed: Option<crate::source::Span>,
    /// G93: an F is the inverse of a time, not a length a minute.
    inverse_time: bool,
    /// G96: an S is a surface speed, m/min or ft/min.
    surface_speed: bool,
}

impl UnitsPass {
    fn new(cx: &Context<'_>) -> UnitsPass {
        UnitsPass {
            output: cx.start.output_units,
            current: cx.start.program_units,
            polar: false,
            plane: ir::Plane::XY,
            machine_feed: None,
            inverse_time: false,
            surface_speed: false,
        }
    }

    /// LinuxCNC's least feed under G93, 0.1 of the program's units a
    /// minute, in the output's (at `stmt`, where G93 begins or the units
    /// change under it).
    fn inverse_floor(&self, stmt: &Stmt) -> Stmt {
        stmt.with_op(Op::InverseTimeFloor(0.1 * self.factor()))
    }

    /// The factor from the program's units to the output's.
    fn factor(&self) -> f64 {
        match (self.current, self.output) {
            (Some(from), Some(to)) => from.factor(to),
            _ => 1.0,
        }
    }

    /// A surface speed in the output's units: m/min in mm, ft/min in
    /// inch (0.3048 m a foot).
    fn surface(&self, s: &mut f64) {
        match (self.current, self.output) {
            (Some(Units::Inch), Some(Units::Mm)) => *s *= 0.3048,
            (Some(Units::Mm), Some(Units::Inch)) => *s /= 0.3048,
            _ => {}
        }
    }

    /// Scale a move's lengths, but not a polar angle.
    fn scale_axes(&self, to: ir::Axes, k: f64) -> ir::Axes {
        let angle = self
            .polar
            .then(|| Axis::ALL[self.plane.axes().1])
            .and_then(|b| to.get(b).map(|v| (b, v)));
        let mut to = to.map_lengths(|v| v * k);
        if let Some((axis, degrees)) = angle {
            to.set(axis, degrees);
        }
        to
    }
}

impl Pass for UnitsPass {
    /// Lengths times one, and the program's units known (no feed to warn
    /// of): a run of moves stays as it is.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        if self.factor() == 1.0 && self.current.is_some() && follows_only(input) {
            return 0;
        }
        feed_in_turn(self, input, to)
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let k = self.factor();
        let scale = |v: &mut f64| *v *= k;
        match &mut stmt.op {
            Op::Units(u) => {
                if let Some(feed) = self.machine_feed.take() {
                    out.report(LowerError::new(LowerErrorKind::FeedInMachineUnits, feed));
                }
                self.current = Some(*u);
                // The first statement of units stays, and fixes them.
                let first = self.output.is_none();
                self.output.get_or_insert(*u);
                if self.inverse_time {
                    out.push(self.inverse_floor(stmt));
                }
                return first;
            }
            Op::Polar(on) => self.polar = *on,
            Op::Plane(p) => self.plane = *p,
            // Times one: as they are (most moves of most programs).
            Op::Move(_) | Op::MachineMove(_) | Op::IncrementalMove(_) if k == 1.0 => {}
            Op::Move(m) | Op::MachineMove(m) | Op::IncrementalMove(m) => {
                m.to = self.scale_axes(m.to, k);
                m.corner = m.corner.map(|c| c.scaled(k));
                m.lead = m.lead.map(|l| l * k);
                if let Some(arc) = &mut m.arc {
                    arc.geometry = match arc.geometry {
                        ArcGeometry::Center(c) => ArcGeometry::Center(c.map(|v| v.map(|v| v * k))),
                        ArcGeometry::Radius(r) => ArcGeometry::Radius(r * k),
                    };
                }
            }
            Op::RigidTap(t) => (t.to, t.lead) = (self.scale_axes(t.to, k), t.lead * k),
            Op::Spline(s) => (s.to, s.kind) = (self.scale_axes(s.to, k), s.kind.scaled(k)),
            Op::Cycle(c) => {
                c.at = self.scale_axes(c.at, k);
                scale(&mut c.r);
                for v in c.q.iter_mut() {
                    scale(v);
                }
                c.ijk = c.ijk.map(|v| v.map(|v| v * k));
            }
            Op::Home { via: a, .. }
            | Op::SetWorkOffset { origin: a, .. }
            | Op::SetWorkOffsetHere { at: a, .. }
            | Op::LocalOffset(a)
            | Op::SetPosition(a) => *a = a.map_lengths(|v| v * k),
            Op::SetToolData(data) => data
                .radius
                .iter_mut()
                .chain(data.length.iter_mut())
                .for_each(scale),
            Op::InverseTime(on) => {
                self.inverse_time = *on;
                if *on {
                    out.push(self.inverse_floor(stmt));
                }
            }
            Op::Feed(_) if self.inverse_time => {}
            Op::Feed(f) => {
                if self.current.is_none() {
                    self.machine_feed.get_or_insert(stmt.span);
                }
                scale(f)
            }
            Op::Comp {
                radius: CompRadius::Diameter(d),
                ..
            } => scale(d),
            Op::SpindleMode(ir::SpindleMode::Rpm) => self.surface_speed = false,
            Op::SpindleMode(ir::SpindleMode::SurfaceSpeed { speed: s, .. }) => {
                self.surface_speed = true;
                self.surface(s);
            }
            Op::Speed(s) if self.surface_speed => self.surface(s),
            Op::PathControl(ir::PathControl::Blend { tolerance, naive }) => {
                for v in [tolerance, naive].into_iter().flatten() {
                    scale(v);
                }
            }
            Op::Comp { .. }
            | Op::Speed(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::ReadPosition(_)
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::End
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::SelectWorkOffset(_)
            | Op::CancelPosition
            | Op::ToolLength { .. }
            | Op::CancelToolLength
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::CycleOff
            | Op::CompOff
            | Op::PathControl(_)
            | Op::Comment(_)
            // (Made here, from G93 and the units.)
            | Op::InverseTimeFloor(_)
            | Op::Passthrough(_) => {}
        }
        true
    }
}
