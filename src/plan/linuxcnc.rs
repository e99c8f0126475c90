//! LinuxCNC's trajectory planner as `ger stats` models it (learnt from
//! `src/emc/tp/` of LinuxCNC: `tc.c`, `blendmath.c`). Each move is one
//! segment: a line at its feed within each axis's velocity and
//! acceleration and the path's (`[TRAJ]`); an arc whole, each of its
//! plane's axes and (a helix) its normal axis held to its limits over
//! its share of the path, and held to the speed at which its normal
//! acceleration stays within `BLEND_ACC_RATIO_NORMAL` of that
//! acceleration, its tangential acceleration the rest. Where one segment
//! meets the next: under G61.1 a stop; under G61 a stop unless they are
//! tangent; under G64 the speed of the circular blend LinuxCNC puts in
//! the corner, as large as the tolerance (P, else the profile's, else a
//! quarter of each move) and half of each move allow.
//!
//! Left out (README, "What the model covers"): the blend arc's shortening
//! of the path (the corner is taken at the blend's speed, over the
//! programmed length), the larger radius of curvature LinuxCNC takes for
//! a helix (`pmCircleEffectiveMinRadius`: ger keeps the circle's, the
//! slower), LinuxCNC's merging of short collinear moves (G64
//! Q), the S-curve planner, the exact path LinuxCNC keeps inside canned
//! cycles (ger's output has their moves, not the cycle).
//!
//! Architecture Invariant: planner arithmetic only, on the blocks and
//! limits of `plan.rs`; never sees the IR.

use super::block::{along, direction, dot, sized_block, sub, Block, Limits};
use crate::ir::PathControl;
use crate::toolpath::{Along, Move, MoveKind};

/// `BLEND_ACC_RATIO_TANGENTIAL`: the share of the acceleration an arc
/// keeps for speeding up and slowing down at its speed limit.
const ACC_RATIO_TANGENTIAL: f64 = 0.5;
/// What a blend may take of each move (`tcFindBlendTolerance`'s ratio for
/// the tolerance when none is given).
const TOLERANCE_RATIO: f64 = 0.25;
/// `BLEND_DIST_FRACTION`: how much of each move a blend may consume.
const BLEND_DIST_FRACTION: f64 = 0.5;
/// Directions this close (cosine) are tangent: no corner.
const TANGENT_COS: f64 = 0.999_999;

/// `BLEND_ACC_RATIO_NORMAL`: the share of the acceleration left for the
/// normal acceleration of an arc or a blend.
fn acc_ratio_normal() -> f64 {
    (1.0 - ACC_RATIO_TANGENTIAL * ACC_RATIO_TANGENTIAL).sqrt()
}

/// The segment of move `m`, the `index`th (its points `along` and its
/// `length`), if it has some length.
pub(super) fn block(
    m: &Move,
    (along, length): (&Along, f64),
    index: usize,
    limits: &Limits,
) -> Option<Block> {
    let block = match m.kind {
        MoveKind::Arc(_) => arc_block(m, (along, length), limits),
        MoveKind::Rapid | MoveKind::Feed => {
            let line = sized_block(m, sub(m.end, m.start), length, limits);
            line.map(|b| Block {
                nominal: b.nominal.min(limits.max_path_rate),
                accel: b.accel.min(limits.max_path_accel),
                ..b
            })
        }
    };
    block.map(|b| Block { source: index, ..b })
}

/// An arc: its speed held where the normal acceleration `v²/r` would pass
/// its share of the plane's acceleration (`tcUpdateArcLimits`).
fn arc_block(m: &Move, (along, length): (&Along, f64), limits: &Limits) -> Option<Block> {
    let (MoveKind::Arc(a), Some((_, radius, _))) = (m.kind, along.arc_shape()) else {
        return None;
    };
    if length <= 0.0 {
        return None;
    }
    let (p, q, n) = a.plane.axes();
    let shares = helix_shares(length, m.end[n] - m.start[n]);
    let a_max = over_shares(limits.max_accel, (p, q, n), shares).min(limits.max_path_accel);
    let v_axes = over_shares(limits.max_rate, (p, q, n), shares).min(limits.max_path_rate);
    let v_cutoff = (acc_ratio_normal() * a_max * radius).sqrt();
    let feed = (m.state.feed_rate() / 60.0).min(v_axes);
    let (nominal, ratio) = match feed * feed / radius.max(1e-12) > acc_ratio_normal() * a_max {
        true => (v_cutoff, ACC_RATIO_TANGENTIAL),
        false => {
            let normal = feed * feed / radius.max(1e-12) / a_max;
            (feed, (1.0 - normal * normal).max(0.0).sqrt())
        }
    };
    let step = 1e-6;
    Some(Block {
        length,
        unit_in: direction(m.start, along.at(step)),
        unit_out: direction(along.at(1.0 - step), m.end),
        nominal: nominal.max(1e-9),
        accel: (a_max * ratio).max(1e-9),
        stopped_before: false,
        smooth_before: false,
        control: m.state.path_control,
        source: 0,
    })
}

/// The shares of a helix `length` long that lie in its plane and along
/// its normal axis, whose ends differ by `rise` (an arc in its plane:
/// all in the plane).
fn helix_shares(length: f64, rise: f64) -> (f64, f64) {
    match rise == 0.0 {
        true => (1.0, 0.0),
        false => (
            (length * length - rise * rise).max(0.0).sqrt() / length,
            rise.abs() / length,
        ),
    }
}

/// The largest path speed or acceleration of a helix whose limits per
/// axis are `limits`: the slower of the plane's two axes over the
/// plane's share of the path, and the normal axis over its share. As
/// LinuxCNC's canon (`ARC_FEED` in `emccanon.cc`) limits a helix: the
/// time the circle needs at the plane's axes' limits and the time the
/// rise needs at the normal axis's, whichever is longer, over the whole
/// length, for the maximum velocity, and the same with accelerations
/// for the maximum acceleration the planner then splits between normal
/// and tangential.
fn over_shares(
    limits: [f64; 3],
    (p, q, n): (usize, usize, usize),
    (plane, normal): (f64, f64),
) -> f64 {
    let in_plane = limits[p].min(limits[q]) / plane;
    match normal > 0.0 {
        true => in_plane.min(limits[n] / normal),
        false => in_plane,
    }
}

/// The largest speed squared from `a` into `b`: the path control in force
/// while `a` runs decides how it ends.
pub(super) fn junction_sqr(a: &Block, b: &Block, limits: &Limits) -> f64 {
    let cos = dot(a.unit_out, b.unit_in);
    let tangent = cos > TANGENT_COS;
    match a.control {
        PathControl::ExactStop => 0.0,
        PathControl::ExactPath if tangent => f64::INFINITY,
        PathControl::ExactPath => 0.0,
        PathControl::Blend { .. } if tangent => f64::INFINITY,
        PathControl::Blend { tolerance, .. } => {
            let tolerance = tolerance.unwrap_or(limits.path_tolerance);
            blend_speed(a, b, cos, tolerance, limits).powi(2)
        }
    }
}

/// The speed of the circular blend LinuxCNC puts in the corner between
/// `a` and `b` (`blendComputeParameters`): its radius as large as the
/// tolerance and half of each move allow, its speed that at which the
/// normal acceleration stays within its share.
fn blend_speed(a: &Block, b: &Block, cos: f64, tolerance: f64, limits: &Limits) -> f64 {
    // θ, half the angle between the two moves' lines at the corner (π/2
    // straight on, 0 straight back), by its sine and cosine from the
    // half-angle formulas: cos 2θ = x. Straight back (θ = 0): a stop.
    let x = (-cos).clamp(-1.0, 1.0);
    if x >= 1.0 {
        return 0.0;
    }
    let cos_sqr = 0.5 * (1.0 + x);
    let (sin, cos) = ((0.5 * (1.0 - x)).sqrt(), cos_sqr.sqrt());
    let quarter = TOLERANCE_RATIO * a.length.min(b.length);
    let tolerance = match tolerance > 0.0 {
        true => tolerance.min(quarter),
        false => quarter,
    };
    // tolerance / (1 − sin θ), without the cancellation near straight on:
    // 1 − sin θ = cos² θ / (1 + sin θ).
    let h = tolerance * (1.0 + sin) / cos_sqr;
    let d_tol = cos * h;
    let d_lengths = BLEND_DIST_FRACTION * a.length.min(b.length);
    let radius = sin / cos * d_tol.min(d_lengths);
    let a_max = along(limits.max_accel, a.unit_out)
        .min(along(limits.max_accel, b.unit_in))
        .min(limits.max_path_accel);
    (acc_ratio_normal() * a_max * radius).sqrt()
}
