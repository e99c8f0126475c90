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
//! The first and last h chords are planned one by one, each corner
//! between two of them taken at v² without being worked out (the same
//! bound: `min(corner, v², v²)` is v²; only the first chord's corner,
//! with the move before, is), as is every chord
//! of an arc that does not qualify (a buffer too short for the feed: the
//! look-ahead then limits the speed, chord by chord). Where the machine's
//! steps are known the chords are `mc_arc`'s own on whole steps
//! (`steps.rs`), no longer alike: the same holds with L the shortest of
//! them and every corner between them checked, not only the end ones —
//! or, on arcs whose chords are long beside their steps, with L and the
//! corners bounded from the circle's chords and the steps' rounding
//! (`bounded_run`), the middle then summed from the circle within a
//! proven share of its stepped length, and only the end chords made.
//!
//! Architecture Invariant: planner arithmetic only, on the blocks and
//! limits of `block.rs`; never sees the IR.

use super::block::{
    direction, direction_and_length, dot, line_block, sized_block, sub, Block, Limits,
};
use super::steps::{on_steps, McArc, Steps};
use crate::toolpath::{Along, Move, MoveKind, Point};

/// What the planner takes: a block, or a run of an arc's middle chords.
pub(super) enum Piece {
    Block(Block),
    /// `chords` chords entered and left at the nominal speed: `run` has
    /// their total length, the nominal speed, and the least acceleration.
    /// The chords after it are `smooth_before` (no corner is worked out
    /// from it).
    Cruise {
        run: Block,
        chords: usize,
    },
}

/// The pieces of move `m`, the `index`th (its points `along` and its
/// `length`), handed to `out` in order, none marked as starting from rest
/// (the tally marks the first after a sync).
pub(super) fn pieces(
    m: &Move,
    (along, length): (&Along, f64),
    index: usize,
    (limits, lines): (&Limits, &mut LineSteps),
    out: &mut impl Take,
) {
    let chord = |from: Point, to: Point| chord_block(m, index, from, to, limits);
    let stepped = limits.steps_per_mm.iter().any(Option::is_some);
    let Some((sweep, r0, r1)) = along.arc_shape() else {
        let line = match stepped {
            true => {
                let start = lines.start_of(m);
                let end = lines.end_of(m);
                line_block(m, start, end, limits)
            }
            // Its ends as written: its length is known.
            false => sized_block(m, sub(m.end, m.start), length, limits),
        };
        if let Some(b) = line {
            out.take(Piece::Block(Block { source: index, ..b }));
        }
        return;
    };
    let n = arc_segments(r0, sweep, limits.arc_tolerance);
    if stepped {
        return stepped_arc(m, (sweep, r0, r1), index, n, (limits, lines), out);
    }
    let point = |k: usize| along.at(k as f64 / n as f64);
    if n < 4 {
        return (0..n).for_each(|k| out_chord(chord(point(k), point(k + 1)), out));
    }
    // The ends' points and chords, which the check, the end chords and
    // a run's last chord (two from the end in the usual run) need, each
    // found once.
    let ends = along.end_points(n);
    let at = |k: usize| match k {
        0..=2 => ends[k],
        _ if k + 3 >= n => ends[k + 6 - n],
        _ => point(k),
    };
    let end_chords = [
        chord(ends[0], ends[1]),
        chord(ends[1], ends[2]),
        chord(ends[4], ends[5]),
        chord(ends[5], ends[6]),
    ];
    let block = |k: usize| match k {
        0 | 1 => end_chords[k],
        _ if k + 2 >= n => end_chords[k + 4 - n],
        _ => chord(at(k), at(k + 1)),
    };
    let Some(Cruise { ends: h, length }) = cruise(m, n, (sweep, r0, r1), limits, &end_chords)
    else {
        return (0..n).for_each(|k| out_chord(block(k), out));
    };
    // Chords of some length (`cruise` checked the shortest), every corner
    // between them proved to allow the feed.
    (0..h).for_each(|k| out_chord(start_chord(k, block(k)), out));
    if let Some(template) = end_chords[2] {
        out.take(Piece::Cruise {
            run: run_block(m, template, length, limits),
            chords: n - 2 * h,
        });
    }
    (n - h..n).for_each(|k| out_chord(smooth(block(k)), out));
}

/// `chord` marked as after a corner proved to allow the feed (a run's
/// end chords but an arc's first).
#[inline(always)]
fn smooth(chord: Option<Block>) -> Option<Block> {
    chord.map(|b| Block {
        smooth_before: true,
        ..b
    })
}

/// A run's `k`th chord before its middle: after the first (whose corner
/// is with the move before), [`smooth`].
#[inline(always)]
fn start_chord(k: usize, chord: Option<Block>) -> Option<Block> {
    match k {
        0 => chord,
        _ => smooth(chord),
    }
}

/// The block of a run of `length` from one of arc `m`'s chords
/// (`template`: its nominal speed, the feed, is every chord's): the
/// least acceleration of the arc's axes, its corner after the chord
/// before it proved.
#[inline(always)]
fn run_block(m: &Move, template: Block, length: f64, limits: &Limits) -> Block {
    Block {
        length,
        accel: least(m, limits.max_accel),
        smooth_before: true,
        ..template
    }
}

/// The machine's steps (for lines and stepped arcs), and the end of the
/// last move as written and on its steps (the next move's start is most
/// often the same point, rounded once).
pub(super) struct LineSteps {
    steps: Steps,
    last_end: Option<(Point, Point)>,
}

impl LineSteps {
    pub(super) fn of(limits: &Limits) -> LineSteps {
        LineSteps {
            steps: Steps::of(limits.steps_per_mm),
            last_end: None,
        }
    }

    /// The start of `m` on its steps: the last end's, where it is that
    /// point.
    #[inline(always)]
    fn start_of(&self, m: &Move) -> Point {
        match self.last_end {
            Some((end, on)) if end == m.start => on,
            _ => on_steps(m.start, &self.steps),
        }
    }

    /// The end of `m` on its steps, kept for the next move's start.
    #[inline(always)]
    fn end_of(&mut self, m: &Move) -> Point {
        let on = on_steps(m.end, &self.steps);
        self.last_end = Some((m.end, on));
        on
    }
}

/// What takes the pieces: the planner (a closure, in tests).
pub(super) trait Take {
    fn take(&mut self, piece: Piece);
}

impl<F: FnMut(Piece)> Take for F {
    fn take(&mut self, piece: Piece) {
        self(piece)
    }
}

/// A chord with some length to `out`.
#[inline(always)]
fn out_chord(chord: Option<Block>, out: &mut impl Take) {
    if let Some(b) = chord {
        out.take(Piece::Block(b));
    }
}

/// The chord from `from` to `to` of move `m`, the `index`th, as a block
/// (`None`: no length).
#[inline(always)]
fn chord_block(m: &Move, index: usize, from: Point, to: Point, limits: &Limits) -> Option<Block> {
    line_block(m, from, to, limits).map(|b| Block { source: index, ..b })
}

/// How many chords grbl's `mc_arc` cuts an arc of `radius` through
/// `sweep` radians into: as many as keep each within the arc `tolerance`
/// of the arc.
pub(super) fn arc_segments(radius: f64, sweep: f64, tolerance: f64) -> usize {
    let chord_angle = 2.0 * (tolerance * (2.0 * radius - tolerance)).max(0.0).sqrt();
    let segments = match chord_angle > 0.0 {
        true => ((0.5 * sweep * radius) / (0.5 * chord_angle)).max(1.0),
        false => 1.0,
    };
    // Cut toward zero: `floor` (it is at least 1) without libm's call.
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
    let v2 = cruising_feed(m, n, limits)?.max(1e-9).powi(2);
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
    let ends = run_ends(v2, per_chord, n, limits)?;
    // grbl's corner (`junction_sqr`) at the sharpest end corner, at the
    // least acceleration: no corner between two chords is slower.
    let cos = (-dot(first.unit_out, second.unit_in)).max(-dot(before_last.unit_out, last.unit_in));
    let fast_enough = corner_sqr(cos, accel, limits) >= v2 * (1.0 + CORNER_MARGIN);
    if !fast_enough {
        return None;
    }
    Some(Cruise {
        ends,
        length: middle_length(m, n, ends, shape),
    })
}

/// How many of an arc's `n` chords to plan one by one at each end of its
/// run (the module's note): as many as reach the feed (`v2`, its square)
/// from a stop, each adding `per_chord` at least, fewer than the buffer
/// holds, and two chords or more left between them; `None`: no run.
fn run_ends(v2: f64, per_chord: f64, n: usize, limits: &Limits) -> Option<usize> {
    let ends = (v2 * (1.0 + SUM_MARGIN) / per_chord).ceil().max(1.0);
    let fits = ends < limits.blocks as f64 && n as f64 >= 2.0 * ends + 2.0;
    fits.then_some(ends as usize)
}

/// The feed (mm/s) of arc `m`, cut into `n` chords, if its chords may
/// cruise at it: within every rate of the arc's axes (so each chord's
/// nominal speed), four chords or more, a buffer of two blocks or more.
fn cruising_feed(m: &Move, n: usize, limits: &Limits) -> Option<f64> {
    let feed = m.state.feed_rate() / 60.0;
    let within_rates = feed > 0.0 && feed <= least(m, limits.max_rate);
    (n >= 4 && limits.blocks >= 2 && within_rates).then_some(feed)
}

/// grbl's corner speed squared (`junction_sqr`) where the chords' `cos`
/// (of the angle between the first reversed and the second) is taken at
/// `accel`: a bound on every chord corner as sharp or less, since no
/// corner of an arc's axes allows less than their least acceleration.
fn corner_sqr(cos: f64, accel: f64, limits: &Limits) -> f64 {
    if cos > 0.999_999 {
        return 0.0;
    }
    let sin_half = (0.5 * (1.0 - cos)).sqrt();
    match sin_half < 1.0 {
        true => accel * limits.junction_deviation * sin_half / (1.0 - sin_half),
        false => f64::INFINITY,
    }
}

/// Arc `m`'s `n` chords (through `sweep` radians) as grbl makes them
/// where the machine's steps are known (`steps.rs`): `mc_arc`'s chord
/// ends, each on its steps; a chord of no steps is no block, as grbl
/// drops it. The middle chords are a run where they provably cruise (the
/// module's note, each corner and length checked on the stepped chords
/// themselves).
fn stepped_arc(
    m: &Move,
    shape: (f64, f64, f64),
    index: usize,
    n: usize,
    (limits, lines): (&Limits, &mut LineSteps),
    out: &mut impl Take,
) {
    if let Some(run) = bounded_run(m, n, shape, limits) {
        stepped_ends(m, shape.0, n, run, index, (limits, lines), out);
        return;
    }
    walked_arc(m, shape.0, index, n, (limits, &lines.steps), out);
}

/// Arc `m`'s stepped chords, seen one by one: the middle ones a run if
/// each corner and length allows it (`stepped_run`), else each a block.
fn walked_arc(
    m: &Move,
    sweep: f64,
    index: usize,
    n: usize,
    (limits, steps): (&Limits, &Steps),
    out: &mut impl Take,
) {
    let chords = || {
        let mut from = on_steps(m.start, steps);
        McArc::new(m, n, sweep).map(move |p| {
            let to = on_steps(p, steps);
            (std::mem::replace(&mut from, to), to)
        })
    };
    let mut block = |(from, to): Chord| chord_block(m, index, from, to, limits);
    let Some(run) = stepped_run(m, n, limits, chords()) else {
        chords()
            .filter_map(&mut block)
            .for_each(|b| out.take(Piece::Block(b)));
        return;
    };
    // Every chord has steps and every corner allows the feed
    // (`stepped_run`): a corner worked out only into the first.
    for (k, chord) in run.first.into_iter().enumerate() {
        out_chord(start_chord(k, block(chord)), out);
    }
    if let Some(last) = block(run.last_middle) {
        out.take(Piece::Cruise {
            run: run_block(m, last, run.middle, limits),
            chords: run.chords,
        });
    }
    run.last
        .into_iter()
        .for_each(|chord| out_chord(smooth(block(chord)), out));
}

/// A stepped arc's middle chords as a run without seeing them, where
/// they cruise whatever their steps do (`steps.rs`). `mc_arc`'s chord
/// ends lie within `err` of its circle (or helix) through the start —
/// half a step on each axis, its single precision, its rotation's drift
/// between exact points — and its last, the arc's end, `dr` further (the
/// end radius's difference from the start's). So each chord is within
/// 2·err + dr of the circle's chord (length `chord`) and turns at most
/// θ + asin(2·err / chord) + asin((2·err + dr) / chord) from the one
/// before; with those bounds in place of the measured ones the module's
/// note holds as for `stepped_run`. The middle's length: the circle's
/// chords', plus what the steps move its two ends along its end chords
/// (`stepped_ends`); what is left of the stepped chords' sum is the
/// ends' single precision, the displacements of the points between
/// weighed by the turn of the chords at each (err · θ each), and a
/// second-order term, at most 2·err² / (chord − 2·err) a chord and never
/// below zero — within `MIDDLE_SHARE` of the middle's length, or the arc
/// is walked chord by chord.
fn bounded_run(
    m: &Move,
    n: usize,
    (sweep, r0, r1): (f64, f64, f64),
    limits: &Limits,
) -> Option<Cruise> {
    let v2 = cruising_feed(m, n, limits)?.powi(2);
    let MoveKind::Arc(a) = m.kind else {
        return None;
    };
    let (p, q, l) = a.plane.axes();
    let turns = n as f64;
    let theta = sweep / turns;
    let rise = m.end[l] - m.start[l];
    let half_sin = (0.5 * theta).sin();
    let chord = crate::geometry::hypot((2.0 * r0 * half_sin, rise / turns));
    let step = |i: usize| limits.steps_per_mm[i].map_or(0.0, |s| (0.5 / s).powi(2));
    let half_step = (step(p) + step(q) + if rise != 0.0 { step(l) } else { 0.0 }).sqrt();
    // Single precision: the centre and a point (a unit in the last place
    // of the largest coordinate each), the rotation's rounding over the
    // 12 rotations between exact points, the angle's, and the normal's
    // steps added one by one.
    let size = (a.center[p].abs().max(a.center[q].abs()) + r0)
        .max(m.start[l].abs())
        .max(m.end[l].abs());
    let added = if rise != 0.0 { turns * size } else { 0.0 };
    let float = f64::from(f32::EPSILON) * (2.0 * size + 64.0 * r0 + 4.0 * r0 * sweep + added);
    // The third-order rotation shrinks the radius by θ⁴/24 a chord and
    // turns short by θ⁵/30 a chord, for up to 12 chords.
    let unstepped = float + r0 * theta.powi(4);
    let err = half_step + unstepped;
    let dr = (r1 - r0).abs();
    // (NaN fails too.)
    let long = 4.0 * err + 2.0 * dr;
    if long.partial_cmp(&chord) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let accel = least(m, limits.max_accel);
    let widened = [2.0 * err / chord, (2.0 * err + dr) / chord];
    let fast_enough = turn_cos(theta, half_sin, widened)
        .is_some_and(|cos| corner_sqr(-cos, accel, limits) >= v2 * (1.0 + CORNER_MARGIN));
    if !fast_enough {
        return None;
    }
    let per_chord = 2.0 * accel * (chord - 2.0 * err - dr) * (1.0 - SUM_MARGIN);
    let ends = run_ends(v2, per_chord, n, limits)?;
    let middle = (n - 2 * ends) as f64;
    let length = middle * chord;
    // The ends' displacements are measured along chords of single
    // precision, within 2·unstepped / chord of the circle's.
    let at_ends = 2.0 * unstepped + 4.0 * err * unstepped / chord;
    let between = err * theta * middle;
    let second = 2.0 * middle * err * err / (chord - 2.0 * err);
    let off = at_ends + between + second;
    (off <= MIDDLE_SHARE * length).then_some(Cruise { ends, length })
}

/// The cosine of θ + asin(s₁) + asin(s₂) (`bounded_run`'s turn: the
/// circle's chords' θ, `half_sin` = sin θ/2, and the two widenings of
/// the steps, each sine below ½), if that sum is below π; by the angle
/// sums' formulas where θ < π/2, without an arcsine or a cosine.
fn turn_cos(theta: f64, half_sin: f64, [s1, s2]: [f64; 2]) -> Option<f64> {
    if theta >= std::f64::consts::FRAC_PI_2 {
        let turn = theta + s1.asin() + s2.asin();
        return (turn < std::f64::consts::PI).then(|| turn.cos());
    }
    let (c1, c2) = ((1.0 - s1 * s1).sqrt(), (1.0 - s2 * s2).sqrt());
    let (cos_w, sin_w) = (c1 * c2 - s1 * s2, s1 * c2 + c1 * s2);
    let cos_t = 1.0 - 2.0 * half_sin * half_sin;
    let sin_t = 2.0 * half_sin * (1.0 - half_sin * half_sin).sqrt();
    // Both sums within [0, π]: θ + w < π where cos w > cos(π − θ).
    (cos_w > -cos_t).then_some(cos_t * cos_w - sin_t * sin_w)
}

/// How far a stepped arc's run may be from the length of its stepped
/// chords (`bounded_run`), as a share of it: the planned time of its
/// middle chords is within as much of grbl's.
const MIDDLE_SHARE: f64 = 0.005;

/// The pieces of stepped arc `m` (the `index`th move) whose middle
/// chords `run` proved a run: its first and last `run.ends` chords as
/// `mc_arc` makes them and planned one by one, the run between them
/// ending with the stepped chord before the last ones.
fn stepped_ends(
    m: &Move,
    sweep: f64,
    n: usize,
    run: Cruise,
    index: usize,
    (limits, lines): (&Limits, &mut LineSteps),
    out: &mut impl Take,
) -> Option<()> {
    let h = run.ends;
    let mut arc = McArc::new(m, n, sweep);
    let block = |from: Point, to: Point| chord_block(m, index, from, to, limits);
    let steps = &lines.steps;
    let mut from = lines.start_of(m);
    let mut raw = m.start;
    // Every corner between two chords allows the feed (`bounded_run`): a
    // corner worked out only into the first.
    for k in 0..h {
        raw = arc.next()?;
        let to = on_steps(raw, steps);
        out_chord(start_chord(k, block(from, to)), out);
        from = to;
    }
    // The steps' displacement of the run's ends along its end chords:
    // the terms of its length that do not cancel (`bounded_run`).
    let off = |stepped: Point, raw: Point| std::array::from_fn(|i| stepped[i] - raw[i]);
    let after = arc.next()?;
    let first_end = dot(direction(raw, after), off(from, raw));
    // n ≥ 2h + 2: the run's last chord starts after the first h + 1.
    let raw_before = match n - h - 1 {
        k if k == h + 1 => after,
        k => arc.jump(k as u32),
    };
    let raw_end = arc.next()?;
    let mut from = on_steps(raw_end, steps);
    // The run's last chord as `mc_arc` has it, before its steps: its
    // direction, and the run's nominal speed.
    let raw_last = block(raw_before, raw_end)?;
    let last_end = dot(raw_last.unit_out, off(from, raw_end));
    let length = run.length + last_end - first_end;
    out.take(Piece::Cruise {
        run: run_block(m, raw_last, length, limits),
        chords: n - 2 * h,
    });
    for _ in n - h..n {
        let to = on_steps(arc.next()?, steps);
        out_chord(smooth(block(from, to)), out);
        from = to;
    }
    // The last chord end is the arc's end: the next move starts there.
    lines.last_end = Some((m.end, from));
    Some(())
}

/// A chord's ends.
type Chord = (Point, Point);

/// A stepped arc's chords when its middle ones cruise: the `first` and
/// `last` planned one by one, the run's length and count, and its last
/// chord.
struct SteppedRun {
    first: Vec<Chord>,
    middle: f64,
    chords: usize,
    last_middle: Chord,
    last: Vec<Chord>,
}

/// Arc `m`'s `n` stepped `chords`, seen once, as a run if its middle
/// ones provably cruise: every chord has steps, every corner between two
/// allows the feed, and h chords of the shortest reach it from a stop
/// (h below the buffer's depth, so only that many at each end are kept).
fn stepped_run(
    m: &Move,
    n: usize,
    limits: &Limits,
    chords: impl Iterator<Item = Chord>,
) -> Option<SteppedRun> {
    let v2 = cruising_feed(m, n, limits)?.powi(2);
    let accel = least(m, limits.max_accel);
    // corner_sqr(cos) ≥ v² (1 + margin) as a bound on cos, which is all
    // each corner needs: sin(θ/2) ≥ v² / (a·δ + v²).
    let need = v2 * (1.0 + CORNER_MARGIN);
    let sin_half = need / (accel * limits.junction_deviation + need);
    let sharpest = (1.0 - 2.0 * sin_half * sin_half).min(0.999_999);
    let keep = limits.blocks.min(n);
    let mut first: Vec<(Chord, f64)> = Vec::with_capacity(keep);
    let mut tail: std::collections::VecDeque<(Chord, f64)> =
        std::collections::VecDeque::with_capacity(keep + 1);
    let (mut total, mut shortest) = (0.0, f64::INFINITY);
    let mut before: Option<[f64; 3]> = None;
    for chord in chords {
        let (unit, length) = direction_and_length(chord.0, chord.1);
        if length.is_nan() || length <= 0.0 {
            return None;
        }
        if before.is_some_and(|b| -dot(b, unit) > sharpest) {
            return None;
        }
        before = Some(unit);
        (total, shortest) = (total + length, shortest.min(length));
        if first.len() < keep {
            first.push((chord, length));
        }
        if tail.len() > keep {
            tail.pop_front();
        }
        tail.push_back((chord, length));
    }
    let per_chord = 2.0 * accel * shortest * (1.0 - SUM_MARGIN);
    let h = run_ends(v2, per_chord, n, limits)?;
    first.truncate(h);
    let last = tail.split_off(tail.len() - h);
    let (last_middle, _) = *tail.back()?;
    let ends_length: f64 = first.iter().chain(&last).map(|(_, l)| l).sum();
    Some(SteppedRun {
        first: first.into_iter().map(|(c, _)| c).collect(),
        middle: total - ends_length,
        chords: n - 2 * h,
        last_middle,
        last: last.into_iter().map(|(c, _)| c).collect(),
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
    use crate::plan::tests::feed_move;
    use crate::toolpath::{ArcPath, ToolPath};

    fn machine(accel: [f64; 3], blocks: usize) -> Limits {
        Limits {
            controller: Controller::Grbl,
            max_rate: [80.0, 80.0, 20.0],
            max_accel: accel,
            rapid_rate: None,
            max_path_rate: f64::INFINITY,
            max_path_accel: f64::INFINITY,
            junction_deviation: 0.01,
            path_tolerance: 0.0,
            arc_tolerance: 0.002,
            blocks,
            tool_change_s: 0.0,
            spindle_start_s: 0.0,
            steps_per_mm: [None; 3],
        }
    }

    /// A line into the arc at a corner, the arc (radius `r`, ending
    /// `rise` higher and `grow` further out), a line out of it: as
    /// planned, and with the arc written as the lines of its chords
    /// (`stepped`: `mc_arc`'s).
    fn arc_and_its_chords(
        r: f64,
        grow: f64,
        rise: f64,
        feed: f64,
        stepped: bool,
    ) -> (ToolPath, ToolPath) {
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
        let points: Vec<Point> = match stepped {
            false => arc.points(n).collect(),
            true => std::iter::once(start)
                .chain(McArc::new(&arc, n, sweep))
                .collect(),
        };
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
            pieces(
                m,
                (&m.along(), m.length()),
                i,
                (limits, &mut LineSteps::of(limits)),
                &mut |p| count += usize::from(matches!(p, Piece::Cruise { .. })),
            );
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
            let (arc, chords) = arc_and_its_chords(r, grow, rise, feed, false);
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

    #[test]
    fn a_stepped_arc_takes_the_time_of_its_stepped_chords_one_by_one() {
        // At 250 steps/mm: circles with a run of middle chords (a helix, a
        // CAM end radius off by rounding, axes of unequal acceleration),
        // and arcs of a fraction of a millimetre, whose chords of a few
        // steps are planned one by one.
        let cases = [
            (10.0, 0.0, 0.0, 1500.0, [250.0, 250.0, 100.0], true),
            (10.0, 0.0004, 2.0, 1000.0, [500.0, 300.0, 100.0], true),
            (40.0, 0.0, 0.0, 3000.0, [200.0, 400.0, 100.0], true),
            (0.25, 0.0, 0.0, 1000.0, [250.0, 250.0, 100.0], false),
            (0.01, 0.0, 0.0, 1000.0, [1000.0, 500.0, 100.0], false),
        ];
        for (r, grow, rise, feed, accel, expect_run) in cases {
            let limits = Limits {
                steps_per_mm: [Some(250.0); 3],
                ..machine(accel, 15)
            };
            let (arc, chords) = arc_and_its_chords(r, grow, rise, feed, true);
            assert_eq!(runs(&arc, &limits) > 0, expect_run, "r {r} feed {feed}");
            let [into, middle, out] = [0, 1, 2].map(|i| &arc.moves[i]);
            let (_, walked) = bounded_and_walked([into, middle, out], &limits);
            let one_by_one = crate::plan::plan(&chords, Some(&limits)).time_s.unwrap();
            let off = (walked - one_by_one).abs() / one_by_one;
            assert!(off < 1e-12, "r {r}: {walked} vs {one_by_one} ({off:e})");
            // Where the run is proven without the chords, within its
            // share of them (`a_bounded_run_is_within_…`).
            let planned = crate::plan::plan(&arc, Some(&limits)).time_s.unwrap();
            let off = (planned - walked).abs() / walked;
            assert!(
                off <= MIDDLE_SHARE,
                "r {r}: {planned} vs {walked} ({off:e})"
            );
            // The steps move the corners of the small arcs: not the
            // exact chords' time.
            let exact = crate::plan::plan(&arc, Some(&machine(accel, 15)))
                .time_s
                .unwrap();
            let moved = (planned - exact).abs() / exact;
            assert_eq!(moved > 1e-3, r < 1.0, "r {r}: {planned} vs {exact}");
        }
    }

    /// The time of `into`, `arc` and `out` on `limits`, the arc's
    /// chords as `pieces` hands them and as `walked_arc` does.
    fn bounded_and_walked(moves: [&Move; 3], limits: &Limits) -> (f64, f64) {
        let time = |walk: bool| {
            let mut planner = crate::plan::Planner::new(limits);
            let mut total = 0.0;
            let mut timed = |_: usize, s: f64| total += s;
            for (i, m) in moves.into_iter().enumerate() {
                let along = m.along();
                let mut take = |p: Piece| planner.take(p, &mut timed);
                match (walk, along.arc_shape()) {
                    (true, Some((sweep, r0, _))) => {
                        let n = arc_segments(r0, sweep, limits.arc_tolerance);
                        walked_arc(
                            m,
                            sweep,
                            i,
                            n,
                            (limits, &Steps::of(limits.steps_per_mm)),
                            &mut take,
                        );
                    }
                    _ => pieces(
                        m,
                        (&along, along.length()),
                        i,
                        (limits, &mut LineSteps::of(limits)),
                        &mut take,
                    ),
                }
            }
            planner.finish(&mut timed);
            total
        };
        (time(false), time(true))
    }

    /// Numbers uniform in `low..high` from a xorshift seeded by `seed`:
    /// the same cases on every run.
    fn uniform_from(mut seed: u64) -> impl FnMut(f64, f64) -> f64 {
        move |low, high| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            low + (high - low) * (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn the_turns_cosine_by_the_angle_sums_is_the_arcsines() {
        // θ over (0, π), each sine below ½: the cosine within 1e-12 of
        // cos(θ + asin s₁ + asin s₂), and None where that sum reaches π.
        let mut uniform = uniform_from(0x9e37_79b9_7f4a_7c15);
        for _ in 0..100_000 {
            let theta = uniform(1e-6, std::f64::consts::PI - 1e-6);
            let s = [uniform(0.0, 0.5), uniform(0.0, 0.5)];
            let turn = theta + s[0].asin() + s[1].asin();
            let cos = turn_cos(theta, (0.5 * theta).sin(), s);
            if (turn - std::f64::consts::PI).abs() < 1e-9 {
                continue;
            }
            match cos {
                Some(c) => assert!(
                    turn < std::f64::consts::PI && (c - turn.cos()).abs() < 1e-12,
                    "{theta} {s:?}: {c} vs {}",
                    turn.cos()
                ),
                None => assert!(turn > std::f64::consts::PI, "{theta} {s:?}"),
            }
        }
    }

    #[test]
    fn a_bounded_run_is_within_its_bound_of_the_stepped_chords_walked() {
        // 20,000 arcs of every size, place, direction, sweep and rise
        // (some ending off their radius, as CAM's do), on machines of every step, feed and acceleration: where
        // `bounded_run` finds a run, the planned time differs from the
        // chords walked one by one only by what the middle's length does,
        // within the bound it proves.
        let mut uniform = uniform_from(0x2545_f491_4f6c_dd1d);
        let (mut bounded, mut worst_share, mut worst_time) = (0, 0.0_f64, 0.0_f64);
        for _ in 0..20_000 {
            let r = 10f64.powf(uniform(-0.5, 2.0));
            let center = [uniform(-400.0, 400.0), uniform(-400.0, 400.0), 0.0];
            let (a0, sweep) = (uniform(0.0, 6.3), uniform(0.2, 6.3));
            let rise = if uniform(0.0, 1.0) < 0.3 {
                uniform(-5.0, 5.0)
            } else {
                0.0
            };
            let clockwise = uniform(0.0, 1.0) < 0.5;
            let turn = if clockwise { -sweep } else { sweep };
            let at = |a: f64, z: f64| [center[0] + r * a.cos(), center[1] + r * a.sin(), z];
            let (start, mut end) = (at(a0, 0.0), at(a0 + turn, rise));
            // A CAM end a few microns off the radius, now and then.
            if uniform(0.0, 1.0) < 0.3 {
                end[0] += uniform(-0.003, 0.003);
            }
            let feed = uniform(100.0, 6000.0);
            let steps = uniform(40.0, 1000.0);
            let accel = uniform(50.0, 2000.0);
            let limits = Limits {
                steps_per_mm: [Some(steps), Some(steps), Some(steps * 1.6)],
                max_rate: [120.0, 120.0, 40.0],
                ..machine([accel, accel * 0.8, 100.0], 15)
            };
            let arc = Move {
                kind: MoveKind::Arc(ArcPath {
                    center,
                    plane: Plane::XY,
                    clockwise,
                    turns: 1,
                }),
                ..feed_move(MoveKind::Feed, start, end, feed)
            };
            let (sweep, r0, r1) = arc.along().arc_shape().unwrap();
            let n = arc_segments(r0, sweep, limits.arc_tolerance);
            let Some(run) = bounded_run(&arc, n, (sweep, r0, r1), &limits) else {
                continue;
            };
            bounded += 1;
            let into = feed_move(
                MoveKind::Feed,
                [start[0] - 3.0, start[1] + 1.0, 0.0],
                start,
                feed,
            );
            let out = feed_move(
                MoveKind::Feed,
                end,
                [end[0] + 2.0, end[1] - 4.0, rise],
                feed,
            );
            let (with_run, walked) = bounded_and_walked([&into, &arc, &out], &limits);
            let middle_s = run.length / (feed / 60.0);
            let share = (with_run - walked).abs() / middle_s;
            assert!(
                share <= MIDDLE_SHARE,
                "r {r} sweep {sweep} rise {rise} feed {feed} steps {steps}: {with_run} vs {walked}"
            );
            worst_share = worst_share.max(share);
            worst_time = worst_time.max((with_run - walked).abs() / walked);
        }
        eprintln!(
            "{bounded} of 20000 arcs bounded; the middle's time off by at most {:.2e} of it, \
             the whole by {:.2e}",
            worst_share, worst_time
        );
        assert!(bounded > 5_000, "{bounded}");
    }
}
