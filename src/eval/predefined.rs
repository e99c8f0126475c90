//! rs274's predefined parameters (`#<_x>`, `#<_metric>`, `#<_feed>`, …,
//! and the numbered ones that are the interpreter's own state: `#5400`
//! the tool, `#5420`–`#5428` the position, `#5220` the coordinate
//! system), worked out from what ger knows at the line that reads them,
//! as `interp_namedparams.cc` computes them. A value only the machine has
//! (where the tool stands before the program moves it, an offset or a
//! tool length ger was not given, the machine's units or pockets) reads as
//! [`Slot::Machine`], an error at its use naming it. It follows the
//! statements the evaluator admits; it must not emit, evaluate
//! expressions or change what any other part of the evaluator keeps.

use super::error::{EvalError, EvalErrorKind};
use super::evaluator::Evaluator;
use super::known::{
    Param, Predefined, ADAPTIVE_FEED, FEED_HOLD, FEED_OVERRIDE, SPEED_OVERRIDE, VERSION,
};
use super::value::{Slot, Value};
use super::watch::{each_read, each_read_in};
use crate::ast::{self, Symbol};
use crate::ir::{self, Axis, Units};
use crate::source::Span;

impl Evaluator<'_> {
    /// Set every predefined parameter the program names to its value
    /// before the statement at `span` runs (`None`: between statements,
    /// where `_line` stays).
    pub(super) fn refresh_predefined(&mut self, span: Option<Span>) {
        for i in 0..self.predefined.named.len() {
            let (symbol, param) = self.predefined.named[i];
            if param == Param::Line && span.is_none() {
                continue;
            }
            let slot = match self.predefined_value(param, span) {
                Some(v) => Slot::Set(Value::Number(v)),
                None => Slot::Machine,
            };
            self.store(symbol, slot);
        }
    }

    /// The first read of `#<_task>`: a warning that the output takes the
    /// preview's branch.
    pub(super) fn warn_task(&mut self, stmt: &ast::Stmt) {
        if self.predefined.task_warned {
            return;
        }
        let Some(&(task, _)) = self
            .predefined
            .named
            .iter()
            .find(|(_, p)| *p == Param::Task)
        else {
            return;
        };
        let mut at = None;
        let mut find = |name: Symbol, span: Span| {
            if name == task && at.is_none() {
                at = Some(span);
            }
        };
        match &stmt.kind {
            // Its condition is read before each test.
            ast::StmtKind::While(w) => each_read_in(&w.cond, &mut find),
            _ => each_read(stmt, &mut find),
        }
        if let Some(at) = at {
            self.predefined.task_warned = true;
            self.report(EvalError::new(EvalErrorKind::TaskAsPreview, at));
        }
    }

    /// Is `name` one of rs274's read-only named parameters?
    pub(super) fn read_only(&self, name: Symbol) -> bool {
        self.predefined.named.iter().any(|(s, _)| *s == name)
            && self.names.text(name).starts_with("#<")
    }

    /// The value `param` reads now, if ger knows it.
    pub(super) fn predefined_value(&self, param: Param, span: Option<Span>) -> Option<f64> {
        let p = &self.predefined;
        let m = &self.modal;
        let flag = |b: bool| Some(f64::from(u8::from(b)));
        let units = m.units.or(self.options.units);
        match param {
            Param::Position(axis) => p.here[axis.index()],
            Param::Absolute | Param::Pocket | Param::MetricMachine => None,
            Param::Metric => units.and_then(|u| flag(u == Units::Mm)),
            Param::Imperial => units.and_then(|u| flag(u == Units::Inch)),
            Param::AbsoluteMode => flag(m.distance == ir::Distance::Absolute),
            Param::IncrementalMode => flag(m.distance == ir::Distance::Incremental),
            Param::InverseTime => flag(m.inverse_time),
            Param::UnitsPerMinute => flag(!m.inverse_time),
            Param::UnitsPerRev => flag(false),
            Param::CoordSystem => Some(coord_system(m.work_offset)),
            Param::CoordIndex => Some(f64::from(m.work_offset)),
            Param::ToolOffset => p.tool_offset.and_then(flag),
            Param::RetractR | Param::RetractOldZ => {
                let level = m
                    .return_level
                    .unwrap_or(self.options.from.power_up_return_level());
                flag((level == ir::ReturnLevel::R) == (param == Param::RetractR))
            }
            Param::RpmMode => flag(!p.surface_speed),
            Param::CssMode => flag(p.surface_speed),
            Param::IjkAbsolute => flag(m.arc_centers == ir::Distance::Absolute),
            Param::DiameterMode => flag(m.diameter_mode),
            Param::RadiusMode => flag(!m.diameter_mode),
            Param::SpindleOn => flag(m.spindle != ir::Spindle::Off),
            Param::SpindleCw => flag(m.spindle == ir::Spindle::Clockwise),
            Param::Mist => flag(p.mist),
            Param::Flood => flag(p.flood),
            Param::Enable(i) => flag(p.enables[i]),
            Param::Feed => Some(m.feed.unwrap_or(0.0)),
            Param::Rpm => Some(p.speed.abs()),
            Param::CurrentTool => p.tool.map(f64::from),
            Param::SelectedTool => m.selected.map(f64::from),
            Param::MotionMode => Some(p.motion),
            Param::Plane => Some(match m.plane {
                ir::Plane::XY => 170.0,
                ir::Plane::ZX => 180.0,
                ir::Plane::YZ => 190.0,
            }),
            Param::CutterComp => Some(match m.comp {
                None => 400.0,
                Some((ir::Side::Left, _)) => 410.0,
                Some((ir::Side::Right, _)) => 420.0,
            }),
            Param::Line => span.map(|s| f64::from(s.line)),
            Param::CallLevel => Some(self.macros.calls.len() as f64),
            Param::RemapLevel => Some(0.0),
            // rs274 run alone (a preview) reads 0; LinuxCNC's task reads 1.
            Param::Task => Some(0.0),
            Param::VersionMajor => Some(VERSION.0),
            Param::VersionMinor => Some(VERSION.1),
        }
    }

    /// Follow `op` before the modal state takes it (`self.modal` still
    /// holds the state before it).
    pub(super) fn follow_predefined(&mut self, op: &ir::Op) {
        let m = &self.modal;
        let p = &mut self.predefined;
        match op {
            // Followed even before a predefined name is seen: a program
            // read in parts meets its names part by part, and must read
            // them as the whole program does.
            ir::Op::Move(mv) => self.follow_move(mv),
            ir::Op::Cycle(c) => {
                p.motion = f64::from(c.kind.code()) * 10.0;
                self.follow_cycle(c);
            }
            ir::Op::CycleOff => p.motion = 800.0,
            ir::Op::RigidTap(_) => p.motion = 331.0,
            ir::Op::Units(to) => {
                let from = m.units.or(self.options.units);
                for (i, at) in p.here.iter_mut().enumerate() {
                    let rotary = (3..6).contains(&i);
                    *at = match from {
                        _ if rotary => *at,
                        Some(from) => at.map(|a| a * from.factor(*to)),
                        None => None,
                    };
                }
            }
            ir::Op::Speed(s) => p.speed = *s,
            ir::Op::SpindleMode(mode) => {
                p.surface_speed = matches!(mode, ir::SpindleMode::SurfaceSpeed { .. });
                if let ir::SpindleMode::SurfaceSpeed { speed, .. } = mode {
                    p.speed = *speed;
                }
            }
            ir::Op::Coolant(c) => match c {
                ir::Coolant::Mist => p.mist = true,
                ir::Coolant::Flood => p.flood = true,
                ir::Coolant::Off => (p.mist, p.flood) = (false, false),
            },
            ir::Op::ChangeTool => {
                if let Some(t) = m.selected {
                    p.tool = Some(t);
                }
            }
            ir::Op::Passthrough(ir::Passthrough::MCode { number, words }) => {
                let word = |l: u8| words.iter().find(|(w, _)| *w == l).map(|(_, v)| *v);
                follow_m_code(p, *number, word(b'Q'), word(b'P'));
            }
            ir::Op::SetPosition(axes) => {
                for (axis, v) in axes.iter() {
                    p.here[axis.index()] = Some(v);
                }
            }
            ir::Op::SetWorkOffsetHere { index, at } => {
                if *index == 0 || *index == m.work_offset {
                    for (axis, v) in at.iter() {
                        p.here[axis.index()] = Some(v);
                    }
                }
            }
            ir::Op::SetWorkOffset { index, .. } if *index != 0 && *index != m.work_offset => {}
            ir::Op::SelectWorkOffset(index) if *index == m.work_offset => {}
            ir::Op::ToolLength { tool, .. } => {
                let zero = tool.and_then(|t| self.setup.tool_length_is_zero(t));
                if p.tool_offset != Some(false) || zero != Some(true) {
                    p.here[Axis::Z.index()] = None;
                }
                p.tool_offset = zero.map(|z| !z);
            }
            ir::Op::CancelToolLength => {
                if p.tool_offset != Some(false) {
                    p.here[Axis::Z.index()] = None;
                }
                p.tool_offset = Some(false);
            }
            ir::Op::LocalOffset(axes) => {
                for (axis, _) in axes.iter() {
                    p.here[axis.index()] = None;
                }
            }
            ir::Op::CancelPosition => p.here = [None; 9],
            _ => {
                let unknown = op.unknown_after();
                for (i, axis) in Axis::ALL.iter().enumerate() {
                    if unknown(*axis) {
                        p.here[i] = None;
                    }
                }
            }
        }
    }

    /// A move: the motion mode, and where it leaves the tool.
    fn follow_move(&mut self, mv: &ir::Move) {
        let m = &self.modal;
        let p = &mut self.predefined;
        p.motion = match mv.motion {
            ir::Motion::Rapid => 0.0,
            ir::Motion::Linear if mv.lead.is_some() => 330.0,
            ir::Motion::Linear => 10.0,
            ir::Motion::ArcCw => 20.0,
            ir::Motion::ArcCcw => 30.0,
        };
        let (u, v, _) = m.plane.axes();
        // Under compensation rs274's point in the plane is the
        // tool centre's, which the comp pass works out later; a
        // G16 move's words are a radius and an angle.
        let lost = m.comp.is_some() || m.polar;
        for (i, axis) in Axis::ALL.iter().enumerate() {
            let Some(to) = mv.to.get(*axis) else {
                continue;
            };
            let gone = (lost && (i == u || i == v)) || self.this_line.machine_coordinates;
            p.here[i] = match m.distance {
                _ if gone => None,
                ir::Distance::Absolute => Some(to),
                ir::Distance::Incremental => p.here[i].map(|at| at + to),
            };
        }
        if lost {
            p.here[u] = None;
            p.here[v] = None;
        }
    }

    /// Where a canned cycle block leaves the tool: over its hole, at R
    /// (G99) or the higher of R and where the run began (G98), as rs274's
    /// `convert_cycle` leaves it.
    fn follow_cycle(&mut self, c: &ir::Cycle) {
        let (u, v, w) = self.modal.plane.axes();
        let here = &mut self.predefined.here;
        if self.modal.distance == ir::Distance::Incremental || self.modal.comp.is_some() {
            *here = [None; 9];
            return;
        }
        let start = here[w];
        for i in [u, v] {
            if let Some(at) = c.at.get(Axis::ALL[i]) {
                here[i] = Some(at);
            }
        }
        let level = self
            .modal
            .return_level
            .unwrap_or(self.options.from.power_up_return_level());
        here[w] = match level {
            ir::ReturnLevel::R => Some(c.r),
            ir::ReturnLevel::Initial => start.map(|z| z.max(c.r)),
        };
    }
}

/// The M codes rs274 keeps state for that ger passes through: M61 (the
/// tool number, no change) and the enables M48–M53.
fn follow_m_code(p: &mut Predefined, number: u32, q: Option<f64>, pw: Option<f64>) {
    let on = pw.is_none_or(|v| v != 0.0);
    match number {
        61 => {
            p.tool = q
                .filter(|q| *q >= 0.0 && q.fract() == 0.0)
                .map(|q| q as u32)
        }
        48 => (p.enables[SPEED_OVERRIDE], p.enables[FEED_OVERRIDE]) = (true, true),
        49 => (p.enables[SPEED_OVERRIDE], p.enables[FEED_OVERRIDE]) = (false, false),
        50 => p.enables[FEED_OVERRIDE] = on,
        51 => p.enables[SPEED_OVERRIDE] = on,
        52 => p.enables[ADAPTIVE_FEED] = on,
        53 => p.enables[FEED_HOLD] = on,
        _ => {}
    }
}

/// `#<_coord_system>` of the system `index` (1 = G54): 540 … 590, then
/// 591 … 593 for G59.1 … G59.3.
fn coord_system(index: u8) -> f64 {
    let i = f64::from(index);
    if index < 7 {
        530.0 + 10.0 * i
    } else {
        584.0 + i
    }
}
