//! The corner between two moves of the plane (lines or arcs) worked out as
//! `,R`/`,C` say: where the first move now ends, where the second now
//! starts, and the round's centre. Plain geometry on points of the plane:
//! it must not know statements or spans (the pass attaches them).
//!
//! A round is the arc of radius r tangent to both moves on the side the
//! path turns to (inside the corner); where two such arcs exist (a line or
//! an arc meeting an arc), the one nearest the corner. A chamfer's legs are
//! c along a line and, on an arc, the chord c from the corner (Fanuc's
//! and most controls' reading; docs/decisions.md, "Corners").

use crate::ir::Corner;
use std::f64::consts::TAU;

pub(super) type P2 = [f64; 2];

/// Ends of moves closer than this (relative to their size) are the same
/// point, and a corner's sine under it is no corner.
pub(super) const EPSILON: f64 = 1e-9;

/// A move of the plane as a corner sees it; the corner is at the first
/// move's `to`, the second's `from`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Element {
    Line {
        from: P2,
        to: P2,
    },
    /// An arc about `centre` (absolute); its radius is taken at the corner.
    Arc {
        from: P2,
        to: P2,
        centre: P2,
        ccw: bool,
    },
}

/// A corner worked out: the first move ends at `start`, the corner goes
/// from there to `end` (round: about `centre`, relative to `start`).
#[derive(Debug, PartialEq)]
pub(super) struct Cut {
    pub start: P2,
    pub end: P2,
    pub round: Option<Round>,
}

#[derive(Debug, PartialEq)]
pub(super) struct Round {
    pub centre: P2,
    pub counter_clockwise: bool,
}

/// Why a corner cannot be cut, before the next move's span is known.
#[derive(Debug, PartialEq)]
pub(super) enum CutError {
    /// The corner takes `need` of a move only `room` long (along it).
    TooShort { need: f64, room: f64 },
    /// Two lines in line.
    InLine,
    /// A move meeting an arc tangent (or turning straight back).
    Tangent,
    /// No arc of the round's radius touches both moves; no point of an arc
    /// is the chamfer's length from the corner.
    NoCut,
}

/// The corner between `a` and `b`, cut as `corner` says.
pub(super) fn corner_cut(a: Element, b: Element, corner: Corner) -> Result<Cut, CutError> {
    match (a, b) {
        (Element::Line { from, to: at }, Element::Line { to, .. }) => {
            line_cut(from, at, to, corner)
        }
        _ => curved_cut(a, b, corner),
    }
}

/// The corner at `at` between the line from `from` and the line to `to`,
/// cut as `corner` says. The round's arc is tangent to both moves: it
/// starts and ends `r·tan(θ/2)` from the corner, θ the angle the path
/// turns by; the chamfer's legs are `c` along each move.
fn line_cut(from: P2, at: P2, to: P2, corner: Corner) -> Result<Cut, CutError> {
    let a = [at[0] - from[0], at[1] - from[1]];
    let b = [to[0] - at[0], to[1] - at[1]];
    let (la, lb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
    let room = la.min(lb);
    let size = match corner {
        Corner::Round(r) | Corner::Chamfer(r) => r,
    };
    if room <= EPSILON * la.max(lb) {
        return Err(CutError::TooShort { need: size, room });
    }
    let (d1, d2) = ([a[0] / la, a[1] / la], [b[0] / lb, b[1] / lb]);
    let sine = d1[0] * d2[1] - d1[1] * d2[0];
    let cosine = d1[0] * d2[0] + d1[1] * d2[1];
    if sine.abs() <= EPSILON {
        return Err(CutError::InLine);
    }
    let need = match corner {
        // tan(θ/2) = sin θ / (1 + cos θ)
        Corner::Round(r) => r * sine.abs() / (1.0 + cosine),
        Corner::Chamfer(c) => c,
    };
    if need > room * (1.0 + EPSILON) {
        return Err(CutError::TooShort { need, room });
    }
    let need = need.min(room);
    let start = [at[0] - d1[0] * need, at[1] - d1[1] * need];
    let end = [at[0] + d2[0] * need, at[1] + d2[1] * need];
    let round = match corner {
        Corner::Round(r) => {
            let counter_clockwise = sine > 0.0;
            // The centre is r to the side the path turns to.
            let side = if counter_clockwise { 1.0 } else { -1.0 };
            Some(Round {
                centre: [-d1[1] * r * side, d1[0] * r * side],
                counter_clockwise,
            })
        }
        Corner::Chamfer(_) => None,
    };
    Ok(Cut { start, end, round })
}

/// Which end of a move the corner is at: the first move's end, or the
/// second's start.
#[derive(Clone, Copy, PartialEq)]
enum End {
    Last,
    First,
}

/// A move seen from the corner: its direction there, how far it goes
/// from the corner (along it), and the points at a distance along it.
struct Side {
    element: Element,
    end: End,
    corner: P2,
    /// The arc's radius at the corner (0 for a line).
    radius: f64,
    /// Its length, from its other end to the corner.
    length: f64,
}

impl Side {
    fn new(element: Element, end: End) -> Side {
        let at = |from: P2, to: P2| match end {
            End::Last => to,
            End::First => from,
        };
        let (corner, radius, length) = match element {
            Element::Line { from, to } => (at(from, to), 0.0, dist(from, to)),
            Element::Arc {
                from,
                to,
                centre,
                ccw,
            } => {
                let r = dist(at(from, to), centre);
                (at(from, to), r, r * sweep(from, to, centre, ccw))
            }
        };
        Side {
            element,
            end,
            corner,
            radius,
            length,
        }
    }

    /// The unit direction of travel at point `p` of the move.
    fn direction_at(&self, p: P2) -> P2 {
        match self.element {
            Element::Line { from, to } => unit(sub(to, from)),
            Element::Arc { centre, ccw, .. } => {
                let n = unit(sub(p, centre));
                if ccw {
                    [-n[1], n[0]]
                } else {
                    [n[1], -n[0]]
                }
            }
        }
    }

    /// How far point `p` of the move is from the corner, along the move
    /// (negative: a line's point beyond the corner).
    fn along(&self, p: P2) -> f64 {
        match self.element {
            Element::Line { .. } => {
                let d = self.direction_at(p);
                match self.end {
                    End::Last => dot(sub(self.corner, p), d),
                    End::First => dot(sub(p, self.corner), d),
                }
            }
            Element::Arc { centre, ccw, .. } => {
                let (from, to) = match self.end {
                    End::Last => (p, self.corner),
                    End::First => (self.corner, p),
                };
                self.radius * turned(from, to, centre, ccw)
            }
        }
    }

    /// The point of the move `chord` in a straight line from the corner
    /// (along a line, the length along it), if there is one.
    fn at_chord(&self, chord: f64) -> Option<P2> {
        let back = if self.end == End::Last { -1.0 } else { 1.0 };
        match self.element {
            Element::Line { .. } => {
                let d = self.direction_at(self.corner);
                Some([
                    self.corner[0] + back * chord * d[0],
                    self.corner[1] + back * chord * d[1],
                ])
            }
            Element::Arc { centre, ccw, .. } => {
                if chord > 2.0 * self.radius {
                    return None;
                }
                let angle = 2.0 * (chord / (2.0 * self.radius)).min(1.0).asin();
                let turn = if ccw { 1.0 } else { -1.0 };
                Some(rotate(self.corner, centre, back * turn * angle))
            }
        }
    }

    /// The curve `offset` to the left of the move (negative: the right),
    /// on which a round's centre lies: a line, or a circle about the arc's
    /// centre (`None` when it shrinks to a point).
    fn offset(&self, offset: f64) -> Option<Offset> {
        match self.element {
            Element::Line { from, to } => {
                let d = unit(sub(to, from));
                let n = [-d[1], d[0]];
                let through = [from[0] + offset * n[0], from[1] + offset * n[1]];
                Some(Offset::Line { through, d })
            }
            Element::Arc { centre, ccw, .. } => {
                // The left of a counter-clockwise arc is towards its centre.
                let radius = if ccw {
                    self.radius - offset
                } else {
                    self.radius + offset
                };
                (radius.abs() > EPSILON * self.radius).then_some(Offset::Circle { centre, radius })
            }
        }
    }

    /// The point of the move nearest `c`, where a circle about `c` that
    /// lies on the offset (the circle's radius from the move) touches it.
    fn touching(&self, c: P2, offset: &Offset) -> P2 {
        match (self.element, offset) {
            (Element::Arc { centre, .. }, Offset::Circle { radius, .. }) => {
                let n = unit(sub(c, centre));
                let k = self.radius * radius.signum();
                [centre[0] + k * n[0], centre[1] + k * n[1]]
            }
            _ => {
                let d = self.direction_at(self.corner);
                let t = dot(sub(c, self.corner), d);
                [self.corner[0] + t * d[0], self.corner[1] + t * d[1]]
            }
        }
    }

    /// A cut `need` from the corner leaves something of the move: all of
    /// it may go on a line (the line is left out), not on an arc (what is
    /// left would be a full circle).
    fn check_room(&self, need: f64) -> Result<(), CutError> {
        let room = self.length;
        let fits = match self.element {
            Element::Line { .. } => need <= room * (1.0 + EPSILON),
            Element::Arc { .. } => need < room * (1.0 - EPSILON),
        };
        match fits && need >= -EPSILON * room.max(self.radius) {
            true => Ok(()),
            false => Err(CutError::TooShort { need, room }),
        }
    }
}

/// A curve a round's centre lies on.
enum Offset {
    Line { through: P2, d: P2 },
    Circle { centre: P2, radius: f64 },
}

/// A corner with at least one arc: the round's centre is where the two
/// moves' offsets by r (to the side the path turns to) meet, nearest the
/// corner; the chamfer's ends are the chord c from it on each move.
fn curved_cut(a: Element, b: Element, corner: Corner) -> Result<Cut, CutError> {
    let (a, b) = (Side::new(a, End::Last), Side::new(b, End::First));
    let at = a.corner;
    let (d1, d2) = (a.direction_at(at), b.direction_at(at));
    let sine = cross(d1, d2);
    if sine.abs() <= EPSILON || a.length <= 0.0 || b.length <= 0.0 {
        return Err(CutError::Tangent);
    }
    match corner {
        Corner::Chamfer(c) => {
            let (Some(start), Some(end)) = (a.at_chord(c), b.at_chord(c)) else {
                return Err(CutError::NoCut);
            };
            a.check_room(a.along(start))?;
            b.check_room(b.along(end))?;
            Ok(Cut {
                start,
                end,
                round: None,
            })
        }
        Corner::Round(r) => {
            let side = sine.signum();
            let (Some(oa), Some(ob)) = (a.offset(side * r), b.offset(side * r)) else {
                return Err(CutError::NoCut);
            };
            let scale = r.max(a.radius).max(b.radius);
            // The nearest round that fits; else why the nearest does not.
            let mut fits: Option<(f64, P2, P2, P2)> = None;
            let mut nearest: Option<(f64, CutError)> = None;
            for c in meet(&oa, &ob, scale) {
                let (start, end) = (a.touching(c, &oa), b.touching(c, &ob));
                let (s1, s2) = (a.along(start), b.along(end));
                match a.check_room(s1).and_then(|_| b.check_room(s2)) {
                    Ok(()) if fits.is_none_or(|(t, ..)| s1 + s2 < t) => {
                        fits = Some((s1 + s2, start, end, c));
                    }
                    Ok(()) => {}
                    Err(e)
                        if nearest
                            .as_ref()
                            .is_none_or(|(t, _)| s1.abs() + s2.abs() < *t) =>
                    {
                        nearest = Some((s1.abs() + s2.abs(), e));
                    }
                    Err(_) => {}
                }
            }
            let Some((_, start, end, c)) = fits else {
                return Err(nearest.map_or(CutError::NoCut, |(_, e)| e));
            };
            Ok(Cut {
                start,
                end,
                round: Some(Round {
                    centre: sub(c, start),
                    counter_clockwise: side > 0.0,
                }),
            })
        }
    }
}

/// Where two offsets meet (two lines are the line-to-line corner's,
/// never here); `scale`, the size tangency is judged against.
fn meet(a: &Offset, b: &Offset, scale: f64) -> Vec<P2> {
    match (a, b) {
        (Offset::Line { through, d }, Offset::Circle { centre, radius })
        | (Offset::Circle { centre, radius }, Offset::Line { through, d }) => {
            // |through + t·d − centre| = |radius|
            let w = sub(*through, *centre);
            let half_b = dot(w, *d);
            let disc = half_b * half_b - (dot(w, w) - radius * radius);
            roots(disc, scale)
                .into_iter()
                .map(|s| {
                    let t = -half_b + s;
                    [through[0] + t * d[0], through[1] + t * d[1]]
                })
                .collect()
        }
        (
            Offset::Circle {
                centre: c1,
                radius: r1,
            },
            Offset::Circle {
                centre: c2,
                radius: r2,
            },
        ) => {
            let (r1, r2) = (r1.abs(), r2.abs());
            let apart = dist(*c1, *c2);
            if apart <= EPSILON * scale {
                return Vec::new();
            }
            let e = unit(sub(*c2, *c1));
            let along = (r1 * r1 - r2 * r2 + apart * apart) / (2.0 * apart);
            roots(r1 * r1 - along * along, scale)
                .into_iter()
                .map(|h| {
                    [
                        c1[0] + along * e[0] - h * e[1],
                        c1[1] + along * e[1] + h * e[0],
                    ]
                })
                .collect()
        }
        (Offset::Line { .. }, Offset::Line { .. }) => Vec::new(),
    }
}

/// ±√disc: none when disc is negative beyond rounding, one when it is
/// (within rounding) zero.
fn roots(disc: f64, scale: f64) -> Vec<f64> {
    let tolerance = EPSILON * scale * scale;
    if disc < -tolerance {
        Vec::new()
    } else if disc <= tolerance {
        vec![0.0]
    } else {
        vec![disc.sqrt(), -disc.sqrt()]
    }
}

/// The angle the arc about `centre` turns through from `from` to `to`, in
/// its direction, in [0, 2π).
fn turned(from: P2, to: P2, centre: P2, ccw: bool) -> f64 {
    let a0 = (from[1] - centre[1]).atan2(from[0] - centre[0]);
    let a1 = (to[1] - centre[1]).atan2(to[0] - centre[0]);
    let d = if ccw { a1 - a0 } else { a0 - a1 };
    d.rem_euclid(TAU)
}

/// An arc's sweep: as [`turned`], but a full turn where the ends meet
/// (geometry::sweep's rule, which rs274 follows).
fn sweep(from: P2, to: P2, centre: P2, ccw: bool) -> f64 {
    let d = turned(from, to, centre, ccw);
    if d < 1e-9 {
        TAU
    } else {
        d
    }
}

fn rotate(p: P2, about: P2, angle: f64) -> P2 {
    let (s, c) = angle.sin_cos();
    let v = sub(p, about);
    [
        about[0] + v[0] * c - v[1] * s,
        about[1] + v[0] * s + v[1] * c,
    ]
}

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dist(a: P2, b: P2) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn unit(v: P2) -> P2 {
    let l = v[0].hypot(v[1]);
    [v[0] / l, v[1] / l]
}

#[cfg(test)]
mod tests;
