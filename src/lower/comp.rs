//! Pass comp (SPEC §4.6): cutter radius compensation (G41/G42 D, G41.1/
//! G42.1 D, G40) resolved into the tool-centre path LinuxCNC's rs274
//! computes (`interp_convert.cc`'s `convert_*_comp*`, in G17 and G18).
//!
//! In the plane's axes (u, v) = (X, Y) in G17, (Z, X) in G18:
//! - the entry move ends offset square to its own direction at its end;
//! - each later move is offset by the radius on the tool's side; the move
//!   before it is held back until it arrives, because the corner between
//!   them decides where the held move ends: an outside corner gets an arc
//!   of the tool radius around the programmed corner (a chord after G0),
//!   an inside corner trims the held move to where the two offset paths
//!   meet, and a corner within 0.05 rad of straight gets neither;
//! - moves that do not move in the plane (a plunge) and the other
//!   statements that come after the held move wait behind it, so they
//!   happen after it (the corner arc runs at the next block's feed);
//! - G40 ends the held move at its untrimmed offset end; the next move
//!   goes straight from there to its programmed point.
//!
//! A held move that a trim would reverse, or an arc whose sweep it would
//! grow, is a gouge: an error at the line, with the held move's line.

use super::error::CompError;
use super::error::LowerError;
use super::pass::{feed_in_turn, Batch, Context, Out, Pass, PassInfo};
use super::position::Tracker;
use crate::ir::{self, Axis, CompRadius, Motion, Op, Position, Side, Stmt};
use crate::source::Span;
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

pub const PASS: PassInfo = PassInfo {
    name: "comp",
    make: |cx| Box::new(CompPass::new(cx)),
};

/// Corners within this many radians of straight get no arc and no trim.
const SMALL: f64 = 0.05;

type P2 = [f64; 2];

fn dir(a: f64) -> P2 {
    [a.cos(), a.sin()]
}

fn add(p: P2, d: P2, k: f64) -> P2 {
    [p[0] + d[0] * k, p[1] + d[1] * k]
}

fn angle(from: P2, to: P2) -> f64 {
    (to[1] - from[1]).atan2(to[0] - from[0])
}

fn dist(a: P2, b: P2) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The signed sweep from `s` to `e` around `o` with turn `t` (+n CCW,
/// −n CW); end = start is a whole turn.
fn find_turn(s: P2, o: P2, t: i32, e: P2) -> f64 {
    let (mut a, mut b) = (angle(o, s), angle(o, e));
    if t > 0 {
        if b <= a {
            b += TAU;
        }
        b - a + f64::from(t - 1) * TAU
    } else if t < 0 {
        if a <= b {
            a += TAU;
        }
        b - a + f64::from(t + 1) * TAU
    } else {
        0.0
    }
}

/// The tool is on the centre side of an arc of turn `t`.
fn inside(side: Side, t: i32) -> bool {
    (side == Side::Left && t > 0) || (side == Side::Right && t < 0)
}

#[derive(Clone, Debug)]
enum Shape {
    /// A line (or a rapid): its programmed direction, (0, 0) for one that
    /// does not move in the plane; the entry line keeps its offset normal.
    Line { dir: P2 },
    /// An arc: its centre, turn, and the sweep a trim may not grow (0 for
    /// none).
    Arc { center: P2, t: i32, sweep: f64 },
}

/// A compensated arc at a concave corner: its centre and radius, its
/// turn, and the corner's angles (`beta`, the turn at the corner; `theta`,
/// the offset's direction at its start).
#[derive(Clone, Copy)]
struct ArcCorner {
    centre: P2,
    radius: f64,
    t: i32,
    beta: f64,
    theta: f64,
}

/// A compensated move not yet sent: its end may still move.
#[derive(Clone, Debug)]
struct Held {
    stmt: Stmt,
    start: P2,
    end: P2,
    shape: Shape,
}

#[derive(Debug)]
enum Queued {
    Move(Held),
    Other(Stmt),
}

struct On {
    side: Side,
    r: f64,
    /// Where compensation was turned on.
    since: Span,
    /// No move yet: the next is the entry.
    first: bool,
    /// The tool point (the compensated end of the last move).
    c: P2,
    /// The held move first, then what waits behind it.
    queue: Vec<Queued>,
    /// Where the held move starts, for the gouge checks.
    s: Option<P2>,
    /// `--comp-entry lookahead`: the held entry ends where the next move's
    /// offset starts, once that move is known.
    entry_waits: bool,
}

struct CompPass {
    /// `--comp keep`: everything passes through.
    keep: bool,
    /// `--comp-entry lookahead`.
    lookahead: bool,
    tools: BTreeMap<u32, ir::Tool>,
    selected: Option<u32>,
    loaded: Option<u32>,
    /// The plane, and the programmed point (the tool point while
    /// compensation is off).
    at: Tracker,
    on: Option<On>,
    /// After G40: the next move writes u and v (the tool is at the last
    /// offset point) and may not be an arc. The G40's span, and that point.
    after_off: Option<(Span, P2)>,
    /// The tolerance on a trimmed arc's sweep (rs274's: 0.001 / 0.0254).
    sweep_tol: f64,
    /// How far an arc's start and end radii may differ for LinuxCNC to
    /// read it (0.0283 mm).
    spiral_tol: f64,
}

impl CompPass {
    fn new(cx: &Context<'_>) -> CompPass {
        CompPass {
            keep: cx.options.keep_comp,
            lookahead: cx.options.comp_entry_lookahead,
            tools: cx.start.setup.tools.clone(),
            selected: None,
            loaded: None,
            at: Tracker::new(),
            on: None,
            after_off: None,
            sweep_tol: match cx.start.output_units {
                Some(ir::Units::Inch) => 0.001,
                Some(ir::Units::Mm) | None => 0.0254,
            },
            spiral_tol: match cx.start.output_units {
                Some(ir::Units::Inch) => 0.02 * std::f64::consts::SQRT_2 / 25.4,
                Some(ir::Units::Mm) | None => 0.02 * std::f64::consts::SQRT_2,
            },
        }
    }

    /// The plane's two axes (u, v) and the third.
    fn axes(&self) -> (usize, usize, usize) {
        self.at.plane.axes()
    }

    /// The plane coordinates of a point, or the error where one is unknown.
    fn uv(&self, p: &Position, span: Span) -> Result<P2, LowerError> {
        let (u, v, _) = self.axes();
        let get = |i: usize| p[i].ok_or_else(|| self.at.unknown(i, "cutter compensation", span));
        Ok([get(u)?, get(v)?])
    }

    fn radius(&self, radius: CompRadius, span: Span) -> Result<f64, LowerError> {
        let tool = match radius {
            CompRadius::Diameter(d) => return Ok(d / 2.0),
            CompRadius::Tool(n) => n,
            CompRadius::LoadedTool => self
                .loaded
                .ok_or_else(|| LowerError::new(CompError::NoTool, span))?,
        };
        self.tools
            .get(&tool)
            .map(|t| t.diameter / 2.0)
            .ok_or_else(|| LowerError::new(CompError::UnknownTool { tool }, span))
    }

    /// [`Pass::feed`]: whether the statement goes on as it is.
    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> Result<bool, LowerError> {
        let span = stmt.span;
        match &stmt.op {
            Op::SetToolData(data) => data.apply(&mut self.tools, false),
            Op::Comp { side, radius } => {
                self.turn_on(*side, *radius, span)?;
                return Ok(false);
            }
            Op::CompOff => {
                self.turn_off(span, out)?;
                return Ok(false);
            }
            Op::Move(m) => {
                let m = *m;
                return self.motion(stmt, &m, out);
            }
            Op::Stop(_) | Op::End => self.stop(matches!(stmt.op, Op::End), span, out)?,
            Op::Plane(p) => self.at.plane = *p,
            Op::SelectTool(t) => {
                self.selected = Some(*t);
                // rs274 selects at once, before a held move.
                return Ok(true);
            }
            Op::ChangeTool => self.loaded = self.selected,
            Op::ReadPosition(_) => {
                self.read_position();
                return Ok(false);
            }
            // The first move after G40 leaves compensation (rs274), a
            // machine move too.
            Op::Home {
                via, incremental, ..
            } if self.after_off.is_some() => {
                let (via, incremental) = (*via, *incremental);
                self.home_after_off(stmt, via, incremental, out);
            }
            // The tool's path needs where the tool is: known here where a
            // tool change read it back (after G40), else an error.
            Op::IncrementalMove(m) if self.on.is_some() || self.after_off.is_some() => {
                let (mut m, steps) = (*m, m.to);
                for (axis, v) in steps.iter() {
                    match self.at.position[axis.index()] {
                        Some(p) => m.to.set(axis, p + v),
                        None => {
                            return Err(self.at.unknown(axis.index(), "cutter compensation", span))
                        }
                    }
                }
                stmt.op = Op::Move(m);
                return self.motion(stmt, &m, out);
            }
            Op::IncrementalMove(_) => self.at.follow(&stmt.op, span),
            // (Refused under compensation by the evaluator.)
            Op::SetPosition(a) => self.at.set_position(a),
            Op::MachineMove(_) if self.after_off.is_some() => {
                let off = self.after_off.map_or(span, |(off, _)| off);
                return Err(LowerError::new(
                    CompError::MachineMoveAfterOff { off },
                    span,
                ));
            }
            Op::MachineMove(_)
            | Op::Home { .. }
            | Op::CancelPosition
            | Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::ToolLength { .. }
            | Op::CancelToolLength => self.at.forget_after(&stmt.op, span),
            Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Units(_)
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::InverseTime(_)
            | Op::InverseTimeFloor(_)
            | Op::LocalOffset(_)
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::Cycle(_)
            | Op::CycleOff
            | Op::PathControl(_)
            // (Splines are arcs by now; G33.1 is refused under comp.)
            | Op::Spline(_)
            | Op::RigidTap(_)
            | Op::Comment(_)
            | Op::Passthrough(_) => {}
        }
        match &mut self.on {
            Some(on) if !on.queue.is_empty() => {
                on.queue.push(Queued::Other(stmt.clone()));
                Ok(false)
            }
            _ => Ok(true),
        }
    }

    /// G41/G42: compensation on, from where the tool is. A negative
    /// radius is the other side.
    fn turn_on(&mut self, side: Side, radius: CompRadius, span: Span) -> Result<(), LowerError> {
        let (mut side, mut r) = (side, self.radius(radius, span)?);
        if r < 0.0 {
            r = -r;
            side = match side {
                Side::Left => Side::Right,
                Side::Right => Side::Left,
            };
        }
        let c = if r > 0.0 {
            self.uv(&self.at.position, span)?
        } else {
            [0.0; 2]
        };
        self.on = Some(On {
            side,
            r,
            since: span,
            first: true,
            c,
            queue: Vec::new(),
            s: None,
            entry_waits: false,
        });
        Ok(())
    }

    /// G40: the held move ends at its offset end, and the next move leaves
    /// compensation from there.
    fn turn_off(&mut self, span: Span, out: &mut Out<'_>) -> Result<(), LowerError> {
        if let Some(mut on) = self.on.take() {
            if on.r > 0.0 && !on.first {
                let c = on.c;
                self.trim(&mut on, c, span, out)?;
                self.after_off = Some((span, c));
            }
        }
        Ok(())
    }

    /// M0/M1 (`end` false) or M2/M30: the held move ends at its offset
    /// end; compensation stays on after M0/M1.
    fn stop(&mut self, end: bool, span: Span, out: &mut Out<'_>) -> Result<(), LowerError> {
        let Some(mut on) = self.on.take() else {
            return Ok(());
        };
        if on.r > 0.0 && !on.first {
            let c = on.c;
            self.trim(&mut on, c, span, out)?;
            on.s = None;
        }
        if end {
            // LinuxCNC turns compensation off at M2/M30, the tool left
            // there: a warning, the path is rs274's.
            out.report(LowerError::new(
                CompError::StillOn { since: on.since },
                span,
            ));
        } else {
            self.on = Some(on);
        }
        Ok(())
    }

    /// A tool change after G40, before any move: LinuxCNC takes the
    /// tool's point, the last offset one, as the current point (the next
    /// move must still be straight).
    fn read_position(&mut self) {
        if let Some((_, tool)) = self.after_off {
            let (u, v, _) = self.axes();
            if self.at.position[u].is_some() && self.at.position[v].is_some() {
                self.at.position[u] = Some(tool[0]);
                self.at.position[v] = Some(tool[1]);
            }
        }
    }

    /// G28/G30 as the first move after G40: it leaves compensation
    /// (rs274), with a rapid to the intermediate point first, the
    /// programmed point standing in for the plane's axes it leaves out
    /// (the home move's own is then in place).
    fn home_after_off(&mut self, stmt: &Stmt, via: ir::Axes, incremental: bool, out: &mut Out<'_>) {
        self.after_off = None;
        let (u, v, _) = self.axes();
        if !(via.has(Axis::ALL[u]) && via.has(Axis::ALL[v])) {
            // (Zero steps from an unknown point: the point is here.)
            let mut to = if incremental { ir::Axes::NONE } else { via };
            for i in [u, v] {
                if !via.has(Axis::ALL[i]) {
                    if let Some(p) = self.at.position[i] {
                        to.set(Axis::ALL[i], p);
                    }
                }
            }
            if !to.is_empty() {
                out.push(stmt.with_op(Op::Move(ir::Move {
                    motion: Motion::Rapid,
                    to,
                    arc: None,
                    corner: None,
                    lead: None,
                })));
            }
        }
        self.at.forget_after(&stmt.op, stmt.span);
    }

    /// A move: passed on (compensation off or radius 0), or compensated.
    fn motion(
        &mut self,
        stmt: &mut Stmt,
        m: &ir::Move,
        out: &mut Out<'_>,
    ) -> Result<bool, LowerError> {
        let span = stmt.span;
        // After the absolute pass the written axes are absolute.
        let end = self.at.end_of(&m.to, "cutter compensation", span)?;
        let Some(mut on) = self.on.take_if(|on| on.r > 0.0) else {
            if let Some((off, _)) = self.after_off.take() {
                if m.motion.is_arc() {
                    return Err(LowerError::new(CompError::ArcAfterOff { off }, span));
                }
                // The tool is at the last offset point: give u and v.
                let (u, v, _) = self.axes();
                if let Op::Move(mm) = &mut stmt.op {
                    for i in [u, v] {
                        if let Some(p) = end[i] {
                            mm.to.set(Axis::ALL[i], p);
                        }
                    }
                }
            }
            self.at.position = end;
            return Ok(true);
        };
        let result = self.compensate(&mut on, stmt.clone(), m, &end, out);
        self.on = Some(on);
        self.at.position = end;
        result.map(|()| false)
    }

    fn compensate(
        &self,
        on: &mut On,
        stmt: Stmt,
        m: &ir::Move,
        end: &Position,
        out: &mut Out<'_>,
    ) -> Result<(), LowerError> {
        let span = stmt.span;
        let op = self.uv(&self.at.position, span)?;
        let p = self.uv(end, span)?;
        let arc = match &m.arc {
            Some(a) => {
                let (u, v, _) = self.axes();
                let ir::ArcGeometry::Center(rel) = a.geometry else {
                    return Err(LowerError::new(CompError::ArcTooSmall, span));
                };
                let o = [op[0] + rel[u].unwrap_or(0.0), op[1] + rel[v].unwrap_or(0.0)];
                let n = a.turns.min(i32::MAX as u32) as i32;
                Some((o, if m.motion == Motion::ArcCcw { n } else { -n }))
            }
            None => None,
        };
        if on.first {
            on.first = false;
            return self.entry(on, stmt, p, arc);
        }
        match arc {
            None => self.line(on, stmt, op, p, out),
            Some((o, t)) => self.arc(on, stmt, op, p, o, t, out),
        }
    }

    /// The first move after G41/G42.
    fn entry(
        &self,
        on: &mut On,
        stmt: Stmt,
        p: P2,
        arc: Option<(P2, i32)>,
    ) -> Result<(), LowerError> {
        let span = stmt.span;
        let (c, r) = (on.c, on.r);
        let left = on.side == Side::Left;
        match arc {
            None if self.lookahead => {
                if dist(p, c) <= r {
                    return Err(LowerError::new(
                        CompError::EntryTooShort { radius: r },
                        span,
                    ));
                }
                // Its end is the next move's offset start.
                on.s = Some(c);
                on.queue.push(Queued::Move(Held {
                    stmt,
                    start: c,
                    end: p,
                    shape: Shape::Line {
                        dir: [p[0] - c[0], p[1] - c[1]],
                    },
                }));
                on.c = p;
                on.entry_waits = true;
            }
            None => {
                if dist(p, c) <= r {
                    return Err(LowerError::new(
                        CompError::EntryTooShort { radius: r },
                        span,
                    ));
                }
                let a = angle(c, p) + if left { FRAC_PI_2 } else { -FRAC_PI_2 };
                let e = add(p, dir(a), r);
                on.s = Some(c);
                on.queue.push(Queued::Move(Held {
                    stmt,
                    start: c,
                    end: e,
                    shape: Shape::Line { dir: dir(a) },
                }));
                on.c = e;
            }
            Some((o, t)) => {
                if dist(p, c) <= r {
                    return Err(LowerError::new(
                        CompError::EntryTooShort { radius: r },
                        span,
                    ));
                }
                let ins = inside(on.side, t);
                if ins && dist(o, c) <= r {
                    return Err(LowerError::new(CompError::ArcTooSmall, span));
                }
                let g = if ins { angle(p, o) } else { angle(o, p) };
                let e = add(p, dir(g), r);
                // A circle through the start and the offset end, its centre
                // on the line from the end to the programmed centre.
                let b = dist(c, e) / 2.0;
                let ab = angle(e, o);
                let a = angle(e, c) - ab;
                if a.cos().abs() < 1e-4 {
                    return Err(LowerError::new(CompError::ArcTooSmall, span));
                }
                let center = add(e, dir(ab), b / a.cos());
                on.queue.push(Queued::Move(Held {
                    stmt,
                    start: c,
                    end: e,
                    shape: Shape::Arc {
                        center,
                        t,
                        sweep: find_turn(c, center, t, e),
                    },
                }));
                on.c = e;
            }
        }
        Ok(())
    }

    /// A straight move after the entry.
    fn line(
        &self,
        on: &mut On,
        stmt: Stmt,
        op: P2,
        p: P2,
        out: &mut Out<'_>,
    ) -> Result<(), LowerError> {
        let span = stmt.span;
        let (c, r) = (on.c, on.r);
        if p == op {
            // Not in the plane: it waits behind the held move, where the
            // tool is.
            on.queue.push(Queued::Move(Held {
                stmt,
                start: c,
                end: c,
                shape: Shape::Line { dir: [0.0; 2] },
            }));
            return Ok(());
        }
        let rapid = matches!(&stmt.op, Op::Move(m) if m.motion == Motion::Rapid);
        let (mut theta, mut alpha) = (angle(op, c), angle(op, p));
        let (beta, gamma) = match on.side {
            Side::Left => {
                if theta < alpha {
                    theta += TAU;
                }
                (theta - alpha - FRAC_PI_2, FRAC_PI_2)
            }
            Side::Right => {
                if alpha < theta {
                    alpha += TAU;
                }
                (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
            }
        };
        let e = add(p, dir(alpha + gamma), r);
        let mid = add(op, dir(alpha + gamma), r);
        if on.entry_waits {
            self.end_entry(on, mid, out);
            on.queue.push(Queued::Move(Held {
                stmt,
                start: mid,
                end: e,
                shape: Shape::Line {
                    dir: [p[0] - op[0], p[1] - op[1]],
                },
            }));
            on.c = e;
            return Ok(());
        }
        let front_arc = match on.queue.first() {
            Some(Queued::Move(Held {
                shape: Shape::Arc { center, t, .. },
                end,
                ..
            })) => Some((*center, *t, *end)),
            _ => None,
        };
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            || (beta > PI - SMALL && front_arc.is_some_and(|(_, t, _)| !inside(on.side, t)));
        if !concave && beta > SMALL {
            self.trim(on, c, span, out)?;
            let corner = if rapid {
                self.straight_to(&stmt, Motion::Rapid, mid)
            } else {
                self.corner_arc(&stmt, on.side, c, op, mid)
            };
            out.push(corner);
            on.s = Some(mid);
        } else if concave {
            self.held_for_trim(on, span)?;
            let point = match front_arc {
                None => {
                    let retreat = r / ((beta + PI) / 2.0).tan();
                    add(c, dir(theta + gamma), retreat)
                }
                Some(held_arc) => self.arc_into_line_point(on, op, p, held_arc, span)?,
            };
            self.trim(on, point, span, out)?;
        } else {
            self.flush(on, out);
            on.s = Some(c);
        }
        on.queue.push(Queued::Move(Held {
            stmt,
            start: on.s.unwrap_or(c),
            end: e,
            shape: Shape::Line {
                dir: [p[0] - op[0], p[1] - op[1]],
            },
        }));
        on.c = e;
        Ok(())
    }

    /// Where the offset of the held arc (`centre`, turn `t`, ending at
    /// `end`) meets the offset of the line `op`→`p` after it, at a concave
    /// corner: the point the held arc is trimmed to. An error where they
    /// do not meet (the cutter would gouge).
    #[inline]
    fn arc_into_line_point(
        &self,
        on: &On,
        op: P2,
        p: P2,
        (centre, t, end): (P2, i32, P2),
        span: Span,
    ) -> Result<P2, LowerError> {
        let r = on.r;
        let rho = dist(centre, end);
        let base = angle(op, p);
        let th = if t > 0 {
            base + FRAC_PI_2
        } else {
            base - FRAC_PI_2
        };
        let phi = angle(op, centre);
        let ins = inside(on.side, t);
        let d = (if ins { rho + r } else { rho - r }) * (th - phi).cos();
        let l = (if ins { d - r } else { d + r }) / rho;
        if !(-1.0..=1.0).contains(&l) {
            return Err(self.gouge("an arc into a line", on, span));
        }
        let ang = match (ins, t > 0) {
            (true, true) | (false, false) => th + PI - l.acos(),
            (true, false) | (false, true) => th + PI + l.acos(),
        };
        Ok(add(centre, dir(ang), rho))
    }

    /// An arc after the entry.
    #[allow(clippy::too_many_arguments)]
    fn arc(
        &self,
        on: &mut On,
        stmt: Stmt,
        op: P2,
        p: P2,
        o: P2,
        t: i32,
        out: &mut Out<'_>,
    ) -> Result<(), LowerError> {
        let span = stmt.span;
        let (c, r, side) = (on.c, on.r, on.side);
        let ra = dist(o, p);
        let left = side == Side::Left;
        let theta = angle(op, c) + if left { -FRAC_PI_2 } else { FRAC_PI_2 };
        let mut delta = angle(op, o);
        let alpha = if t > 0 {
            delta - FRAC_PI_2
        } else {
            delta + FRAC_PI_2
        };
        let mut beta = if left { theta - alpha } else { alpha - theta };
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        let ins = inside(side, t);
        let g = if ins {
            if ra <= r {
                return Err(LowerError::new(CompError::ArcTooSmall, span));
            }
            angle(p, o)
        } else {
            delta += PI;
            angle(o, p)
        };
        let e = add(p, dir(g), r);
        let sweep = find_turn(op, o, t, p);
        if on.entry_waits {
            let mid = add(op, dir(delta), r);
            self.end_entry(on, mid, out);
            on.queue.push(Queued::Move(Held {
                stmt,
                start: mid,
                end: e,
                shape: Shape::Arc {
                    center: o,
                    t,
                    sweep,
                },
            }));
            on.c = e;
            return Ok(());
        }
        let concave = !(-SMALL..=PI + SMALL).contains(&beta) || ((beta - PI).abs() < SMALL && !ins);
        if concave {
            self.held_for_trim(on, span)?;
            let corner = ArcCorner {
                centre: o,
                radius: ra,
                t,
                beta,
                theta,
            };
            let point = self.arc_trim_point(on, &corner, span)?;
            self.trim(on, point, span, out)?;
        } else if beta > SMALL {
            self.flush(on, out);
            let mid = add(op, dir(delta), r);
            out.push(self.corner_arc(&stmt, side, c, op, mid));
            on.s = Some(mid);
        } else {
            self.flush(on, out);
            on.s = Some(c);
        }
        let start = on.s.unwrap_or(c);
        self.check_spiral(start, e, o, span)?;
        on.queue.push(Queued::Move(Held {
            stmt,
            start,
            end: e,
            shape: Shape::Arc {
                center: o,
                t,
                sweep,
            },
        }));
        on.c = e;
        Ok(())
    }

    /// A corner within SMALL of tangent starts the arc off its circle
    /// (rs274 makes a spiral): the output could not say it as an arc.
    #[inline]
    fn check_spiral(&self, start: P2, end: P2, centre: P2, span: Span) -> Result<(), LowerError> {
        let (r0, r1) = (dist(start, centre), dist(end, centre));
        let differ = (r0 - r1).abs();
        if differ > self.spiral_tol && differ > 0.001 * r0.max(r1) {
            return Err(LowerError::new(
                CompError::Spiral { start: r0, end: r1 },
                span,
            ));
        }
        Ok(())
    }

    /// Where the offset of a concave corner's arc meets the offset of the
    /// held move before it (an arc or a line): the point both are trimmed
    /// to. An error where they do not meet (the cutter would gouge).
    fn arc_trim_point(&self, on: &On, arc: &ArcCorner, span: Span) -> Result<P2, LowerError> {
        let ArcCorner {
            centre: o,
            radius: ra,
            t,
            beta,
            theta,
        } = *arc;
        let (r, ins) = (on.r, inside(on.side, t));
        if let Some(Queued::Move(Held {
            shape: Shape::Arc {
                center: a, t: tp, ..
            },
            end: ae,
            ..
        })) = on.queue.first()
        {
            let (a, tp, ae) = (*a, *tp, *ae);
            let rho = dist(a, ae);
            let rn = if ins { ra - r } else { ra + r };
            let d = dist(o, a);
            if rho == 0.0 || d == 0.0 {
                return Err(self.gouge("two arcs with one centre", on, span));
            }
            let k = (rho * rho + d * d - rn * rn) / (2.0 * rho * d);
            if !(-1.0..=1.0).contains(&k) {
                return Err(self.gouge("an arc into an arc", on, span));
            }
            let (psi, pb) = (angle(a, o), k.acos());
            let ang = match (inside(on.side, tp), t > 0) {
                (true, true) | (false, false) => psi + pb,
                (true, false) | (false, true) => psi - pb,
            };
            return Ok(add(a, dir(ang), rho));
        }
        let y0 = ra * (beta - FRAC_PI_2).sin();
        let (rho, l) = if ins {
            (ra - r, (y0 + r) / (ra - r))
        } else {
            (ra + r, (y0 - r) / (ra + r))
        };
        if !(-1.0..=1.0).contains(&l) {
            return Err(self.gouge("a line into an arc", on, span));
        }
        let ang = match (ins, t > 0) {
            (true, true) => theta + l.asin(),
            (true, false) => theta - l.asin(),
            (false, true) => theta + PI - l.asin(),
            (false, false) => theta + PI + l.asin(),
        };
        Ok(add(o, dir(ang), rho))
    }

    /// `--comp-entry lookahead`: the held entry ends at `mid`, where the
    /// next move's offset path starts, and goes out.
    fn end_entry(&self, on: &mut On, mid: P2, out: &mut Out<'_>) {
        on.entry_waits = false;
        if let Some(Queued::Move(h)) = on.queue.first_mut() {
            h.end = mid;
        }
        self.flush(on, out);
        on.s = Some(mid);
    }

    /// An inside corner trims the move before it, which must still be
    /// held: after M0/M1 it has gone out (rs274 then reads a stale entry
    /// and does not trim, which gouges).
    fn held_for_trim(&self, on: &On, span: Span) -> Result<(), LowerError> {
        match on.queue.first() {
            Some(Queued::Move(_)) => Ok(()),
            _ => Err(LowerError::new(CompError::CornerAfterStop, span)),
        }
    }

    fn gouge(&self, what: &'static str, on: &On, span: Span) -> LowerError {
        let held = match on.queue.first() {
            Some(Queued::Move(h)) => Some(h.stmt.span),
            _ => None,
        };
        LowerError::new(CompError::Gouge { what, held }, span)
    }

    /// rs274's `move_endpoint_and_flush`: the held moves end at `to`
    /// (checked for a gouge), then everything queued goes out.
    fn trim(&self, on: &mut On, to: P2, span: Span, out: &mut Out<'_>) -> Result<(), LowerError> {
        if on.queue.is_empty() {
            return Ok(());
        }
        for i in 0..on.queue.len() {
            let Queued::Move(h) = &on.queue[i] else {
                continue;
            };
            match h.shape {
                Shape::Line { dir } => {
                    if let Some(s) = on.s {
                        if dir[0] * (to[0] - s[0]) + dir[1] * (to[1] - s[1]) < 0.0 {
                            return Err(self.gouge("a line into a corner", on, span));
                        }
                    }
                }
                Shape::Arc { center, t, sweep } => {
                    if sweep != 0.0 {
                        if let Some(s) = on.s {
                            let grown = find_turn(s, center, t, to);
                            if grown.abs() > sweep.abs() + self.sweep_tol {
                                return Err(self.gouge("an arc into a corner", on, span));
                            }
                        }
                    }
                }
            }
            if let Queued::Move(h) = &mut on.queue[i] {
                h.end = to;
                if matches!(h.shape, Shape::Line { dir } if dir == [0.0; 2]) {
                    // A plunge waiting at the corner goes with it.
                    h.start = to;
                }
            }
        }
        self.flush(on, out);
        on.s = Some(to);
        Ok(())
    }

    /// Send everything queued, in order.
    fn flush(&self, on: &mut On, out: &mut Out<'_>) {
        for q in on.queue.drain(..) {
            match q {
                Queued::Move(h) => out.push(self.held_stmt(h)),
                Queued::Other(s) => out.push(s),
            }
        }
        on.s = None;
    }

    /// A held move as a statement: its plane axes at the compensated end,
    /// an arc's centre relative to its start.
    fn held_stmt(&self, h: Held) -> Stmt {
        let (u, v, _) = self.axes();
        let mut stmt = h.stmt;
        if let Op::Move(m) = &mut stmt.op {
            m.to.set(Axis::ALL[u], h.end[0]);
            m.to.set(Axis::ALL[v], h.end[1]);
            if let (Some(arc), Shape::Arc { center, .. }) = (&mut m.arc, &h.shape) {
                let mut rel: ir::Center = [None; 3];
                rel[u] = Some(center[0] - h.start[0]);
                rel[v] = Some(center[1] - h.start[1]);
                arc.geometry = ir::ArcGeometry::Center(rel);
            }
        }
        stmt
    }

    fn straight_to(&self, like: &Stmt, motion: Motion, to: P2) -> Stmt {
        let (u, v, _) = self.axes();
        let mut axes = ir::Axes::default();
        axes.set(Axis::ALL[u], to[0]);
        axes.set(Axis::ALL[v], to[1]);
        like.with_op(Op::Move(ir::Move {
            motion,
            to: axes,
            arc: None,
            corner: None,
            lead: None,
        }))
    }

    /// The arc of the tool radius around an outside corner `corner`, from
    /// `from` to `to`: clockwise on the left, counter-clockwise on the right.
    fn corner_arc(&self, like: &Stmt, side: Side, from: P2, corner: P2, to: P2) -> Stmt {
        let (u, v, _) = self.axes();
        let mut stmt = self.straight_to(like, Motion::Linear, to);
        let mut rel: ir::Center = [None; 3];
        rel[u] = Some(corner[0] - from[0]);
        rel[v] = Some(corner[1] - from[1]);
        if let Op::Move(m) = &mut stmt.op {
            m.motion = match side {
                Side::Left => Motion::ArcCw,
                Side::Right => Motion::ArcCcw,
            };
            m.arc = Some(ir::Arc {
                geometry: ir::ArcGeometry::Center(rel),
                turns: 1,
            });
        }
        stmt
    }
}

impl Pass for CompPass {
    /// Compensation kept for the controller, or off: a run of moves is
    /// only followed (as `feed` below).
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        if self.keep || (self.on.is_none() && self.after_off.is_none() && self.at.follow_run(input))
        {
            return 0;
        }
        feed_in_turn(self, input, to)
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        if self.keep {
            return true;
        }
        // Compensation off (nearly every statement of most programs): a
        // move only moves the programmed point.
        if self.on.is_none() && self.after_off.is_none() {
            if let Op::Move(_) = &stmt.op {
                self.at.follow(&stmt.op, stmt.span);
                return true;
            }
        }
        CompPass::feed(self, stmt, out).unwrap_or_else(|e| {
            out.report(e);
            // One error per profile: the rest of it would repeat it.
            self.on = None;
            self.after_off = None;
            false
        })
    }

    fn finish(&mut self, out: &mut Out<'_>) {
        if let Some(mut on) = self.on.take() {
            self.flush(&mut on, out);
            out.report(LowerError::new(
                CompError::StillOn { since: on.since },
                on.since,
            ));
        }
    }
}
