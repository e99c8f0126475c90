//! The IR: a stream of machine statements, each carrying the source span
//! that produced it. It is still G-code, modal and in the program's own
//! units; every lowering pass maps IR to simpler IR, and every stage prints
//! as valid G-code (`emit`). Nothing here knows the AST.

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

/// Where the evaluator sends the program: its statements in order, in
/// batches, once the setup is complete and the output units are known
/// (the back end then lowers and prints each batch and keeps nothing).
pub trait Sink {
    /// Take the statements of `batch`, leaving it empty.
    fn batch(&mut self, setup: &Setup, output_units: Units, batch: &mut Vec<Stmt>);
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stmt {
    pub op: Op,
    pub span: Span,
}

/// Optional X, Y, Z values as written (a missing axis keeps its position).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axes {
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub z: Option<f64>,
}

impl Axes {
    pub fn is_empty(&self) -> bool {
        self.x.is_none() && self.y.is_none() && self.z.is_none()
    }

    pub fn get(&self, axis: usize) -> Option<f64> {
        [self.x, self.y, self.z][axis]
    }

    pub fn set(&mut self, axis: usize, value: Option<f64>) {
        match axis {
            0 => self.x = value,
            1 => self.y = value,
            _ => self.z = value,
        }
    }

    /// Apply `f` to every present value.
    pub fn map(self, f: impl Fn(f64) -> f64) -> Axes {
        Axes {
            x: self.x.map(&f),
            y: self.y.map(&f),
            z: self.z.map(&f),
        }
    }

    pub fn full(p: [f64; 3]) -> Axes {
        Axes {
            x: Some(p[0]),
            y: Some(p[1]),
            z: Some(p[2]),
        }
    }
}

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

/// How an arc's geometry was given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArcGeometry {
    /// I, J, K: the centre relative to the start point.
    Center(Axes),
    /// R: positive for the short arc, negative for the long one.
    Radius(f64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub motion: Motion,
    pub to: Axes,
    /// Present exactly when `motion` is an arc.
    pub arc: Option<Arc>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    pub geometry: ArcGeometry,
    /// Full turns (G2/G3 P); 1 is an ordinary arc.
    pub turns: u32,
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

#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    Move(Move),
    /// F, in length units per minute.
    Feed(f64),
    /// S, rpm.
    Speed(f64),
    /// T: the tool the next M6 loads.
    SelectTool(u32),
    /// M6
    ChangeTool,
    Spindle(Spindle),
    Coolant(Coolant),
    /// G4, in seconds.
    Dwell(f64),
    Stop(Stop),
    /// M2 / M30
    End,
    Units(Units),
    Distance(Distance),
    Plane(Plane),
    /// G54..G59 as 1..=6.
    SelectWorkOffset(u8),
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
    /// G43 H`tool` (positive) / G44 (negative).
    ToolLength {
        tool: u32,
        negative: bool,
    },
    /// G49
    CancelToolLength,
    /// G16 (true) / G15 (false).
    Polar(bool),
    /// G40
    CompOff,
    /// G80
    CycleOff,
    Comment(String),
}

/// The machine as the setup directives (SPEC §3) describe it. Lengths are
/// in the output units.
#[derive(Clone, Debug, Default)]
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
    pub length: f64,
    pub shape: ToolShape,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolShape {
    Flat,
    Ball,
    Drill,
    Vee,
}

impl ToolShape {
    pub fn from_name(name: &str) -> Option<ToolShape> {
        match name.to_ascii_lowercase().as_str() {
            "flat" => Some(ToolShape::Flat),
            "ball" => Some(ToolShape::Ball),
            "drill" => Some(ToolShape::Drill),
            "vee" | "v" => Some(ToolShape::Vee),
            _ => None,
        }
    }
}
