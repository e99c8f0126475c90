//! grbl's chords of a move (`mc_arc` cuts an arc into chords within the
//! arc tolerance), handed to the planner as pieces: each chord a block,
//! or, where the planner provably runs them at the feed, an arc's middle
//! chords as one run timed in closed form.
//!
//! Why a run is exact. Let v be the feed, every chord's nominal speed
//! (the feed is within each axis's rate the arc uses), s_k = 2 a_k L_k
//! what chord k adds to a speed squared (a_k ≥ a, the least acceleration
//! of the arc's axes; L_k ≥ L, the shorter end chord: lengths change
//! monotonically along an arc), and every junction between two chords at
//! least v² (its bound from the sharpest end corner at acceleration a).
//! Take h with h·2aL ≥ v², h < the buffer's depth, n ≥ 2h + 2. Then the
//! reverse pass gives every chord 1 ..= n − h − 1 the limit v² as soon as
//! the buffer reaches chord h (h chords after it add at least v²); the
//! forward pass reaches v² by chord h from any entry; so chords h ..
//! n − h − 1 enter and leave at v: each takes L_k / v, whatever the
//! buffer holds, and the blocks before them see the limit v² at chord h.
//! The first and last h chords are planned one by one, as is every chord
//! of an arc that does not qualify (a buffer too short for the feed: the
//! look-ahead then limits the speed, chord by chord).
//!
//! Architecture Invariant: planner arithmetic only, on the blocks and
//! limits of `block.rs`; never sees the IR.

use super::block::{dot, line_block, Block, Limits};
use crate::toolpath::{Along, Move, MoveKind, Point};

/// What the planner takes: a block, or a run of an arc's middle chords.
pub(super) enum Piece {
    Block(Block),
    /// `chords` chords entered and left at the nominal speed: `run` has
    /// their total length, the nominal speed, and the least acceleration;
    /// `last` is the last of them (the next chord's corner is from it).
    Cruise {
        run: Block,
        chords: usize,
        last: Block,
    },
}

/// The pieces of move `m`, the `index`th (its points `along`), handed to
/// `out` in order; the first chord starts from rest after a sync
/// (`stopped`).
pub(super) fn pieces(
    m: &Move,
    along: &Along,
    index: usize,
    stopped: bool,
    limits: &Limits,
    out: &mut impl FnMut(Piece),
) {
    let chord = |k: usize, from: Point, to: Point| {
        line_block(m, from, to, limits).map(|b| Block {
            stopped_before: stopped && k == 0,
            source: index,
            ..b
        })
    };
    let Some((sweep, r0, r1)) = along.arc_shape() else {
        if let Some(b) = chord(0, m.start, m.end) {
            out(Piece::Block(b));
        }
        return;
    };
    let n = arc_segments(r0, sweep, limits.arc_tolerance);
    let point = |k: usize| along.at(k as f64 / n as f64);
    if n < 4 {
        return (0..n).for_each(|k| out_chord(chord(k, point(k), point(k + 1)), out));
    }
    // The ends' points and chords, which the check and the end chords
    // both need, each found once.
    let ends = [
        point(0),
        point(1),
        point(2),
        point(n - 2),
        point(n - 1),
        point(n),
    ];
    let at = |k: usize| match k {
        0..=2 => ends[k],
        _ if k + 2 >= n => ends[k + 5 - n],
        _ => point(k),
    };
    let end_chords = [
        chord(0, ends[0], ends[1]),
        chord(1, ends[1], ends[2]),
        chord(n - 2, ends[3], ends[4]),
        chord(n - 1, ends[4], ends[5]),
    ];
    let block = |k: usize| match k {
        0 | 1 => end_chords[k],
        _ if k + 2 >= n => end_chords[k + 4 - n],
        _ => chord(k, at(k), at(k + 1)),
    };
    let Some(Cruise { ends: h, length }) = cruise(m, n, (sweep, r0, r1), limits, &end_chords)
    else {
        return (0..n).for_each(|k| out_chord(block(k), out));
    };
    (0..h).for_each(|k| out_chord(block(k), out));
    // Chords of some length (`cruise` checked the shortest).
    if let Some(last) = block(n - h - 1) {
        let run = Block { length, ..last };
        let accel = least(m, limits.max_accel);
        out(Piece::Cruise {
            run: Block { accel, ..run },
            chords: n - 2 * h,
            last,
        });
    }
    (n - h..n).for_each(|k| out_chord(block(k), out));
}

/// A chord with some length to `out`.
fn out_chord(chord: Option<Block>, out: &mut impl FnMut(Piece)) {
    if let Some(b) = chord {
        out(Piece::Block(b));
    }
}

/// How many chords grbl's `mc_arc` cuts an arc of `radius` through
/// `sweep` radians into: as many as keep each within the arc `tolerance`
/// of the arc.
pub(super) fn arc_segments(radius: f64, sweep: f64, tolerance: f64) -> usize {
    let chord_angle = 2.0 * (tolerance * (2.0 * radius - tolerance)).max(0.0).sqrt();
    let segments = match chord_angle > 0.0 {
        true => ((0.5 * sweep * radius) / (0.5 * chord_angle))
            .floor()
            .max(1.0),
        false => 1.0,
    };
    (segments as usize).clamp(1, 1 << 20)
}

/// The least of `limits` over the axes arc `m` moves (its plane's, and
/// the normal's when it is a helix): no chord's limit along it is lower.
fn least(m: &Move, limits: [f64; 3]) -> f64 {
    let MoveKind::Arc(a) = m.kind else {
        return limits.into_iter().fold(f64::INFINITY, f64::min);
    };
    let (p, q, l) = a.plane.axes();
    let plane = limits[p].min(limits[q]);
    match m.end[l] != m.start[l] {
        true => plane.min(limits[l]),
        false => plane,
    }
}

/// An arc's middle chords as a run: `ends` chords at each end planned
/// one by one, the middle ones' total `length`.
struct Cruise {
    ends: usize,
    length: f64,
}

/// Margins for the rounding of what the proof (the module's note) bounds:
/// a sum of a few speeds squared, a corner's speed squared.
const SUM_MARGIN: f64 = 1e-9;
const CORNER_MARGIN: f64 = 1e-6;
/// Arcs whose radius changes more than this share of the radius per
/// radian are spirals whose corners the end corners may not bound.
const SPIRAL_LIMIT: f64 = 1e-3;

/// The run of arc `m`'s `n` chords (its sweep and its radii at the start
/// and the end in `shape`, its first two and last two chords in
/// `end_chords`), if the middle ones provably cruise (the module's note).
fn cruise(
    m: &Move,
    n: usize,
    shape: (f64, f64, f64),
    limits: &Limits,
    end_chords: &[Option<Block>; 4],
) -> Option<Cruise> {
    let feed = m.state.feed_rate() / 60.0;
    let within_rates = feed > 0.0 && feed <= least(m, limits.max_rate);
    if n < 4 || limits.blocks < 2 || !within_rates {
        return None;
    }
    let v2 = feed.max(1e-9).powi(2);
    let accel = least(m, limits.max_accel);
    let (sweep, r0, r1) = shape;
    let turn = r0.min(r1) * sweep;
    let circle_like = turn > 0.0 && (r1 - r0).abs() <= SPIRAL_LIMIT * turn;
    if !circle_like {
        return None;
    }
    let [Some(first), Some(second), Some(before_last), Some(last)] = *end_chords else {
        return None;
    };
    let shortest = first.length.min(last.length) * (1.0 - SUM_MARGIN);
    let per_chord = 2.0 * accel * shortest;
    if per_chord.is_nan() || per_chord <= 0.0 {
        return None;
    }
    let ends = (v2 * (1.0 + SUM_MARGIN) / per_chord).ceil().max(1.0);
    if ends >= limits.blocks as f64 || (n as f64) < 2.0 * ends + 2.0 {
        return None;
    }
    // grbl's corner (`junction_sqr`) at the sharpest end corner, at the
    // least acceleration: no corner between two chords is slower.
    let cos = (-dot(first.unit_out, second.unit_in)).max(-dot(before_last.unit_out, last.unit_in));
    if cos > 0.999_999 {
        return None;
    }
    let sin_half = (0.5 * (1.0 - cos)).sqrt();
    let corner = match sin_half < 1.0 {
        true => accel * limits.junction_deviation * sin_half / (1.0 - sin_half),
        false => f64::INFINITY,
    };
    let fast_enough = corner >= v2 * (1.0 + CORNER_MARGIN);
    if !fast_enough {
        return None;
    }
    let ends = ends as usize;
    Some(Cruise {
        ends,
        length: middle_length(m, n, ends, shape),
    })
}

/// The total length of chords `ends .. n - ends` of arc `m` cut into `n`
/// (its `sweep`, radius `r0` at the start, `r1` at the end, as
/// [`Move::along`] has them): each from its radii and the angle between
/// them, without their points.
fn middle_length(m: &Move, n: usize, ends: usize, (sweep, r0, r1): (f64, f64, f64)) -> f64 {
    let MoveKind::Arc(a) = m.kind else {
        return 0.0;
    };
    let (_, _, l) = a.plane.axes();
    let half = (0.5 * sweep / n as f64).sin();
    let rise = (m.end[l] - m.start[l]) / n as f64;
    let radius = |k: usize| r0 + (r1 - r0) * (k as f64 / n as f64);
    let length = |k: usize| {
        let (a, b) = (radius(k), radius(k + 1));
        ((b - a).powi(2) + 4.0 * a * b * half * half + rise * rise).sqrt()
    };
    match r1 == r0 {
        true => (n - 2 * ends) as f64 * length(ends),
        false => (ends..n - ends).map(length).sum(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::machine::Controller;
    use crate::ir::Plane;
    use crate::toolpath::{ArcPath, State, ToolPath};

    fn machine(accel: [f64; 3], blocks: usize) -> Limits {
        Limits {
            controller: Controller::Grbl,
            max_rate: [80.0, 80.0, 20.0],
            max_accel: accel,
            rapid_rate: None,
            junction_deviation: 0.01,
            path_tolerance: 0.0,
            arc_tolerance: 0.002,
            blocks,
            tool_change_s: 0.0,
            spindle_start_s: 0.0,
        }
    }

    fn feed_move(kind: MoveKind, start: Point, end: Point, feed: f64) -> Move {
        Move {
            kind,
            start,
            end,
            extra: [0.0; 6],
            state: State {
                feed,
                tool: 1,
                ..State::default()
            },
            span: crate::source::Span::new(0, 1, 0, 0),
            guessed: [false; 3],
        }
    }

    /// A line into the arc at a corner, the arc (radius `r`, ending
    /// `rise` higher and `grow` further out), a line out of it: as
    /// planned, and with the arc written as the lines of its chords.
    fn arc_and_its_chords(r: f64, grow: f64, rise: f64, feed: f64) -> (ToolPath, ToolPath) {
        let start = [r, 0.0, 0.0];
        let end = [-(r + grow), 0.0, rise];
        let arc = Move {
            kind: MoveKind::Arc(ArcPath {
                center: [0.0; 3],
                plane: Plane::XY,
                clockwise: false,
                turns: 1,
            }),
            ..feed_move(MoveKind::Feed, start, end, feed)
        };
        let into = feed_move(MoveKind::Feed, [r - 3.0, -4.0, 0.0], start, feed);
        let out = feed_move(MoveKind::Feed, end, [-(r + grow) - 5.0, 2.0, rise], feed);
        let (sweep, radius, _) = arc.along().arc_shape().unwrap();
        let n = arc_segments(radius, sweep, 0.002);
        let points: Vec<Point> = arc.points(n).collect();
        let mut lines = vec![into];
        lines.extend(
            points
                .windows(2)
                .map(|p| feed_move(MoveKind::Feed, p[0], p[1], feed)),
        );
        lines.push(out);
        let path = |moves| ToolPath {
            moves,
            ..ToolPath::default()
        };
        (path(vec![into, arc, out]), path(lines))
    }

    /// Runs in `path`'s pieces on `limits`.
    fn runs(path: &ToolPath, limits: &Limits) -> usize {
        let mut count = 0;
        for (i, m) in path.moves.iter().enumerate() {
            pieces(m, &m.along(), i, i == 0, limits, &mut |p| {
                count += usize::from(matches!(p, Piece::Cruise { .. }))
            });
        }
        count
    }

    #[test]
    fn an_arc_with_a_run_takes_the_time_of_its_chords_one_by_one() {
        // Circles, a CAM arc whose end radius is off by rounding, a
        // helix, a feed that needs most of the buffer, axes of unequal
        // acceleration, a buffer too short for the feed (no run).
        let cases = [
            (2.5, 0.0, 0.0, 800.0, [250.0, 250.0, 100.0], 16, true),
            (10.0, 0.0004, 0.0, 3000.0, [500.0, 300.0, 100.0], 16, true),
            (10.0, 0.0, 2.0, 1000.0, [500.0, 500.0, 200.0], 16, true),
            (40.0, 0.0, 0.0, 3000.0, [200.0, 400.0, 100.0], 16, true),
            (40.0, 0.0, 0.0, 4500.0, [50.0, 50.0, 100.0], 16, false),
            (5.0, 0.0, 0.0, 1200.0, [250.0, 250.0, 100.0], 4, true),
        ];
        for (r, grow, rise, feed, accel, blocks, expect_run) in cases {
            let limits = machine(accel, blocks);
            let (arc, chords) = arc_and_its_chords(r, grow, rise, feed);
            assert_eq!(
                runs(&arc, &limits) > 0,
                expect_run,
                "r {r} feed {feed} {accel:?}"
            );
            let planned = crate::plan::plan(&arc, Some(&limits)).time_s.unwrap();
            let one_by_one = crate::plan::plan(&chords, Some(&limits)).time_s.unwrap();
            let off = (planned - one_by_one).abs() / one_by_one;
            assert!(
                off < 1e-12,
                "r {r} feed {feed}: {planned} vs {one_by_one} ({off:e})"
            );
        }
    }
}
