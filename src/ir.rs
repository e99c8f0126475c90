//! The IR: a stream of machine statements, each carrying the source span
//! that produced it. It is still G-code, modal and in the program's own
//! units; every lowering pass maps IR to simpler IR, and every stage prints
//! as valid G-code (`emit`). Nothing here knows the AST.
//!
//! Architecture invariant: [`Op`] has one variant per G-code concept, and
//! every pass matches it without a catch-all, so a new op fails to compile
//! wherever it needs a decision.

use crate::source::Span;
use std::collections::BTreeMap;

/// The largest length, feed or speed a program may give (10 km in mm,
/// 254 km in inches): anything beyond is a typo.
pub const MAX_LENGTH: f64 = 1e7;

/// The largest machine position (the absolute pass checks every move): with
/// 9 decimals it is 10^18 steps, inside the printer's `i64` grid.
pub const MAX_POSITION: f64 = 1e9;

/// Within ±[`MAX_LENGTH`] (and a number).
pub fn is_length(v: f64) -> bool {
    v.abs() < MAX_LENGTH
}

/// Within ±[`MAX_POSITION`] (and a number).
pub fn is_position(v: f64) -> bool {
    v.abs() < MAX_POSITION
}

/// What the evaluator knows when it starts sending statements (after the
/// setup directives, before the first move).
#[derive(Clone, Debug)]
pub struct Start {
    pub setup: Setup,
    /// The units the output is written in; `None`: the program never says,
    /// and its numbers pass through in the machine's units (SPEC §3).
    pub output_units: Option<Units>,
    /// The units the program is in before its first G20/G21.
    pub program_units: Option<Units>,
    /// Where canned cycles return before the program says G98 or G99: the
    /// machine's power-up state, as the source flavour (`--from`) has it.
    pub return_level: ReturnLevel,
}

/// Where the evaluator sends the program: its statements in order, in
/// batches (the back end lowers and prints each batch and keeps nothing).
pub trait Sink {
    /// Called once, before the first batch.
    fn start(&mut self, start: &Start);
    /// Take the statements of `batch`, leaving it empty.
    fn batch(&mut self, batch: &mut Vec<Stmt>);
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stmt {
    pub op: Op,
    pub span: Span,
    /// Written on a block-delete line (`/`): printed with its `/`.
    pub block_delete: bool,
    /// The N word of its source line, for `--numbers keep`; `None` for
    /// statements ger makes and those a called subprogram makes.
    pub number: Option<u32>,
}

impl Stmt {
    pub fn new(op: Op, span: Span) -> Stmt {
        Stmt {
            op,
            span,
            block_delete: false,
            number: None,
        }
    }

    /// Another statement from the same source block.
    pub fn with_op(&self, op: Op) -> Stmt {
        Stmt {
            op,
            span: self.span,
            block_delete: self.block_delete,
            number: self.number,
        }
    }
}

/// The axes of a move: three linear (X Y Z), three rotary in degrees
/// (A B C) and three more linear (U V W), in the order they are printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
    A,
    B,
    C,
    U,
    V,
    W,
}

impl Axis {
    pub const ALL: [Axis; 9] = [
        Axis::X,
        Axis::Y,
        Axis::Z,
        Axis::A,
        Axis::B,
        Axis::C,
        Axis::U,
        Axis::V,
        Axis::W,
    ];

    pub fn index(self) -> usize {
        self as usize
    }

    pub fn letter(self) -> u8 {
        b"XYZABCUVW"[self as usize]
    }

    pub fn from_letter(letter: u8) -> Option<Axis> {
        let i = b"XYZABCUVW".iter().position(|&l| l == letter)?;
        Some(Axis::ALL[i])
    }

    /// A B C turn (degrees); the others are lengths.
    pub fn is_rotary(self) -> bool {
        matches!(self, Axis::A | Axis::B | Axis::C)
    }
}

/// Axis values as written: an axis left out keeps its position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axes {
    present: u16,
    values: [f64; 9],
}

impl Axes {
    /// No axis.
    pub const NONE: Axes = Axes {
        present: 0,
        values: [0.0; 9],
    };

    pub fn is_empty(&self) -> bool {
        self.present == 0
    }

    pub fn get(&self, axis: Axis) -> Option<f64> {
        (self.present & (1 << axis as u16) != 0).then(|| self.values[axis as usize])
    }

    pub fn has(&self, axis: Axis) -> bool {
        self.present & (1 << axis as u16) != 0
    }

    /// The axes present, a bit each (bit `Axis::index`).
    pub fn bits(&self) -> u16 {
        self.present
    }

    pub fn set(&mut self, axis: Axis, value: f64) {
        self.present |= 1 << axis as u16;
        self.values[axis as usize] = value;
    }

    pub fn put(&mut self, axis: Axis, value: Option<f64>) {
        match value {
            Some(v) => self.set(axis, v),
            None => self.present &= !(1 << axis as u16),
        }
    }

    /// The axes present, in printing order (the order of their bits).
    pub fn iter(&self) -> impl Iterator<Item = (Axis, f64)> + '_ {
        let mut left = self.present;
        std::iter::from_fn(move || {
            let i = left.trailing_zeros() as usize;
            let axis = *Axis::ALL.get(i)?;
            left &= left - 1;
            Some((axis, self.values[i]))
        })
    }

    /// Whether every present value satisfies `f`. Over the nine slots
    /// (unrolled, no bounds checks) rather than [`Axes::iter`]: the passes
    /// and the printer follow every move with it.
    #[inline]
    pub fn all_values(&self, f: impl Fn(f64) -> bool) -> bool {
        (0..9).all(|i| self.present & (1 << i) == 0 || f(self.values[i]))
    }

    /// Put each present value, made into `T` by `f`, in its slot of
    /// `slots` (by `Axis::index`); the others are left as they are. Over
    /// the nine slots, as [`Axes::all_values`].
    #[inline]
    pub fn place<T>(&self, slots: &mut [T; 9], f: impl Fn(f64) -> T) {
        for (i, slot) in slots.iter_mut().enumerate() {
            if self.present & (1 << i) != 0 {
                *slot = f(self.values[i]);
            }
        }
    }

    /// Add `shift` to every present value, slot by slot.
    #[inline]
    pub fn shift_by(&mut self, shift: &[f64; 9]) {
        for (i, (value, by)) in self.values.iter_mut().zip(shift).enumerate() {
            if self.present & (1 << i) != 0 {
                *value += by;
            }
        }
    }

    /// Apply `f` to every present length (not to A B C).
    pub fn map_lengths(mut self, f: impl Fn(f64) -> f64) -> Axes {
        for axis in Axis::ALL {
            if !axis.is_rotary() && self.has(axis) {
                self.values[axis as usize] = f(self.values[axis as usize]);
            }
        }
        self
    }

    pub fn xyz(x: f64, y: f64, z: f64) -> Axes {
        let mut a = Axes::default();
        a.set(Axis::X, x);
        a.set(Axis::Y, y);
        a.set(Axis::Z, z);
        a
    }
}

/// What is known of the machine's position, per axis.
pub type Position = [Option<f64>; 9];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
}

impl Motion {
    pub fn is_arc(self) -> bool {
        matches!(self, Motion::ArcCw | Motion::ArcCcw)
    }
}

/// An arc's centre offset I, J, K (relative to the start point).
pub type Center = [Option<f64>; 3];

/// How an arc's geometry was given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArcGeometry {
    Center(Center),
    /// R: positive for the short arc, negative for the long one.
    Radius(f64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub motion: Motion,
    pub to: Axes,
    /// Present exactly when `motion` is an arc.
    pub arc: Option<Arc>,
    /// Fanuc's `,R`/`,C` on a G1, G2 or G3: the corner to the next move is
    /// rounded or chamfered. Only before the corners pass, which lowers it.
    pub corner: Option<Corner>,
    /// LinuxCNC's G33: a straight feed locked to the spindle, this far
    /// along the path per revolution (K, in the IR's length units).
    pub lead: Option<f64>,
}

/// LinuxCNC's G33.1: a feed locked to the spindle from where the tool
/// is to `to`, the spindle reversed, and the same way back; the tool
/// ends where it started.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidTap {
    pub to: Axes,
    /// K: this far along the path per spindle revolution, both ways (in
    /// the IR's length units).
    pub lead: f64,
    /// I: the spindle this many times faster on the way out, as written
    /// (LinuxCNC takes less than 1 as 1).
    pub speedup: Option<f64>,
}

/// How the corner at the end of a G1, G2 or G3 is cut (Fanuc's
/// "chamfering and corner R"), its size in the IR's length units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corner {
    /// `,R`: an arc of this radius, tangent to both moves.
    Round(f64),
    /// `,C`: a straight cut from this far back along the move to this far
    /// along the next one (on an arc, the chord from the corner).
    Chamfer(f64),
}

impl Corner {
    /// Its size times `k` (a change of units).
    pub fn scaled(self, k: f64) -> Corner {
        match self {
            Corner::Round(r) => Corner::Round(r * k),
            Corner::Chamfer(c) => Corner::Chamfer(c * k),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    pub geometry: ArcGeometry,
    /// Full turns (G2/G3 P); 1 is an ordinary arc.
    pub turns: u32,
}

impl Arc {
    /// An arc to fill in (no centre, one turn).
    pub const BLANK: Arc = Arc {
        geometry: ArcGeometry::Center([None; 3]),
        turns: 1,
    };
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    Inch,
    Mm,
}

impl Units {
    /// Factor that converts a length in `self` to `to`.
    pub fn factor(self, to: Units) -> f64 {
        match (self, to) {
            (Units::Inch, Units::Mm) => 25.4,
            (Units::Mm, Units::Inch) => 1.0 / 25.4,
            _ => 1.0,
        }
    }

    /// Millimetres per unit of lengths in `units`; a program that states
    /// no units is taken as mm (the tool path, the picture).
    pub fn mm_per(units: Option<Units>) -> f64 {
        units.map_or(1.0, |u| u.factor(Units::Mm))
    }

    pub fn name(self) -> &'static str {
        match self {
            Units::Inch => "inch",
            Units::Mm => "mm",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    Absolute,
    Incremental,
}

/// The arc plane. Axis indices are (first, second, normal) in X=0, Y=1,
/// Z=2, oriented so that counter-clockwise is positive about the normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    XY,
    ZX,
    YZ,
}

impl Plane {
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::ZX => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        }
    }

    /// The point at `a` and `b` along the plane's two axes (in
    /// [`Plane::axes`]' order) and `c` along its normal, made whole (in
    /// registers: written an axis at a time by index and read back whole,
    /// a point waits for its stores).
    #[inline(always)]
    pub fn place(self, a: f64, b: f64, c: f64) -> [f64; 3] {
        match self {
            Plane::XY => [a, b, c],
            Plane::ZX => [b, c, a],
            Plane::YZ => [c, a, b],
        }
    }
}

/// Path control (G61, G61.1, G64): how the controller joins one move to
/// the next. The machine's state, passed on to targets that have it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathControl {
    /// G61: the path exactly, slowing at each corner as much as it needs.
    ExactPath,
    /// G61.1: a stop at the end of every move.
    ExactStop,
    /// G64: corners blended. `tolerance` (P): how far the blend may leave
    /// the programmed corner, in length units; `None`, the controller's
    /// default (as fast as it can on LinuxCNC). `naive` (Q): LinuxCNC's
    /// tolerance for joining short collinear moves; `None`, `tolerance`.
    Blend {
        tolerance: Option<f64>,
        naive: Option<f64>,
    },
}

/// Every controller starts blending as its settings say (LinuxCNC: G64
/// with no tolerance).
impl Default for PathControl {
    fn default() -> PathControl {
        PathControl::Blend {
            tolerance: None,
            naive: None,
        }
    }
}

impl PathControl {
    /// The blend tolerance and the naive-CAM tolerance as LinuxCNC applies
    /// them (0: none given, as fast as it can), or `None` for an exact
    /// mode.
    pub fn tolerances(self) -> Option<(f64, f64)> {
        match self {
            PathControl::ExactPath | PathControl::ExactStop => None,
            PathControl::Blend { tolerance, naive } => {
                let p = tolerance.unwrap_or(0.0);
                Some((p, naive.unwrap_or(p)))
            }
        }
    }

    /// Its lengths times `k`.
    pub fn scaled(self, k: f64) -> PathControl {
        match self {
            PathControl::Blend { tolerance, naive } => PathControl::Blend {
                tolerance: tolerance.map(|v| v * k),
                naive: naive.map(|v| v * k),
            },
            exact => exact,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    Clockwise,
    CounterClockwise,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coolant {
    Mist,
    Flood,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// M0
    Program,
    /// M1
    Optional,
}

/// G28 or G30: a return to a home position the machine stores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Home {
    G28,
    G30,
}

/// Where a canned cycle retracts to between holes (G98 / G99).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReturnLevel {
    /// G98: the level where the run of cycles began.
    Initial,
    /// G99: the R level.
    R,
}

/// The canned cycles (SPEC §4 cycles).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleKind {
    /// G73 chip-breaking peck.
    G73,
    /// G74 left-hand tapping.
    G74,
    /// G76 fine boring (Fanuc's): at the bottom an oriented spindle stop,
    /// a shift of Q away from the wall, and out.
    G76,
    /// G81 drill.
    G81,
    /// G82 drill with dwell.
    G82,
    /// G83 deep peck.
    G83,
    /// G84 right-hand tapping.
    G84,
    /// G85 bore, feed out.
    G85,
    /// G86 bore, spindle stop, rapid out.
    G86,
    /// G87 back bore (LinuxCNC's: I, J, K).
    G87,
    /// G87 back bore as Fanuc's: shifted by Q down past the bore to R
    /// (below the bottom word, which is the top of the back bore), fed up.
    G87Fanuc,
    /// G88 bore, dwell, spindle stop, manual retract (program stop).
    G88,
    /// G89 bore, dwell, feed out.
    G89,
}

impl CycleKind {
    pub fn code(self) -> u32 {
        match self {
            CycleKind::G73 => 73,
            CycleKind::G74 => 74,
            CycleKind::G76 => 76,
            CycleKind::G81 => 81,
            CycleKind::G82 => 82,
            CycleKind::G83 => 83,
            CycleKind::G84 => 84,
            CycleKind::G85 => 85,
            CycleKind::G86 => 86,
            CycleKind::G87 | CycleKind::G87Fanuc => 87,
            CycleKind::G88 => 88,
            CycleKind::G89 => 89,
        }
    }
}

/// One block of a canned cycle. The front end fills in what rs274 lets a
/// block leave out (R, the depth, Q, P, I/J/K of the previous block of the
/// same cycle), so every block is complete. Under G91 the plane words are
/// the step per repeat, R is measured from the run's start level and the
/// depth from R, as in rs274.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycle {
    pub kind: CycleKind,
    /// The hole position (plane axes, as written) and the bottom (the
    /// plane's normal axis, always given).
    pub at: Axes,
    /// The R level, on the normal axis.
    pub r: f64,
    /// Peck depth (G73, G83); G76's shift off the wall.
    pub q: Option<f64>,
    /// Dwell at the bottom, seconds (G82, G84, G74, G86, G88, G89).
    pub dwell: Option<f64>,
    /// Holes drilled (L, or Fanuc's K), from 1.
    pub repeats: u32,
    /// G87's I, J (back-bore offset) and K (back-bore level).
    pub ijk: Center,
    /// The first block of a run of cycles (after any other motion code or
    /// G80): where the tool is before it is the G98 level of the run.
    pub starts_run: bool,
    /// The number of pecks (G73, G83) as rs274 counts them, by repeated
    /// subtraction in the program's own units and coordinates; known when
    /// the front end can count them (G90).
    pub pecks: Option<u32>,
    /// Set by the cycles pass on a cycle it keeps (`--cycles keep`).
    pub kept: Option<KeptCycle>,
}

/// A cycle block the output keeps, normalised: absolute, one hole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeptCycle {
    /// Written on the block (G98/G99).
    pub level: ReturnLevel,
    /// The level of the normal axis the cycle ends at.
    pub ends_at: f64,
}

/// Which side of the path the tool runs on (G41 left, G42 right).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// Where compensation takes its radius from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompRadius {
    /// G41/G42 D`n`: half of tool `n`'s diameter in the table.
    Tool(u32),
    /// G41/G42 without D: the loaded tool.
    LoadedTool,
    /// G41.1/G42.1 D`d`: the diameter itself.
    Diameter(f64),
}

/// A machine code ger does not interpret: passed through as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Passthrough {
    /// An M code with its P, Q, E, L words (M40, M62, M100…).
    MCode { number: u32, words: Vec<(u8, f64)> },
    /// A controller command line such as grbl's `$H`, verbatim.
    Line(String),
}

/// A G5 or G5.1 curve from the current point to `to` (X and Y as
/// written), in the XY plane at the current Z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spline {
    pub to: Axes,
    pub kind: SplineKind,
}

/// The inner control points, each relative to the end it belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplineKind {
    /// G5, a cubic: I J from the start, P Q from the end.
    Cubic { start: [f64; 2], end: [f64; 2] },
    /// G5.1, a quadratic: I J from the start.
    Quadratic { control: [f64; 2] },
}

impl SplineKind {
    /// Its offsets times `k` (a change of units).
    pub fn scaled(self, k: f64) -> SplineKind {
        let by = |p: [f64; 2]| [p[0] * k, p[1] * k];
        match self {
            SplineKind::Cubic { start, end } => SplineKind::Cubic {
                start: by(start),
                end: by(end),
            },
            SplineKind::Quadratic { control } => SplineKind::Quadratic {
                control: by(control),
            },
        }
    }
}

/// How S is read: G97 (rpm, where every program starts) or G96.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpindleMode {
    Rpm,
    /// S (`speed`, on G96's line as rs274 wants it) is the speed of the
    /// surface at the tool's X radius, in length units per minute (m/min
    /// in a mm program, ft/min in an inch one); the spindle turns at most
    /// `max_rpm` (D) when given.
    SurfaceSpeed {
        speed: f64,
        max_rpm: Option<f64>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    Move(Move),
    /// G53: a straight move in machine coordinates (passed through; the
    /// position is unknown after it).
    MachineMove(Move),
    /// A straight move by steps from wherever the tool is (G91), made by
    /// the absolute pass for an incremental move on an axis whose position
    /// only the machine knows; printed between G91 and G90. The axes it
    /// moves stay unknown, the others it moves from where they were.
    IncrementalMove(Move),
    /// G28/G30: to the stored home position through `via`, absolute
    /// (passed through; the position is unknown after it).
    Home {
        home: Home,
        via: Axes,
        /// `via` is relative to the current point: only when the absolute
        /// pass cannot know that point and every increment is 0 (Fusion's
        /// `G28 G91 Z0.`: home, straight from where the tool is).
        incremental: bool,
    },
    /// F, in length units per minute.
    Feed(f64),
    /// S: rpm, or under G96 the surface speed ([`SpindleMode`]).
    Speed(f64),
    /// G96 (constant surface speed, D its limit in rpm) / G97 (S in rpm).
    SpindleMode(SpindleMode),
    /// T: the tool the next M6 loads.
    SelectTool(u32),
    /// M6
    ChangeTool,
    /// The current point read back from where the tool is, as LinuxCNC
    /// does at a tool change (M6, M61): made only after G40 with no move
    /// since, where the tool still stands at its last offset point and
    /// the programmed point differs from it in the plane's two axes. The
    /// comp pass knows that point; the passes before it forget the two.
    ReadPosition(Plane),
    Spindle(Spindle),
    Coolant(Coolant),
    /// G4, in seconds.
    Dwell(f64),
    Stop(Stop),
    /// M2 / M30
    End,
    Units(Units),
    Distance(Distance),
    /// G90.1 (`Absolute`): the I/J/K of the arcs after it are their
    /// centre's coordinates, in the program's frame as X/Y/Z are; G91.1
    /// (`Incremental`, where every program starts): the centre relative
    /// to the arc's start. Made only where the mode changes; the absolute
    /// pass makes every centre relative and drops these.
    ArcCenters(Distance),
    /// G93 (true): the F of each feed move, given on its line, is the
    /// inverse of the move's time in minutes; G94 (false), where every
    /// program starts. Made only where the mode changes; the absolute pass
    /// turns each such F into a feed per minute (the move's length times
    /// F, as LinuxCNC does) and drops these.
    InverseTime(bool),
    /// Under G93, the least feed (output units a minute) a feed move gets
    /// from its F: LinuxCNC raises a move's rate to 0.1 of the program's
    /// units a minute at least. Made by the units pass where G93 begins
    /// and where the units change under it (it alone knows the program's
    /// units); the absolute pass takes it and drops it.
    InverseTimeFloor(f64),
    Plane(Plane),
    /// G54..G59.3 as 1..=9.
    SelectWorkOffset(u8),
    /// G10 L1: a tool's radius and length from here on.
    SetToolData(ToolData),
    /// G10 L2 P`index` (1 = G54): the origin of that system.
    SetWorkOffset {
        index: u8,
        origin: Axes,
    },
    /// G10 L20 P`index`: that system is moved so the current point has
    /// these coordinates.
    SetWorkOffsetHere {
        index: u8,
        at: Axes,
    },
    /// G52: shift of the program zero; `G52 X0 Y0 Z0` cancels it.
    LocalOffset(Axes),
    /// G92: the current point takes these coordinates.
    SetPosition(Axes),
    /// G92.1: cancel G92.
    CancelPosition,
    /// G43 H`tool` (positive) / G44 (negative); `None`: the loaded tool,
    /// not known.
    ToolLength {
        tool: Option<u32>,
        negative: bool,
    },
    /// G49
    CancelToolLength,
    /// G16 (true) / G15 (false).
    Polar(bool),
    /// G7 (true): X words are diameters; G8 (false): radii.
    DiameterMode(bool),
    /// G98 / G99.
    ReturnLevel(ReturnLevel),
    /// G73, G74, G81–G89 and the blocks that repeat them.
    /// Boxed: it is the largest op, and rare.
    Cycle(Box<Cycle>),
    /// G80
    CycleOff,
    /// G41/G42 (G41.1/G42.1).
    Comp {
        side: Side,
        radius: CompRadius,
    },
    /// G40
    CompOff,
    /// G61, G61.1, G64 P Q.
    PathControl(PathControl),
    /// G5/G5.1 (LinuxCNC): a curve in the XY plane, made arcs by the
    /// absolute pass. Boxed: rare.
    Spline(Box<Spline>),
    /// G33.1 (LinuxCNC): a rigid tap from where the tool is.
    RigidTap(RigidTap),
    Comment(String),
    Passthrough(Passthrough),
}

impl Op {
    /// The axes whose position ger no longer knows after this statement:
    /// the machine moved them on its own (G53, G28/G30: the axes named,
    /// or all), or their coordinates changed meaning by an offset passed
    /// through (a work offset: all; a tool length: Z). Every pass and
    /// printer that tracks the position forgets exactly these.
    pub fn unknown_after(&self) -> impl Fn(Axis) -> bool + '_ {
        move |axis| match self {
            Op::MachineMove(m) => m.to.has(axis),
            Op::Home { via, .. } => via.is_empty() || via.has(axis),
            // (A `G10 L2` gets past the offsets pass only passed through.)
            Op::SelectWorkOffset(_) | Op::SetWorkOffset { .. } | Op::SetWorkOffsetHere { .. } => {
                true
            }
            Op::ToolLength { .. } | Op::CancelToolLength => axis == Axis::Z,
            // (A G92.1 gets past the offsets pass only where the machine
            // has a G92 the program passed through.)
            Op::CancelPosition => true,
            Op::ReadPosition(plane) => {
                let (u, v, _) = plane.axes();
                axis.index() == u || axis.index() == v
            }
            // (An incremental move's unknown axes were unknown before it.)
            Op::Move(_)
            | Op::IncrementalMove(_)
            | Op::Spline(_)
            | Op::RigidTap(_)
            | Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
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
            | Op::Plane(_)
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::Cycle(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            | Op::PathControl(_)
            | Op::Comment(_)
            | Op::SetToolData(_)
            | Op::Passthrough(_) => false,
        }
    }
}

/// G54..G59.3 for the work offsets 1..=9 (`None` for any other number).
pub fn work_offset_code(index: u8) -> Option<&'static str> {
    const CODES: [&str; 9] = [
        "G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3",
    ];
    CODES.get(usize::from(index).checked_sub(1)?).copied()
}

/// The machine as the setup directives (SPEC §3) describe it. Lengths are
/// in the output units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Setup {
    /// `SetUnits`: the output units, if given.
    pub units: Option<Units>,
    pub margin: Option<f64>,
    /// `SetPart x y z`: the stock size.
    pub part: Option<[f64; 3]>,
    /// `SetZero x y z`: the program zero measured from the stock's
    /// top-lower-left corner.
    pub zero: Option<[f64; 3]>,
    pub tools: BTreeMap<u32, Tool>,
    /// `SetOffset 55..59`: origins of G55..G59 (index 2..=6).
    pub work_offsets: BTreeMap<u8, [f64; 3]>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tool {
    pub diameter: f64,
    /// `None`: unknown (a G43 with it passes through).
    pub length: Option<f64>,
    pub shape: ToolShape,
}

/// G10 L1 P`tool` R`radius` Z`length`: each value only where given (the
/// rest of the tool's entry stays). G10 L10/L11 give, instead of the
/// length, the Z the current point is to read (`measured`); the offsets
/// pass works the length out and makes them L1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolData {
    pub tool: u32,
    pub radius: Option<f64>,
    /// The length (L1), or the Z the current point is to read (L10, L11).
    pub length: Option<f64>,
    pub measured: Measured,
    /// A lathe tool's orientation and front and back angles (Q, I, J),
    /// as written: they change no mill's path, but they are the machine's
    /// tool table, so they are passed on.
    pub lathe: [Option<f64>; 3],
}

/// How a G10's Z sets a tool's length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measured {
    /// G10 L1: Z is the length.
    Given,
    /// G10 L10: the length that makes the current point read Z, with the
    /// offsets in force.
    Here,
    /// G10 L11: the same in G59.3 (a fixture) without G92 or G52.
    InFixture,
}

impl Measured {
    /// G10's L number.
    pub fn l_number(self) -> u32 {
        match self {
            Measured::Given => 1,
            Measured::Here => 10,
            Measured::InFixture => 11,
        }
    }
}

impl ToolData {
    /// These values written into `tools`. A tool not in the table is
    /// added when R gives its diameter; with only Z it is added when
    /// `length_only` (the offsets pass, which reads lengths alone), else
    /// left out, so that a radius ger does not know stays an error where
    /// compensation needs it. A Z still to be measured (L10, L11: the
    /// offsets pass works it out) is not a length, and is left out.
    pub fn apply(&self, tools: &mut BTreeMap<u32, Tool>, length_only: bool) {
        if self.radius.is_none() && !length_only && !tools.contains_key(&self.tool) {
            return;
        }
        let entry = tools.entry(self.tool).or_insert(Tool {
            diameter: 0.0,
            length: None,
            shape: ToolShape::Flat,
        });
        if let Some(r) = self.radius {
            entry.diameter = 2.0 * r;
        }
        if self.measured == Measured::Given && self.length.is_some() {
            entry.length = self.length;
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToolShape {
    Flat,
    Ball,
    /// A drill with its point angle (118°).
    Drill,
    /// A vee cutter with its included angle in degrees (default 90°).
    Vee(f64),
}

impl ToolShape {
    /// `flat`, `ball`, `drill`, `vee` (90°) or `vee60` (a vee of that
    /// included angle, more than 0 and less than 180 degrees).
    pub fn from_name(name: &str) -> Option<ToolShape> {
        let name = name.to_ascii_lowercase();
        match name.as_str() {
            "flat" => Some(ToolShape::Flat),
            "ball" => Some(ToolShape::Ball),
            "drill" => Some(ToolShape::Drill),
            "vee" | "v" => Some(ToolShape::Vee(90.0)),
            _ => {
                let angle: f64 = name.strip_prefix("vee")?.parse().ok()?;
                (angle > 0.0 && angle < 180.0).then_some(ToolShape::Vee(angle))
            }
        }
    }
}
