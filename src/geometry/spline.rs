//! LinuxCNC's splines (G5 cubic, G5.1 quadratic) as the arcs LinuxCNC's
//! motion planner cuts them with: the curve cut at equal steps of its
//! parameter (four per control point), each step a biarc — two arcs that
//! meet tangentially, the first leaving along the curve's tangent at the
//! step's start, the second arriving along the tangent at its end — and an
//! arc too flat to tell from its chord a straight line. rs274 only names
//! the curve (`NURBS_FEED`); this is LinuxCNC's task layer's reading of it
//! (`emccanon.cc`), so the machine's path and ger's agree arc for arc.
//!
//! Plane points in one unit, no spans: the caller places them.

/// A point or a direction in the spline's plane.
pub type Point2 = [f64; 2];

/// One piece of the path: where it ends, and for an arc its centre and
/// turning sense.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub end: Point2,
    /// `None`: a straight line.
    pub arc: Option<PieceArc>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PieceArc {
    pub center: Point2,
    pub clockwise: bool,
}

/// The step LinuxCNC's tangent is measured over (a difference quotient,
/// kept: where the curve's derivative vanishes, at a control point on its
/// end point, the quotient still points along the curve).
const TANGENT_STEP: f64 = 1e-5;

/// Below this (twice the chord times the sine of the turn, in length
/// units) an arc is cut as its chord, as LinuxCNC does.
const FLAT: f64 = 1e-6;

/// The Bézier curve of control points `points` (3: G5.1, 4: G5) as
/// LinuxCNC's biarcs, in order from `points[0]` to the last point.
pub fn biarcs(points: &[Point2]) -> Vec<Piece> {
    let steps = points.len() * 4;
    let mut pieces = Vec::with_capacity(steps * 2);
    let mut from = points[0];
    let mut from_tangent = tangent(points, 0.0);
    for i in 1..=steps {
        let u = i as f64 / steps as f64;
        let to = if i == steps {
            points[points.len() - 1]
        } else {
            point(points, u)
        };
        let to_tangent = tangent(points, u);
        biarc(from, from_tangent, to, to_tangent, &mut pieces);
        from = to;
        from_tangent = to_tangent;
    }
    pieces
}

/// The curve at `u` in 0..=1 (Bernstein's form, de Casteljau's steps).
pub fn point(points: &[Point2], u: f64) -> Point2 {
    let mut p: Vec<Point2> = points.to_vec();
    for k in (1..p.len()).rev() {
        for i in 0..k {
            p[i] = [
                p[i][0] + (p[i + 1][0] - p[i][0]) * u,
                p[i][1] + (p[i + 1][1] - p[i][1]) * u,
            ];
        }
    }
    p[0]
}

/// The unit tangent at `u`: the curve's difference over a small step
/// about it (one-sided at the ends); zero where the curve stands still.
fn tangent(points: &[Point2], u: f64) -> Point2 {
    let (lo, hi) = ((u - TANGENT_STEP).max(0.0), (u + TANGENT_STEP).min(1.0));
    let (a, b) = (point(points, lo), point(points, hi));
    unit([(b[0] - a[0]) / (hi - lo), (b[1] - a[1]) / (hi - lo)])
}

fn unit(v: Point2) -> Point2 {
    let h = v[0].hypot(v[1]);
    if h == 0.0 {
        v
    } else {
        [v[0] / h, v[1] / h]
    }
}

fn dot(a: Point2, b: Point2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The biarc from `p0` leaving along `t0` to `p4` arriving along `t4`,
/// with equal tangent lengths on both sides (LinuxCNC's choice): the two
/// arcs meet at the point between the ends of those tangents, weighted by
/// their lengths.
fn biarc(p0: Point2, t0: Point2, p4: Point2, t4: Point2, pieces: &mut Vec<Piece>) {
    let v = [p0[0] - p4[0], p0[1] - p4[1]];
    let c = dot(v, v);
    let b = 2.0 * dot(v, [t0[0] + t4[0], t0[1] + t4[1]]);
    let a = 2.0 * (dot(t0, t4) - 1.0);
    // a <= 0 and c >= 0: the roots have opposite signs, and the tangent
    // length is the positive one. With parallel tangents (a = 0) the
    // quadratic is linear; LinuxCNC divides by zero there and cuts
    // nothing sensible: its limit, -c/b, is taken (a straight step has
    // b < 0), else the step is cut as its chord.
    let beta = if a < 0.0 {
        let root = (b * b - 4.0 * a * c).max(0.0).sqrt();
        ((-b - root) / (2.0 * a)).max((-b + root) / (2.0 * a))
    } else if b < 0.0 {
        -c / b
    } else {
        pieces.push(Piece { end: p4, arc: None });
        return;
    };
    if !(beta.is_finite() && beta > 0.0) {
        pieces.push(Piece { end: p4, arc: None });
        return;
    }
    let p1 = [p0[0] + beta * t0[0], p0[1] + beta * t0[1]];
    let p3 = [p4[0] - beta * t4[0], p4[1] - beta * t4[1]];
    let p2 = [(p1[0] + p3[0]) / 2.0, (p1[1] + p3[1]) / 2.0];
    let t2 = unit([p3[0] - p2[0], p3[1] - p2[1]]);
    pieces.push(arc(p0, p2, t0));
    pieces.push(arc(p2, p4, t2));
}

/// The arc from `p0` leaving along `t0` that ends at `p1`, or the chord
/// where the arc is too flat.
fn arc(p0: Point2, p1: Point2, t0: Point2) -> Piece {
    let (x, y) = (p1[0] - p0[0], p1[1] - p0[1]);
    let den = 2.0 * (y * t0[0] - x * t0[1]);
    if den.abs() <= FLAT {
        return Piece { end: p1, arc: None };
    }
    let r = -(x * x + y * y) / den;
    Piece {
        end: p1,
        arc: Some(PieceArc {
            center: [p0[0] + t0[1] * r, p0[1] - t0[0] * r],
            clockwise: r > 0.0,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How far `q` is from the piece that starts at `from`.
    fn off_piece(from: Point2, piece: &Piece, q: Point2) -> f64 {
        match piece.arc {
            None => {
                let d = [piece.end[0] - from[0], piece.end[1] - from[1]];
                let len2 = dot(d, d).max(1e-300);
                let t = (dot([q[0] - from[0], q[1] - from[1]], d) / len2).clamp(0.0, 1.0);
                (from[0] + t * d[0] - q[0]).hypot(from[1] + t * d[1] - q[1])
            }
            Some(a) => {
                let r = (from[0] - a.center[0]).hypot(from[1] - a.center[1]);
                ((q[0] - a.center[0]).hypot(q[1] - a.center[1]) - r).abs()
            }
        }
    }

    /// Every point of the curve lies near the arcs, the arcs join, and
    /// they end where the curve does.
    fn follows(points: &[Point2], within: f64) {
        let pieces = biarcs(points);
        // Two pieces a step (one where a step is cut as its chord).
        let steps = points.len() * 4;
        assert!(
            (steps..=2 * steps).contains(&pieces.len()),
            "{}",
            pieces.len()
        );
        assert_eq!(pieces.last().map(|p| p.end), points.last().copied());
        let mut from = points[0];
        for piece in &pieces {
            if let Some(a) = piece.arc {
                // Each arc passes through both its ends.
                let r0 = (from[0] - a.center[0]).hypot(from[1] - a.center[1]);
                let r1 = (piece.end[0] - a.center[0]).hypot(piece.end[1] - a.center[1]);
                assert!((r0 - r1).abs() < 1e-9 * r0.max(1.0), "{r0} {r1}");
            }
            from = piece.end;
        }
        for k in 0..=1000 {
            let q = point(points, f64::from(k) / 1000.0);
            let mut from = points[0];
            let mut best = f64::INFINITY;
            for piece in &pieces {
                best = best.min(off_piece(from, piece, q));
                from = piece.end;
            }
            assert!(best < within, "u {k}/1000 is {best} off");
        }
    }

    #[test]
    fn a_cubic_is_followed_closely() {
        follows(&[[0.0, 0.0], [1.0, 2.0], [9.0, 2.0], [10.0, 0.0]], 5e-4);
        // An S: the curvature changes sign.
        follows(&[[0.0, 0.0], [10.0, 10.0], [0.0, 10.0], [10.0, 20.0]], 1e-3);
    }

    #[test]
    fn a_quadratic_is_followed_closely() {
        follows(&[[0.0, 0.0], [5.0, 5.0], [30.0, 0.0]], 1e-3);
    }

    #[test]
    fn a_straight_spline_is_lines() {
        let pieces = biarcs(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]);
        assert!(pieces.iter().all(|p| p.arc.is_none()));
        assert_eq!(pieces.last().map(|p| p.end), Some([3.0, 0.0]));
    }

    #[test]
    fn a_control_point_on_the_start_still_leaves_along_the_curve() {
        // The derivative is zero at the start: the tangent is the limit.
        follows(&[[0.0, 0.0], [0.0, 0.0], [10.0, 0.0], [10.0, 5.0]], 1e-3);
        let pieces = biarcs(&[[0.0, 0.0], [0.0, 0.0], [10.0, 0.0], [10.0, 5.0]]);
        let first = pieces[0].arc.map(|a| a.center);
        // Leaving along +X (towards the next control point), turning left
        // (the tangent a difference over a step: off by a hair).
        assert!(
            first.is_some_and(|c| c[0].abs() < 1e-4 && c[1] > 0.0),
            "{first:?}"
        );
    }
}
