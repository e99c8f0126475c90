//! Travel limits (SPEC §9): each move of the lowered program checked
//! against the machine's travel (`[machine.x] min`/`max`, machine
//! coordinates). Where the machine position is known (a G53 move, or a
//! work offset the program sets with `G10 L2`) a move past the travel is
//! an error at its line naming the axis and by how much; where it is not
//! (G54's origin is the machine's, set at the machine), one warning says
//! where that origin must lie for the program to fit. Arcs count with
//! their bulge, not only their ends; G28/G30 with their intermediate
//! point.
//!
//! Architecture Invariant: reads lowered IR statements (absolute, one
//! unit, G54's frame) and the travel; prints nothing, touches no file.

use crate::diagnostic::{error, warning, Diagnostic};
use crate::geometry;
use crate::ir::{ArcGeometry, Axes, Axis, Op, Plane, Stmt, Units};
use crate::source::Span;

/// Each of X, Y, Z's travel in machine coordinates, mm: `(min, max)`.
pub type Travel = [Option<(f64, f64)>; 3];

/// A side of the travel an axis went past.
#[derive(Clone, Copy, Debug)]
struct Past {
    first: Span,
    last: Span,
    /// The most it went past by, mm.
    by: f64,
    moves: usize,
}

/// The check, fed the lowered program's statements in order.
#[derive(Clone, Debug)]
pub struct TravelCheck {
    travel: Travel,
    to_mm: f64,
    plane: Plane,
    /// X Y Z in the program's frame, output units.
    position: [Option<f64>; 3],
    /// The origin of each work offset (1..=9: G54 … G59.3) in machine
    /// coordinates, mm, where the program set it.
    origins: [[Option<f64>; 3]; 10],
    active: usize,
    /// Axes shifted by what only the machine knows (G92, G52 or a tool
    /// length passed through).
    shifted: [bool; 3],
    /// Per axis: below `min`, above `max`.
    past: [[Option<Past>; 2]; 3],
    /// The first move whose machine position is unknown, and the range of
    /// each axis over such moves (mm, the program's frame).
    unchecked: Option<Span>,
    range: [Option<(f64, f64)>; 3],
}

impl TravelCheck {
    /// `units`: the output units (the IR's lengths).
    pub fn new(travel: Travel, units: Option<Units>) -> TravelCheck {
        TravelCheck {
            travel,
            to_mm: Units::mm_per(units),
            plane: Plane::XY,
            position: [None; 3],
            origins: [[None; 3]; 10],
            active: 1,
            shifted: [false; 3],
            past: [[None; 2]; 3],
            unchecked: None,
            range: [None; 3],
        }
    }

    pub fn feed(&mut self, stmt: &Stmt) {
        let k = self.to_mm;
        match &stmt.op {
            Op::Move(m) => {
                let start = self.position;
                for (axis, v) in m.to.iter().filter(|(a, _)| a.index() < 3) {
                    self.position[axis.index()] = Some(v);
                }
                self.at(self.position, stmt.span);
                if let Some(arc) = &m.arc {
                    if let ArcGeometry::Center(c) = arc.geometry {
                        let clockwise = m.motion == crate::ir::Motion::ArcCw;
                        for p in self.bulge(start, c, clockwise, arc.turns) {
                            self.at(p, stmt.span);
                        }
                    }
                }
                return;
            }
            Op::IncrementalMove(m) => {
                for (axis, v) in m.to.iter().filter(|(a, _)| a.index() < 3) {
                    let p = &mut self.position[axis.index()];
                    *p = p.map(|p| p + v);
                }
                self.at(self.position, stmt.span);
            }
            Op::MachineMove(m) => {
                for (axis, v) in m.to.iter().filter(|(a, _)| a.index() < 3) {
                    self.check(axis.index(), v * k, stmt.span);
                }
            }
            Op::Home {
                via, incremental, ..
            } => self.via(via, *incremental, stmt.span),
            Op::Units(u) => self.to_mm = u.factor(Units::Mm),
            Op::Plane(p) => self.plane = *p,
            Op::SetWorkOffset { index, origin } => {
                let table = self.table(*index);
                for (axis, v) in origin.iter().filter(|(a, _)| a.index() < 3) {
                    self.origins[table][axis.index()] = Some(v * k);
                }
            }
            Op::SetWorkOffsetHere { index, .. } => self.origins[self.table(*index)] = [None; 3],
            Op::SelectWorkOffset(index) => self.active = self.table(*index),
            Op::LocalOffset(a) | Op::SetPosition(a) => {
                for i in 0..3 {
                    self.shifted[i] |= a.is_empty() || a.has(Axis::ALL[i]);
                }
            }
            Op::ToolLength { .. } => self.shifted[2] = true,
            Op::CancelToolLength => self.shifted[2] = false,
            _ => {}
        }
        let lost = stmt.op.unknown_after();
        for (i, p) in self.position.iter_mut().enumerate() {
            if lost(Axis::ALL[i]) {
                *p = None;
            }
        }
    }

    /// G28/G30's intermediate point, where the machine goes first (grbl
    /// and LinuxCNC, in the program's frame): checked as a move's end, on
    /// the axes it names. The home itself is the machine's own, and after
    /// it those axes are unknown (`unknown_after`).
    fn via(&mut self, via: &Axes, incremental: bool, span: Span) {
        let mut point = [None; 3];
        for (axis, v) in via.iter().filter(|(a, _)| a.index() < 3) {
            let i = axis.index();
            point[i] = match incremental {
                true => self.position[i].map(|p| p + v),
                false => Some(v),
            };
        }
        self.at(point, span);
    }

    /// The table of work offset `index` (0: the active one).
    fn table(&self, index: u8) -> usize {
        match index as usize {
            0 => self.active,
            i => i.min(9),
        }
    }

    /// The points where an arc from `start` about `start + center` to
    /// the position is furthest along an axis of its plane, within its
    /// sweep. It needs only its plane's two axes known at both ends (a
    /// laser's program may never set Z); an axis not known stays out of
    /// the points, as it does for a line.
    fn bulge(
        &self,
        start: [Option<f64>; 3],
        center: [Option<f64>; 3],
        clockwise: bool,
        turns: u32,
    ) -> Vec<[Option<f64>; 3]> {
        let (p, q, _) = self.plane.axes();
        let end = self.position;
        let (Some(sp), Some(sq), Some(ep), Some(eq)) = (start[p], start[q], end[p], end[q]) else {
            return Vec::new();
        };
        let (cp, cq) = (sp + center[p].unwrap_or(0.0), sq + center[q].unwrap_or(0.0));
        let a0 = (sq - cq).atan2(sp - cp);
        let sweep = geometry::sweep_between(a0, (eq - cq).atan2(ep - cp), clockwise, turns);
        let r0 = (sp - cp).hypot(sq - cq);
        let r1 = (ep - cp).hypot(eq - cq);
        // At the radius it has there: a spiral's goes from the start's to
        // the end's as it turns.
        let mut points = Vec::new();
        geometry::axis_shares(a0, sweep, |t, [u, v]| {
            let r = r0 + (r1 - r0) * t;
            let mut point = start;
            point[p] = Some(cp + r * u);
            point[q] = Some(cq + r * v);
            points.push(point);
        });
        points
    }

    /// A point of the path, in the program's frame.
    fn at(&mut self, point: [Option<f64>; 3], span: Span) {
        for (i, v) in point.iter().enumerate() {
            let (Some(v), Some(_)) = (v, self.travel[i]) else {
                continue;
            };
            let v = v * self.to_mm;
            match self.origins[self.active][i].filter(|_| !self.shifted[i]) {
                Some(origin) => self.check(i, origin + v, span),
                None => {
                    self.unchecked.get_or_insert(span);
                    let (lo, hi) = self.range[i].get_or_insert((v, v));
                    (*lo, *hi) = (lo.min(v), hi.max(v));
                }
            }
        }
    }

    /// Axis `i` at machine coordinate `v` (mm).
    fn check(&mut self, i: usize, v: f64, span: Span) {
        let Some((min, max)) = self.travel[i] else {
            return;
        };
        // A hair past is the printed grid's rounding, not a crash.
        let slack = 1e-6;
        let (side, by) = match v {
            _ if v < min - slack => (0, min - v),
            _ if v > max + slack => (1, v - max),
            _ => return,
        };
        let past = self.past[i][side].get_or_insert(Past {
            first: span,
            last: span,
            by,
            moves: 1,
        });
        past.by = past.by.max(by);
        if past.last != span {
            (past.last, past.moves) = (span, past.moves + 1);
        }
    }

    /// The errors, and the warning for moves the check could not place.
    pub fn finish(&self) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for (i, sides) in self.past.iter().enumerate() {
            let Some((min, max)) = self.travel[i] else {
                continue;
            };
            for (side, past) in sides.iter().enumerate() {
                let Some(Past {
                    first, by, moves, ..
                }) = *past
                else {
                    continue;
                };
                let axis = Axis::ALL[i].letter() as char;
                let end = if side == 0 {
                    "below its minimum"
                } else {
                    "above its maximum"
                };
                let mut d = error(
                    format!("{axis} leaves the machine's travel by {by:.3} mm"),
                    first,
                    format!("{axis} goes {end} here"),
                )
                .with_note(format!(
                    "ger.toml's [machine.{}] travel is {min} … {max} mm (machine coordinates)",
                    axis.to_ascii_lowercase()
                ));
                if moves > 1 {
                    d = d.with_note(format!(
                        "{moves} moves go past it, the furthest by {by:.3} mm"
                    ));
                }
                out.push(d);
            }
        }
        out.extend(self.unplaced());
        out
    }

    /// The warning for moves in a frame only the machine knows: where its
    /// origin must be for them to stay inside the travel.
    fn unplaced(&self) -> Option<Diagnostic> {
        let first = self.unchecked?;
        let mut fits = Vec::new();
        let mut cannot = Vec::new();
        for i in 0..3 {
            let (Some((min, max)), Some((lo, hi))) = (self.travel[i], self.range[i]) else {
                continue;
            };
            let axis = Axis::ALL[i].letter() as char;
            let (from, to) = (min - lo, max - hi);
            match from <= to {
                true => fits.push(format!("{axis} {from:.3} … {to:.3}")),
                false => cannot.push(format!(
                    "{axis} spans {:.3} mm, {:.3} mm more than its travel",
                    hi - lo,
                    (hi - lo) - (max - min)
                )),
            }
        }
        let d = warning(
            "travel limits checked only where the work offset is known",
            first,
            "the machine position of this move depends on an offset set at the machine",
        );
        Some(match cannot.is_empty() {
            true => d.with_note(format!(
                "the program stays inside the travel if the work offset's origin is within {} mm (machine coordinates)",
                fits.join(", ")
            )),
            false => d.with_note(format!(
                "the program cannot fit the travel wherever the offset is: {}",
                cannot.join("; ")
            )),
        })
    }
}
