//! Pass cycles (SPEC §4.4): G73, G74, G81–G86, G89 expanded to rapids,
//! feeds, dwells and spindle codes that move the tool as LinuxCNC's rs274
//! moves it; with `--cycles keep`, each hole kept as one normalised cycle
//! block instead (absolute, G98/G99 on it, R and the depth given, no L).
//!
//! Each block (rs274's `convert_cycle_xy` and friends), in the plane's
//! axes a, b and the normal axis n along which it drills:
//! - the run's G98 level IL is where n was at the run's first block;
//! - G90: R and the bottom as written; G91: R is measured from IL, the
//!   bottom from R, and a/b are the step from hole to hole;
//! - if IL is below R, the tool first rises to R where it is;
//! - the clear level is R under G99, max(IL, R) under G98;
//! - each of the L holes: a rapid over it (at the current level for the
//!   first hole of a block when that is above R, else to the clear level,
//!   then down to R), the body of the cycle, and out to the clear level.
//!
//! Fanuc's G76 (fine boring) and G87 (back boring) are expanded even when
//! cycles are kept (LinuxCNC's are threading and another back bore): at
//! the bottom of a G76, its dwell, M19 (the oriented stop), a rapid of Q
//! along +a off the wall, out, back over the hole, the spindle on again;
//! a G87 goes down to R so shifted, and back up the same way from the top
//! of the back bore (its depth word), to the initial level (G98 only).
//!
//! G87 (back boring: oriented spindle stops) and G88 (the operator takes
//! the tool out by hand) have no expansion ger's output can express; they
//! are errors unless kept. So is tapping outside G17, where rs274 feeds to
//! the wrong axes.

use super::error::CycleError;
use super::error::LowerError;
use super::pass::{feed_in_turn, Batch, Context, Out, Pass, PassInfo};
use super::position::Tracker;
use crate::ir::{
    self, Axes, Axis, CycleKind, Distance, Motion, Op, Plane, ReturnLevel, Spindle, Stmt,
};
use crate::source::Span;

pub const PASS: PassInfo = PassInfo {
    name: "cycles",
    make: |cx| Box::new(CyclesPass::new(cx)),
};

/// The most statements the cycles of one program may expand to.
pub const MAX_EXPANDED: u64 = 20_000_000;

/// G73's back-off and G83's re-entry clearance: rs274's 0.010 in.
const PECK_CLEARANCE_MM: f64 = 0.254;

struct CyclesPass {
    at: Tracker,
    keep: bool,
    /// The peck clearance in output units, when they are known.
    clearance: Option<f64>,
    /// G98/G99; rs274 starts in G99.
    level: ReturnLevel,
    /// The G98 level of the current run.
    initial: Option<f64>,
    spindle: Spindle,
    /// Statements the cycles expanded to so far (about).
    expanded: u64,
}

/// One expanded block: where its holes are and how deep, in output
/// coordinates.
struct Block {
    axes: [usize; 3],
    r: f64,
    bottom: f64,
    clear: f64,
}

impl CyclesPass {
    fn new(cx: &Context<'_>) -> CyclesPass {
        CyclesPass {
            at: Tracker::new(),
            keep: cx.options.keep_cycles,
            clearance: cx.start.output_units.map(|u| match u {
                ir::Units::Mm => PECK_CLEARANCE_MM,
                ir::Units::Inch => PECK_CLEARANCE_MM / 25.4,
            }),
            level: cx.start.return_level,
            initial: None,
            spindle: Spindle::Off,
            expanded: 0,
        }
    }

    /// The current position of `axis`, or the error.
    fn current(&self, axis: usize, span: Span) -> Result<f64, LowerError> {
        self.at.position[axis].ok_or_else(|| self.at.unknown(axis, "a canned cycle", span))
    }

    fn check(&self, c: &ir::Cycle, span: Span) -> Result<(), LowerError> {
        let problem = match c.kind {
            CycleKind::G87 | CycleKind::G88 if !self.keep => CycleError::NeedsOperator {
                code: c.kind.code(),
            },
            CycleKind::G84 | CycleKind::G74 if !self.keep && self.at.plane != Plane::XY => {
                CycleError::TappingOutsideXy {
                    code: c.kind.code(),
                }
            }
            CycleKind::G73 if self.keep && c.dwell.is_some() => CycleError::PeckDwellKept,
            CycleKind::G87Fanuc if self.level == ReturnLevel::R => CycleError::BackBoreToR,
            CycleKind::G73 | CycleKind::G83 if !self.keep && self.clearance.is_none() => {
                CycleError::PeckUnits {
                    code: c.kind.code(),
                }
            }
            _ => return Ok(()),
        };
        Err(LowerError::new(problem, span))
    }

    fn cycle(&mut self, c: &ir::Cycle, stmt: &Stmt, out: &mut Out<'_>) -> Result<(), LowerError> {
        let span = stmt.span;
        self.check(c, span)?;
        // LinuxCNC's G76 is threading: Fanuc's fine boring is always
        // expanded.
        let keep = self.keep && !matches!(c.kind, CycleKind::G76 | CycleKind::G87Fanuc);
        let (a, b, n) = self.at.plane.axes();
        let axes = [a, b, n];
        let level = self.current(n, span)?;
        if c.starts_run || self.initial.is_none() {
            self.initial = Some(level);
        }
        let initial = self.initial.unwrap_or(level);
        let written = |i: usize| c.at.get(Axis::ALL[i]);
        let incremental = self.at.distance == Distance::Incremental;
        let (mut hole, step) = self.hole_and_step(c, incremental, span)?;
        let (r, bottom) = if incremental {
            let r = c.r + initial;
            (r, r + written(n).unwrap_or(0.0))
        } else {
            (c.r, written(n).unwrap_or(level))
        };
        // Under G91 the moves are written absolute, between G90 and G91.
        let mut emit = Emitter {
            stmt,
            out,
            axes,
            now: [self.at.position[a], self.at.position[b], Some(level)],
            incremental,
            switched: false,
        };
        let mut old = initial;
        let mut level = level;
        if old < r && c.kind != CycleKind::G87Fanuc {
            if !keep {
                emit.rapid(None, Some(r));
            }
            old = r;
            level = r;
        }
        let clear = match self.level {
            ReturnLevel::R => r,
            ReturnLevel::Initial => old,
        };
        let block = Block {
            axes,
            r,
            bottom,
            clear,
        };
        let pecks = self.pecks_within_budget(c, r, bottom, span)?;
        for i in 0..c.repeats {
            hole = [hole[0] + step[0], hole[1] + step[1]];
            if keep {
                self.keep_hole(c, &block, hole, i == 0, &mut emit);
                continue;
            }
            if i == 0 && level > r {
                emit.rapid(Some(hole), None);
            } else {
                emit.rapid(Some(hole), Some(clear));
            }
            // Fanuc's back bore goes down to R off the wall, in its body.
            if c.kind != CycleKind::G87Fanuc {
                emit.rapid(None, Some(r));
            }
            self.body(c, &block, pecks.unwrap_or(0), &mut emit);
        }
        emit.done();
        for (k, &i) in axes.iter().enumerate() {
            self.at.position[i] = Some(match k {
                0 | 1 => hole[k],
                _ => clear,
            });
        }
        Ok(())
    }

    /// Where the holes start from, before the first step, and the step
    /// between them (zero under G90): a hole's a and b from its words,
    /// else from where the tool is; under G91 the words are the step.
    fn hole_and_step(
        &self,
        c: &ir::Cycle,
        incremental: bool,
        span: Span,
    ) -> Result<([f64; 2], [f64; 2]), LowerError> {
        let (a, b, _) = self.at.plane.axes();
        let mut hole = [0.0; 2];
        let mut step = [0.0; 2];
        for (k, i) in [a, b].into_iter().enumerate() {
            match (incremental, c.at.get(Axis::ALL[i])) {
                (false, Some(v)) => hole[k] = v,
                (true, v) => {
                    hole[k] = self.current(i, span)?;
                    step[k] = v.unwrap_or(0.0);
                }
                (false, None) => hole[k] = self.current(i, span)?,
            }
        }
        Ok((hole, step))
    }

    /// The pecks of each hole (counted here for a G73/G83 under G91,
    /// whose depth the evaluator did not know), counted against the
    /// program's budget of expanded statements.
    fn pecks_within_budget(
        &mut self,
        c: &ir::Cycle,
        r: f64,
        bottom: f64,
        span: Span,
    ) -> Result<Option<u32>, LowerError> {
        let pecks = match (c.kind, c.pecks) {
            (CycleKind::G73 | CycleKind::G83, None) => {
                let q = c.q.unwrap_or(r - bottom);
                let n = crate::eval::count_pecks(r, bottom, q)
                    .ok_or_else(|| LowerError::new(CycleError::TooManyPecks, span))?;
                Some(n)
            }
            (_, known) => known,
        };
        self.expanded += u64::from(c.repeats) * (3 * u64::from(pecks.unwrap_or(0)) + 8);
        if self.expanded > MAX_EXPANDED {
            return Err(LowerError::new(
                CycleError::TooLarge {
                    limit: MAX_EXPANDED,
                },
                span,
            ));
        }
        Ok(pecks)
    }

    /// `--cycles keep`: the hole as one normalised block.
    fn keep_hole(
        &self,
        c: &ir::Cycle,
        block: &Block,
        hole: [f64; 2],
        first: bool,
        emit: &mut Emitter<'_, '_, '_>,
    ) {
        let [a, b, n] = block.axes.map(|i| Axis::ALL[i]);
        let mut at = Axes::default();
        at.set(a, hole[0]);
        at.set(b, hole[1]);
        at.set(n, block.bottom);
        let mut ijk = c.ijk;
        if self.at.distance == Distance::Incremental {
            // G87's K is measured from the bottom under G91.
            if let Some(k) = &mut ijk[block.axes[2]] {
                *k += block.bottom;
            }
        }
        emit.absolute();
        // Haas's G81 P is everyone's G82.
        let kind = match (c.kind, c.dwell) {
            (CycleKind::G81, Some(_)) => CycleKind::G82,
            (kind, _) => kind,
        };
        emit.push(Op::Cycle(Box::new(ir::Cycle {
            kind,
            at,
            r: block.r,
            repeats: 1,
            ijk,
            starts_run: c.starts_run && first,
            pecks: None,
            kept: Some(ir::KeptCycle {
                level: self.level,
                ends_at: block.clear,
            }),
            ..*c
        })));
        emit.now = [Some(hole[0]), Some(hole[1]), Some(block.clear)];
    }

    /// Fanuc's oriented stop (M19), a rapid of Q off the wall, along the
    /// plane's first axis plus (Fanuc's default, parameter RD1/RD2 = 0:
    /// +X in G17), to `level`, back over the hole, the spindle on again.
    fn shifted_to(&self, c: &ir::Cycle, level: f64, emit: &mut Emitter<'_, '_, '_>) {
        emit.push(Op::Passthrough(ir::Passthrough::MCode {
            number: 19,
            words: Vec::new(),
        }));
        let [a, b, _] = emit.now;
        let shift = c.q.unwrap_or(0.0);
        if let (Some(a), Some(b)) = (a, b) {
            emit.rapid(Some([a + shift, b]), None);
            emit.rapid(None, Some(level));
            emit.rapid(Some([a, b]), None);
        }
        emit.push(Op::Spindle(self.spindle));
    }

    /// One hole's cycle, from R over the hole.
    fn body(&mut self, c: &ir::Cycle, k: &Block, pecks: u32, emit: &mut Emitter<'_, '_, '_>) {
        let dwell = c.dwell.unwrap_or(0.0);
        match c.kind {
            CycleKind::G81 => {
                emit.feed(k.bottom);
                // Haas's G81 P dwells as G82 does.
                if c.dwell.is_some() {
                    emit.push(Op::Dwell(dwell));
                }
                emit.rapid(None, Some(k.clear));
            }
            CycleKind::G82 => {
                emit.feed(k.bottom);
                emit.push(Op::Dwell(dwell));
                emit.rapid(None, Some(k.clear));
            }
            CycleKind::G73 | CycleKind::G83 => {
                let q = c.q.unwrap_or(k.r - k.bottom);
                let clearance = self.clearance.unwrap_or(PECK_CLEARANCE_MM);
                let mut depth = k.r - q;
                for _ in 0..pecks {
                    emit.feed(depth);
                    if c.kind == CycleKind::G83 {
                        emit.rapid(None, Some(k.r));
                    }
                    emit.rapid(None, Some(depth + clearance));
                    depth -= q;
                }
                emit.feed(k.bottom);
                if c.dwell.is_some() {
                    emit.push(Op::Dwell(dwell));
                }
                emit.rapid(None, Some(k.clear));
            }
            CycleKind::G76 => {
                emit.feed(k.bottom);
                if c.dwell.is_some_and(|d| d > 0.0) {
                    emit.push(Op::Dwell(dwell));
                }
                self.shifted_to(c, k.clear, emit);
            }
            CycleKind::G87Fanuc => {
                // Down past the bore off the wall, fed up to the top.
                self.shifted_to(c, k.r, emit);
                emit.feed(k.bottom);
                if c.dwell.is_some_and(|d| d > 0.0) {
                    emit.push(Op::Dwell(dwell));
                }
                self.shifted_to(c, k.clear, emit);
            }
            CycleKind::G84 | CycleKind::G74 => {
                let (turn, back) = match c.kind {
                    CycleKind::G84 => (Spindle::Clockwise, Spindle::CounterClockwise),
                    _ => (Spindle::CounterClockwise, Spindle::Clockwise),
                };
                emit.feed(k.bottom);
                emit.push(Op::Spindle(Spindle::Off));
                emit.push(Op::Spindle(back));
                if dwell > 0.0 {
                    emit.push(Op::Dwell(dwell));
                }
                emit.feed(k.clear);
                emit.push(Op::Spindle(Spindle::Off));
                emit.push(Op::Spindle(turn));
            }
            CycleKind::G85 => {
                emit.feed(k.bottom);
                emit.feed(k.r);
                emit.rapid(None, Some(k.clear));
            }
            CycleKind::G86 => {
                emit.feed(k.bottom);
                // rs274 dwells (P0 too); Fanuc's G86 has no dwell word.
                if c.dwell.is_some() {
                    emit.push(Op::Dwell(dwell));
                }
                emit.push(Op::Spindle(Spindle::Off));
                emit.rapid(None, Some(k.clear));
                emit.push(Op::Spindle(self.spindle));
            }
            CycleKind::G89 => {
                emit.feed(k.bottom);
                emit.push(Op::Dwell(dwell));
                emit.feed(k.clear);
            }
            // Refused by `check` unless kept.
            CycleKind::G87 | CycleKind::G88 => {}
        }
    }
}

/// Writes the moves of one block, in absolute coordinates of the three
/// axes, each only with the axes it changes.
struct Emitter<'s, 'o, 'p> {
    stmt: &'s Stmt,
    out: &'o mut Out<'p>,
    axes: [usize; 3],
    /// Where the tool is (a, b unknown until the first hole).
    now: [Option<f64>; 3],
    incremental: bool,
    /// A G90 was written for this block.
    switched: bool,
}

impl Emitter<'_, '_, '_> {
    fn push(&mut self, op: Op) {
        self.out.push(self.stmt.with_op(op));
    }

    /// Under G91, switch to G90 before the first move.
    fn absolute(&mut self) {
        if self.incremental && !self.switched {
            self.switched = true;
            self.push(Op::Distance(Distance::Absolute));
        }
    }

    fn motion(&mut self, motion: Motion, plane: Option<[f64; 2]>, normal: Option<f64>) {
        let mut target = self.now;
        if let Some([x, y]) = plane {
            target[0] = Some(x);
            target[1] = Some(y);
        }
        if normal.is_some() {
            target[2] = normal;
        }
        let mut to = Axes::default();
        for ((t, now), &axis) in target.iter().zip(self.now).zip(&self.axes) {
            if let Some(v) = t.filter(|&v| now != Some(v)) {
                to.set(Axis::ALL[axis], v);
            }
        }
        if to.is_empty() {
            return;
        }
        self.absolute();
        self.now = target;
        self.push(Op::Move(ir::Move {
            motion,
            to,
            arc: None,
            corner: None,
            lead: None,
        }));
    }

    fn rapid(&mut self, plane: Option<[f64; 2]>, normal: Option<f64>) {
        self.motion(Motion::Rapid, plane, normal);
    }

    fn feed(&mut self, normal: f64) {
        self.motion(Motion::Linear, None, Some(normal));
    }

    /// Back to G91 if the block switched.
    fn done(&mut self) {
        if self.switched {
            self.push(Op::Distance(Distance::Incremental));
        }
    }
}

impl Pass for CyclesPass {
    /// A run of moves (no cycle among them) is only followed.
    fn feed_each(&mut self, input: &mut [Stmt], to: &mut Batch<'_, '_>) -> usize {
        match self.at.follow_run(input) {
            true => 0,
            false => feed_in_turn(self, input, to),
        }
    }

    fn feed(&mut self, stmt: &mut Stmt, out: &mut Out<'_>) -> bool {
        match &stmt.op {
            Op::Cycle(c) => {
                let c = **c;
                if let Err(e) = self.cycle(&c, stmt, out) {
                    out.report(e);
                }
                return false;
            }
            // Kept cycles carry their own.
            Op::ReturnLevel(level) => {
                self.level = *level;
                return false;
            }
            Op::CycleOff if !self.keep => return false,
            Op::Spindle(s) => self.spindle = *s,
            Op::Move(_)
            | Op::IncrementalMove(_)
            | Op::Spline(_)
            | Op::RigidTap(_)
            | Op::MachineMove(_)
            | Op::Home { .. }
            | Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::ReadPosition(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::End
            | Op::Units(_)
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::InverseTime(_)
            | Op::InverseTimeFloor(_)
            | Op::Plane(_)
            | Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::CancelPosition
            | Op::ToolLength { .. }
            | Op::CancelToolLength
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            | Op::PathControl(_)
            | Op::Comment(_)
            | Op::SetToolData(_)
            | Op::Passthrough(_) => {}
        }
        self.at.follow(&stmt.op, stmt.span);
        true
    }
}
