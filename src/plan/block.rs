//! The planner's units of work and the machine's limits, shared by
//! grbl's planner (`plan.rs`) and LinuxCNC's (`linuxcnc.rs`): a block,
//! the limits along a direction, a rapid's rate. Pure arithmetic;
//! imports nothing of the planners.

use crate::driver::machine::{Controller, Machine};
use crate::ir::PathControl;
use crate::toolpath::{Move, MoveKind, Point};

/// grbl's defaults where the profile says nothing.
pub(super) const DEFAULT_JUNCTION_DEVIATION: f64 = 0.01;
pub(super) const DEFAULT_ARC_TOLERANCE: f64 = 0.002;
/// grbl's `BLOCK_BUFFER_SIZE` (planner.h) on a stock build.
pub(super) const DEFAULT_GRBL_BLOCKS: usize = 16;
/// LinuxCNC's `[TRAJ]ARC_BLEND_OPTIMIZATION_DEPTH` default.
pub(super) const DEFAULT_LINUXCNC_BLOCKS: usize = 50;

/// What the planner needs of the machine, in mm, mm/s and s.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits {
    /// Whose planner: grbl's or LinuxCNC's.
    pub controller: Controller,
    /// Per axis, mm/s.
    pub max_rate: [f64; 3],
    /// Per axis, mm/s².
    pub max_accel: [f64; 3],
    /// mm/s for rapids, else each axis's maximum (LinuxCNC: at most
    /// its path's `max_path_rate`).
    pub rapid_rate: Option<f64>,
    /// LinuxCNC's limits on the path of every move after each axis's
    /// (`[TRAJ]`), mm/s and mm/s²; infinite where none.
    pub max_path_rate: f64,
    pub max_path_accel: f64,
    /// grbl's junction deviation, mm.
    pub junction_deviation: f64,
    /// LinuxCNC's blend tolerance where the program's G64 gives no P, mm
    /// (0: none, the blend as large as a quarter of the moves allows).
    pub path_tolerance: f64,
    /// grbl's arc tolerance, mm.
    pub arc_tolerance: f64,
    /// Blocks the planner holds, the one running included (one fewer
    /// than a grbl profile's `planner-blocks`, its buffer's slots).
    pub blocks: usize,
    pub tool_change_s: f64,
    pub spindle_start_s: f64,
    /// grbl's steps per mm of each axis (`$100`–`$102`), where known:
    /// its planner puts every block's end on a whole step.
    pub steps_per_mm: [Option<f64>; 3],
}

impl Limits {
    /// The planner's limits of `machine`; `Err`: what it lacks.
    pub fn of(machine: &Machine) -> Result<Limits, String> {
        let mut max_rate = [0.0; 3];
        let mut max_accel = [0.0; 3];
        for (i, axis) in machine.axes.iter().enumerate() {
            let name = ["x", "y", "z"][i];
            max_rate[i] = axis
                .max_velocity
                .ok_or_else(|| format!("[machine.{name}] has no max-velocity"))?
                / 60.0;
            max_accel[i] = axis
                .max_acceleration
                .ok_or_else(|| format!("[machine.{name}] has no max-acceleration"))?;
        }
        let blocks = match machine.controller {
            Controller::Grbl => DEFAULT_GRBL_BLOCKS,
            Controller::LinuxCnc => DEFAULT_LINUXCNC_BLOCKS,
        };
        let blocks = machine.planner_blocks.map_or(blocks, |b| b as usize);
        let held = match machine.controller {
            // grbl's ring buffer keeps one slot free to tell full from
            // empty (plan_check_full_buffer): 16 slots hold 15 blocks.
            Controller::Grbl => blocks.saturating_sub(1).max(1),
            Controller::LinuxCnc => blocks,
        };
        Ok(Limits {
            controller: machine.controller,
            max_rate,
            max_accel,
            rapid_rate: rapids_cap(machine).map(|r| r / 60.0),
            max_path_rate: machine.max_velocity.map_or(f64::INFINITY, |v| v / 60.0),
            max_path_accel: machine.max_acceleration.unwrap_or(f64::INFINITY),
            junction_deviation: machine
                .junction_deviation
                .unwrap_or(DEFAULT_JUNCTION_DEVIATION),
            path_tolerance: machine.path_tolerance.unwrap_or(0.0),
            arc_tolerance: machine.arc_tolerance.unwrap_or(DEFAULT_ARC_TOLERANCE),
            blocks: held,
            tool_change_s: machine.tool_change_s.unwrap_or(0.0),
            spindle_start_s: machine.spindle_start_s.unwrap_or(0.0),
            steps_per_mm: machine.axes.map(|a| a.steps_per_mm),
        })
    }
}

/// The rate of every rapid, mm/min, where something other than the axes'
/// rates limits it: the profile's `rapid-rate`, and LinuxCNC's path limit
/// (`max-velocity`, as `[TRAJ] MAX_LINEAR_VELOCITY` caps a rapid), the
/// lesser.
fn rapids_cap(machine: &Machine) -> Option<f64> {
    match (machine.rapid_rate, machine.max_velocity) {
        (Some(r), Some(v)) => Some(r.min(v)),
        (r, v) => r.or(v),
    }
}

/// grbl's `DWELL_TIME_STEP` (config.h), ms: it dwells in steps of it.
const GRBL_DWELL_STEP_MS: u16 = 50;

impl Limits {
    /// How long the controller dwells for a `G4` of `seconds`: grbl counts
    /// whole steps of 50 ms, rounding up (`delay_sec`: `ceil(1000 /
    /// DWELL_TIME_STEP * seconds)` in single precision), in a 16-bit
    /// counter, so a dwell past 65,535 steps (3,276.75 s) wraps: `G4
    /// P4000` dwells 723.2 s; LinuxCNC as written.
    pub fn dwell_s(&self, seconds: f64) -> f64 {
        match self.controller {
            Controller::Grbl => {
                let per_second = f32::from(1000 / GRBL_DWELL_STEP_MS);
                let steps = f64::from(per_second * seconds as f32).ceil().max(0.0);
                let counted = (steps as u64 % (1 << 16)) as f64;
                counted * f64::from(GRBL_DWELL_STEP_MS) / 1000.0
            }
            Controller::LinuxCnc => seconds,
        }
    }
}

/// The largest value along `unit` that keeps each axis within its own
/// (grbl's `limit_value_by_axis_maximum`); along a vector of any length,
/// that over its length.
/// In one division: the axis whose limit over its share is least is
/// found by comparing l_i·|v_j| with l_j·|v_i| (all positive), and only
/// its quotient is taken (the least of the three quotients, but where two
/// are within rounding of each other).
#[inline(always)]
pub(super) fn along(limits: [f64; 3], unit: [f64; 3]) -> f64 {
    let (mut limit, mut share) = (f64::INFINITY, 1.0);
    for i in 0..3 {
        let s = unit[i].abs();
        if s != 0.0 && limits[i] * share < limit * s {
            (limit, share) = (limits[i], s);
        }
    }
    limit / share
}

/// One planner block: a straight piece of a move (grbl), or a move
/// (LinuxCNC).
#[derive(Clone, Copy, Debug)]
pub(super) struct Block {
    /// mm.
    pub(super) length: f64,
    /// The direction it starts and ends in (the same for a line).
    pub(super) unit_in: [f64; 3],
    pub(super) unit_out: [f64; 3],
    /// mm/s.
    pub(super) nominal: f64,
    /// mm/s².
    pub(super) accel: f64,
    /// The machine is stopped before it (a sync, or the start).
    pub(super) stopped_before: bool,
    /// An arc's chord whose corner with the chord before it, of the same
    /// move, is proved to allow both their nominal speeds (`chords.rs`'s
    /// runs): the planner takes that corner at the lesser of them without
    /// working it out.
    pub(super) smooth_before: bool,
    /// G61, G61.1, G64 (tolerances in mm) while it runs.
    pub(super) control: PathControl,
    /// The move it is part of.
    pub(super) source: usize,
}

/// `b − a`.
#[inline(always)]
pub(super) fn sub(b: [f64; 3], a: [f64; 3]) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

#[inline(always)]
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn direction(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    direction_and_length(a, b).0
}

/// The direction from `a` to `b` and the distance (`toolpath::distance`'s,
/// one square root for both).
pub(super) fn direction_and_length(a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64) {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    match n > 0.0 {
        true => ([d[0] / n, d[1] / n, d[2] / n], n),
        false => ([0.0; 3], n),
    }
}

/// A rapid's rate along `v` (mm/s), a vector `length` long (a unit
/// vector: 1).
#[inline(always)]
pub(super) fn rapid_rate(limits: &Limits, v: [f64; 3], length: f64) -> f64 {
    let axes = along(limits.max_rate, v) * length;
    limits.rapid_rate.map_or(axes, |r| r.min(axes))
}

/// The straight block of move `m` from `from` to `to` (grbl's chord, or a
/// line's LinuxCNC segment): a rapid at the rapid rate, else at the
/// move's feed within each axis's rate; `None`: no length. It is not
/// after a stop and belongs to move 0 until the caller says otherwise.
#[inline(always)]
pub(super) fn line_block(m: &Move, from: Point, to: Point, limits: &Limits) -> Option<Block> {
    let d = sub(to, from);
    sized_block(m, d, dot(d, d).sqrt(), limits)
}

/// [`line_block`] of the displacement `d` whose `length` is known (a
/// line's, from [`Along::length`](crate::toolpath::Along::length): the
/// same square root of the same sum).
#[inline(always)]
pub(super) fn sized_block(m: &Move, d: [f64; 3], length: f64, limits: &Limits) -> Option<Block> {
    if length <= 0.0 || length.is_nan() {
        return None;
    }
    // The limits along it from `d`; the direction divided component by
    // component, as `direction_and_length` divides it.
    let unit = d.map(|x| x / length);
    let nominal = match m.kind {
        MoveKind::Rapid => rapid_rate(limits, d, length),
        _ => feed_rate(m.state.feed_rate() / 60.0, limits, unit),
    };
    Some(Block {
        length,
        unit_in: unit,
        unit_out: unit,
        nominal: nominal.max(1e-9),
        accel: along(limits.max_accel, d) * length,
        stopped_before: false,
        smooth_before: false,
        control: m.state.path_control,
        source: 0,
    })
}

/// `feed` (mm/s) within each axis's rate along `unit`. A feed within every
/// axis's rate needs no division: no component of a unit vector exceeds
/// 1 (`direction_and_length` divides each by a norm at least as large),
/// so each axis allows at least its own rate.
#[inline(always)]
fn feed_rate(feed: f64, limits: &Limits, unit: [f64; 3]) -> f64 {
    let [x, y, z] = limits.max_rate;
    match feed <= x.min(y).min(z) {
        true => feed,
        false => feed.min(along(limits.max_rate, unit)),
    }
}
