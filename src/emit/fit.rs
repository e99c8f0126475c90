//! `--arcs fit`: which stretches of a run of straight feed moves are
//! written as one arc, each one proven. A run is its points in the arc
//! plane's axes order (first, second, normal); a stretch of at least
//! [`MIN_SEGMENTS`] lines becomes an arc (a helix when the normal axis
//! moves in step with the angle) only when the arc *as printed* (its
//! rounded end points and centre, run as a controller runs them: the
//! radius going linearly from the start's to the end's) is within the
//! tolerance of every vertex and every segment it replaces.
//!
//! Pure geometry: it knows nothing of statements, of printing or of which
//! moves may form a run (the program printer decides that).

use std::f64::consts::TAU;

/// Fewer lines than this stay lines: three points always lie on a circle.
pub(super) const MIN_SEGMENTS: usize = 3;

/// A stretch of the run, in order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Piece {
    /// The next segment, as it was.
    Line,
    /// The next `segments` segments as one arc about `center` (on the
    /// output grid, in the plane's first and second axes).
    Arc {
        segments: usize,
        center: [i64; 2],
        clockwise: bool,
    },
}

/// A run to fit: `exact[k]` is where the program puts the tool after the
/// k-th move (`exact[0]`: where the run starts), `printed[k]` the same
/// point as the output writes it (on the grid of `1 / scale`).
pub(super) struct Run<'a> {
    pub exact: &'a [[f64; 3]],
    pub printed: &'a [[i64; 3]],
    pub scale: f64,
    pub tolerance: f64,
}

/// The share of the tolerance the cheap test of a candidate allows a
/// vertex off its circle (the proof uses the whole tolerance).
const CANDIDATE_SHARE: f64 = 0.5;

/// The share of the tolerance left for the curve between two samples of
/// the proof.
const SAMPLE_SHARE: f64 = 0.1;

impl Run<'_> {
    /// The pieces of the run, longest arcs first (greedy from the start).
    pub fn fit(&self) -> Vec<Piece> {
        let segments = self.exact.len().saturating_sub(1);
        let mut pieces = Vec::new();
        let mut i = 0;
        while i < segments {
            match self.longest_arc(i) {
                Some(arc @ Piece::Arc { segments, .. }) => {
                    pieces.push(arc);
                    i += segments;
                }
                _ => {
                    pieces.push(Piece::Line);
                    i += 1;
                }
            }
        }
        pieces
    }

    /// The longest proven arc from vertex `i`: the stretch grows while a
    /// circle through its ends and middle passes the cheap test (doubling,
    /// then halving the step), then shrinks until the proof holds.
    fn longest_arc(&self, i: usize) -> Option<Piece> {
        let last = self.exact.len() - 1;
        let mut good = i + MIN_SEGMENTS;
        if good > last || self.candidate(i, good).is_none() {
            return None;
        }
        let mut step = MIN_SEGMENTS;
        while good + step <= last && self.candidate(i, good + step).is_some() {
            good += step;
            step *= 2;
        }
        while step > 1 {
            step /= 2;
            if good + step <= last && self.candidate(i, good + step).is_some() {
                good += step;
            }
        }
        let mut j = good;
        // A few shorter tries: the cheap test passed, so rounding is what
        // failed, and a shorter arc has a better-placed centre.
        for _ in 0..4 {
            if let Some(arc) = self.candidate(i, j).and_then(|c| self.proven(i, j, c)) {
                return Some(arc);
            }
            j = i + ((j - i) * 3 / 4);
            if j < i + MIN_SEGMENTS {
                break;
            }
        }
        None
    }

    /// The circle through vertices `i`, the middle and `j`, if every vertex
    /// and chord between lies near it, in order and less than a turn, and
    /// the normal axis keeps in step with the angle: its centre and
    /// whether it turns clockwise.
    fn candidate(&self, i: usize, j: usize) -> Option<([f64; 2], bool)> {
        let points = &self.exact[i..=j];
        let off_budget = self.tolerance * CANDIDATE_SHARE;
        // What is left after the rounding of the centre and of the ends.
        let budget = (self.tolerance - 1.0 / self.scale).max(self.tolerance * 0.6);
        let (p, m, q) = (
            points[0],
            points[points.len() / 2],
            points[points.len() - 1],
        );
        let center = circle_through(p, m, q)?;
        let radius = (p[0] - center[0]).hypot(p[1] - center[1]);
        // Past this a chain is as good as straight; the arc would only
        // trouble the controller's arithmetic.
        if radius > self.tolerance * 1e6 {
            return None;
        }
        let clockwise = cross(sub(m, xy(p)), sub(q, xy(m))) < 0.0;
        // One pass without trigonometry (the cheap test runs on every
        // stretch tried): each step turns the arc's way by less than a
        // quarter, each vertex lies near the circle, each chord's bulge
        // (from its length) fits, and the angle (chord over radius, a
        // little under the true one) stays under a turn.
        let (z0, z1) = (p[2], q[2]);
        let mut along = 0.0;
        for (k, point) in points.iter().enumerate() {
            let off_circle = ((point[0] - center[0]).hypot(point[1] - center[1]) - radius).abs();
            let mut bulge = 0.0;
            if k > 0 {
                let (u, v) = (sub(points[k - 1], center), sub(*point, center));
                let turn = cross(u, v);
                if (if clockwise { -turn } else { turn }) < 0.0 || u[0] * v[0] + u[1] * v[1] <= 0.0
                {
                    return None;
                }
                let chord = (v[0] - u[0]).hypot(v[1] - u[1]);
                along += chord;
                bulge = radius - (radius * radius - 0.25 * chord * chord).max(0.0).sqrt();
            }
            let off_level = if z0 == z1 { (point[2] - z0).abs() } else { 0.0 };
            if off_circle > off_budget || off_circle + bulge > budget || off_level > off_budget {
                return None;
            }
        }
        if along <= 0.0 || along / radius >= TAU - 0.05 {
            return None;
        }
        // A helix: the normal axis in step with the way along.
        if z0 != z1 {
            let mut so_far = 0.0;
            for w in points.windows(2) {
                so_far += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
                if (w[1][2] - (z0 + (z1 - z0) * so_far / along)).abs() > off_budget {
                    return None;
                }
            }
        }
        Some((center, clockwise))
    }

    /// The arc of vertices `i..=j` about the grid point nearest `center`
    /// (or one of its neighbours), as the output prints it, if it is
    /// within the tolerance of every vertex and segment.
    fn proven(&self, i: usize, j: usize, (center, clockwise): ([f64; 2], bool)) -> Option<Piece> {
        let base = center.map(|v| crate::emit::number::to_grid(v, self.scale));
        let neighbours = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)];
        neighbours.into_iter().find_map(|(da, db)| {
            let q = [base[0] + da, base[1] + db];
            let center = q.map(|v| v as f64 / self.scale);
            self.proves(i, j, center, clockwise).then_some(Piece::Arc {
                segments: j - i,
                center: q,
                clockwise,
            })
        })
    }

    /// Whether the arc from printed vertex `i` to printed vertex `j`
    /// about `center` (any point, not only one on the grid: the centre a
    /// controller finds from an R) is within the tolerance of every
    /// vertex and segment between.
    pub(super) fn proves(&self, i: usize, j: usize, center: [f64; 2], clockwise: bool) -> bool {
        PrintedArc::new(self, i, j, center, clockwise)
            .is_some_and(|printed| printed.within(&self.exact[i..=j], self.tolerance))
    }
}

/// An arc as the controller runs it from the printed numbers: the angle
/// goes from the start's to the end's, the radius and the normal axis
/// linearly with it.
struct PrintedArc {
    center: [f64; 2],
    start_angle: f64,
    /// Signed: negative clockwise.
    sweep: f64,
    radius: [f64; 2],
    normal: [f64; 2],
}

impl PrintedArc {
    fn new(run: &Run<'_>, i: usize, j: usize, center: [f64; 2], clockwise: bool) -> Option<Self> {
        let unit = |v: i64| v as f64 / run.scale;
        let (s, e) = (run.printed[i].map(unit), run.printed[j].map(unit));
        let (vs, ve) = (sub(s, center), sub(e, center));
        let radius = [vs[0].hypot(vs[1]), ve[0].hypot(ve[1])];
        // Two radii that differ by more than the grid's rounding is a
        // spiral some controllers refuse.
        // And an arc smaller than the tolerance is lost in the rounding
        // (rs274 refuses a radius near zero).
        if (radius[0] - radius[1]).abs() > 2.0 / run.scale || radius[0] < 2.0 * run.tolerance {
            return None;
        }
        let start_angle = vs[1].atan2(vs[0]);
        let turn = ve[1].atan2(ve[0]) - start_angle;
        let sweep = if clockwise {
            -(-turn).rem_euclid(TAU)
        } else {
            turn.rem_euclid(TAU)
        };
        // Equal angles are a full circle to a controller: never meant here.
        if sweep.abs() < 1e-9 {
            return None;
        }
        Some(PrintedArc {
            center,
            start_angle,
            sweep,
            radius,
            normal: [s[2], e[2]],
        })
    }

    /// The point at `t` (0 at the start, 1 at the end).
    fn at(&self, t: f64) -> [f64; 3] {
        let angle = self.start_angle + self.sweep * t;
        let r = self.radius[0] + (self.radius[1] - self.radius[0]) * t;
        [
            self.center[0] + r * angle.cos(),
            self.center[1] + r * angle.sin(),
            self.normal[0] + (self.normal[1] - self.normal[0]) * t,
        ]
    }

    /// Where along the arc (0..=1) each point lies by its angle about the
    /// centre, if they go round in the arc's direction.
    fn positions(&self, points: &[[f64; 3]]) -> Option<Vec<f64>> {
        let clockwise = self.sweep < 0.0;
        let angles = unwrapped_angles(points, self.center, clockwise)?;
        let first = sub(points[0], self.center);
        // The first point's angle from the printed start (it may lie a
        // rounding before it).
        let mut offset = first[1].atan2(first[0]) - self.start_angle;
        offset = (offset + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI;
        let offset = if clockwise { -offset } else { offset };
        Some(
            angles
                .iter()
                .map(|a| ((a + offset) / self.sweep.abs()).clamp(0.0, 1.0))
                .collect(),
        )
    }

    /// Every vertex within `tolerance` of the arc (of its point at the
    /// vertex's angle, which is at least as far as the arc), and the arc
    /// within `tolerance` of the segment between each two vertices. The
    /// arc between two samples strays from their chord by at most the
    /// `bow` below, and the distance to a segment along a chord is at most
    /// that at its ends (it is convex): the samples' largest distance plus
    /// the bow bounds the arc's.
    fn within(&self, points: &[[f64; 3]], tolerance: f64) -> bool {
        let Some(at) = self.positions(points) else {
            return false;
        };
        let bow = tolerance * SAMPLE_SHARE;
        let radius = self.radius[0].max(self.radius[1])
            + 2.0 * (self.radius[1] - self.radius[0]).abs() / self.sweep.abs();
        // The angle between samples whose chord bows `bow` at most.
        let step = (8.0 * bow / radius).sqrt() / self.sweep.abs();
        let vertices_near = points
            .iter()
            .zip(&at)
            .all(|(p, &t)| distance(*p, self.at(t)) <= tolerance);
        vertices_near
            && points.windows(2).zip(at.windows(2)).all(|(seg, t)| {
                let samples = ((t[1] - t[0]) / step).ceil().max(1.0) as usize;
                (0..=samples).all(|s| {
                    let u = t[0] + (t[1] - t[0]) * s as f64 / samples as f64;
                    segment_distance(self.at(u), seg[0], seg[1]) + bow <= tolerance
                })
            })
    }
}

/// Each point's angle about `center` from the first one's, going round in
/// the direction given; `None` if a point goes back.
fn unwrapped_angles(points: &[[f64; 3]], center: [f64; 2], clockwise: bool) -> Option<Vec<f64>> {
    let mut angles = Vec::with_capacity(points.len());
    let mut total = 0.0;
    angles.push(0.0);
    for w in points.windows(2) {
        let (u, v) = (sub(w[0], center), sub(w[1], center));
        let turn = cross(u, v).atan2(u[0] * v[0] + u[1] * v[1]);
        let turn = if clockwise { -turn } else { turn };
        if turn < 0.0 {
            return None;
        }
        total += turn;
        angles.push(total);
    }
    Some(angles)
}

/// The centre of the circle through three points (first two axes), if
/// they are not in a line.
fn circle_through(p: [f64; 3], m: [f64; 3], q: [f64; 3]) -> Option<[f64; 2]> {
    let (b, c) = (sub(m, xy(p)), sub(q, xy(p)));
    let d = 2.0 * cross(b, c);
    if d.abs() < 1e-18 {
        return None;
    }
    let (bb, cc) = (b[0] * b[0] + b[1] * b[1], c[0] * c[0] + c[1] * c[1]);
    let center = [
        p[0] + (c[1] * bb - b[1] * cc) / d,
        p[1] + (b[0] * cc - c[0] * bb) / d,
    ];
    center.iter().all(|v| v.is_finite()).then_some(center)
}

fn xy(p: [f64; 3]) -> [f64; 2] {
    [p[0], p[1]]
}

fn sub(p: [f64; 3], c: [f64; 2]) -> [f64; 2] {
    [p[0] - c[0], p[1] - c[1]]
}

fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}

fn distance(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The distance from `p` to the segment from `a` to `b`.
fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    distance(p, [a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t])
}

#[cfg(test)]
mod tests {
    use super::{Piece, Run};
    use crate::geometry::arc_points;
    use crate::ir::Plane;
    use proptest::prelude::*;
    use std::f64::consts::{PI, TAU};

    const SCALE: f64 = 1000.0;
    const TOLERANCE: f64 = 0.005;

    /// A run through `points` (the first is where it starts), printed on
    /// the grid of 0.001; its pieces.
    fn fitted(points: &[[f64; 3]]) -> (Vec<[i64; 3]>, Vec<Piece>) {
        let printed: Vec<[i64; 3]> = points
            .iter()
            .map(|p| p.map(|v| (v * SCALE).round() as i64))
            .collect();
        let run = Run {
            exact: points,
            printed: &printed,
            scale: SCALE,
            tolerance: TOLERANCE,
        };
        let pieces = run.fit();
        (printed, pieces)
    }

    /// The largest distance between each fitted arc, as a controller runs
    /// its printed numbers (`geometry::arc_points`, the printer's own model
    /// of `--arcs lines`, far finer than the tolerance), and the lines it
    /// replaced: each vertex to the arc, each point of the arc to the
    /// lines. Measured apart from the proof, by brute force.
    fn deviation(points: &[[f64; 3]], printed: &[[i64; 3]], pieces: &[Piece]) -> f64 {
        let mut worst: f64 = 0.0;
        let mut k = 0;
        for piece in pieces {
            let Piece::Arc {
                segments,
                center,
                clockwise,
            } = *piece
            else {
                k += 1;
                continue;
            };
            let unit = |q: [i64; 3]| q.map(|v| v as f64 / SCALE);
            let (s, e) = (unit(printed[k]), unit(printed[k + segments]));
            let c = [center[0] as f64 / SCALE, center[1] as f64 / SCALE, 0.0];
            let mut arc = vec![s];
            arc.extend(arc_points(
                s,
                e,
                c,
                Plane::XY,
                clockwise,
                1,
                TOLERANCE / 1000.0,
            ));
            // Points every tolerance/40 along the arc's fine chords.
            let mut dense = Vec::new();
            for w in arc.windows(2) {
                let n = (super::distance(w[0], w[1]) / (TOLERANCE / 40.0))
                    .ceil()
                    .max(1.0) as usize;
                dense.extend((0..=n).map(|i| lerp(w[0], w[1], i as f64 / n as f64)));
            }
            let lines = &points[k..=k + segments];
            // Each point's nearest in a wide window about the last one's:
            // both go the same way round.
            let per_segment = dense.len() / segments;
            let mut at: usize = 0;
            for v in lines {
                let window = at.saturating_sub(per_segment + 64)
                    ..(at + 3 * per_segment + 64).min(dense.len());
                let (i, near) = nearest(window.map(|i| (i, super::distance(*v, dense[i]))));
                worst = worst.max(near);
                at = i;
            }
            let mut at: usize = 0;
            for d in &dense {
                let window = at.saturating_sub(8)..(at + 64).min(lines.len() - 1);
                let (i, near) = nearest(
                    window.map(|i| (i, super::segment_distance(*d, lines[i], lines[i + 1]))),
                );
                worst = worst.max(near);
                at = i;
            }
            k += segments;
        }
        worst
    }

    fn nearest(candidates: impl Iterator<Item = (usize, f64)>) -> (usize, f64) {
        candidates.fold((0, f64::MAX), |best, c| if c.1 < best.1 { c } else { best })
    }

    fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
        [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
    }

    fn moves(pieces: &[Piece]) -> usize {
        pieces.len()
    }

    /// Chords of a helix about `center` (the radius going from `r0` to
    /// `r1`), `n` of them, the normal axis rising by `rise`.
    fn chords(
        center: [f64; 2],
        (r0, r1): (f64, f64),
        (start, sweep): (f64, f64),
        n: usize,
        rise: f64,
    ) -> Vec<[f64; 3]> {
        (0..=n)
            .map(|i| {
                let t = i as f64 / n as f64;
                let a = start + sweep * t;
                let r = r0 + (r1 - r0) * t;
                [
                    center[0] + r * a.cos(),
                    center[1] + r * a.sin(),
                    -1.0 + rise * t,
                ]
            })
            .collect()
    }

    #[test]
    fn a_half_circle_of_chords_is_one_arc() {
        let points = chords([10.0, 5.0], (20.0, 20.0), (0.0, PI), 180, 0.0);
        let (printed, pieces) = fitted(&points);
        assert_eq!(
            pieces,
            vec![Piece::Arc {
                segments: 180,
                center: [10_000, 5_000],
                clockwise: false
            }]
        );
        assert!(deviation(&points, &printed, &pieces) <= TOLERANCE);
    }

    #[test]
    fn a_helix_of_chords_is_one_clockwise_arc() {
        let points = chords([0.0, 0.0], (5.0, 5.0), (1.0, -2.0), 60, -0.6);
        let (printed, pieces) = fitted(&points);
        assert!(
            matches!(
                pieces[..],
                [Piece::Arc {
                    segments: 60,
                    clockwise: true,
                    ..
                }]
            ),
            "{pieces:?}"
        );
        assert!(deviation(&points, &printed, &pieces) <= TOLERANCE);
    }

    #[test]
    fn corners_and_short_chains_stay_lines() {
        let square = [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 10.0, 0.0],
            [0.0, 0.0, 0.0],
        ];
        assert!(fitted(&square).1.iter().all(|p| *p == Piece::Line));
        // Chords that bow more than the tolerance from their arc.
        let coarse = chords([0.0, 0.0], (20.0, 20.0), (0.0, PI), 12, 0.0);
        assert!(fitted(&coarse).1.iter().all(|p| *p == Piece::Line));
        // A straight chain: no arc of a huge radius.
        let straight: Vec<_> = (0..20).map(|i| [i as f64, 0.0, 0.0]).collect();
        assert!(fitted(&straight).1.iter().all(|p| *p == Piece::Line));
    }

    #[test]
    fn a_whole_circle_is_more_than_one_arc() {
        let points = chords([0.0, 0.0], (3.0, 3.0), (0.0, TAU), 120, 0.0);
        let (printed, pieces) = fitted(&points);
        assert!((2..=3).contains(&moves(&pieces)), "{pieces:?}");
        assert!(deviation(&points, &printed, &pieces) <= TOLERANCE);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Chords of a smooth curve (an arc or helix, rounded to the grid as
        /// CAM writes it) are fitted back within the tolerance, into few
        /// arcs.
        #[test]
        fn chords_of_an_arc_fit_back_within_the_tolerance(
            cx in -100.0..100.0f64,
            cy in -100.0..100.0f64,
            radius in 0.5..100.0f64,
            start in -PI..PI,
            sweep in prop_oneof![0.3..6.0f64, -6.0..-0.3f64],
            rise in prop_oneof![Just(0.0), -3.0..3.0f64],
            fine in 0.05..0.9f64,
        ) {
            // Chords that bow at most `fine` of the tolerance.
            let bow = TOLERANCE * fine;
            let step = 2.0 * (1.0 - bow / radius).acos();
            let n = ((sweep.abs() / step).ceil() as usize).clamp(3, 3000);
            let points: Vec<[f64; 3]> = chords([cx, cy], (radius, radius), (start, sweep), n, rise)
                .into_iter()
                .map(|p| p.map(|v| (v * SCALE).round() / SCALE))
                .collect();
            let (printed, pieces) = fitted(&points);
            let d = deviation(&points, &printed, &pieces);
            prop_assert!(d <= TOLERANCE * 1.03, "deviation {d}");
            if n >= 12 && fine < 0.4 {
                prop_assert!(moves(&pieces) * 4 <= n, "{n} chords as {} moves", moves(&pieces));
            }
        }

        /// Polylines that are not arcs (random walks, ellipses, spirals,
        /// waves): whatever is fitted is within the tolerance.
        #[test]
        fn other_polylines_are_never_fitted_beyond_the_tolerance(
            kind in 0..4u8,
            n in 4..400usize,
            a in 0.5..50.0f64,
            b in 0.5..50.0f64,
            turns in prop::collection::vec(-0.5..0.5f64, 400),
            scale in prop_oneof![Just(0.001), 0.001..0.1f64],
        ) {
            let points: Vec<[f64; 3]> = match kind {
                0 => {
                    let (mut p, mut heading) = ([0.0, 0.0, 0.0], 0.0f64);
                    let mut out = vec![p];
                    for t in turns.iter().take(n) {
                        heading += t;
                        p = [p[0] + scale * 10.0 * heading.cos(), p[1] + scale * 10.0 * heading.sin(), 0.0];
                        out.push(p);
                    }
                    out
                }
                1 => (0..=n).map(|i| {
                    let t = i as f64 / n as f64 * TAU * 0.9;
                    [a * t.cos(), b * t.sin(), 0.0]
                }).collect(),
                2 => chords([0.0, 0.0], (a, b), (0.0, 5.0), n, 0.0),
                _ => (0..=n).map(|i| {
                    let x = i as f64 * scale;
                    [x, a * 0.01 * (x * b).sin(), 0.0]
                }).collect(),
            };
            let (printed, pieces) = fitted(&points);
            let d = deviation(&points, &printed, &pieces);
            prop_assert!(d <= TOLERANCE * 1.03, "deviation {d} of {pieces:?}");
        }
    }
}
