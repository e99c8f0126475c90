//! Pass polar (SPEC §4.3): G16/G15 with Fanuc semantics. In the active
//! plane the first axis word is the radius and the second the angle in
//! degrees, counter-clockwise from the first axis. Under G90 the pole is
//! the program zero (the result is an absolute program point); under G91
//! it is the current position (the result is an incremental move). A word
//! left out keeps the last radius or angle of this G16 block; the first
//! polar move must give both. Changing offsets under G16 is an error.

use super::Errors;
use crate::diagnostic::{error, DiagnosticExt};
use crate::ir::{self, Op, Plane};
use crate::source::Span;

pub struct State {
    plane: Plane,
    /// Some((radius, angle)) while G16 is on; the values are the last given.
    polar: Option<(Option<f64>, Option<f64>)>,
    entered: Option<Span>,
    pub errors: Errors,
}

impl State {
    pub fn new() -> State {
        State {
            plane: Plane::XY,
            polar: None,
            entered: None,
            errors: Errors::default(),
        }
    }

    pub fn run(&mut self, stmts: &mut Vec<ir::Stmt>) {
        let State {
            plane,
            polar,
            entered,
            errors,
        } = self;
        stmts.retain_mut(|stmt| {
            match &mut stmt.op {
                Op::Polar(on) => {
                    if *on {
                        if polar.is_none() {
                            *entered = Some(stmt.span);
                        }
                        polar.get_or_insert((None, None));
                    } else {
                        *polar = None;
                    }
                    return false;
                }
                Op::Plane(p) => {
                    if polar.is_some() && *p != *plane {
                        errors.push(
                            error(
                                "plane changed under G16",
                                stmt.span,
                                "polar coordinates are on",
                            )
                            .with_help("cancel polar coordinates with G15 first"),
                        );
                    }
                    *plane = *p;
                }
                op if polar.is_some() && changes_offsets(op) => {
                    let mut d = error(
                        "offsets changed under G16",
                        stmt.span,
                        "polar coordinates are on here",
                    )
                    .with_help("cancel polar coordinates with G15 before changing offsets");
                    if let Some(at) = *entered {
                        d = d.with_secondary(at, "G16 is on from here");
                    }
                    errors.push(d);
                }
                Op::Move(m) => {
                    if let Some((radius, angle)) = polar {
                        let (a, b, _) = plane.axes();
                        if let Some(r) = m.to.get(a) {
                            *radius = Some(r);
                        }
                        if let Some(t) = m.to.get(b) {
                            *angle = Some(t);
                        }
                        let touches_plane = m.to.get(a).is_some() || m.to.get(b).is_some();
                        if touches_plane {
                            match (*radius, *angle) {
                                (Some(r), Some(t)) => {
                                    let t = t.to_radians();
                                    m.to.set(a, Some(r * t.cos()));
                                    m.to.set(b, Some(r * t.sin()));
                                }
                                _ => errors.push(
                                    error(
                                        "polar move without radius and angle",
                                        stmt.span,
                                        "the first move under G16 needs both",
                                    )
                                    .with_note(polar_words(*plane)),
                                ),
                            }
                        }
                    }
                }
                _ => {}
            }
            true
        });
    }
}

fn polar_words(plane: Plane) -> &'static str {
    match plane {
        Plane::XY => "in G17 the X word is the radius and Y the angle (degrees from +X)",
        Plane::ZX => "in G18 the Z word is the radius and X the angle (degrees from +Z)",
        Plane::YZ => "in G19 the Y word is the radius and Z the angle (degrees from +Y)",
    }
}

/// Statements that enter or leave an offset (SPEC §4.2).
pub(super) fn changes_offsets(op: &Op) -> bool {
    matches!(
        op,
        Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::CancelPosition
            | Op::ToolLength { .. }
            | Op::CancelToolLength
    )
}
