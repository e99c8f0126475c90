//! Pass units (SPEC §4.1): every length in the output units; G20/G21 are
//! removed. Feeds are converted when they are given, so a feed set before a
//! unit switch keeps its machine value, as on LinuxCNC. The program starts
//! in the output units. Tool and offset tables are already in them (§3).
//! Under G16 the angle word is left alone: it is in degrees.

use crate::ir::{self, ArcGeometry, Op, Units};

pub struct State {
    output: Units,
    current: Units,
    /// Under G16 the plane's second axis word is an angle, not a length.
    polar: bool,
    plane: ir::Plane,
}

impl State {
    pub fn new(output: Units) -> State {
        State {
            output,
            current: output,
            polar: false,
            plane: ir::Plane::XY,
        }
    }

    pub fn run(&mut self, stmts: &mut Vec<ir::Stmt>) {
        stmts.retain_mut(|stmt| {
            let k = self.current.factor(self.output);
            match &mut stmt.op {
                Op::Units(u) => {
                    self.current = *u;
                    return false;
                }
                Op::Polar(on) => self.polar = *on,
                Op::Plane(p) => self.plane = *p,
                _ if k == 1.0 => {}
                Op::Move(m) => {
                    let angle = self
                        .polar
                        .then(|| self.plane.axes().1)
                        .and_then(|b| m.to.get(b).map(|v| (b, v)));
                    m.to = m.to.map(|v| v * k);
                    if let Some((axis, degrees)) = angle {
                        m.to.set(axis, Some(degrees));
                    }
                    if let Some(arc) = &mut m.arc {
                        arc.geometry = match arc.geometry {
                            ArcGeometry::Center(c) => ArcGeometry::Center(c.map(|v| v * k)),
                            ArcGeometry::Radius(r) => ArcGeometry::Radius(r * k),
                        };
                    }
                }
                Op::Feed(f) => *f *= k,
                Op::SetWorkOffset { origin: a, .. }
                | Op::SetWorkOffsetHere { at: a, .. }
                | Op::LocalOffset(a)
                | Op::SetPosition(a) => *a = a.map(|v| v * k),
                _ => {}
            }
            true
        });
    }
}
