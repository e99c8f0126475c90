//! The cutters the picture knows (SPEC §7) and the one question the
//! simulation asks of them: over a point of the stock, how low does the
//! cutter reach anywhere along one straight or circular move? Answered
//! exactly, in closed form, for every shape: along a line, the height of
//! the cutter's underside over a point is a convex function of the
//! position on the line, so its minimum is the one stationary point, or an
//! end of the stretch where the point is under the cutter.

use crate::ir::{Tool, ToolShape};

/// The underside of a cutter, as a height above its tip at a distance from
/// its axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Profile {
    Flat,
    Ball,
    /// A cone (vee cutters, drill points): `rise` is the height gained per
    /// unit of distance from the axis, 1/tan(half the included angle).
    Cone {
        rise: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    pub radius: f64,
    pub profile: Profile,
}

/// A drill's point angle (SPEC §7).
const DRILL_POINT_DEGREES: f64 = 118.0;

impl Cutter {
    /// The cutter of a tool table entry, its lengths times `scale`.
    pub fn of(tool: &Tool, scale: f64) -> Cutter {
        let cone = |included: f64| Profile::Cone {
            rise: 1.0 / (included.to_radians() / 2.0).tan(),
        };
        Cutter {
            radius: tool.diameter * scale / 2.0,
            profile: match tool.shape {
                ToolShape::Flat => Profile::Flat,
                ToolShape::Ball => Profile::Ball,
                ToolShape::Drill => cone(DRILL_POINT_DEGREES),
                ToolShape::Vee(angle) => cone(angle),
            },
        }
    }

    /// The height of the underside above the tip at distance `d` (at most
    /// the radius) from the axis.
    pub fn lift(&self, d: f64) -> f64 {
        let r = self.radius;
        match self.profile {
            Profile::Flat => 0.0,
            Profile::Ball => r - (r * r - d * d).max(0.0).sqrt(),
            Profile::Cone { rise } => rise * d,
        }
    }

    /// The lowest the cutter reaches over `(x, y)` while its tip runs
    /// along the level arc `arc`.
    pub fn lowest_on_arc(&self, arc: &Arc, x: f64, y: f64) -> Option<f64> {
        let d = arc.distance(x, y);
        (d <= self.radius).then(|| arc.z + self.lift(d))
    }
}

/// A straight move of the tip from `a`, by `v` in the plane and `dz`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub a: [f64; 3],
    pub v: [f64; 2],
    pub dz: f64,
    /// |v|.
    pub length: f64,
}

impl Line {
    pub fn new(a: [f64; 3], b: [f64; 3]) -> Line {
        let v = [b[0] - a[0], b[1] - a[1]];
        Line {
            a,
            v,
            dz: b[2] - a[2],
            length: v[0].hypot(v[1]),
        }
    }

    pub fn end(&self) -> [f64; 3] {
        [
            self.a[0] + self.v[0],
            self.a[1] + self.v[1],
            self.a[2] + self.dz,
        ]
    }
}

/// An x interval `(from, to)` on a row.
pub type Interval = (f64, f64);

/// A cutter running along a line, with what every cell asks of it worked
/// out once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSweep {
    pub cutter: Cutter,
    pub line: Line,
    r2: f64,
    inv_length: f64,
    /// Height per unit of travel in the plane.
    slope: f64,
    /// Where along the line the underside is lowest, before clamping: per
    /// unit of `reach` for a ball, of the distance from the line for a
    /// cone; `None` for a cone steeper than its side.
    stationary: Option<f64>,
    /// sqrt(1 + slope²).
    incline: f64,
    /// For a cone, the rise of its lowest point per unit of distance from
    /// the line: slope*k + rise*sqrt(1 + k²).
    cone_side: f64,
    /// The end of the line.
    b: [f64; 3],
    /// The band's long edges (the line offset by the radius both ways);
    /// its short ends lie inside the discs at the ends.
    corners: [(f64, f64); 4],
    /// Lowest tip height, and the path's extent in y.
    pub z_min: f64,
    y_min: f64,
    y_max: f64,
}

impl LineSweep {
    pub fn new(cutter: Cutter, line: Line) -> LineSweep {
        let r = cutter.radius;
        let b = line.end();
        let (inv_length, slope) = if line.length > 1e-12 {
            (1.0 / line.length, line.dz / line.length)
        } else {
            (0.0, 0.0)
        };
        let stationary = match cutter.profile {
            Profile::Flat => Some(0.0),
            // slope*u - sqrt(rho² - u²) is least at u = -slope*rho/sqrt(1+slope²).
            Profile::Ball => Some(-slope / (1.0 + slope * slope).sqrt()),
            // slope*u + rise*sqrt(h² + u²) is least at u = -slope*h/sqrt(rise²-slope²),
            // when the line is shallower than the cone's side.
            Profile::Cone { rise } => {
                (slope.abs() < rise).then(|| -slope / (rise * rise - slope * slope).sqrt())
            }
        };
        let (nx, ny) = (-line.v[1] * inv_length * r, line.v[0] * inv_length * r);
        let cone_side = match (cutter.profile, stationary) {
            (Profile::Cone { rise }, Some(k)) => slope * k + rise * (1.0 + k * k).sqrt(),
            _ => 0.0,
        };
        LineSweep {
            cutter,
            line,
            r2: r * r,
            inv_length,
            slope,
            stationary,
            incline: (1.0 + slope * slope).sqrt(),
            cone_side,
            b,
            corners: [
                (line.a[0] + nx, line.a[1] + ny),
                (b[0] + nx, b[1] + ny),
                (b[0] - nx, b[1] - ny),
                (line.a[0] - nx, line.a[1] - ny),
            ],
            z_min: line.a[2].min(b[2]),
            y_min: line.a[1].min(b[1]),
            y_max: line.a[1].max(b[1]),
        }
    }

    /// The lowest the cutter reaches over the point `(x, y)`; `None` when
    /// the point is never under it, or when another sweep carves it:
    /// - `start_carved`: the sweep before this one ended where this starts,
    ///   with this cutter, and the lowest is at the start: that sweep
    ///   reached it already;
    /// - `next`: a ball sweep that starts where this one ends, with this
    ///   cutter, and the lowest here is at the end, but there it is not at
    ///   its start: it reaches lower (it passes through this end).
    #[inline]
    pub fn lowest(
        &self,
        x: f64,
        y: f64,
        start_carved: bool,
        next: Option<&LineSweep>,
    ) -> Option<f64> {
        let line = &self.line;
        let (wx, wy) = (x - line.a[0], y - line.a[1]);
        let w2 = wx * wx + wy * wy;
        if self.inv_length == 0.0 {
            // A plunge: the point stays at one distance from the axis.
            return (w2 <= self.r2).then(|| self.z_min + self.cutter.lift(w2.sqrt()));
        }
        // Along the line, u is the signed distance (in the plane) from the
        // point's foot, from -along at the start to length - along at the
        // end; the point is under the cutter for |u| <= reach.
        let along = (wx * line.v[0] + wy * line.v[1]) * self.inv_length;
        let h2 = (w2 - along * along).max(0.0);
        let reach2 = self.r2 - h2;
        let (start, end) = (-along, line.length - along);
        if reach2 < 0.0
            || (start > 0.0 && start * start > reach2)
            || (end < 0.0 && end * end > reach2)
        {
            return None;
        }
        let slope = self.slope;
        let radius = self.cutter.radius;
        if let (Profile::Ball, Some(k)) = (self.cutter.profile, self.stationary) {
            // The lowest is at u = k*reach (|k| < 1, so within reach),
            // clamped to the ends; placed without a square root.
            return if at_most(k, reach2, start) {
                // At the start: where the cutter stood, with the start disc.
                (!start_carved).then(|| line.a[2] + radius - (self.r2 - w2).max(0.0).sqrt())
            } else if !at_most(k, reach2, end) {
                if next.is_some_and(|n| !n.ball_lowest_at_start(x, y)) {
                    return None;
                }
                let (bx, by) = (wx - line.v[0], wy - line.v[1]);
                Some(self.b[2] + radius - (self.r2 - bx * bx - by * by).max(0.0).sqrt())
            } else {
                // On the capsule: r - reach*sqrt(1 + slope²) above the foot.
                Some(line.a[2] + slope * along + radius - reach2.sqrt() * self.incline)
            };
        }
        let reach = reach2.sqrt();
        let (u0, u1) = (start.max(-reach), end.min(reach));
        // The tip's height at u is z_foot + slope * u.
        let z_foot = line.a[2] + slope * along;
        let (u, z) = match (self.cutter.profile, self.stationary) {
            (Profile::Flat, _) => {
                let u = if slope >= 0.0 { u0 } else { u1 };
                (u, z_foot + slope * u)
            }
            (Profile::Cone { rise }, k) => {
                let h = h2.sqrt();
                let u = match k {
                    Some(k) if (u0..=u1).contains(&(k * h)) => {
                        // The cone's side along the line: a fixed rise per h.
                        return Some(z_foot + h * self.cone_side);
                    }
                    Some(k) => (k * h).clamp(u0, u1),
                    None if slope > 0.0 => u0,
                    None => u1,
                };
                (u, z_foot + slope * u + rise * (h2 + u * u).sqrt())
            }
            (Profile::Ball, _) => (u0, z_foot + slope * u0 + radius),
        };
        (!(start_carved && u == start)).then_some(z)
    }

    /// Whether a ball sweep is lowest over `(x, y)` at its start (false for
    /// other cutters, and where it does not reach).
    fn ball_lowest_at_start(&self, x: f64, y: f64) -> bool {
        let (Profile::Ball, Some(k)) = (self.cutter.profile, self.stationary) else {
            return false;
        };
        let line = &self.line;
        let (wx, wy) = (x - line.a[0], y - line.a[1]);
        let along = (wx * line.v[0] + wy * line.v[1]) * self.inv_length;
        let reach2 = self.r2 - (wx * wx + wy * wy - along * along).max(0.0);
        self.inv_length != 0.0 && reach2 >= 0.0 && at_most(k, reach2, -along)
    }

    /// The x interval of the points within the radius of the line (in the
    /// plane) on the row at `y`, `None` if there are none (the set is
    /// convex, so it is the hull of its three parts: the discs at the ends
    /// and the band between them); and on the same row the x interval of
    /// the start disc that a sweep continuing the one before it need not
    /// carve again (see [`LineSweep::start_carved`]).
    #[inline]
    pub fn spans(&self, y: f64) -> Option<(Interval, Option<Interval>)> {
        let r = self.cutter.radius;
        let b = self.b;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        let start =
            chord_half(r, y - self.line.a[1]).map(|w| (self.line.a[0] - w, self.line.a[0] + w));
        if let Some((s0, s1)) = start {
            (lo, hi) = (s0, s1);
        }
        if let Some(w) = chord_half(r, y - b[1]) {
            lo = lo.min(b[0] - w);
            hi = hi.max(b[0] + w);
        }
        if self.inv_length > 0.0 {
            let c = &self.corners;
            for k in [0, 2] {
                if let Some(x) = crossing(c[k], c[k + 1], y) {
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        (lo <= hi).then_some(((lo, hi), start.filter(|_| self.start_carved())))
    }

    /// No point of the row at `y` is cut lower than this.
    pub fn row_floor(&self, y: f64) -> f64 {
        let dy = (self.y_min - y).max(y - self.y_max).max(0.0);
        self.z_min + self.cutter.lift(dy.min(self.cutter.radius))
    }

    /// A flat cutter that does not go down reaches no lower over its start
    /// disc than where it starts: a sweep that continues the one before it
    /// (which ended there) has nothing to carve in that disc.
    fn start_carved(&self) -> bool {
        self.line.dz >= 0.0 && self.cutter.profile == Profile::Flat
    }
}

/// Whether `k * sqrt(q) <= c` (q >= 0), without the square root.
#[inline]
fn at_most(k: f64, q: f64, c: f64) -> bool {
    match (k <= 0.0, c >= 0.0) {
        (true, true) => true,
        (false, true) => k * k * q <= c * c,
        (true, false) => k * k * q >= c * c,
        (false, false) => false,
    }
}

/// Where the edge from `p` to `q` crosses the row at `y`, if it does.
pub fn crossing(p: (f64, f64), q: (f64, f64), y: f64) -> Option<f64> {
    ((p.1 - y) * (q.1 - y) <= 0.0 && p.1 != q.1)
        .then(|| p.0 + (y - p.1) * (q.0 - p.0) / (q.1 - p.1))
}

/// Half the chord a circle of radius `r` cuts on a line `dy` from its
/// centre.
pub fn chord_half(r: f64, dy: f64) -> Option<f64> {
    (dy.abs() <= r).then(|| (r * r - dy * dy).sqrt())
}

/// A level arc of the tip in the XY plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    pub center: [f64; 2],
    pub radius: f64,
    pub z: f64,
    /// Start and end, from the centre, with the arc running
    /// counter-clockwise from `from` to `to` (a clockwise arc is stored
    /// the other way round).
    pub from: [f64; 2],
    pub to: [f64; 2],
    /// The sweep in radians (positive).
    pub sweep: f64,
}

impl Arc {
    /// Whether the direction `(x, y)` from the centre is within the arc.
    fn covers(&self, x: f64, y: f64) -> bool {
        let cross = |a: [f64; 2], bx: f64, by: f64| a[0] * by - a[1] * bx;
        if self.sweep >= std::f64::consts::TAU - 1e-12 {
            true
        } else if self.sweep <= std::f64::consts::PI {
            cross(self.from, x, y) >= 0.0 && -cross(self.to, x, y) >= 0.0
        } else {
            // Outside the complement, which runs from `to` to `from`.
            !(cross(self.to, x, y) > 0.0 && -cross(self.from, x, y) > 0.0)
        }
    }

    /// The distance in the plane from `(x, y)` to the arc.
    pub fn distance(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = (x - self.center[0], y - self.center[1]);
        // Plain square roots: `hypot` guards against overflow at a cost
        // this inner loop cannot pay, and these lengths are small.
        let length = |x: f64, y: f64| (x * x + y * y).sqrt();
        if self.covers(dx, dy) {
            (length(dx, dy) - self.radius).abs()
        } else {
            let (f, t) = (self.from, self.to);
            length(dx - f[0], dy - f[1]).min(length(dx - t[0], dy - t[1]))
        }
    }

    /// The x intervals that hold every point within `r` of the arc on the
    /// row at `y` (they may overlap): the ring around the whole circle,
    /// and the discs at the ends.
    pub fn spans(&self, r: f64, y: f64) -> [Option<(f64, f64)>; 4] {
        let [cx, cy] = self.center;
        let dy = y - cy;
        let mut out = [None; 4];
        if let Some(outer) = chord_half(self.radius + r, dy) {
            match chord_half(self.radius - r, dy).filter(|_| self.radius > r) {
                Some(inner) => {
                    out[0] = Some((cx - outer, cx - inner));
                    out[1] = Some((cx + inner, cx + outer));
                }
                None => out[0] = Some((cx - outer, cx + outer)),
            }
        }
        for (k, end) in [self.from, self.to].into_iter().enumerate() {
            out[2 + k] = chord_half(r, dy - end[1]).map(|w| (cx + end[0] - w, cx + end[0] + w));
        }
        out
    }

    /// Its bounds in the plane: `[min x, min y, max x, max y]`.
    pub fn bounds(&self) -> [f64; 4] {
        let [cx, cy] = self.center;
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut add = |x: f64, y: f64| {
            b[0] = b[0].min(cx + x);
            b[1] = b[1].min(cy + y);
            b[2] = b[2].max(cx + x);
            b[3] = b[3].max(cy + y);
        };
        add(self.from[0], self.from[1]);
        add(self.to[0], self.to[1]);
        let r = self.radius;
        for (x, y) in [(r, 0.0), (0.0, r), (-r, 0.0), (0.0, -r)] {
            if self.covers(x, y) {
                add(x, y);
            }
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lowest point by sampling the line densely.
    fn sampled(cutter: &Cutter, line: &Line, x: f64, y: f64) -> Option<f64> {
        let b = line.end();
        (0..=20_000)
            .filter_map(|k| {
                let t = f64::from(k) / 20_000.0;
                let p: Vec<f64> = (0..3).map(|i| line.a[i] + (b[i] - line.a[i]) * t).collect();
                let d = (x - p[0]).hypot(y - p[1]);
                (d <= cutter.radius).then(|| p[2] + cutter.lift(d))
            })
            .reduce(f64::min)
    }

    #[test]
    fn closed_form_agrees_with_sampling_on_sloped_lines() {
        let shapes = [
            Profile::Flat,
            Profile::Ball,
            Profile::Cone { rise: 1.0 },
            Profile::Cone { rise: 0.3 },
        ];
        let lines = [
            Line::new([0.0, 0.0, 0.0], [10.0, 3.0, -4.0]),
            Line::new([2.0, 1.0, -3.0], [-5.0, 4.0, 2.0]),
            Line::new([0.0, 0.0, 0.0], [0.5, 0.0, -9.0]),
        ];
        for profile in shapes {
            let cutter = Cutter {
                radius: 2.0,
                profile,
            };
            for line in &lines {
                for k in 0..200 {
                    let (x, y) = (-6.0 + 0.09 * f64::from(k), -1.0 + 0.04 * f64::from(k));
                    let exact = LineSweep::new(cutter, *line).lowest(x, y, false, None);
                    let dense = sampled(&cutter, line, x, y);
                    match (exact, dense) {
                        (Some(a), Some(b)) => assert!(
                            a <= b + 1e-9 && b - a < 2e-3,
                            "{profile:?} {line:?} at ({x}, {y}): {a} vs {b}"
                        ),
                        // Sampling may miss a point just inside the edge.
                        (Some(_), None) | (None, None) => {}
                        (None, Some(b)) => panic!("{profile:?} missed ({x}, {y}) at {b}"),
                    }
                }
            }
        }
    }

    #[test]
    fn arc_distance_inside_and_beyond_its_ends() {
        // A quarter from (1, 0) counter-clockwise to (0, 1).
        let arc = Arc {
            center: [0.0, 0.0],
            radius: 1.0,
            z: 0.0,
            from: [1.0, 0.0],
            to: [0.0, 1.0],
            sweep: std::f64::consts::FRAC_PI_2,
        };
        assert!((arc.distance(2.0, 2.0) - (8f64.sqrt() - 1.0)).abs() < 1e-12);
        assert!((arc.distance(-1.0, 0.0) - 2f64.sqrt()).abs() < 1e-12);
        assert!((arc.distance(1.0, -1.0) - 1.0).abs() < 1e-12);
        let b = arc.bounds();
        assert_eq!(b, [0.0, 0.0, 1.0, 1.0]);
    }
}
