//! Pass absolute (SPEC §4.5, and the arc rules of §4): G91 → G90, every
//! move's written axes absolute machine coordinates (axes it did not
//! write stay out, so the emitter knows what the source commanded), and every arc checked and given as
//! a centre relative to its start in the active plane (R arcs resolved,
//! I/J/K arcs checked: radii within 1 %). The given centre is kept, as
//! LinuxCNC keeps it (a small radius difference is a slight spiral); the
//! larger radius is what `--arcs r` writes. An axis the program never set stays unknown and is not
//! written; an incremental move or an arc on an unknown axis is an error.
//! Until cycles and cutter compensation have passes, G80 and G40 (no-ops:
//! G8x and G41/G42 are refused earlier) are dropped here.

use super::{unknown_position, Errors};
use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::geometry::{self, ArcError, Point};
use crate::ir::{self, ArcGeometry, Axes, Distance, Op, Plane};
use crate::source::Span;

pub struct State {
    distance: Distance,
    plane: Plane,
    position: [Option<f64>; 3],
    pub errors: Errors,
}

impl State {
    pub fn new() -> State {
        State {
            distance: Distance::Absolute,
            plane: Plane::XY,
            position: [None; 3],
            errors: Errors::default(),
        }
    }

    pub fn run(&mut self, stmts: &mut Vec<ir::Stmt>) {
        let State {
            distance,
            plane,
            position,
            errors,
        } = self;
        stmts.retain_mut(|stmt| match &mut stmt.op {
            Op::Distance(d) => {
                *distance = *d;
                false
            }
            Op::CompOff | Op::CycleOff => false,
            Op::Plane(p) => {
                *plane = *p;
                true
            }
            Op::Move(m) => {
                let mut end = *position;
                for (axis, end_axis) in end.iter_mut().enumerate() {
                    let Some(v) = m.to.get(axis) else { continue };
                    *end_axis = match *distance {
                        Distance::Absolute => Some(v),
                        Distance::Incremental => match position[axis] {
                            Some(p) => Some(p + v),
                            None => {
                                errors.push(unknown_position(
                                    stmt.span,
                                    axis,
                                    "an incremental move",
                                ));
                                return true;
                            }
                        },
                    };
                    if let Some(e) = end_axis.filter(|&e| !ir::is_position(e)) {
                        let letter = ['X', 'Y', 'Z'][axis];
                        errors.push(
                            error(
                                format!("the move takes {letter} out of range"),
                                stmt.span,
                                format!("{letter} would be {e:e}"),
                            )
                            .with_note(format!(
                                "machine positions must be between -{0} and {0}",
                                ir::MAX_POSITION
                            )),
                        );
                        return true;
                    }
                }
                if let Some(arc) = &mut m.arc {
                    match resolve_arc(
                        *position,
                        end,
                        arc.geometry,
                        *plane,
                        m.motion == ir::Motion::ArcCw,
                        stmt.span,
                    ) {
                        Ok(center) => arc.geometry = ArcGeometry::Center(center),
                        Err(d) => {
                            errors.push(d);
                            return true;
                        }
                    }
                }
                // Only the axes the statement wrote: a Z retract stays a Z move.
                m.to = Axes {
                    x: m.to.x.and(end[0]),
                    y: m.to.y.and(end[1]),
                    z: m.to.z.and(end[2]),
                };
                *position = end;
                true
            }
            _ => true,
        });
    }
}

/// The centre of an arc, relative to its start, in the plane's two axes.
fn resolve_arc(
    start: [Option<f64>; 3],
    end: [Option<f64>; 3],
    geometry: ArcGeometry,
    plane: Plane,
    clockwise: bool,
    span: Span,
) -> Result<Axes, Diagnostic> {
    let (a, b, n) = plane.axes();
    for axis in [a, b, n] {
        if start[axis].is_none() && (axis != n || end[axis].is_some()) {
            return Err(unknown_position(span, axis, "an arc"));
        }
    }
    let s: Point = start.map(|v| v.unwrap_or(0.0));
    let mut e: Point = end.map(|v| v.unwrap_or(0.0));
    e[n] = end[n].unwrap_or(s[n]);
    let arc_error = |err: ArcError| {
        match err {
        ArcError::RadiusTooSmall { radius, half_chord } => error(
            "arc radius too small",
            span,
            format!("R{radius} cannot reach an end point {} away", fmt(2.0 * half_chord)),
        )
        .with_note(format!("the radius must be at least half the distance: {}", fmt(half_chord))),
        ArcError::SamePoints => error(
            "an R arc cannot be a full circle",
            span,
            "the end point is the start point",
        )
        .with_help("give a full circle's centre with I/J/K"),
        ArcError::RadiiDiffer { start, end } => error(
            "arc end is not on the circle",
            span,
            format!("radius {} at the start, {} at the end", fmt(start), fmt(end)),
        )
        .with_note("the two radii may differ by at most 1%; check the centre (I/J/K are relative to the start)"),
        ArcError::ZeroRadius => error("arc with zero radius", span, "the centre is the start point"),
    }
    };
    let center: Point = match geometry {
        ArcGeometry::Radius(r) => {
            geometry::center_from_radius(s, e, r, plane, clockwise).map_err(arc_error)?
        }
        ArcGeometry::Center(c) => {
            let mut center = s;
            center[a] += c.get(a).unwrap_or(0.0);
            center[b] += c.get(b).unwrap_or(0.0);
            geometry::check_center(s, e, center, plane).map_err(arc_error)?;
            center
        }
    };
    let mut rel = Axes::default();
    rel.set(a, Some(center[a] - s[a]));
    rel.set(b, Some(center[b] - s[b]));
    Ok(rel)
}

fn fmt(v: f64) -> String {
    let mut s = String::new();
    crate::emit::push_fixed(&mut s, v, 4);
    s
}
