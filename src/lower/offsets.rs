//! Pass offsets (SPEC §4.2): G54–G59 (table from `SetOffset`, changed by
//! G10 L2/L20), G52, G92/G92.1 and G43/G44/G49 folded into the
//! coordinates, which become machine coordinates: the frame in which G54's
//! origin is the program zero (PRZ). Under G90 an axis word gets the
//! active offset added; G91 moves are unchanged. An axis left out keeps its
//! machine position, as on LinuxCNC. Changing an offset under G91 is an
//! error. Lengths are in the output units (the units pass ran first).

// `axis` indexes several per-axis arrays at once in this pass.
#![allow(clippy::needless_range_loop)]

use super::{unknown_position, Errors};
use crate::diagnostic::{error, DiagnosticExt};
use crate::ir::{self, Distance, Op};
use crate::source::Span;
use std::collections::BTreeMap;

struct Offsets {
    /// Origins of G54..G59 (index 1..=6); G54 starts at the PRZ.
    work: [[f64; 3]; 7],
    active: usize,
    local: [f64; 3],
    position: [f64; 3],
    tool_length: f64,
}

impl Offsets {
    fn total(&self, axis: usize) -> f64 {
        self.work[self.active][axis]
            + self.local[axis]
            + self.position[axis]
            + if axis == 2 { self.tool_length } else { 0.0 }
    }
}

/// The pass's state between batches.
pub struct State {
    off: Offsets,
    tools: BTreeMap<u32, ir::Tool>,
    distance: Distance,
    incremental_since: Option<Span>,
    /// Machine position of each axis, once known.
    machine: [Option<f64>; 3],
    pub errors: Errors,
}

impl State {
    pub fn new(setup: &ir::Setup) -> State {
        let mut off = Offsets {
            work: [[0.0; 3]; 7],
            active: 1,
            local: [0.0; 3],
            position: [0.0; 3],
            tool_length: 0.0,
        };
        for (&index, origin) in &setup.work_offsets {
            off.work[index as usize] = *origin;
        }
        State {
            off,
            tools: setup.tools.clone(),
            distance: Distance::Absolute,
            incremental_since: None,
            machine: [None; 3],
            errors: Errors::default(),
        }
    }

    pub fn run(&mut self, stmts: &mut Vec<ir::Stmt>) {
        let State {
            off,
            tools,
            distance,
            incremental_since,
            machine,
            errors,
        } = self;
        stmts.retain_mut(|stmt| {
            let span = stmt.span;
            if super::polar::changes_offsets(&stmt.op) && *distance == Distance::Incremental {
                let mut d = error(
                    "offsets changed under G91",
                    span,
                    "incremental mode is on here",
                )
                .with_help("switch to G90 before changing offsets");
                if let Some(at) = *incremental_since {
                    d = d.with_secondary(at, "G91 from here");
                }
                errors.push(d);
                return false;
            }
            match &mut stmt.op {
                Op::Distance(d) => {
                    *distance = *d;
                    if *d == Distance::Incremental {
                        *incremental_since = Some(span);
                    }
                    true
                }
                Op::Move(m) => {
                    for axis in 0..3 {
                        let Some(v) = m.to.get(axis) else { continue };
                        match *distance {
                            Distance::Absolute => {
                                let value = v + off.total(axis);
                                m.to.set(axis, Some(value));
                                machine[axis] = Some(value);
                            }
                            Distance::Incremental => machine[axis] = machine[axis].map(|p| p + v),
                        }
                    }
                    true
                }
                Op::SelectWorkOffset(i) => {
                    off.active = *i as usize;
                    // SPEC §4.2: G54 cancels G52.
                    if *i == 1 {
                        off.local = [0.0; 3];
                    }
                    false
                }
                Op::SetWorkOffset { index, origin } => {
                    for axis in 0..3 {
                        if let Some(v) = origin.get(axis) {
                            off.work[*index as usize][axis] = v;
                        }
                    }
                    false
                }
                Op::SetWorkOffsetHere { index, at } => {
                    let index = *index as usize;
                    for axis in 0..3 {
                        let Some(v) = at.get(axis) else { continue };
                        match machine[axis] {
                            Some(m) => {
                                let others = off.total(axis) - off.work[off.active][axis];
                                off.work[index][axis] = m - v - others;
                            }
                            None => errors.push(unknown_position(span, axis, "G10 L20")),
                        }
                    }
                    false
                }
                Op::LocalOffset(a) => {
                    for axis in 0..3 {
                        if let Some(v) = a.get(axis) {
                            off.local[axis] = v;
                        }
                    }
                    false
                }
                Op::SetPosition(a) => {
                    for axis in 0..3 {
                        let Some(v) = a.get(axis) else { continue };
                        match machine[axis] {
                            Some(m) => {
                                // Choose the G92 shift so that here reads `v`.
                                off.position[axis] = 0.0;
                                off.position[axis] = m - v - off.total(axis);
                            }
                            None => errors.push(unknown_position(span, axis, "G92")),
                        }
                    }
                    false
                }
                Op::CancelPosition => {
                    off.position = [0.0; 3];
                    false
                }
                Op::ToolLength { tool, negative } => {
                    let length = match tools.get(tool) {
                        Some(t) => t.length,
                        None if *tool == 1 => 0.0,
                        None => {
                            errors.push(
                                error(
                                    format!("tool {tool} has no length"),
                                    span,
                                    "G43 needs the tool's length",
                                )
                                .with_help(format!(
                                    "add `SetTool {tool} diameter length` to the setup"
                                )),
                            );
                            0.0
                        }
                    };
                    off.tool_length = if *negative { -length } else { length };
                    false
                }
                Op::CancelToolLength => {
                    off.tool_length = 0.0;
                    false
                }
                _ => true,
            }
        });
    }
}
