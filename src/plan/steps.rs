//! grbl's arithmetic where it changes the blocks its planner gets, on a
//! machine whose steps per mm are known: every block's end on a whole
//! step (`plan_buffer_line` rounds the target, and takes a block's length
//! and direction from the steps between its ends), and an arc's chord
//! ends as `mc_arc` makes them (single precision, a third-order rotation
//! from one chord end to the next, exact sines and cosines every
//! `N_ARC_CORRECTION` chords). A chord of a few steps is then as long,
//! and turns as sharply, as its steps make it: on arcs of a fraction of a
//! millimetre this moves the corners' speeds by tens of percent.
//!
//! Architecture Invariant: arithmetic on points only; knows neither
//! blocks nor the planner.

use crate::ir::Plane;
use crate::toolpath::{Move, MoveKind, Point};

/// grbl's `N_ARC_CORRECTION` (config.h): chords rotated by the
/// approximation between two exact ones.
const ARC_CORRECTION: u32 = 12;

/// A machine's steps per mm (`$100`–`$102`) where known, and the mm of a
/// step: a point goes on its steps by multiplications only.
#[derive(Clone, Copy, Debug)]
pub(super) struct Steps {
    per_mm: [f64; 3],
    mm: [f64; 3],
    known: [bool; 3],
    /// Every axis's known (as `ger machine import` writes them): a point
    /// goes on its steps without a test per axis.
    all: bool,
}

impl Steps {
    pub(super) fn of(per_mm: [Option<f64>; 3]) -> Steps {
        Steps {
            per_mm: per_mm.map(|n| n.unwrap_or(0.0)),
            mm: per_mm.map(|n| n.map_or(0.0, |n| 1.0 / n)),
            known: per_mm.map(|n| n.is_some()),
            all: per_mm.iter().all(Option::is_some),
        }
    }
}

/// Where grbl's planner puts `p`: each axis whose steps per mm are known
/// on its nearest whole step (`lround`: halves away from zero), back in
/// mm (by the mm of a step: within a unit in the last place of the
/// division).
#[inline(always)]
pub(super) fn on_steps(p: Point, steps: &Steps) -> Point {
    // `round` without libm's call: half a step added away from zero, then
    // cut toward it (machine positions stay far below i64's range,
    // `ir::MAX_POSITION`).
    let on = |i: usize| {
        let v = p[i] * steps.per_mm[i];
        (v + 0.5_f64.copysign(v)) as i64 as f64 * steps.mm[i]
    };
    match steps.all {
        true => [on(0), on(1), on(2)],
        false => std::array::from_fn(|i| if steps.known[i] { on(i) } else { p[i] }),
    }
}

/// The ends of arc `m`'s `n` chords after its start, as grbl's `mc_arc`
/// computes them (the last is the arc's end); a straight move's end.
pub(super) struct McArc {
    /// The plane (its axes and normal: grbl's `axis_0`, `axis_1`,
    /// `axis_linear`).
    plane: Plane,
    center: [f32; 2],
    /// From the start to the centre (grbl's `offset`).
    offset: [f32; 2],
    /// From the centre to the last chord end.
    radius: [f32; 2],
    linear: f32,
    linear_per_chord: f32,
    theta: f32,
    cos_t: f32,
    sin_t: f32,
    /// Chords made, and approximate rotations since the last exact one.
    made: u32,
    count: u32,
    chords: u32,
    end: Point,
}

impl McArc {
    /// `m` cut into `n` chords; `sweep` is its [`Move::sweep`].
    pub(super) fn new(m: &Move, n: usize, sweep: f64) -> McArc {
        let plane = match m.kind {
            MoveKind::Arc(a) => a.plane,
            MoveKind::Rapid | MoveKind::Feed => Plane::XY,
        };
        let (p, q, l) = plane.axes();
        let (center, clockwise) = match m.kind {
            MoveKind::Arc(a) => (a.center, a.clockwise),
            MoveKind::Rapid | MoveKind::Feed => (m.start, false),
        };
        let offset = [
            (center[p] - m.start[p]) as f32,
            (center[q] - m.start[q]) as f32,
        ];
        let chords = n.clamp(1, u32::MAX as usize) as u32;
        let sweep = sweep * if clockwise { -1.0 } else { 1.0 };
        let theta = sweep as f32 / chords as f32;
        // As the C reads: a float product, double constants.
        let cos_t = (2.0 - f64::from(theta * theta)) as f32;
        let sin_t = (f64::from(theta) * 0.166_666_67 * (f64::from(cos_t) + 4.0)) as f32;
        let linear = m.start[l] as f32;
        McArc {
            plane,
            center: [m.start[p] as f32 + offset[0], m.start[q] as f32 + offset[1]],
            offset,
            radius: [-offset[0], -offset[1]],
            linear,
            linear_per_chord: (m.end[l] as f32 - linear) / chords as f32,
            theta,
            cos_t: (f64::from(cos_t) * 0.5) as f32,
            sin_t,
            made: 0,
            count: 0,
            chords,
            end: m.end,
        }
    }
}

impl McArc {
    /// From one chord end to the next (`made` already counts it): the
    /// rotation, exact every `ARC_CORRECTION + 1` chords, and the normal.
    #[inline(always)]
    fn turn(&mut self) {
        let [r0, r1] = self.radius;
        self.radius = match self.count < ARC_CORRECTION {
            true => {
                self.count += 1;
                [
                    r0 * self.cos_t - r1 * self.sin_t,
                    r0 * self.sin_t + r1 * self.cos_t,
                ]
            }
            false => {
                self.count = 0;
                let angle = f64::from(self.made as f32 * self.theta);
                let (sin, cos) = (angle.sin() as f32, angle.cos() as f32);
                let [o0, o1] = self.offset;
                [-o0 * cos + o1 * sin, -o0 * sin - o1 * cos]
            }
        };
        self.linear += self.linear_per_chord;
    }

    /// The chord end after `made` chords, the iterator moved on to it:
    /// what `made` calls of `next` give last, without the rotations
    /// before the last exact point (a multiple of `ARC_CORRECTION + 1`
    /// chords at or before it; the normal's steps are added one by one,
    /// as grbl adds them). `made` is at most the chord count.
    pub(super) fn jump(&mut self, made: u32) -> Point {
        let made = made.clamp(1, self.chords);
        let exact = made - made % (ARC_CORRECTION + 1);
        if exact > self.made + 1 {
            // As `exact - 1` calls leave it, but for the rotation, which
            // call `exact` makes anew from sines and cosines.
            let adds = exact - 1 - self.made;
            if self.linear_per_chord != 0.0 {
                self.linear = (0..adds).fold(self.linear, |z, _| z + self.linear_per_chord);
            }
            self.made = exact - 1;
            self.count = ARC_CORRECTION;
        }
        // Turned to the chord end before, then made as `next` makes it.
        while self.made + 1 < made {
            self.made += 1;
            self.turn();
        }
        self.next().unwrap_or(self.end)
    }
}

impl Iterator for McArc {
    type Item = Point;

    #[inline(always)]
    fn next(&mut self) -> Option<Point> {
        self.made += 1;
        if self.made > self.chords {
            return None;
        }
        if self.made == self.chords {
            return Some(self.end);
        }
        self.turn();
        Some(self.plane.place(
            f64::from(self.center[0] + self.radius[0]),
            f64::from(self.center[1] + self.radius[1]),
            f64::from(self.linear),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{ArcPath, State};

    fn circle(r: f64, clockwise: bool) -> Move {
        Move {
            kind: MoveKind::Arc(ArcPath {
                center: [0.0; 3],
                plane: Plane::XY,
                clockwise,
                turns: 1,
            }),
            start: [r, 0.0, 0.0],
            end: [r, 0.0, 0.0],
            extra: [0.0; 6],
            state: State::default(),
            span: crate::source::Span::new(0, 1, 0, 0),
            guessed: [false; 3],
        }
    }

    #[test]
    fn mc_arc_points_drift_inwards_between_exact_ones() {
        // The third-order rotation shrinks the radius by θ⁴/24 a chord:
        // a circle of r 0.25 in 24 chords (θ = π/12) is 0.2497 from its
        // centre after 6 chords, as grbl 1.1h's mc_arc has it (traced in
        // its plan_buffer_line: X -0.0000609 Y -0.2497132), and exact again
        // at the 13th, where grbl takes sin and cos.
        let m = circle(0.25, true);
        let points: Vec<Point> = McArc::new(&m, 24, m.sweep()).collect();
        assert_eq!(points.len(), 24);
        let p6 = points[5];
        assert!((p6[0] - -0.000_060_9).abs() < 2e-7, "{p6:?}");
        assert!((p6[1] - -0.249_713_2).abs() < 2e-7, "{p6:?}");
        let r13 = points[12][0].hypot(points[12][1]);
        assert!((r13 - 0.25).abs() < 1e-6, "{r13}");
        assert_eq!(points[23], m.end);
        // Counter-clockwise goes the other way round.
        let ccw = circle(0.25, false);
        let ccw: Vec<Point> = McArc::new(&ccw, 24, ccw.sweep()).collect();
        assert!(ccw[5][1] > 0.249);
    }

    #[test]
    fn a_jump_lands_where_the_chords_one_by_one_do() {
        // A circle, and a helix whose normal grbl adds chord by chord in
        // single precision: from the start and from chords already made,
        // onto exact points and between them, and on to the end.
        let mut helix = circle(3.7, false);
        helix.end[2] = -1.3;
        for m in [circle(25.0, true), helix] {
            let n = 97;
            let all: Vec<Point> = McArc::new(&m, n, m.sweep()).collect();
            for (before, to) in [
                (0, 1),
                (0, 13),
                (0, 40),
                (5, 26),
                (14, 27),
                (30, 90),
                (0, 97),
            ] {
                let mut arc = McArc::new(&m, n, m.sweep());
                let _ = arc.by_ref().take(before).count();
                assert_eq!(arc.jump(to as u32), all[to - 1], "{before} → {to}");
                let rest: Vec<Point> = arc.collect();
                assert_eq!(rest, all[to..], "{before} → {to}");
            }
        }
    }

    #[test]
    fn points_go_to_the_nearest_whole_step() {
        // 250 steps/mm: 0.1 mm is 25 steps; 0.0021 is 0.525 of a step,
        // so 1; -0.002 is half a step, rounded away from zero.
        let steps = Steps::of([Some(250.0), Some(250.0), None]);
        let p = on_steps([0.1, 0.0021, 0.0013], &steps);
        assert!((p[0] - 0.1).abs() < 1e-16 && p[1] == 0.004, "{p:?}");
        assert_eq!(p[2], 0.0013);
        assert_eq!(on_steps([-0.002, 0.0, 0.0], &steps)[0], -0.004);
    }
}
