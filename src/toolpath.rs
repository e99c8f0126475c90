//! The tool path: what a program makes the machine do, as data. Straight
//! and arc moves (start, end, centre, plane, direction, feed) and the
//! events between them (tool changes, spindle, coolant, dwells, stops),
//! each with the source line that caused it, in millimetres. Built from
//! the lowered IR ([`Builder`]); the tests build the same type from
//! LinuxCNC's `rs274` and compare the two ([`compare`]); the picture and
//! the compensation geometry read it.
//!
//! Where the program leaves an axis unknown (never set, or after a move
//! the machine makes on its own: G28, G53), it counts as 0, as where
//! `rs274` starts, and the machine's tables (work offsets, tool lengths,
//! home) are taken as zero, as in a fresh `rs274` parameter file. A move
//! by steps from an unknown point, and a G92 there, are taken from that
//! guess: the moves after a G92 are known in its frame (the picture's),
//! not on the machine.

pub mod compare;

use crate::geometry;
use crate::ir::{self, ArcGeometry, Axis, Op, Plane, Stmt, Units};
use crate::source::Span;

pub type Point = [f64; 3];

#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolPath {
    pub moves: Vec<Move>,
    pub events: Vec<Event>,
    /// The output units (the program's numbers when `None`), for the
    /// picture's scale.
    pub units: Option<Units>,
    /// The setup directives (stock, zero, tools), in the output units.
    pub setup: ir::Setup,
    /// A tool's length was given (by the table, `SetTool` or a G10, even
    /// of a tool `setup` leaves out for want of its radius): the tip's
    /// path may not be the machine's.
    pub lengths_given: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    Rapid,
    Feed,
    Arc(ArcPath),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcPath {
    pub center: Point,
    pub plane: Plane,
    pub clockwise: bool,
    /// Full turns (G2/G3 P); 1 is an ordinary arc.
    pub turns: u32,
}

/// The machine state a cutting move runs with.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State {
    /// mm/min.
    pub feed: f64,
    pub rpm: f64,
    /// `None`: off.
    pub spindle: Option<ir::Spindle>,
    pub flood: bool,
    pub mist: bool,
    /// The tool loaded (M6).
    pub tool: u32,
    /// The tool the last `T` word selected (0: none).
    pub selected: u32,
    /// G61, G61.1, G64 (tolerances in mm).
    pub path_control: ir::PathControl,
    /// A G33 move's K, mm along the path per spindle revolution: its
    /// speed is the spindle's, not `feed`. `None` on every other move.
    pub lead: Option<f64>,
}

impl State {
    /// What a feed move goes at, mm/min: F, or on a move locked to the
    /// spindle (G33, G33.1) its lead times the spindle's rpm.
    pub fn feed_rate(&self) -> f64 {
        match self.lead {
            Some(lead) => lead * self.rpm,
            None => self.feed,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub kind: MoveKind,
    pub start: Point,
    pub end: Point,
    /// A B C (degrees) and U V W (mm) at the end.
    pub extra: [f64; 6],
    pub state: State,
    /// The source line (for `rs274`'s path, the line its N word names).
    pub span: Span,
    /// Which of X Y Z at the start the program never set, or lost to a
    /// machine move (G28, G53): taken as 0 (or the machine's home) here,
    /// where the real machine may be anywhere.
    pub guessed: [bool; 3],
}

impl Move {
    /// The arc's sweep in radians (positive), or 0 for a straight move.
    pub fn sweep(&self) -> f64 {
        match self.kind {
            MoveKind::Arc(a) => geometry::sweep(
                self.start,
                self.end,
                a.center,
                a.plane,
                a.clockwise,
                a.turns,
            )
            .abs(),
            MoveKind::Rapid | MoveKind::Feed => 0.0,
        }
    }

    /// Length of the path in the plane and along the normal (arcs by
    /// their start radius).
    pub fn length(&self) -> f64 {
        match self.kind {
            MoveKind::Arc(a) => {
                let (p, q, n) = a.plane.axes();
                let r = (self.start[p] - a.center[p]).hypot(self.start[q] - a.center[q]);
                arc_length(r, self.sweep(), self.end[n] - self.start[n])
            }
            MoveKind::Rapid | MoveKind::Feed => distance(self.start, self.end),
        }
    }

    /// The point at `t` in 0..=1 along the move.
    pub fn at(&self, t: f64) -> Point {
        self.along().at(t)
    }

    /// The points at `k / parts` along the move for `k` in `0..=parts`
    /// (each [`Move::at`]'s, the arc's angles and radii found once).
    pub fn points(&self, parts: usize) -> impl Iterator<Item = Point> + '_ {
        let along = self.along();
        (0..=parts).map(move |k| along.at(k as f64 / parts as f64))
    }

    /// Its points by their share of it ([`Along::at`], [`Move::at`]'s),
    /// an arc's constants found once.
    pub fn along(&self) -> Along {
        match self.kind {
            MoveKind::Arc(a) => {
                let (p, q, _) = a.plane.axes();
                let (sp, sq) = (self.start[p] - a.center[p], self.start[q] - a.center[q]);
                let (ep, eq) = (self.end[p] - a.center[p], self.end[q] - a.center[q]);
                // `Move::sweep`'s, its angles found once.
                let angle = sq.atan2(sp);
                let sweep = geometry::sweep_between(angle, eq.atan2(ep), a.clockwise, a.turns);
                Along {
                    start: self.start,
                    end: self.end,
                    arc: Some(ArcAlong {
                        arc: a,
                        sweep,
                        radius: sp.hypot(sq),
                        end_radius: ep.hypot(eq),
                        angle,
                    }),
                }
            }
            MoveKind::Rapid | MoveKind::Feed => Along {
                start: self.start,
                end: self.end,
                arc: None,
            },
        }
    }
}

/// A move's points by their share of it: an arc's constants computed
/// once for many points.
pub struct Along {
    start: Point,
    end: Point,
    arc: Option<ArcAlong>,
}

struct ArcAlong {
    arc: ArcPath,
    /// Signed, radians.
    sweep: f64,
    radius: f64,
    end_radius: f64,
    /// Of the start about the centre.
    angle: f64,
}

impl Along {
    /// An arc's sweep (radians, unsigned, [`Move::sweep`]'s) and its
    /// radius at the start and at the end; `None`: a line.
    pub fn arc_shape(&self) -> Option<(f64, f64, f64)> {
        self.arc
            .as_ref()
            .map(|a| (a.sweep.abs(), a.radius, a.end_radius))
    }

    /// [`Move::length`], from the constants already found.
    pub fn length(&self) -> f64 {
        match &self.arc {
            Some(a) => {
                let (_, _, n) = a.arc.plane.axes();
                arc_length(a.radius, a.sweep.abs(), self.end[n] - self.start[n])
            }
            None => distance(self.start, self.end),
        }
    }

    /// The points `k / n` along for k = 0, 1, 2, n − 3, n − 2, n − 1, n
    /// (`n` ≥ 3): an arc's turned from its start and from its end by
    /// multiples of one angle (one sine and cosine, where [`Along::at`]
    /// takes one for each), the ends themselves exact.
    pub fn end_points(&self, n: usize) -> [Point; 7] {
        let t = |k: usize| k as f64 / n as f64;
        let Some(a) = self
            .arc
            .as_ref()
            .filter(|a| a.radius > 0.0 && a.end_radius > 0.0)
        else {
            return [0, 1, 2, n - 3, n - 2, n - 1, n].map(|k| self.at(t(k)));
        };
        let (p, q, l) = a.arc.plane.axes();
        let (sin, cos) = (a.sweep / n as f64).sin_cos();
        // The turns by one, two and three of the angle, each way.
        let two = (cos * cos - sin * sin, 2.0 * sin * cos);
        let three = (cos * two.0 - sin * two.1, sin * two.0 + cos * two.1);
        let point = |from: Point, radius: f64, k: usize, (c, s): (f64, f64), back: f64| {
            let (u, v) = (from[p] - a.arc.center[p], from[q] - a.arc.center[q]);
            let scale = (a.radius + (a.end_radius - a.radius) * t(k)) / radius;
            let s = s * back;
            a.arc.plane.place(
                a.arc.center[p] + scale * (u * c - v * s),
                a.arc.center[q] + scale * (u * s + v * c),
                self.start[l] + (self.end[l] - self.start[l]) * t(k),
            )
        };
        let (start, end) = (self.start, self.end);
        [
            start,
            point(start, a.radius, 1, (cos, sin), 1.0),
            point(start, a.radius, 2, two, 1.0),
            point(end, a.end_radius, n - 3, three, -1.0),
            point(end, a.end_radius, n - 2, two, -1.0),
            point(end, a.end_radius, n - 1, (cos, sin), -1.0),
            end,
        ]
    }

    /// The points where an arc is furthest along an axis of its plane
    /// between its ends ([`geometry::axis_shares`]), each to `each`, at
    /// the radius it has there (along the normal, a helix's start: its
    /// ends bound it); none for a line. With its ends, the move's box.
    #[inline(always)]
    pub fn bulges(&self, mut each: impl FnMut(Point)) {
        let Some(a) = &self.arc else {
            return;
        };
        let (p, q, l) = a.arc.plane.axes();
        geometry::axis_shares(a.angle, a.sweep, |t, [u, v]| {
            let r = a.radius + (a.end_radius - a.radius) * t;
            each(a.arc.plane.place(
                a.arc.center[p] + r * u,
                a.arc.center[q] + r * v,
                self.start[l],
            ));
        });
    }

    pub fn at(&self, t: f64) -> Point {
        let Some(a) = &self.arc else {
            return std::array::from_fn(|i| self.start[i] + (self.end[i] - self.start[i]) * t);
        };
        let (p, q, n) = a.arc.plane.axes();
        let r = a.radius + (a.end_radius - a.radius) * t;
        let angle = a.angle + a.sweep * t;
        a.arc.plane.place(
            a.arc.center[p] + r * angle.cos(),
            a.arc.center[q] + r * angle.sin(),
            self.start[n] + (self.end[n] - self.start[n]) * t,
        )
    }
}

/// An arc's length: `sweep` radians at `radius` in the plane, `rise`
/// along its normal.
fn arc_length(radius: f64, sweep: f64, rise: f64) -> f64 {
    geometry::hypot((radius * sweep, rise))
}

pub fn distance(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    ToolChange(u32),
    Dwell(f64),
    Stop(ir::Stop),
    /// The spindle or the coolant changed (M3, M4, M5; an S while the
    /// spindle turns; M7, M8, M9): the controller finishes the moves
    /// before it first (grbl's spindle and coolant syncs; LinuxCNC waits
    /// for motion before them). `spindle_start`: the spindle was off and
    /// now turns.
    Sync {
        spindle_start: bool,
    },
    End,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    pub kind: EventKind,
    /// How many moves came before it.
    pub after_move: usize,
    pub span: Span,
}

/// What takes a tool path move by move as it is made, instead of the
/// whole [`ToolPath`] (the planner of `ger stats`): moves and events in
/// the program's order, each event before the move that follows it.
pub trait PathSink: Send {
    fn feed_move(&mut self, m: &Move);
    fn feed_event(&mut self, e: &Event);
    /// Forget what was fed: the program is being read again from its
    /// start.
    fn restart(&mut self);
    /// Whether taking a move costs more than lowering it (grbl's planner,
    /// which cuts arcs into chords): the compile then runs every lowering
    /// pass on the evaluator's thread and leaves the back end's to the sink.
    fn heavy(&self) -> bool {
        false
    }
    /// Tool lengths are known (a tool table, `G10 L1`): where `G43`
    /// folds one in, the path is the machine's controlled point, not the
    /// tool's tip. Told once, when the moves after it are handed on.
    fn tool_lengths_known(&mut self) {}
}

impl ToolPath {
    /// Hand its moves and events to `sink`, in order.
    pub fn feed_to(&self, sink: &mut dyn PathSink) {
        interleave(&self.moves, &self.events, 0, sink);
    }
}

/// `moves` (the first of them the `first`th of the program) and `events`
/// to `sink`, each event before the move its `after_move` counts to.
fn interleave(moves: &[Move], events: &[Event], first: usize, sink: &mut dyn PathSink) {
    let mut events = events.iter().peekable();
    for (i, m) in moves.iter().enumerate() {
        while let Some(e) = events.next_if(|e| e.after_move <= first + i) {
            sink.feed_event(e);
        }
        sink.feed_move(m);
    }
    events.for_each(|e| sink.feed_event(e));
}

/// Builds the tool path from the lowered IR (after the absolute pass:
/// absolute coordinates, arcs with centres).
#[derive(Clone, Debug)]
pub struct Builder {
    path: ToolPath,
    /// Moves handed on by [`Builder::drain_into`] and dropped.
    drained: usize,
    /// The sink was told the tool lengths are known.
    told_lengths: bool,
    /// Factor from the IR's lengths to mm (1 while the units are unknown).
    to_mm: f64,
    position: [f64; 9],
    plane: Plane,
    state: State,
    selected: u32,
    /// The machine's work offsets (index 1..=9: G54 … G59.3), zero until a
    /// statement passed through sets one (G10 L2, G10 L20), and its active
    /// one, whose origin is added to later coordinates.
    tables: [[f64; 9]; 10],
    active: usize,
    /// The machine's G92 shift (a G92 passed through), mm.
    g92: [f64; 9],
    /// X Y Z the program has set (and no machine move has lost since).
    known: [bool; 3],
}

impl Builder {
    /// `units`: the units of the IR's lengths (the output units).
    pub fn new(units: Option<Units>, setup: &ir::Setup) -> Builder {
        Builder {
            path: ToolPath {
                units,
                setup: setup.clone(),
                lengths_given: setup.tools.values().any(|t| t.length.is_some()),
                ..ToolPath::default()
            },
            drained: 0,
            told_lengths: false,
            to_mm: Units::mm_per(units),
            position: [0.0; 9],
            plane: Plane::XY,
            state: State::default(),
            selected: 0,
            tables: [[0.0; 9]; 10],
            active: 1,
            g92: [0.0; 9],
            known: [false; 3],
        }
    }

    pub fn feed(&mut self, stmt: &Stmt) {
        let k = self.to_mm;
        match &stmt.op {
            Op::Move(m) | Op::MachineMove(m) => {
                let kind = self.move_kind(m);
                let machine = matches!(stmt.op, Op::MachineMove(_));
                // Written only when it changes: the move copies the state
                // at once, and a copy read just after a write waits for it.
                let lead = m.lead.map(|l| l * k);
                if self.state.lead != lead {
                    self.state.lead = lead;
                }
                self.move_to(kind, &m.to, stmt.span, machine);
            }
            Op::IncrementalMove(m) => {
                self.state.lead = m.lead.map(|l| l * k);
                self.step(&m.to, stmt.span, m.motion);
            }
            Op::RigidTap(t) => self.rigid_tap(t, stmt.span),
            // The pictures draw each tool with the last radius given.
            Op::SetToolData(data) => {
                self.path.lengths_given |= data.length.is_some();
                data.apply(&mut self.path.setup.tools, false)
            }
            Op::Home {
                via, incremental, ..
            } => self.home(via, *incremental, stmt),
            Op::Feed(f) => self.state.feed = f * k,
            // Under G96 the surface speed, as rs274 prints it.
            Op::Speed(s) | Op::SpindleMode(ir::SpindleMode::SurfaceSpeed { speed: s, .. }) => {
                if *s != self.state.rpm && self.state.spindle.is_some() {
                    self.sync(false, stmt.span);
                }
                self.state.rpm = *s
            }
            Op::SelectTool(t) => {
                self.selected = *t;
                self.state.selected = *t;
            }
            // The comp pass has placed the moves after it.
            Op::ReadPosition(_) => {}
            Op::ChangeTool => {
                self.state.tool = self.selected;
                self.event(EventKind::ToolChange(self.selected), stmt.span);
            }
            Op::Spindle(s) => {
                let turning = (*s != ir::Spindle::Off).then_some(*s);
                if turning != self.state.spindle {
                    self.sync(self.state.spindle.is_none(), stmt.span);
                }
                self.state.spindle = turning;
            }
            Op::Coolant(c) => {
                let (mist, flood) = match c {
                    ir::Coolant::Mist => (true, self.state.flood),
                    ir::Coolant::Flood => (self.state.mist, true),
                    ir::Coolant::Off => (false, false),
                };
                if (mist, flood) != (self.state.mist, self.state.flood) {
                    self.sync(false, stmt.span);
                }
                (self.state.mist, self.state.flood) = (mist, flood);
            }
            Op::Dwell(s) => self.event(EventKind::Dwell(*s), stmt.span),
            Op::Stop(s) => self.event(EventKind::Stop(*s), stmt.span),
            Op::End => {
                self.state.spindle = None;
                (self.state.mist, self.state.flood) = (false, false);
                self.event(EventKind::End, stmt.span);
            }
            Op::Units(u) => self.to_mm = u.factor(Units::Mm),
            // What reaches the printer was passed through to the machine
            // (the offsets pass folds the rest): its tables change, and a
            // system is selected there. (P0: the active one.)
            Op::SetWorkOffsetHere { index, at } => self.set_offset_here(*index, at),
            Op::SetWorkOffset { index, origin } => self.set_offset(*index, origin),
            Op::SelectWorkOffset(index) => self.active = self.table(*index),
            Op::SetPosition(a) => self.set_position(a),
            Op::CancelPosition => self.g92 = [0.0; 9],
            Op::Plane(p) => self.plane = *p,
            Op::PathControl(pc) => self.state.path_control = pc.scaled(k),
            // Folded away before the absolute pass, or the machine's own
            // (taken as zero, see the module doc), or nothing that moves
            // (G97: the rpm stays the S given).
            Op::SpindleMode(_)
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::InverseTime(_)
            | Op::InverseTimeFloor(_)
            | Op::LocalOffset(_)
            | Op::ToolLength { .. }
            | Op::CancelToolLength
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::Cycle(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            // (The absolute pass made splines arcs.)
            | Op::Spline(_)
            | Op::Comment(_)
            | Op::Passthrough(_) => {}
        }
    }

    /// What a move is on the path: a rapid, a feed, or an arc about the
    /// centre its I/J/K give from where the tool is.
    #[inline]
    fn move_kind(&self, m: &ir::Move) -> MoveKind {
        match (m.motion, m.arc.map(|a| (a.geometry, a.turns))) {
            (ir::Motion::Rapid, _) => MoveKind::Rapid,
            (ir::Motion::ArcCw | ir::Motion::ArcCcw, Some((ArcGeometry::Center(c), turns))) => {
                let mut center: Point = std::array::from_fn(|i| self.position[i]);
                for (i, v) in c.iter().enumerate() {
                    center[i] += v.unwrap_or(0.0) * self.to_mm;
                }
                MoveKind::Arc(ArcPath {
                    center,
                    plane: self.plane,
                    clockwise: m.motion == ir::Motion::ArcCw,
                    turns,
                })
            }
            _ => MoveKind::Feed,
        }
    }

    /// G28/G30: a rapid to the via point (none for zero steps from here),
    /// then the homed axes to the machine's home, zero here.
    fn home(&mut self, via: &ir::Axes, incremental: bool, stmt: &Stmt) {
        if !incremental {
            self.move_to(MoveKind::Rapid, via, stmt.span, false);
        }
        let homed = stmt.op.unknown_after();
        let mut home = ir::Axes::default();
        for axis in Axis::ALL.into_iter().filter(|&a| homed(a)) {
            home.set(axis, 0.0);
        }
        self.move_to(MoveKind::Rapid, &home, stmt.span, true);
    }

    /// G10 L20 passed through: work offset `index` moves so that the
    /// tool's point has the coordinates `at`.
    fn set_offset_here(&mut self, index: u8, at: &ir::Axes) {
        let table = self.table(index);
        for (axis, v) in at.iter() {
            let i = axis.index();
            let v = if axis.is_rotary() { v } else { v * self.to_mm };
            self.tables[table][i] = self.position[i] - self.g92[i] - v;
        }
    }

    /// G92 passed through: the tool's point takes the coordinates `a`
    /// (known from here in that frame).
    fn set_position(&mut self, a: &ir::Axes) {
        for (axis, v) in a.iter() {
            let i = axis.index();
            let v = if axis.is_rotary() { v } else { v * self.to_mm };
            self.g92[i] = self.position[i] - self.tables[self.active][i] - v;
            if let Some(known) = self.known.get_mut(i) {
                *known = true;
            }
        }
    }

    /// A move by steps from where the tool is (its unknown axes stay
    /// unknown).
    fn step(&mut self, by: &ir::Axes, span: Span, motion: ir::Motion) {
        let start: Point = std::array::from_fn(|i| self.position[i]);
        for (axis, v) in by.iter() {
            self.position[axis.index()] += if axis.is_rotary() { v } else { v * self.to_mm };
        }
        self.path.moves.push(Move {
            kind: match motion {
                ir::Motion::Rapid => MoveKind::Rapid,
                _ => MoveKind::Feed,
            },
            start,
            end: std::array::from_fn(|i| self.position[i]),
            extra: std::array::from_fn(|i| self.position[i + 3]),
            state: self.state,
            span,
            guessed: self.known.map(|k| !k),
        });
    }

    /// G10 L2 passed through: work offset `index`'s origin.
    fn set_offset(&mut self, index: u8, origin: &ir::Axes) {
        let table = self.table(index);
        for (axis, v) in origin.iter() {
            self.tables[table][axis.index()] = if axis.is_rotary() { v } else { v * self.to_mm };
        }
    }

    /// The table of work offset `index` (0: the active one).
    fn table(&self, index: u8) -> usize {
        match index as usize {
            0 => self.active,
            i => i.min(9),
        }
    }

    /// A move to program coordinates `to` (machine coordinates when
    /// `machine`).
    fn move_to(&mut self, kind: MoveKind, to: &ir::Axes, span: Span, machine: bool) {
        let start: Point = std::array::from_fn(|i| self.position[i]);
        let guessed = self.known.map(|k| !k);
        // Every axis in turn, not the written ones by index: the new
        // position stays in registers for the move made of it (written
        // a word at a time and read back whole, it waited for its stores).
        let mut at = self.position;
        // Most programs move X, Y and Z only: the others looked at only
        // where the move writes one of them.
        let beyond_xyz = to.bits() >> 3 != 0;
        for (i, axis) in Axis::ALL.into_iter().enumerate() {
            if i == 3 && !beyond_xyz {
                break;
            }
            let Some(v) = to.get(axis) else {
                continue;
            };
            if let Some(known) = self.known.get_mut(i) {
                *known = !machine;
            }
            let offset = if machine {
                0.0
            } else {
                self.tables[self.active][i] + self.g92[i]
            };
            at[i] = offset + if axis.is_rotary() { v } else { v * self.to_mm };
        }
        self.position = at;
        self.path.moves.push(Move {
            kind,
            start,
            end: [at[0], at[1], at[2]],
            extra: [at[3], at[4], at[5], at[6], at[7], at[8]],
            state: self.state,
            span,
            guessed,
        });
    }

    /// G33.1: in to its point and back out the same way, both at its lead.
    fn rigid_tap(&mut self, t: &ir::RigidTap, span: Span) {
        let (back, known) = (self.position, self.known);
        self.state.lead = Some(t.lead * self.to_mm);
        self.move_to(MoveKind::Feed, &t.to, span, false);
        self.known = known;
        let start: Point = std::array::from_fn(|i| self.position[i]);
        self.position = back;
        self.path.moves.push(Move {
            kind: MoveKind::Feed,
            start,
            end: std::array::from_fn(|i| back[i]),
            extra: std::array::from_fn(|i| back[i + 3]),
            state: self.state,
            span,
            guessed: known.map(|k| !k),
        });
        self.state.lead = None;
    }

    /// The spindle or the coolant changed here (`spindle_start`: the
    /// spindle from off to on).
    fn sync(&mut self, spindle_start: bool, span: Span) {
        self.event(EventKind::Sync { spindle_start }, span);
    }

    fn event(&mut self, kind: EventKind, span: Span) {
        self.path.events.push(Event {
            kind,
            after_move: self.drained + self.path.moves.len(),
            span,
        });
    }

    /// Hand the moves and events made since the last call to `sink` and
    /// drop them, so that memory does not grow with the program.
    pub fn drain_into(&mut self, sink: &mut dyn PathSink) {
        if self.path.lengths_given && !self.told_lengths {
            sink.tool_lengths_known();
            self.told_lengths = true;
        }
        interleave(&self.path.moves, &self.path.events, self.drained, sink);
        self.drained += self.path.moves.len();
        self.path.moves.clear();
        self.path.events.clear();
    }

    pub fn finish(self) -> ToolPath {
        self.path
    }
}
