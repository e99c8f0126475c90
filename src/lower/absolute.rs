//! Pass absolute (SPEC §4.5, and the arc rules of §4): G91 → G90, every
//! move's written axes absolute machine coordinates (axes it did not write
//! stay out, so the emitter knows what the source commanded), and every
//! arc checked and given as a centre relative to its start in the active
//! plane (R arcs resolved, I/J/K arcs checked: radii within 1 % or
//! LinuxCNC's 0.0283 mm). The given
//! centre is kept, as LinuxCNC keeps it (a small radius difference is a
//! slight spiral); the larger radius is what `--arcs r` writes.
//!
//! A G5/G5.1 spline becomes here the arcs LinuxCNC cuts it with
//! (`geometry::spline`), each absolute and carrying the spline's span.
//!
//! An axis the program never set stays unknown and is not written; so do
//! the axes a machine move (G28, G30, G53) or a passed-through offset left
//! unknown. A straight incremental move on an unknown axis goes on as
//! steps ([`Op::IncrementalMove`]): the machine knows where it starts. An
//! arc, or a move under G93 (its length), on an unknown axis is an error.
//! A G92 passed through makes the point it names known.

use super::error::{LowerError, LowerErrorKind};
use super::pass::{feed_in_turn_quick, Batch, Context, Out, Pass, PassInfo};
use super::position::Tracker;
use crate::geometry::{self, ArcError, Point};
use crate::ir::{self, ArcGeometry, Axes, Axis, Distance, Op, Stmt};
use crate::source::Span;

/// LinuxCNC's absolute tolerance on the two radii of an I/J/K arc in a
/// millimetre program (`CENTER_ARC_RADIUS_TOLERANCE_MM`, 0.02·√2 mm; an
/// inch program's is looser): arcs within it are accepted whatever the
/// ratio of their radii, kept as given (a slight spiral, as LinuxCNC
/// cuts it).
const SPIRAL_MM: f64 = 0.02 * std::f64::consts::SQRT_2;

/// How far an R may be under half the chord and still be drawn, as the
/// half circle about the chord's middle, as Mach3 and Fanuc draw it
/// (rs274 refuses any shortfall): Fusion's Mach3 and Fanuc posts write
/// such arcs, R rounded a few microns short (0.0002 and 0.0004 mm in
/// ../shared/real); 0.005 mm or 0.0005 in is several of their last digits.
const SHORT_R_MM: f64 = 0.005;
const SHORT_R_INCH: f64 = 0.0005;

pub const PASS: PassInfo = PassInfo {
    name: "absolute",
    make: |cx: &Context<'_>| Box::new(AbsolutePass::new(cx.start.output_units)),
};

struct AbsolutePass {
    at: Tracker,
    /// G90.1 (absolute arc centres) or G91.1.
    centers: Distance,
    /// How far apart an arc's two radii may be whatever their ratio
    /// ([`SPIRAL_MM`] in the output's units).
    spiral: f64,
    /// How far an R may be short of half the chord ([`SHORT_R_MM`]).
    short: f64,
    /// The first R arc a hair short, to report (once).
    short_arc: ShortArc,
    /// G93, and the F (per minute of the move's time) of the next feed move.
    inverse_time: bool,
    inverse_feed: f64,
    /// Under G93, the least feed a move gets (`Op::InverseTimeFloor`).
    inverse_floor: f64,
    /// An M2/M30 went by, and the span of the last statement.
    ended: bool,
    last: Option<Span>,
}

impl AbsolutePass {
    fn new(units: Option<ir::Units>) -> AbsolutePass {
        AbsolutePass {
            spiral: match units {
                Some(ir::Units::Mm) => SPIRAL_MM,
                // Inch, or not known: a number within it either way.
                Some(ir::Units::Inch) | None => SPIRAL_MM / 25.4,
            },
            short: match units {
                Some(ir::Units::Mm) => SHORT_R_MM,
                Some(ir::Units::Inch) => SHORT_R_INCH,
                None => SHORT_R_MM / 25.4,
            },
            short_arc: ShortArc::None,
            at: Tracker::new(),
            centers: Distance::Incremental,
            inverse_time: false,
            inverse_feed: 0.0,
            inverse_floor: 0.1,
            ended: false,
            last: None,
        }
    }

    fn lower_move(&mut self, m: &mut ir::Move, span: Span) -> Result<(), LowerError> {
        let clockwise = m.motion == ir::Motion::ArcCw;
        if self.at.distance == Distance::Absolute {
            // The common case, without copies of the position (made and read
            // back at once, a copy waits for its writes): the ends are the
            // words, the other axes stay.
            if let Some(arc) = &mut m.arc {
                self.at.check_absolute(&m.to, span)?;
                let resolved = self.absolute_arc(&m.to, arc.geometry, clockwise, span);
                // A refused arc still ends where it says: the moves after
                // it start there, and report no error of its making.
                let center = resolved.inspect_err(|_| m.to.place(&mut self.at.position, Some))?;
                self.short_arc
                    .check(arc.geometry, center, self.at.plane, span);
                arc.geometry = ArcGeometry::Center(center);
            }
            return self.at.move_absolute(&m.to, span);
        }
        let end = self.at.end_of(&m.to, "an incremental move", span)?;
        if let Some(arc) = &mut m.arc {
            let ends = [end[0], end[1], end[2]];
            let resolved = resolve_arc(
                &self.at,
                ends,
                arc.geometry,
                self.centers,
                [self.spiral, self.short],
                clockwise,
                span,
            );
            let center = resolved.inspect_err(|_| self.at.position = end)?;
            self.short_arc
                .check(arc.geometry, center, self.at.plane, span);
            arc.geometry = ArcGeometry::Center(center);
        }
        // Only the axes the statement wrote: a Z retract stays a Z move.
        let mut written = Axes::default();
        for (axis, _) in m.to.iter() {
            written.put(axis, end[axis.index()]);
        }
        m.to = written;
        self.at.position = end;
        Ok(())
    }

    /// The centre, from its start, of an arc ending at the axes `to`
    /// under G90.
    #[inline(always)]
    fn absolute_arc(
        &self,
        to: &Axes,
        geometry: ArcGeometry,
        clockwise: bool,
        span: Span,
    ) -> Result<ir::Center, LowerError> {
        let at = &self.at.position;
        let end = std::array::from_fn(|i| to.get(Axis::ALL[i]).or(at[i]));
        let limits = [self.spiral, self.short];
        resolve_arc(
            &self.at,
            end,
            geometry,
            self.centers,
            limits,
            clockwise,
            span,
        )
    }

    /// [`Pass::feed`]'s common case, where it only lowers in place and
    /// has nothing to say (for [`feed_in_turn_quick`]): under G90 and not
    /// G93, a move in range whose arc, if any, resolves without a word,
    /// or a feed, speed or comment. `false`: left for `feed`, untouched.
    #[inline(always)]
    fn quick(&mut self, stmt: &mut Stmt) -> bool {
        if self.inverse_time || self.at.distance != Distance::Absolute {
            return false;
        }
        match &mut stmt.op {
            Op::Move(m) => {
                if !m.to.all_values(ir::is_position) {
                    return false;
                }
                if let Some(arc) = &mut m.arc {
                    let clockwise = m.motion == ir::Motion::ArcCw;
                    let resolved = self.absolute_arc(&m.to, arc.geometry, clockwise, stmt.span);
                    let Ok(center) = resolved else {
                        return false;
                    };
                    if self.short_arc.finds(arc.geometry, center, self.at.plane) {
                        return false;
                    }
                    arc.geometry = ArcGeometry::Center(center);
                }
                m.to.place(&mut self.at.position, Some);
            }
            Op::Feed(_) | Op::Speed(_) | Op::Comment(_) => {}
            _ => return false,
        }
        self.last = Some(stmt.span);
        true
    }

    /// A move, lowered; under G93 a feed move's rate as well (F per minute
    /// of its time, times its length), for an F before it.
    #[inline]
    fn timed_move(&mut self, m: &mut ir::Move, span: Span) -> Result<Option<f64>, LowerError> {
        // Under G93, where a feed move starts, for its length.
        let timed = self.inverse_time && m.motion != ir::Motion::Rapid;
        let start = timed.then_some(self.at.position);
        self.lower_move(m, span)?;
        let Some(start) = start else {
            return Ok(None);
        };
        let Some(length) = inverse_time_length(&start, &self.at.position, m, self.at.plane) else {
            let axis = (0..9).find(|&i| start[i].is_none()).unwrap_or(0);
            return Err(self.at.unknown(axis, "a move under G93 (its length)", span));
        };
        // rs274's rate: at least 0.1 of the program's units a minute (a
        // move of no length, an F of 0, a crawl).
        Ok(Some((length * self.inverse_feed).max(self.inverse_floor)))
    }

    /// G28/G30's intermediate point to absolute coordinates. Zero steps
    /// under G91 from an unknown point home straight from where the tool
    /// is: kept relative.
    fn home_via(
        &mut self,
        via: &mut Axes,
        incremental: &mut bool,
        span: Span,
    ) -> Result<(), LowerError> {
        let zero_steps = self.at.distance == Distance::Incremental
            && via.iter().all(|(_, v)| v == 0.0)
            && !via.is_empty();
        let end = match self.at.end_of(via, "an incremental G28/G30", span) {
            Ok(end) => end,
            Err(_) if zero_steps => {
                *incremental = true;
                return Ok(());
            }
            Err(e) => return Err(e),
        };
        let mut absolute = Axes::default();
        for (axis, _) in via.iter() {
            absolute.put(axis, end[axis.index()]);
        }
        *via = absolute;
        Ok(())
    }

    /// A move: steps where only the machine knows where it starts, else
    /// absolute (an inverse-time F made the feed per minute before it).
    fn feed_move(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let span = stmt.span;
        let Op::Move(m) = &mut stmt.op else {
            return true;
        };
        if self.steps_only(m) {
            let m = *m;
            if let Err(e) = self.at.step(&m.to, span) {
                out.report(e);
                return false;
            }
            stmt.op = Op::IncrementalMove(m);
            return true;
        }
        let moved = self.timed_move(m, span);
        self.short_arc.report(out);
        match moved {
            Ok(None) => true,
            Ok(Some(rate)) => {
                out.push(stmt.with_op(Op::Feed(rate)));
                true
            }
            Err(e) => {
                out.report(e);
                false
            }
        }
    }

    /// A move that can only be written as steps: straight, under G91,
    /// on an axis whose position only the machine knows (under G93 its
    /// length is needed: an error, as for an arc).
    fn steps_only(&self, m: &ir::Move) -> bool {
        self.at.distance == Distance::Incremental
            && m.arc.is_none()
            && !self.inverse_time
            && self.at.unknown_axis(&m.to).is_some()
    }

    /// A spline's arcs and lines, sent in its place, absolute, centres
    /// relative to their starts. It starts where the tool is, in X and Y,
    /// which must be known.
    fn spline(&mut self, s: &ir::Spline, stmt: &Stmt, out: &mut Out<'_>) -> Result<(), LowerError> {
        const WHAT: &str = "a spline (G5, G5.1)";
        let span = stmt.span;
        let end = self.at.end_of(&s.to, WHAT, span)?;
        let mut ends = [[0.0; 2]; 2];
        for i in 0..2 {
            let (Some(from), Some(to)) = (self.at.position[i], end[i]) else {
                return Err(self.at.unknown(i, WHAT, span));
            };
            ends[0][i] = from;
            ends[1][i] = to;
        }
        let [p0, p3] = ends;
        let plus = |p: [f64; 2], d: [f64; 2]| [p[0] + d[0], p[1] + d[1]];
        let points = match s.kind {
            ir::SplineKind::Cubic { start, end } => vec![p0, plus(p0, start), plus(p3, end), p3],
            ir::SplineKind::Quadratic { control } => vec![p0, plus(p0, control), p3],
        };
        let mut from = p0;
        for piece in geometry::spline::biarcs(&points) {
            let mut to = Axes::default();
            to.set(Axis::X, piece.end[0]);
            to.set(Axis::Y, piece.end[1]);
            let (motion, arc) = match piece.arc {
                None => (ir::Motion::Linear, None),
                Some(a) => {
                    let center = [
                        Some(a.center[0] - from[0]),
                        Some(a.center[1] - from[1]),
                        None,
                    ];
                    let motion = match a.clockwise {
                        true => ir::Motion::ArcCw,
                        false => ir::Motion::ArcCcw,
                    };
                    (
                        motion,
                        Some(ir::Arc {
                            geometry: ArcGeometry::Center(center),
                            turns: 1,
                        }),
                    )
                }
            };
            out.push(stmt.with_op(Op::Move(ir::Move {
                motion,
                to,
                arc,
                corner: None,
                lead: None,
            })));
            from = piece.end;
        }
        self.at.position[0] = Some(p3[0]);
        self.at.position[1] = Some(p3[1]);
        Ok(())
    }

    /// A rigid tap written absolute (the tool ends where it started):
    /// whether it goes on.
    fn rigid_tap(&self, t: &mut ir::RigidTap, span: Span, out: &mut Out<'_>) -> bool {
        match self.at.end_of(&t.to, "a rigid tap (G33.1)", span) {
            Ok(end) => {
                for (axis, e) in Axis::ALL.into_iter().zip(end) {
                    if let (true, Some(e)) = (t.to.has(axis), e) {
                        t.to.set(axis, e);
                    }
                }
                true
            }
            Err(e) => {
                out.report(e);
                false
            }
        }
    }

    /// Only a kept cycle comes this far, absolute already: the tool ends
    /// over its last hole, at the height it says.
    fn follow_kept_cycle(&mut self, c: &ir::Cycle) {
        let (a, b, n) = self.at.plane.axes();
        for i in [a, b] {
            if let Some(v) = c.at.get(Axis::ALL[i]) {
                self.at.position[i] = Some(v);
            }
        }
        self.at.position[n] = c.kept.map(|k| k.ends_at);
    }
}

impl Pass for AbsolutePass {
    /// Under G90, a run of straight moves in range is only followed (each
    /// in turn would be checked and placed, as `move_absolute` does); any
    /// other batch, an arc or a move out of range among it, in turn.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        let straight = |s: &Stmt| match &s.op {
            Op::Move(m) => m.arc.is_none() && m.to.all_values(ir::is_position),
            Op::Spline(_) => false,
            _ => true,
        };
        // (`follow_run` takes only a run under G90.)
        if !self.inverse_time && input.iter().all(straight) && self.at.follow_run(input) {
            self.last = input.last().map(|s| s.span).or(self.last);
            return 0;
        }
        feed_in_turn_quick(self, input, to, Self::quick)
    }

    /// SPEC §6: the output always ends with a program end.
    fn finish(&mut self, out: &mut Out<'_>) {
        if self.ended || out.failed() {
            return;
        }
        let Some(span) = self.last else {
            out.report(LowerError::new(
                LowerErrorKind::EmptyProgram,
                Span::default(),
            ));
            return;
        };
        out.report(LowerError::new(LowerErrorKind::NoProgramEnd, span));
        out.push(Stmt::new(Op::End, span));
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        let span = stmt.span;
        self.last = Some(span);
        match &mut stmt.op {
            Op::Distance(d) => {
                self.at.distance = *d;
                return false;
            }
            Op::ArcCenters(d) => {
                self.centers = *d;
                return false;
            }
            Op::InverseTime(on) => {
                self.inverse_time = *on;
                return false;
            }
            Op::InverseTimeFloor(floor) => {
                self.inverse_floor = *floor;
                return false;
            }
            // The evaluator saw to an F on each feed move's line.
            Op::Feed(f) if self.inverse_time => {
                self.inverse_feed = *f;
                return false;
            }
            Op::Plane(p) => self.at.plane = *p,
            Op::End => self.ended = true,
            Op::Move(_) => return self.feed_move(stmt, out),
            Op::Spline(s) => {
                let s = **s;
                if let Err(e) = self.spline(&s, stmt, out) {
                    out.report(e);
                }
                return false;
            }
            Op::RigidTap(t) => return self.rigid_tap(t, span, out),
            Op::MachineMove(_) => {
                if self.at.distance == Distance::Incremental {
                    out.report(LowerError::new(
                        LowerErrorKind::MachineMoveIncremental,
                        span,
                    ));
                    return false;
                }
                self.at.forget_after(&stmt.op, span);
            }
            Op::Home {
                via, incremental, ..
            } => {
                if let Err(e) = self.home_via(via, incremental, span) {
                    out.report(e);
                    return false;
                }
                self.at.forget_after(&stmt.op, span);
            }
            // A work offset or tool length passed through to the machine:
            // where the tool is in its coordinates is not known.
            Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::ToolLength { .. }
            | Op::CancelToolLength
            // The point read back is the tool's offset point, which only
            // the comp pass knows.
            | Op::ReadPosition(_) => self.at.forget_after(&stmt.op, span),
            Op::Cycle(c) => self.follow_kept_cycle(c),
            Op::SetPosition(a) => self.at.set_position(a),
            // (G92.1 gets this far only to cancel a G92 passed through.)
            Op::CancelPosition => self.at.forget_after(&stmt.op, span),
            Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::Units(_)
            | Op::LocalOffset(_)
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            | Op::PathControl(_)
            | Op::Comment(_)
            | Op::SetToolData(_)
            | Op::Passthrough(_)
            | Op::IncrementalMove(_) => {}
        }
        true
    }
}

/// The length of a feed move under G93, as rs274 measures it: in X/Y/Z
/// if they move, else in U/V/W, else in A/B/C (degrees); an arc's along
/// its helix. `None` where an axis that moves has no known start.
fn inverse_time_length(
    start: &ir::Position,
    end: &ir::Position,
    m: &ir::Move,
    plane: ir::Plane,
) -> Option<f64> {
    let mut deltas = [0.0; 9];
    for i in 0..9 {
        deltas[i] = match (start[i], end[i]) {
            (Some(s), Some(e)) => e - s,
            (None, None) => 0.0,
            _ => return None,
        };
    }
    if let Some(ir::Arc {
        geometry: ArcGeometry::Center(rel),
        turns,
    }) = m.arc
    {
        let (a, b, n) = plane.axes();
        let s: Point = std::array::from_fn(|i| start[i].unwrap_or(0.0));
        let e: Point = std::array::from_fn(|i| end[i].unwrap_or(0.0));
        let mut center = s;
        center[a] += rel[a].unwrap_or(0.0);
        center[b] += rel[b].unwrap_or(0.0);
        let radius = (center[a] - s[a]).hypot(center[b] - s[b]);
        let clockwise = m.motion == ir::Motion::ArcCw;
        let turn = geometry::sweep(s, e, center, plane, clockwise, turns);
        return Some(if deltas[n] == 0.0 {
            radius * turn.abs()
        } else {
            (radius * turn).hypot(deltas[n])
        });
    }
    const TINY: f64 = 1e-7;
    // Axis::ALL is X Y Z A B C U V W.
    let moves = |g: usize| deltas[g..g + 3].iter().any(|d| d.abs() > TINY);
    let group = if moves(0) {
        0
    } else if moves(6) {
        6
    } else {
        3
    };
    Some(
        deltas[group..group + 3]
            .iter()
            .map(|d| d * d)
            .sum::<f64>()
            .sqrt(),
    )
}

/// The centre of an arc, relative to its start, in the plane's two axes.
/// `end`: where X, Y and Z end (`None`: unknown); `centers`: how I/J/K
/// give the centre (G90.1: its coordinates, both needed, as in LinuxCNC;
/// G91.1: from the start, a missing one 0).
fn resolve_arc(
    pass: &Tracker,
    end: [Option<f64>; 3],
    geometry: ArcGeometry,
    centers: Distance,
    [spiral, short]: [f64; 2],
    clockwise: bool,
    span: Span,
) -> Result<ir::Center, LowerError> {
    let start = pass.position;
    let (a, b, n) = pass.plane.axes();
    for axis in [a, b, n] {
        if start[axis].is_none() && (axis != n || end[axis].is_some()) {
            return Err(pass.unknown(axis, "an arc", span));
        }
    }
    let s: Point = std::array::from_fn(|i| start[i].unwrap_or(0.0));
    let mut e: Point = std::array::from_fn(|i| end[i].unwrap_or(0.0));
    e[n] = end[n].unwrap_or(s[n]);
    let arc_error = |err: ArcError| {
        let kind = match err {
            ArcError::RadiusTooSmall { radius, half_chord } => {
                LowerErrorKind::ArcRadiusTooSmall { radius, half_chord }
            }
            ArcError::SamePoints => LowerErrorKind::FullCircleWithR,
            ArcError::RadiiDiffer { start, end } => LowerErrorKind::ArcRadiiDiffer {
                start,
                end,
                absolute: centers == Distance::Absolute,
            },
            ArcError::ZeroRadius => LowerErrorKind::ArcZeroRadius,
        };
        LowerError::new(kind, span)
    };
    let center: Point = match geometry {
        ArcGeometry::Radius(r) => {
            geometry::center_from_radius(s, e, r, pass.plane, clockwise, short)
                .map_err(arc_error)?
        }
        ArcGeometry::Center(c) => {
            let mut center = s;
            for axis in [a, b] {
                center[axis] = match (centers, c[axis]) {
                    (Distance::Incremental, c) => s[axis] + c.unwrap_or(0.0),
                    (Distance::Absolute, Some(c)) => c,
                    (Distance::Absolute, None) => {
                        let letter = char::from(b"IJK"[axis]);
                        let kind = LowerErrorKind::AbsoluteCentreIncomplete { letter };
                        return Err(LowerError::new(kind, span));
                    }
                };
            }
            geometry::check_center(s, e, center, pass.plane, spiral).map_err(arc_error)?;
            center
        }
    };
    let mut rel: ir::Center = [None; 3];
    rel[a] = Some(center[a] - s[a]);
    rel[b] = Some(center[b] - s[b]);
    Ok(rel)
}

/// The first R arc whose radius is a hair under half its chord: drawn
/// as the half circle about the chord's middle, with one warning.
enum ShortArc {
    None,
    Found(LowerError),
    Reported,
}

impl ShortArc {
    /// An R arc whose centre came out farther than R from its start.
    fn check(&mut self, given: ArcGeometry, center: ir::Center, plane: ir::Plane, span: Span) {
        let (true, ArcGeometry::Radius(r)) = (self.finds(given, center, plane), given) else {
            return;
        };
        let kind = LowerErrorKind::ArcRadiusShort {
            radius: r.abs(),
            half_chord: drawn(center, plane),
        };
        *self = ShortArc::Found(LowerError::new(kind, span));
    }

    /// Whether [`ShortArc::check`] finds this arc short (none yet found).
    #[inline(always)]
    fn finds(&self, given: ArcGeometry, center: ir::Center, plane: ir::Plane) -> bool {
        let (ArcGeometry::Radius(r), ShortArc::None) = (given, self) else {
            return false;
        };
        drawn(center, plane) > r.abs() * (1.0 + 1e-12)
    }

    fn report(&mut self, out: &mut Out<'_>) {
        if let ShortArc::Found(_) = self {
            if let ShortArc::Found(e) = std::mem::replace(self, ShortArc::Reported) {
                out.report(e);
            }
        }
    }
}

/// The radius an arc of `center` (from its start) is drawn with.
fn drawn(center: ir::Center, plane: ir::Plane) -> f64 {
    let (a, b, _) = plane.axes();
    center[a].unwrap_or(0.0).hypot(center[b].unwrap_or(0.0))
}
