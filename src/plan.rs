//! The run time of a tool path on a machine, planned as its controller
//! plans it (SPEC §9). grbl: each move a block (arcs cut into the chords
//! grbl makes of them within its arc tolerance), its speed limited per
//! axis, corners by junction deviation. LinuxCNC (`linuxcnc.rs`): each
//! move a segment (arcs whole, held to the speed their radius allows),
//! a stop after every move under G61.1 and at every corner under G61,
//! corners blended within the G64 tolerance. Both: accelerations per
//! axis, trapezoids, and a look-ahead as deep as the planner's buffer,
//! whose last block must be able to stop. The controller stops where it
//! syncs spindle or coolant, at dwells, tool changes and program stops.
//! Beside it, the length / feed figure other tools give.
//!
//! Architecture Invariant: reads a [`ToolPath`] and a
//! [`Machine`](crate::driver::machine::Machine) only;
//! never sees the IR or the program text.

mod block;
mod chords;
mod linuxcnc;
mod steps;

pub use block::Limits;
mod tally;

use block::{along, direction, dot, Block};
use chords::Piece;
pub use tally::Tally;

use crate::driver::machine::Controller;
use crate::toolpath::{EventKind, Move, MoveKind, Point, ToolPath};
use serde::Serialize;

/// The planned figures of a program.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Figures {
    /// Planned with acceleration (dwells, tool changes and spindle starts
    /// included); `None` without a machine.
    pub time_s: Option<f64>,
    /// Feed moves' length over their feed, rapids at the machine's rapid
    /// rate (left out without a machine), dwells.
    pub feed_time_s: f64,
    pub cut_mm: f64,
    pub rapid_mm: f64,
    /// The dwells as written (`time_s` counts them as the controller
    /// dwells: grbl in whole steps of 50 ms).
    pub dwell_s: f64,
    pub tool_changes: usize,
    pub spindle_starts: usize,
    pub tools: Vec<ToolFigures>,
    /// From one tool change to the next, in order.
    pub operations: Vec<OperationFigures>,
    /// Each move's planned time, in order (empty without a machine).
    #[serde(skip)]
    pub move_s: Vec<f64>,
}

/// The figures of one tool's moves.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ToolFigures {
    pub tool: u32,
    pub time_s: Option<f64>,
    pub feed_time_s: f64,
    pub cut_mm: f64,
    /// The feed moves' bounds: `[[x, y, z] min, [x, y, z] max]`, mm.
    pub bounds: Option<[[f64; 3]; 2]>,
}

/// One operation: the moves from a tool change to the next.
#[derive(Clone, Debug, Default, Serialize)]
pub struct OperationFigures {
    pub tool: u32,
    /// The source line of its tool change (the first operation's: of its
    /// first move).
    pub line: u32,
    /// Its moves and dwells, planned; `None` without a machine.
    pub time_s: Option<f64>,
    pub feed_time_s: f64,
    pub cut_mm: f64,
    pub rapid_mm: f64,
    pub dwell_s: f64,
    /// The feed moves' bounds, mm.
    pub bounds: Option<[[f64; 3]; 2]>,
}

/// The lesser of `a` and `b` (`b` if either is NaN, which no point is):
/// one instruction, where `f64::min` takes several.
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// The greater of `a` and `b` (`b` if either is NaN).
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The box of the ends of `m`.
fn ends_box(m: &Move) -> [[f64; 3]; 2] {
    let (a, b) = (m.start, m.end);
    [
        std::array::from_fn(|i| lesser(a[i], b[i])),
        std::array::from_fn(|i| greater(a[i], b[i])),
    ]
}

/// Widen the box `[low, high]` to hold the ends of `m`.
#[inline(always)]
fn widen_by([low, high]: &mut [[f64; 3]; 2], m: &Move) {
    for i in 0..3 {
        low[i] = lesser(m.start[i], lesser(m.end[i], low[i]));
        high[i] = greater(m.start[i], greater(m.end[i], high[i]));
    }
}

/// Widen the box `[low, high]` to hold `p`.
#[inline(always)]
fn widen_to([low, high]: &mut [[f64; 3]; 2], p: Point) {
    for i in 0..3 {
        low[i] = lesser(p[i], low[i]);
        high[i] = greater(p[i], high[i]);
    }
}

/// Widen `bounds` to hold the box `[low, high]`.
fn widen(bounds: &mut Option<[[f64; 3]; 2]>, [low, high]: [[f64; 3]; 2]) {
    let [l, h] = bounds.get_or_insert([low, high]);
    for i in 0..3 {
        l[i] = lesser(low[i], l[i]);
        h[i] = greater(high[i], h[i]);
    }
}

/// The figures of `path` on the machine `limits` describes (length / feed
/// only, without one), each move's planned time in `move_s`.
pub fn plan(path: &ToolPath, limits: Option<&Limits>) -> Figures {
    let mut tally = Tally::new(limits, true);
    path.feed_to(&mut tally);
    tally.finish()
}

/// The time each move ends at, from the start, in seconds: planned on
/// `limits`, else length / feed (rapids untimed); dwells counted where
/// they stand.
pub fn clock_per_move(path: &ToolPath, limits: Option<&Limits>) -> Vec<f64> {
    plan_with_clock(path, limits).1
}

/// [`plan`]'s figures and [`clock_per_move`]'s clock, the path planned
/// once for both (the studio shows both).
pub fn plan_with_clock(path: &ToolPath, limits: Option<&Limits>) -> (Figures, Vec<f64>) {
    let mut figures = plan(path, limits);
    let mut each = match limits {
        Some(_) => std::mem::take(&mut figures.move_s),
        None => path
            .moves
            .iter()
            .map(|m| match m.kind {
                MoveKind::Rapid => 0.0,
                _ if m.state.feed_rate() > 0.0 => m.length() / (m.state.feed_rate() / 60.0),
                _ => 0.0,
            })
            .collect(),
    };
    for event in &path.events {
        if let (EventKind::Dwell(s), Some(next)) = (event.kind, each.get_mut(event.after_move)) {
            *next += limits.map_or(s, |l| l.dwell_s(s));
        }
    }
    let mut at = 0.0;
    for t in &mut each {
        at += *t;
        *t = at;
    }
    (figures, each)
}

/// A straight move's direction (a zero move's: none).
fn unit(m: &Move) -> [f64; 3] {
    direction(m.start, m.end)
}

/// The blocks planned as they come, with the look-ahead of the buffer
/// (the last block held must be able to stop), corners limited as the
/// controller limits them, each block a trapezoid (or a triangle). Holds
/// only the buffer's blocks: a block is timed, handed on with its time
/// and dropped once the buffer behind it is full.
struct Planner<'l> {
    limits: &'l Limits,
    depth: usize,
    /// The blocks not yet timed (a run of chords counts as its chords).
    window: Ring,
    slots: usize,
    previous: Option<Block>,
    /// The speed into the window's first block, and its square.
    entry: f64,
    entry_sqr: f64,
    /// The time of the move whose blocks were timed last, not yet handed
    /// on (a move's blocks are timed one after another: one hand-off each).
    move_s: Option<(usize, f64)>,
}

/// A block not yet timed: what timing it needs of it (the window holds
/// no more, 56 bytes, so that it moves little).
#[derive(Clone, Copy, Default)]
struct Slot {
    /// mm/s; mm/s².
    nominal: f64,
    accel: f64,
    /// What it adds to a speed squared from end to end: 2 · accel ·
    /// length (its length is in it).
    gain: f64,
    /// The move it is part of.
    source: usize,
    /// Its largest entry speed squared, at the corner before it.
    max_entry: f64,
    /// The largest from which it can still slow down to a stop at the end
    /// of the buffer (grbl's reverse pass, kept from one block to the
    /// next: a new block changes it only back to the first block whose
    /// limit it does not raise).
    reachable: f64,
    /// 1, or a run of an arc's middle chords (`chords.rs`), `gain` of
    /// their total length: it always enters and leaves at its nominal
    /// speed, so its limit never changes.
    chords: usize,
}

impl Slot {
    /// `block`'s slot, alone in the window: entered and left at rest.
    fn of(block: &Block) -> Slot {
        Slot {
            nominal: block.nominal,
            accel: block.accel,
            gain: 2.0 * block.accel * block.length,
            source: block.source,
            max_entry: 0.0,
            reachable: 0.0,
            chords: 1,
        }
    }
}

/// The window's slots in a ring of a power of two of them: a slot's place
/// by a mask (`VecDeque` wraps with a comparison at every index).
struct Ring {
    slots: Vec<Slot>,
    head: usize,
    len: usize,
}

impl Ring {
    /// Room for `held` slots (it grows if ever more are pushed).
    fn new(held: usize) -> Ring {
        Ring {
            slots: vec![Slot::default(); held.next_power_of_two()],
            head: 0,
            len: 0,
        }
    }

    fn len(&self) -> usize {
        self.len
    }

    fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The place of the `j`th slot from the front.
    #[inline(always)]
    fn at(&self, j: usize) -> usize {
        (self.head + j) & (self.slots.len() - 1)
    }

    #[inline(always)]
    fn get(&self, j: usize) -> &Slot {
        &self.slots[self.at(j)]
    }

    #[inline(always)]
    fn get_mut(&mut self, j: usize) -> &mut Slot {
        let at = self.at(j);
        &mut self.slots[at]
    }

    fn front(&self) -> Option<&Slot> {
        (self.len > 0).then(|| self.get(0))
    }

    #[inline(always)]
    fn push_back(&mut self, slot: Slot) {
        if self.len == self.slots.len() {
            // Full: the same slots in order in a ring twice the size.
            let mut slots = vec![Slot::default(); 2 * self.slots.len()];
            for (j, s) in slots.iter_mut().take(self.len).enumerate() {
                *s = *self.get(j);
            }
            (self.slots, self.head) = (slots, 0);
        }
        let at = self.at(self.len);
        self.slots[at] = slot;
        self.len += 1;
    }

    #[inline(always)]
    fn pop_front(&mut self) -> Option<Slot> {
        if self.len == 0 {
            return None;
        }
        let first = self.slots[self.head];
        self.head = self.at(1);
        self.len -= 1;
        Some(first)
    }
}

impl<'l> Planner<'l> {
    fn new(limits: &'l Limits) -> Planner<'l> {
        let depth = limits.blocks.max(1);
        Planner {
            limits,
            depth,
            window: Ring::new(depth + 1),
            slots: 0,
            previous: None,
            entry: 0.0,
            entry_sqr: 0.0,
            move_s: None,
        }
    }

    /// Take `piece`; `timed` gets each block timed (its move's index and
    /// its seconds).
    #[inline(always)]
    fn take(&mut self, piece: Piece, timed: &mut impl FnMut(usize, f64)) {
        match piece {
            Piece::Block(block) => self.push(block, timed),
            Piece::Cruise { run, chords } => {
                let cruise = run.nominal.powi(2);
                self.previous = Some(run);
                self.add(Slot {
                    max_entry: cruise,
                    reachable: cruise,
                    chords,
                    ..Slot::of(&run)
                });
                while self.slots >= self.depth {
                    self.time_first(timed);
                }
            }
        }
    }

    /// Take `block`; `timed` gets each block timed.
    #[inline(always)]
    fn push(&mut self, block: Block, timed: &mut impl FnMut(usize, f64)) {
        let max_entry = match &self.previous {
            Some(a) if !block.stopped_before => {
                let corner = match block.smooth_before && a.source == block.source {
                    true => f64::INFINITY,
                    false => junction(a, &block, self.limits),
                };
                lesser(
                    lesser(corner, a.nominal * a.nominal),
                    block.nominal * block.nominal,
                )
            }
            _ => 0.0,
        };
        self.previous = Some(block);
        // The speed must be 0 at the buffer's end (and is before a block
        // after a stop, whose largest entry is 0).
        let slot = Slot::of(&block);
        self.add(Slot {
            max_entry,
            reachable: lesser(max_entry, slot.gain),
            ..slot
        });
        if self.slots >= self.depth {
            self.time_first(timed);
        }
    }

    /// `slot` at the buffer's end; the reverse pass back from it.
    #[inline(always)]
    fn add(&mut self, slot: Slot) {
        self.slots += slot.chords;
        let mut next = slot.reachable;
        self.window.push_back(slot);
        for j in (1..self.window.len() - 1).rev() {
            let Slot {
                gain,
                max_entry,
                reachable: old,
                chords,
                ..
            } = *self.window.get(j);
            let new = lesser(next + gain, max_entry);
            if new == old || chords > 1 {
                break;
            }
            self.window.get_mut(j).reachable = new;
            next = new;
        }
    }

    /// The first block of the window timed: its exit as fast as the
    /// blocks behind it, up to the buffer's end or a stop, allow (a run
    /// of chords: all of them, at their nominal speed).
    #[inline(always)]
    fn time_first(&mut self, timed: &mut impl FnMut(usize, f64)) {
        let Some(first) = self.window.pop_front() else {
            return;
        };
        let exit_sqr = match first.chords {
            1 => {
                let exit_sqr = self.window.front().map_or(0.0, |next| next.reachable);
                lesser(self.entry_sqr + first.gain, exit_sqr)
            }
            _ => first.max_entry,
        };
        let exit = exit_sqr.sqrt();
        let seconds = trapezoid(&first, (self.entry, self.entry_sqr), (exit, exit_sqr));
        match &mut self.move_s {
            Some((source, s)) if *source == first.source => *s += seconds,
            pending => {
                if let Some((source, s)) = pending.replace((first.source, seconds)) {
                    timed(source, s);
                }
            }
        }
        (self.entry, self.entry_sqr) = (exit, exit_sqr);
        self.slots -= first.chords;
    }

    fn finish(&mut self, timed: &mut impl FnMut(usize, f64)) {
        while !self.window.is_empty() {
            self.time_first(timed);
        }
        if let Some((source, s)) = self.move_s.take() {
            timed(source, s);
        }
    }
}

/// The largest speed squared from block `a` into block `b`, as the
/// controller takes the corner between them.
#[inline(always)]
fn junction(a: &Block, b: &Block, limits: &Limits) -> f64 {
    match limits.controller {
        Controller::Grbl => junction_sqr(a, b, limits),
        Controller::LinuxCnc => linuxcnc::junction_sqr(a, b, limits),
    }
}

/// grbl's largest speed squared through the corner from `a` to `b`: the
/// circle within the junction deviation of the corner, at the acceleration
/// the corner's direction allows.
#[inline(always)]
fn junction_sqr(a: &Block, b: &Block, limits: &Limits) -> f64 {
    let cos = -dot(a.unit_out, b.unit_in);
    if cos > 0.999_999 {
        // Straight back: a stop.
        return 0.0;
    }
    if cos < -0.999_999 {
        // Straight on.
        return f64::INFINITY;
    }
    // Along the corner's direction, b's less a's (`along` scaled by its
    // length: no division to make it a unit).
    let corner: [f64; 3] = std::array::from_fn(|i| b.unit_in[i] - a.unit_out[i]);
    let accel = along(limits.max_accel, corner) * dot(corner, corner).sqrt();
    let sin_half = (0.5 * (1.0 - cos)).sqrt();
    (accel * limits.junction_deviation * sin_half / (1.0 - sin_half)).max(0.0)
}

/// The time of a block entered at `entry` and left at `exit` (mm/s, each
/// with its square): accelerate to its nominal speed, cruise, slow down;
/// a triangle where it is too short to reach it. (In one division: the
/// speeds' changes over `a`, the cruise d/v less what the changes take of
/// d, (v² − u²)/2a each, over v.)
#[inline(always)]
fn trapezoid(b: &Slot, (entry, entry_sqr): (f64, f64), (exit, exit_sqr): (f64, f64)) -> f64 {
    let (a, v) = (b.accel, b.nominal);
    let changes = greater(v * v - entry_sqr, 0.0) + greater(v * v - exit_sqr, 0.0);
    if changes <= b.gain {
        let speeds = greater(v - entry, 0.0) + greater(v - exit, 0.0);
        return (2.0 * v * speeds + b.gain - changes) / (2.0 * a * v);
    }
    let peak = ((b.gain + entry_sqr + exit_sqr) / 2.0).sqrt();
    (greater(peak - entry, 0.0) + greater(peak - exit, 0.0)) / a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::PathControl;
    use crate::toolpath::{Point, State};

    /// A machine of 1000 mm/s² and 200 mm/s on every axis, grbl's
    /// junction deviation (0.01 mm).
    pub(super) fn limits() -> Limits {
        Limits {
            controller: Controller::Grbl,
            max_rate: [200.0; 3],
            max_accel: [1000.0; 3],
            rapid_rate: None,
            max_path_rate: f64::INFINITY,
            max_path_accel: f64::INFINITY,
            junction_deviation: 0.01,
            path_tolerance: 0.0,
            arc_tolerance: 0.002,
            blocks: 16,
            tool_change_s: 0.0,
            spindle_start_s: 0.0,
            steps_per_mm: [None; 3],
        }
    }

    /// A move of `kind` from `start` to `end` at `feed` mm/min, tool 1.
    pub(super) fn feed_move(kind: MoveKind, start: Point, end: Point, feed: f64) -> Move {
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

    /// An arc in XY from `start` to `end` about `center` at `feed`
    /// mm/min, tool 1.
    pub(super) fn arc_move(
        (start, end, center): (Point, Point, Point),
        clockwise: bool,
        feed: f64,
    ) -> Move {
        let kind = MoveKind::Arc(crate::toolpath::ArcPath {
            center,
            plane: crate::ir::Plane::XY,
            clockwise,
            turns: 1,
        });
        feed_move(kind, start, end, feed)
    }

    /// Feed moves through `points` at `feed` mm/min.
    pub(super) fn path(points: &[[f64; 3]], feed: f64) -> ToolPath {
        let moves = points
            .windows(2)
            .map(|p| feed_move(MoveKind::Feed, p[0], p[1], feed))
            .collect();
        ToolPath {
            moves,
            ..ToolPath::default()
        }
    }

    fn planned(points: &[[f64; 3]], feed: f64, limits: &Limits) -> f64 {
        plan(&path(points, feed), Some(limits)).time_s.unwrap()
    }

    #[test]
    fn one_move_is_a_trapezoid() {
        // 100 mm at 100 mm/s, 1000 mm/s²: 5 mm up (0.1 s), 90 mm at
        // speed (0.9 s), 5 mm down (0.1 s).
        let t = planned(&[[0.0; 3], [100.0, 0.0, 0.0]], 6000.0, &limits());
        assert!((t - 1.1).abs() < 1e-12, "{t}");
    }

    #[test]
    fn a_thread_goes_at_its_lead_times_the_rpm_not_at_f() {
        // G33 K1.5 at S2000: 3000 mm/min, 50 mm/s, whatever F is (6000
        // here). 100 mm at 1000 mm/s²: 1.25 mm up (0.05 s), 97.5 mm at
        // speed (1.95 s), 1.25 mm down (0.05 s): 2.05 s in both models;
        // with no machine, the length over the rate: 2 s.
        let mut thread = path(&[[0.0; 3], [0.0, 0.0, -100.0]], 6000.0);
        thread.moves[0].state.lead = Some(1.5);
        thread.moves[0].state.rpm = 2000.0;
        for controller in [Controller::Grbl, Controller::LinuxCnc] {
            let limits = Limits {
                controller,
                ..limits()
            };
            let t = plan(&thread, Some(&limits)).time_s.unwrap();
            assert!((t - 2.05).abs() < 1e-9, "{controller:?}: {t}");
        }
        let t = plan(&thread, None).feed_time_s;
        assert!((t - 2.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn a_short_move_is_a_triangle_that_never_reaches_the_feed() {
        // 4 mm: the peak is sqrt(1000 * 4) = 63.25 mm/s, up and down
        // 0.06325 s each.
        let t = planned(&[[0.0; 3], [4.0, 0.0, 0.0]], 6000.0, &limits());
        let expected = 2.0 * (4000.0_f64).sqrt() / 1000.0;
        assert!((t - expected).abs() < 1e-12, "{t} vs {expected}");
        assert!((expected - 0.126491).abs() < 1e-6);
    }

    #[test]
    fn a_right_angle_is_taken_at_the_junction_speed() {
        // 90°: sin(45°) = 0.70711; the corner's direction (-1, 1)/√2
        // allows 1414.2 mm/s²; v² = 1414.2 × 0.01 × 0.70711 / 0.29289 =
        // 34.142, v = 5.8431 mm/s. Each leg: up 5 mm in 0.1 s, down from
        // 100 to 5.8431 over 4.9829 mm in 0.094157 s, 90.017 mm at
        // 100 mm/s in 0.90017 s: 1.094329 s, the two 2.188657 s.
        let points = [[0.0; 3], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0]];
        let t = planned(&points, 6000.0, &limits());
        let v2 = 1000.0 * std::f64::consts::SQRT_2 * 0.01 * 0.5_f64.sqrt() / (1.0 - 0.5_f64.sqrt());
        let down = (10_000.0 - v2) / 2000.0;
        let leg = 0.1 + (100.0 - v2.sqrt()) / 1000.0 + (100.0 - 5.0 - down) / 100.0;
        assert!((t - 2.0 * leg).abs() < 1e-9, "{t} vs {}", 2.0 * leg);
        assert!((t - 2.188657).abs() < 1e-5, "{t}");
        // Straight on through the same point: no slowing.
        let straight = [[0.0; 3], [100.0, 0.0, 0.0], [200.0, 0.0, 0.0]];
        let t = planned(&straight, 6000.0, &limits());
        assert!((t - 2.1).abs() < 1e-12, "{t}");
    }

    #[test]
    fn the_look_ahead_is_as_deep_as_the_buffer() {
        // 40 moves of 1 mm straight on at 100 mm/s², which needs 50 mm to
        // reach 100 mm/s: with all of them in view, a triangle peaking at
        // √(100 · 40) = 63.25 mm/s. With 16 (the one running and 15 after
        // it) each block must be able to stop within the 15 mm after it:
        // v² ≤ 3000 at each block's end; 15 blocks up to it (0.5477 s),
        // 10 blocks from 3000 to 3000 through a peak of 3100 mid-block
        // (0.018108 s each), 15 down. With 1, each move from rest to rest
        // (0.2 s each).
        let points: Vec<[f64; 3]> = (0..=40).map(|i| [i as f64, 0.0, 0.0]).collect();
        let slow = Limits {
            max_accel: [100.0; 3],
            ..limits()
        };
        let deep = Limits {
            blocks: 1000,
            ..slow.clone()
        };
        let t_deep = planned(&points, 6000.0, &deep);
        let expected = 2.0 * (100.0_f64 * 40.0).sqrt() / 100.0;
        assert!((t_deep - expected).abs() < 1e-9, "{t_deep} vs {expected}");
        let t16 = planned(&points, 6000.0, &slow);
        let cruise = 2.0 * (3100.0_f64.sqrt() - 3000.0_f64.sqrt()) / 100.0;
        let expected = 2.0 * (2.0_f64 * 15.0 / 100.0).sqrt() + 10.0 * cruise;
        assert!((t16 - expected).abs() < 1e-9, "{t16} vs {expected}");
        let t1 = planned(&points, 6000.0, &Limits { blocks: 1, ..slow });
        assert!((t1 - 8.0).abs() < 1e-9, "{t1}");
    }

    #[test]
    fn a_grbl_buffer_of_16_slots_holds_15_blocks() {
        // grbl's ring buffer keeps one of its 16 slots free, so the block
        // running sees 14 after it: 40 moves of 1 mm at 100 mm/s² must
        // each be able to stop within 14 mm (v² ≤ 2800): 14 blocks up,
        // 12 from 2800 to 2800 through a peak of 2900 mid-block, 14
        // down. grbl 1.1h's own planner and stepper (run outside the
        // repository, tests/data/grbl_times.tsv says how) take 1.283298 s.
        let axis = crate::driver::machine::Axis {
            max_velocity: Some(6000.0),
            max_acceleration: Some(100.0),
            travel: None,
            steps_per_mm: None,
        };
        let machine = crate::driver::machine::Machine {
            controller: Controller::Grbl,
            axes: [axis; 3],
            rapid_rate: None,
            max_velocity: None,
            max_acceleration: None,
            junction_deviation: None,
            path_tolerance: None,
            arc_tolerance: None,
            planner_blocks: Some(16),
            tool_change_s: None,
            spindle_start_s: None,
        };
        let stock = Limits::of(&machine).unwrap();
        assert_eq!(stock.blocks, 15);
        let points: Vec<[f64; 3]> = (0..=40).map(|i| [i as f64, 0.0, 0.0]).collect();
        let t = planned(&points, 6000.0, &stock);
        let cruise = 2.0 * (2900.0_f64.sqrt() - 2800.0_f64.sqrt()) / 100.0;
        let expected = 2.0 * (2.0_f64 * 14.0 / 100.0).sqrt() + 12.0 * cruise;
        assert!((t - expected).abs() < 1e-9, "{t} vs {expected}");
        assert!((t / 1.283298 - 1.0).abs() < 0.001, "{t}");
        // LinuxCNC's depth is the moves it looks ahead, all of them held.
        let linuxcnc = crate::driver::machine::Machine {
            controller: Controller::LinuxCnc,
            ..machine
        };
        assert_eq!(Limits::of(&linuxcnc).unwrap().blocks, 16);
    }

    #[test]
    fn each_axis_limits_its_share_of_a_diagonal() {
        // Z at 10 mm/s: a 45° XZ move of 100 mm is held to 14.142 mm/s.
        let slow_z = Limits {
            max_rate: [200.0, 200.0, 10.0],
            ..limits()
        };
        let t = planned(&[[0.0; 3], [70.710678, 0.0, 70.710678]], 6000.0, &slow_z);
        let v = 10.0 * std::f64::consts::SQRT_2;
        let a = 1000.0 * std::f64::consts::SQRT_2;
        let expected = 2.0 * v / a + (100.0 - v * v / a) / v;
        assert!((t - expected).abs() < 1e-6, "{t} vs {expected}");
    }

    #[test]
    fn arcs_are_cut_into_grbls_chords() {
        // r = 10, tolerance 0.002: grbl's mc_arc makes floor(π·10 /
        // √(0.002 · 19.998)) = 157 segments of a full circle.
        let r10 = [10.0, 0.0, 0.0];
        let m = arc_move((r10, r10, [0.0; 3]), false, 600.0);
        let (sweep, radius, _) = m.along().arc_shape().unwrap();
        assert_eq!(chords::arc_segments(radius, sweep, 0.002), 157);
    }

    /// [`limits`] on LinuxCNC's planner.
    fn linuxcnc() -> Limits {
        Limits {
            controller: Controller::LinuxCnc,
            blocks: 50,
            ..limits()
        }
    }

    /// [`path`] with every move under `control`.
    fn controlled(points: &[[f64; 3]], feed: f64, control: PathControl) -> ToolPath {
        let mut p = path(points, feed);
        for m in &mut p.moves {
            m.state.path_control = control;
        }
        p
    }

    fn linuxcnc_time(points: &[[f64; 3]], control: PathControl) -> f64 {
        let path = controlled(points, 6000.0, control);
        plan(&path, Some(&linuxcnc())).time_s.unwrap()
    }

    const SQUARE: [[f64; 3]; 5] = [
        [0.0; 3],
        [100.0, 0.0, 0.0],
        [100.0, 100.0, 0.0],
        [0.0, 100.0, 0.0],
        [0.0; 3],
    ];
    const STRAIGHT: [[f64; 3]; 3] = [[0.0; 3], [100.0, 0.0, 0.0], [200.0, 0.0, 0.0]];
    const CORNER: [[f64; 3]; 3] = [[0.0; 3], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0]];

    #[test]
    fn linuxcnc_exact_stop_stops_after_every_move() {
        // G61.1: each 100 mm leg at 100 mm/s, 1000 mm/s² from rest to
        // rest is 1.1 s (the single trapezoid), straight on or not.
        let t = linuxcnc_time(&SQUARE, PathControl::ExactStop);
        assert!((t - 4.4).abs() < 1e-12, "{t}");
        let t = linuxcnc_time(&STRAIGHT, PathControl::ExactStop);
        assert!((t - 2.2).abs() < 1e-12, "{t}");
    }

    #[test]
    fn linuxcnc_exact_path_stops_at_corners_only() {
        // G61: straight on, one trapezoid over 200 mm (2.1 s); a corner,
        // two (2.2 s).
        let t = linuxcnc_time(&STRAIGHT, PathControl::ExactPath);
        assert!((t - 2.1).abs() < 1e-12, "{t}");
        let t = linuxcnc_time(&CORNER, PathControl::ExactPath);
        assert!((t - 2.2).abs() < 1e-12, "{t}");
    }

    #[test]
    fn linuxcnc_blends_a_right_angle_within_the_tolerance() {
        // G64 P0.01 at 90°: θ = 45°, h = 0.01 / (1 − sin θ) = 0.034142,
        // d = cos θ · h = 0.024142 (far less than half a leg), the blend's
        // radius tan θ · d = 0.024142; its normal acceleration
        // 1000 · √(1 − 0.5²) = 866.03 mm/s² allows v² = 20.908, v = 4.5725
        // mm/s. Each leg: up 5 mm in 0.1 s, down from 100 to v over
        // (10⁴ − v²) / 2000 mm in (100 − v) / 1000 s, the rest at 100 mm/s.
        let p = PathControl::Blend {
            tolerance: Some(0.01),
            naive: None,
        };
        let t = linuxcnc_time(&CORNER, p);
        let theta = std::f64::consts::FRAC_PI_4;
        let radius = theta.tan() * theta.cos() * 0.01 / (1.0 - theta.sin());
        let v2 = 1000.0 * 0.75_f64.sqrt() * radius;
        assert!((v2 - 20.9077).abs() < 1e-4, "{v2}");
        let down = (10_000.0 - v2) / 2000.0;
        let leg = 0.1 + (100.0 - v2.sqrt()) / 1000.0 + (100.0 - 5.0 - down) / 100.0;
        assert!((t - 2.0 * leg).abs() < 1e-9, "{t} vs {}", 2.0 * leg);
        // Without P the blend may take a quarter of each leg: a radius
        // of 25 / (1 − sin θ) · cos θ · tan θ capped at half a leg (50
        // mm), v = √(866 · 50) = 208 mm/s, above the feed: no slowing.
        let t = linuxcnc_time(&CORNER, PathControl::default());
        assert!((t - 2.1).abs() < 1e-12, "{t}");
    }

    #[test]
    fn linuxcnc_holds_an_arc_to_its_normal_acceleration() {
        // A full circle of r = 10 at 100 mm/s: v² / r = 1000 would pass
        // 866.03 mm/s², so v = √(866.03 · 10) = 93.060 mm/s, and the
        // tangential acceleration is half of 1000. From rest to rest:
        // up and down 2 · v / 500 s over v² / 500 mm, the rest at v.
        let r10 = [10.0, 0.0, 0.0];
        let arc = arc_move((r10, r10, [0.0; 3]), false, 6000.0);
        let circle = ToolPath {
            moves: vec![arc],
            ..ToolPath::default()
        };
        let t = plan(&circle, Some(&linuxcnc())).time_s.unwrap();
        let v = (1000.0 * 0.75_f64.sqrt() * 10.0).sqrt();
        let length = 2.0 * std::f64::consts::PI * 10.0;
        let expected = 2.0 * v / 500.0 + (length - v * v / 500.0) / v;
        assert!((t - expected).abs() < 1e-9, "{t} vs {expected}");
    }

    #[test]
    fn linuxcnc_holds_a_helix_to_its_normal_axis() {
        // One turn of r = 10 rising 50 mm at 50 mm/s, Z at 1 mm/s and
        // 100 mm/s² (X and Y 200 mm/s, 1000 mm/s²): the path is L =
        // hypot(20π, 50) = 80.30 mm, Z's share 50 / L, so v = 1 · L / 50
        // = 1.606 mm/s and a = min(1000 · L / 20π, 100 · L / 50) = 2 L =
        // 160.6 mm/s²; v² / r = 0.258 leaves the tangential acceleration
        // a · √(1 − (v² / r / a)²). From rest to rest: 50 s, as Z alone.
        let mut limits = linuxcnc();
        (limits.max_rate[2], limits.max_accel[2]) = (1.0, 100.0);
        let (start, end) = ([10.0, 0.0, 0.0], [10.0, 0.0, -50.0]);
        let helix = arc_move((start, end, [0.0; 3]), true, 3000.0);
        let moves = vec![helix];
        let t = plan(
            &ToolPath {
                moves,
                ..ToolPath::default()
            },
            Some(&limits),
        );
        let length = (20.0 * std::f64::consts::PI).hypot(50.0);
        let (v, a) = (length / 50.0, 2.0 * length);
        let tangential = a * (1.0 - (v * v / 10.0 / a).powi(2)).sqrt();
        let expected = length / v + v / tangential;
        assert!((expected - 50.01).abs() < 1e-4, "{expected}");
        let t = t.time_s.unwrap();
        assert!((t - expected).abs() < 1e-9, "{t} vs {expected}");
    }

    #[test]
    fn linuxcnc_holds_every_move_to_the_paths_limits() {
        // [TRAJ] 20 mm/s and 100 mm/s² under axes of 50 mm/s and 500
        // mm/s²: a 300 mm rapid is 300 / 20 + 20 / 100 = 15.2 s, and so
        // is the line at F6000; a full circle of r 10 (length 20π) at
        // 20 mm/s, its normal acceleration 40 of 100 · 0.866 allowed, its
        // tangential 100 · √(1 − 0.4²).
        let limits = Limits {
            max_rate: [50.0; 3],
            max_accel: [500.0; 3],
            max_path_rate: 20.0,
            max_path_accel: 100.0,
            ..linuxcnc()
        };
        let time = |m: Move| {
            let path = ToolPath {
                moves: vec![m],
                ..ToolPath::default()
            };
            plan(&path, Some(&limits)).time_s.unwrap()
        };
        for kind in [MoveKind::Rapid, MoveKind::Feed] {
            let t = time(feed_move(kind, [0.0; 3], [300.0, 0.0, 0.0], 6000.0));
            assert!((t - 15.2).abs() < 1e-9, "{kind:?}: {t}");
        }
        let r10 = [10.0, 0.0, 0.0];
        let t = time(arc_move((r10, r10, [0.0; 3]), false, 6000.0));
        let tangential = 100.0 * (1.0 - 0.4_f64.powi(2)).sqrt();
        let expected = 20.0 * std::f64::consts::PI / 20.0 + 20.0 / tangential;
        assert!((t - expected).abs() < 1e-9, "{t} vs {expected}");
    }

    #[test]
    fn operations_run_from_tool_change_to_tool_change() {
        // Tool 1 cuts 100 mm, dwells 2 s; tool 2 (changed at line 7) cuts
        // 50 mm: two operations, each with its own time and bounds.
        let mut p = path(&[[0.0; 3], [100.0, 0.0, 0.0], [100.0, 50.0, 0.0]], 6000.0);
        p.moves[1].state.tool = 2;
        let at = |line, after_move, kind| crate::toolpath::Event {
            kind,
            after_move,
            span: crate::source::Span::new(0, line, 0, 0),
        };
        p.events = vec![
            at(5, 1, EventKind::Dwell(2.0)),
            at(7, 1, EventKind::ToolChange(2)),
        ];
        let f = plan(&p, Some(&limits()));
        let ops = &f.operations;
        assert_eq!(ops.len(), 2, "{ops:?}");
        assert_eq!((ops[0].tool, ops[1].tool, ops[1].line), (1, 2, 7));
        assert!((ops[0].cut_mm - 100.0).abs() < 1e-12);
        assert!((ops[0].feed_time_s - 3.0).abs() < 1e-12, "{ops:?}");
        assert!((ops[0].time_s.unwrap() - 3.1).abs() < 1e-12, "{ops:?}");
        assert!((ops[1].time_s.unwrap() - 0.6).abs() < 1e-12, "{ops:?}");
        assert_eq!(ops[1].bounds, Some([[100.0, 0.0, 0.0], [100.0, 50.0, 0.0]]));
        let total = f.time_s.unwrap();
        assert!((total - 3.7).abs() < 1e-12, "{total}");
        assert_eq!(plan(&p, None).operations[1].time_s, None);
    }

    #[test]
    fn an_arcs_box_holds_where_it_bulges_past_its_ends() {
        // A full circle of radius 10 about (10, 0) from the origin, then a
        // quarter counter-clockwise about (25, 0) from (20, 0) to (25, 5)
        // that passes no axis direction between its ends (its box is its
        // ends'), then one clockwise from (25, 5) about (25, 0) to (25, -5)
        // that passes +X at (30, 0): X 0 … 30, Y -10 … 10.
        let arc = |start, end, center, clockwise| arc_move((start, end, center), clockwise, 600.0);
        let moves = vec![
            arc([0.0; 3], [0.0; 3], [10.0, 0.0, 0.0], true),
            feed_move(MoveKind::Feed, [0.0; 3], [20.0, 0.0, 0.0], 600.0),
            arc([20.0, 0.0, 0.0], [25.0, 5.0, 0.0], [25.0, 0.0, 0.0], true),
            arc([25.0, 5.0, 0.0], [25.0, -5.0, 0.0], [25.0, 0.0, 0.0], true),
        ];
        let p = ToolPath {
            moves,
            ..ToolPath::default()
        };
        for limits in [None, Some(&limits())] {
            let f = plan(&p, limits);
            let [low, high] = f.tools[0].bounds.expect("a box");
            let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
            assert!(near(low, [0.0, -10.0, 0.0]), "{low:?}");
            assert!(near(high, [30.0, 10.0, 0.0]), "{high:?}");
        }
    }

    /// The figures of program `text` on `limits`.
    fn planned_program(text: &str, limits: &Limits) -> Figures {
        let mut sources = crate::source::Sources::new();
        let file = sources.add("p.nc", text.to_string());
        let options = crate::driver::CompileOptions::default();
        let (path, problems) = crate::driver::tool_path(&sources, file, &options, None);
        let path = path.unwrap_or_else(|| panic!("{problems:?}"));
        plan(&path, Some(limits))
    }

    #[test]
    fn a_tools_figures_are_its_operations_summed() {
        // Tool 1 twice (rapids, cuts and a dwell each time), tool 2 once:
        // each tool's times are those of its operations, rapids and
        // dwells included, planned and length / feed alike.
        let text = "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z0 F600\nG1 X50\nG4 P1.5\nG0 Z5\n\
                    T2 M6\nG0 X10 Y10\nG1 Z0\nG1 Y60\nG0 Z5\n\
                    T1 M6\nG0 X100 Y0\nG1 Z0\nG4 P0.5\nG1 X150\nG0 Z5\nM30\n";
        let f = planned_program(text, &limits());
        assert_eq!(f.operations.len(), 3);
        for tool in &f.tools {
            let ops = f.operations.iter().filter(|o| o.tool == tool.tool);
            let (time, feed_time) = ops.fold((0.0, 0.0), |(t, ft), o| {
                (t + o.time_s.unwrap(), ft + o.feed_time_s)
            });
            assert!((tool.time_s.unwrap() - time).abs() < 1e-9, "{f:?}");
            assert!((tool.feed_time_s - feed_time).abs() < 1e-9, "{f:?}");
        }
        let one = f.tools.iter().find(|t| t.tool == 1).unwrap();
        assert!(one.feed_time_s > 2.0 + 10.0, "dwells and cuts: {one:?}");
    }

    #[test]
    fn the_spindle_stopped_and_started_between_two_moves_is_a_sync_and_a_start() {
        // M5 M3 between two feed moves: the machine stops at the M5 (and
        // at the M3), and the spindle starts again; an S while it turns
        // and a coolant change stop it too, an S while it is off does not.
        let limits = Limits {
            spindle_start_s: 3.0,
            ..limits()
        };
        let run = |between: &str| {
            let text =
                format!("G21 G90\nS1000 M3\nG0 X0 Y0 Z0\nG1 X100 F6000\n{between}G1 X200\nM30\n");
            planned_program(&text, &limits)
        };
        let straight = run("");
        assert_eq!(straight.spindle_starts, 1);
        let restarted = run("M5\nM3\n");
        assert_eq!(restarted.spindle_starts, 2);
        // Two 100 mm moves each from rest to rest (0.1 s more each way
        // than one 200 mm move) and a 3 s start.
        let more = restarted.time_s.unwrap() - straight.time_s.unwrap();
        assert!((more - 3.1).abs() < 1e-9, "{more}");
        for stops in ["S2000\n", "M8\n"] {
            let f = run(stops);
            assert_eq!(f.spindle_starts, 1, "{stops}");
            let more = f.time_s.unwrap() - straight.time_s.unwrap();
            assert!((more - 0.1).abs() < 1e-9, "{stops}: {more}");
        }
        let off = run("M5\nS2000\nG1 X150\nM3\n");
        assert_eq!(off.spindle_starts, 2);
    }

    #[test]
    fn the_clock_runs_on_the_planned_times_with_dwells_where_they_stand() {
        // Two 100 mm legs at a right angle, a 2 s dwell between them: the
        // clock at the first leg's end is its planned time, at the second
        // the whole run's (as `time_s`), not length / feed (1 s a leg).
        let mut p = path(&[[0.0; 3], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0]], 6000.0);
        p.events = vec![crate::toolpath::Event {
            kind: EventKind::Dwell(2.0),
            after_move: 1,
            span: crate::source::Span::new(0, 3, 0, 0),
        }];
        let limits = limits();
        let clock = clock_per_move(&p, Some(&limits));
        let figures = plan(&p, Some(&limits));
        assert_eq!(clock.len(), 2);
        // Each leg from rest to rest (the dwell stops the machine): 1.1 s.
        assert!((clock[0] - 1.1).abs() < 1e-12, "{clock:?}");
        assert!(
            (clock[1] - figures.time_s.unwrap()).abs() < 1e-12,
            "{clock:?}"
        );
        assert!((clock[1] - 4.2).abs() < 1e-12, "{clock:?}");
        let unplanned = clock_per_move(&p, None);
        assert!((unplanned[1] - 4.0).abs() < 1e-12, "{unplanned:?}");
    }

    #[test]
    fn grbl_dwells_in_whole_steps_of_50_ms() {
        // delay_sec: ceil(20 · P) steps of 50 ms. P0.12 is 2.4 steps, so
        // 3: 0.15 s (grbl 1.1h itself: 0.15 s); P0.1 is 2 steps exactly
        // in single precision; P0.101 is 3. The count is 16 bits: P4000
        // is 80,000 steps, 14,464 once wrapped, 723.2 s (grbl 1.1h itself:
        // 723.2 s). LinuxCNC dwells as written.
        let grbl = limits();
        let cases = [
            (0.12, 0.15),
            (0.1, 0.1),
            (0.101, 0.15),
            (2.0, 2.0),
            (0.0, 0.0),
            (4000.0, 723.2),
        ];
        for (p, dwelt) in cases {
            assert!(
                (grbl.dwell_s(p) - dwelt).abs() < 1e-12,
                "{p}: {}",
                grbl.dwell_s(p)
            );
        }
        assert_eq!(linuxcnc().dwell_s(0.12), 0.12);
        // Two 100 mm legs of 1.1 s from rest to rest (the dwell stops the
        // machine), a G4 P0.12 between: 2.35 s, the dwell figure 0.12 s.
        let mut p = path(&[[0.0; 3], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0]], 6000.0);
        p.events = vec![crate::toolpath::Event {
            kind: EventKind::Dwell(0.12),
            after_move: 1,
            span: crate::source::Span::new(0, 3, 0, 0),
        }];
        let f = plan(&p, Some(&grbl));
        assert!((f.time_s.unwrap() - 2.35).abs() < 1e-12, "{f:?}");
        assert!((f.operations[0].time_s.unwrap() - 2.35).abs() < 1e-12);
        assert!((f.dwell_s - 0.12).abs() < 1e-12);
        let clock = clock_per_move(&p, Some(&grbl));
        assert!((clock[1] - 2.35).abs() < 1e-12, "{clock:?}");
    }

    #[test]
    fn grbl_plans_a_move_between_its_ends_on_whole_steps() {
        // 250 steps/mm: a move of 0.0019 mm is 0.475 of a step, no block
        // (grbl drops it); one of 0.003 mm is 0.75, so one step of 0.004
        // mm, a triangle of 2·√(0.004 / 1000) = 0.004 s. Without steps
        // it is 0.003 mm: 2·√(0.003 / 1000) = 0.003464 s.
        let stepped = Limits {
            steps_per_mm: [Some(250.0); 3],
            ..limits()
        };
        let t = planned(&[[0.0; 3], [0.0019, 0.0, 0.0]], 6000.0, &stepped);
        assert_eq!(t, 0.0);
        let t = planned(&[[0.0; 3], [0.003, 0.0, 0.0]], 6000.0, &stepped);
        assert!((t - 0.004).abs() < 1e-12, "{t}");
        let t = planned(&[[0.0; 3], [0.003, 0.0, 0.0]], 6000.0, &limits());
        assert!((t - 2.0 * 3e-6_f64.sqrt()).abs() < 1e-12, "{t}");
    }

    #[test]
    fn a_move_of_no_length_after_a_sync_leaves_the_machine_stopped() {
        // G1 X10, M8 (a sync), G1 X10 (no block), G1 X20, G1 X30 at
        // 50 mm/s: 10 mm from rest to rest (0.25 s), then 20 mm from rest
        // (0.45 s), as grbl 1.1h gives it (0.700 s): its buffer is empty
        // after the sync, and a move of no steps adds no block to it.
        let points = [
            [0.0; 3],
            [10.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [20.0, 0.0, 0.0],
            [30.0, 0.0, 0.0],
        ];
        let mut p = path(&points, 3000.0);
        for m in &mut p.moves[1..] {
            m.state.flood = true;
        }
        p.events.push(crate::toolpath::Event {
            kind: EventKind::Sync {
                spindle_start: false,
            },
            after_move: 1,
            span: crate::source::Span::new(0, 2, 0, 0),
        });
        for limits in [limits(), linuxcnc()] {
            let t = plan(&p, Some(&limits)).time_s.unwrap();
            assert!((t - 0.7).abs() < 1e-12, "{:?}: {t}", limits.controller);
        }
    }

    #[test]
    fn a_smooth_corner_is_trusted_only_within_one_move() {
        // The right angle above as two blocks, the second marked as after
        // a corner proved to allow the feed. Of another move, the corner
        // is worked out all the same (2.188657 s); of the same move (an
        // arc's chords), it is taken at the feed: 0.1 s up, 190 mm at
        // 100 mm/s, 0.1 s down.
        let limits = limits();
        let timed = |second_source: usize| {
            let leg = |start: Point, end: Point, source| {
                let m = feed_move(MoveKind::Feed, start, end, 6000.0);
                let d = block::sub(end, start);
                Block {
                    source,
                    smooth_before: source == second_source,
                    ..block::sized_block(&m, d, 100.0, &limits).unwrap()
                }
            };
            let mut planner = Planner::new(&limits);
            let mut total = 0.0;
            let mut add = |_: usize, s: f64| total += s;
            planner.take(Piece::Block(leg([0.0; 3], [100.0, 0.0, 0.0], 0)), &mut add);
            let second = leg([100.0, 0.0, 0.0], [100.0, 100.0, 0.0], second_source);
            planner.take(Piece::Block(second), &mut add);
            planner.finish(&mut add);
            total
        };
        let apart = timed(1);
        assert!((apart - 2.188657).abs() < 1e-5, "{apart}");
        let within = timed(0);
        assert!((within - 2.1).abs() < 1e-12, "{within}");
    }

    #[test]
    fn the_window_keeps_its_slots_in_order_as_it_wraps_and_grows() {
        // Room for 2 (a ring of 2): pushed and popped past its end, then
        // pushed past its room (it grows, the order kept).
        let slot = |source| Slot {
            source,
            ..Slot::default()
        };
        let mut ring = Ring::new(2);
        let mut expected = std::collections::VecDeque::new();
        for k in 0..7 {
            ring.push_back(slot(k));
            expected.push_back(k);
            if k % 2 == 1 {
                assert_eq!(ring.pop_front().map(|s| s.source), expected.pop_front());
            }
        }
        assert_eq!(ring.len(), expected.len());
        let held: Vec<usize> = (0..ring.len()).map(|j| ring.get(j).source).collect();
        assert_eq!(held, Vec::from(expected.clone()));
        while let Some(s) = ring.pop_front() {
            assert_eq!(Some(s.source), expected.pop_front());
        }
        assert!(ring.is_empty() && ring.front().is_none());
    }

    #[test]
    fn without_a_machine_only_length_over_feed() {
        let f = plan(&path(&[[0.0; 3], [100.0, 0.0, 0.0]], 600.0), None);
        assert_eq!(f.time_s, None);
        assert!((f.feed_time_s - 10.0).abs() < 1e-12);
        assert!((f.cut_mm - 100.0).abs() < 1e-12);
        assert_eq!(f.tools[0].bounds, Some([[0.0; 3], [100.0, 0.0, 0.0]]));
    }
}
