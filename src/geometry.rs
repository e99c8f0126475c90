//! Plane geometry of arcs: centre from a radius, sweep, linearization.
//! Plain functions on points in one unit; they return plain errors and
//! never see spans or IR statements (the caller attaches the location).

pub mod spline;

use crate::ir::Plane;
use nalgebra::Vector2;
use std::f64::consts::TAU;

pub type Point = [f64; 3];

fn project(p: Point, plane: Plane) -> Vector2<f64> {
    let (a, b, _) = plane.axes();
    Vector2::new(p[a], p[b])
}

/// Why an arc cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub enum ArcError {
    /// R is smaller than half the chord.
    RadiusTooSmall { radius: f64, half_chord: f64 },
    /// R arcs need distinct start and end points.
    SamePoints,
    /// I/J/K radii at start and end differ by more than the tolerance.
    RadiiDiffer { start: f64, end: f64 },
    /// The centre is on the start point.
    ZeroRadius,
}

/// The centre of an R arc (SPEC §4: R > 0 the short arc, R < 0 the long).
/// A radius up to `short` under half the chord is the half circle about
/// the chord's middle, as Mach3 and Fanuc draw it.
pub fn center_from_radius(
    start: Point,
    end: Point,
    radius: f64,
    plane: Plane,
    clockwise: bool,
    short: f64,
) -> Result<Point, ArcError> {
    let (a, b, n) = plane.axes();
    let (s, e) = (project(start, plane), project(end, plane));
    let chord = e - s;
    let d = chord.norm();
    if d < 1e-9 {
        return Err(ArcError::SamePoints);
    }
    let r = radius.abs();
    let half = d / 2.0;
    // Accept a radius a hair too small (rounded input) as a half circle.
    if r < half * (1.0 - 1e-6) - 1e-9 - short {
        return Err(ArcError::RadiusTooSmall {
            radius: r,
            half_chord: half,
        });
    }
    let h = (r * r - half * half).max(0.0).sqrt();
    let u = chord / d;
    let left = Vector2::new(-u.y, u.x);
    let long = radius < 0.0;
    let side = if clockwise == long { 1.0 } else { -1.0 };
    let c = s + chord / 2.0 + left * (h * side);
    let mut center = [0.0; 3];
    center[a] = c.x;
    center[b] = c.y;
    center[n] = start[n];
    Ok(center)
}

/// Check an I/J/K arc: radii at start and end within 1 % (SPEC §4), or
/// within `spiral` of each other (LinuxCNC's absolute tolerance, which
/// real CAM output of tiny arcs needs). Returns the radius to use (the
/// larger).
pub fn check_center(
    start: Point,
    end: Point,
    center: Point,
    plane: Plane,
    spiral: f64,
) -> Result<f64, ArcError> {
    let c = project(center, plane);
    let rs = (project(start, plane) - c).norm();
    let re = (project(end, plane) - c).norm();
    if rs < 1e-9 {
        return Err(ArcError::ZeroRadius);
    }
    let (lo, hi) = if rs < re { (rs, re) } else { (re, rs) };
    if hi - lo > 0.01 * hi && hi - lo > 1e-6 && hi - lo > spiral {
        return Err(ArcError::RadiiDiffer { start: rs, end: re });
    }
    Ok(hi)
}

/// Signed sweep in radians (positive counter-clockwise about the plane
/// normal), including extra full turns. End == start is a full circle.
pub fn sweep(
    start: Point,
    end: Point,
    center: Point,
    plane: Plane,
    clockwise: bool,
    turns: u32,
) -> f64 {
    let c = project(center, plane);
    let vs = project(start, plane) - c;
    let ve = project(end, plane) - c;
    sweep_between(vs.y.atan2(vs.x), ve.y.atan2(ve.x), clockwise, turns)
}

/// [`sweep`] from the angles of the start and the end about the centre
/// (each `atan2`'s, within ±π).
pub fn sweep_between(a0: f64, a1: f64, clockwise: bool, turns: u32) -> f64 {
    let mut d = if clockwise { a0 - a1 } else { a1 - a0 };
    // `rem_euclid(TAU)` without its `fmod`: d is within ±2π, and -2π
    // gives 0 either way, a full turn below.
    if d < 0.0 {
        d += TAU;
    }
    // Nearly equal angles: a full turn (rs274 uses the same rule).
    if d < 1e-9 {
        d = TAU;
    }
    d += TAU * turns.saturating_sub(1) as f64;
    if clockwise {
        -d
    } else {
        d
    }
}

/// √(x² + y²) without overflow (`f64::hypot`), and without libm's call
/// where `y` is 0 (a planar arc's rise), whose result it is exactly.
#[inline(always)]
pub fn hypot((x, y): (f64, f64)) -> f64 {
    match y == 0.0 {
        true => x.abs(),
        false => x.hypot(y),
    }
}

/// The four directions from an arc's centre along the axes of its plane:
/// each one's angle and unit vector.
const AXIS_DIRECTIONS: [(f64, [f64; 2]); 4] = [
    (0.0, [1.0, 0.0]),
    (std::f64::consts::FRAC_PI_2, [0.0, 1.0]),
    (std::f64::consts::PI, [-1.0, 0.0]),
    (-std::f64::consts::FRAC_PI_2, [0.0, -1.0]),
];

/// Where an arc is furthest along an axis of its plane between its ends:
/// `each` is given each of the four directions from its centre along
/// those axes that it passes after its start and before its end (once
/// each, as many as a box needs beside its ends), as the share of its
/// sweep at which it passes it and the direction (a unit vector in the
/// plane). `angle`: of its start about its centre
/// (`atan2`'s, within ±π); `sweep`: signed, as [`sweep`] gives it.
#[inline(always)]
pub fn axis_shares(angle: f64, sweep: f64, mut each: impl FnMut(f64, [f64; 2])) {
    let whole = sweep.abs();
    if whole == 0.0 {
        return;
    }
    for &(direction, unit) in &AXIS_DIRECTIONS {
        // The turn from the start to it the way the arc goes: both
        // angles within ±π, so one full turn brings it within [0, 2π).
        let mut turn = match sweep < 0.0 {
            true => angle - direction,
            false => direction - angle,
        };
        if turn < 0.0 {
            turn += TAU;
        }
        if turn > 0.0 && turn < whole {
            each(turn / whole, unit);
        }
    }
}

/// Is the arc longer than a half circle?
pub fn is_long_arc(start: Point, end: Point, center: Point, plane: Plane, clockwise: bool) -> bool {
    sweep(start, end, center, plane, clockwise, 1).abs() > std::f64::consts::PI + 1e-12
}

/// Points along an arc (excluding the start, including the end exactly) so
/// that no chord is farther than `tolerance` from the arc. The radius
/// changes linearly from start to end, and so does the helical axis.
pub fn arc_points(
    start: Point,
    end: Point,
    center: Point,
    plane: Plane,
    clockwise: bool,
    turns: u32,
    tolerance: f64,
) -> Vec<Point> {
    let (a, b, n) = plane.axes();
    let c = project(center, plane);
    let vs = project(start, plane) - c;
    let r0 = vs.norm();
    let r1 = (project(end, plane) - c).norm();
    let total = sweep(start, end, center, plane, clockwise, turns);
    let r = r0.max(r1);
    let step = if tolerance > 0.0 && tolerance < r {
        2.0 * (1.0 - tolerance / r).acos()
    } else {
        std::f64::consts::FRAC_PI_2
    };
    // Bounded: at most one point per 1e-4 rad, and never more than 10^6.
    let count = ((total.abs() / step.max(1e-4)).ceil() as usize).clamp(1, 1_000_000);
    let a0 = vs.y.atan2(vs.x);
    (1..=count)
        .map(|i| {
            if i == count {
                return end;
            }
            let t = i as f64 / count as f64;
            let angle = a0 + total * t;
            let radius = r0 + (r1 - r0) * t;
            let mut p = [0.0; 3];
            p[a] = c.x + radius * angle.cos();
            p[b] = c.y + radius * angle.sin();
            p[n] = start[n] + (end[n] - start[n]) * t;
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_arcs_pick_the_right_side() {
        // CCW short arc from (0,0) to (2,0) with R1 has its centre at (1,0)
        // (a half circle); with R2 the centre is above for CCW-short.
        let c = center_from_radius([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 2.0, Plane::XY, false, 0.0)
            .unwrap();
        assert!(c[1] > 0.0);
        let c = center_from_radius(
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            -2.0,
            Plane::XY,
            false,
            0.0,
        )
        .unwrap();
        assert!(c[1] < 0.0);
        let c = center_from_radius([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 2.0, Plane::XY, true, 0.0)
            .unwrap();
        assert!(c[1] < 0.0);
        assert!(center_from_radius([0.0; 3], [3.0, 0.0, 0.0], 1.0, Plane::XY, true, 0.0).is_err());
    }

    #[test]
    fn an_arc_passes_the_axis_directions_between_its_ends() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let shares = |angle: f64, sweep: f64| {
            let mut all = Vec::new();
            axis_shares(angle, sweep, |t, unit| all.push((t, unit)));
            all
        };
        // From 45° a quarter turn each way: +Y half way counter-clockwise,
        // +X half way clockwise.
        assert_eq!(shares(PI / 4.0, FRAC_PI_2), [(0.5, [0.0, 1.0])]);
        assert_eq!(shares(PI / 4.0, -FRAC_PI_2), [(0.5, [1.0, 0.0])]);
        // From -170° counter-clockwise through 100°: -X is behind it, -Y
        // is 80° on.
        let s = shares(-170f64.to_radians(), 100f64.to_radians());
        assert_eq!(s.len(), 1);
        assert!(
            (s[0].0 - 0.8).abs() < 1e-12 && s[0].1 == [0.0, -1.0],
            "{s:?}"
        );
        // A whole turn passes all four; not where it starts or ends on
        // one (its ends are in its box already).
        assert_eq!(shares(0.3, -TAU).len(), 4);
        assert_eq!(shares(0.0, -TAU).len(), 3);
        assert!(shares(FRAC_PI_2, 0.1).is_empty());
        assert!(shares(-0.1, 0.1).is_empty());
        // No sweep, no bulge.
        assert!(shares(0.0, 0.0).is_empty());
    }

    #[test]
    fn full_circle_sweeps_a_turn() {
        let s = sweep(
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0; 3],
            Plane::XY,
            false,
            1,
        );
        assert!((s - TAU).abs() < 1e-12);
        let s = sweep(
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0; 3],
            Plane::XY,
            true,
            2,
        );
        assert!((s + TAU + 1.5 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn linearized_points_stay_within_tolerance() {
        let pts = arc_points(
            [10.0, 0.0, 0.0],
            [-10.0, 0.0, -1.0],
            [0.0; 3],
            Plane::XY,
            false,
            1,
            0.01,
        );
        let mut prev = [10.0, 0.0, 0.0];
        for p in &pts {
            let mid = [(prev[0] + p[0]) / 2.0, (prev[1] + p[1]) / 2.0];
            let err = 10.0 - mid[0].hypot(mid[1]);
            assert!(err <= 0.0100001, "chord error {err}");
            prev = *p;
        }
        assert_eq!(*pts.last().unwrap(), [-10.0, 0.0, -1.0]);
    }
}
