//! LinuxCNC's saved modal state: `M70` saves it at the current call
//! level, `M71` forgets it, `M72` restores it, `M73` saves it to be
//! restored when the subroutine returns (`interp_convert.cc`'s
//! `save_settings` and `restore_settings`). A restore runs the lines rs274
//! makes of the difference (G20/G21 first; then F, S and the G codes of
//! each modal group that changed; then one line per M code), so the
//! output states what the restored machine runs in. It must not restore
//! what rs274 does not (the motion mode, the tool, G92).

use super::evaluator::{Evaluator, Flow};
use super::state::{Modes, Saved};
use crate::ast::{self, Number, WordValue};
use crate::ir;
use crate::source::Span;

impl Evaluator<'_> {
    /// M70 (`on_return` false) or M73: save the state at this call level.
    pub(super) fn save_modes(&mut self, on_return: bool) {
        let level = self.macros.calls.len();
        let saved = Saved {
            modes: self.modes(),
            on_return: on_return && level > 0,
        };
        let contexts = &mut self.macros.contexts;
        if contexts.len() <= level {
            contexts.resize(level + 1, None);
        }
        contexts[level] = Some(saved);
    }

    /// M71: forget the state saved at this call level.
    pub(super) fn forget_modes(&mut self) {
        let level = self.macros.calls.len();
        if let Some(c) = self.macros.contexts.get_mut(level) {
            *c = None;
        }
    }

    /// M72: the state saved at this call level (`None`: none is).
    pub(super) fn saved_modes(&self) -> Option<Modes> {
        let level = self.macros.calls.len();
        let saved = self.macros.contexts.get(level)?.as_ref()?;
        Some(saved.modes.clone())
    }

    /// A subroutine called at `level` is entered or left: what it saved
    /// is gone, and returned when M73 asked for it back.
    pub(super) fn leave_level(&mut self, level: usize) -> Option<Modes> {
        let saved = self.macros.contexts.get_mut(level)?.take()?;
        saved.on_return.then_some(saved.modes)
    }

    fn modes(&self) -> Modes {
        let m = &self.modal;
        let p = &self.predefined;
        Modes {
            units: m.units.or(self.options.units),
            plane: m.plane,
            comp: m.comp.map(|(side, _)| side),
            distance: m.distance,
            inverse_time: m.inverse_time,
            work_offset: m.work_offset,
            tool_offset: p.tool_offset(),
            return_level: m
                .return_level
                .unwrap_or(self.options.from.power_up_return_level()),
            arc_centers: m.arc_centers,
            diameter_mode: m.diameter_mode,
            feed: m.feed,
            speed: p.speed(),
            spindle: m.spindle,
            mist: p.coolant().0,
            flood: p.coolant().1,
        }
    }

    /// Bring the state back to `saved`, as rs274 does, at `span`.
    pub(super) fn restore_modes(&mut self, saved: &Modes, span: Span) -> Flow {
        let now = self.modes();
        if saved.units != now.units {
            if let Some(u) = saved.units {
                let g = if u == ir::Units::Inch { 20.0 } else { 21.0 };
                let flow = self.run_made_line(&[(b'G', g)], span);
                if flow != Flow::Next {
                    return flow;
                }
            }
        }
        let mut line = Vec::new();
        // rs274 writes F with one decimal and S with none, always.
        if let Some(f) = saved.feed {
            line.push((b'F', (f * 10.0).round() / 10.0));
        }
        line.push((b'S', saved.speed.round()));
        line.extend(g_codes(saved, &now).into_iter().map(|g| (b'G', g)));
        let flow = self.run_made_line(&line, span);
        if flow != Flow::Next {
            return flow;
        }
        for m in m_codes(saved, &now) {
            let flow = self.run_made_line(&[(b'M', m)], span);
            if flow != Flow::Next {
                return flow;
            }
        }
        Flow::Next
    }

    /// Run a line ger made of `words`, every word at `span`.
    fn run_made_line(&mut self, words: &[(u8, f64)], span: Span) -> Flow {
        let words: Vec<ast::Word> = words
            .iter()
            .map(|&(letter, value)| ast::Word {
                letter,
                value: WordValue::Number(Number {
                    value,
                    int_digits: 1,
                    has_point: true,
                }),
                span,
            })
            .collect();
        self.exec_words(&words, false)
    }
}

/// The G codes of the groups whose state differs, in rs274's order.
fn g_codes(saved: &Modes, now: &Modes) -> Vec<f64> {
    let mut codes = Vec::new();
    let mut differs = |changed: bool, code: f64| {
        if changed {
            codes.push(code);
        }
    };
    differs(
        saved.plane != now.plane,
        match saved.plane {
            ir::Plane::XY => 17.0,
            ir::Plane::ZX => 18.0,
            ir::Plane::YZ => 19.0,
        },
    );
    differs(
        saved.comp != now.comp,
        match saved.comp {
            None => 40.0,
            Some(ir::Side::Left) => 41.0,
            Some(ir::Side::Right) => 42.0,
        },
    );
    let distance = |d: ir::Distance, absolute: f64, incremental: f64| match d {
        ir::Distance::Absolute => absolute,
        ir::Distance::Incremental => incremental,
    };
    differs(
        saved.distance != now.distance,
        distance(saved.distance, 90.0, 91.0),
    );
    differs(
        saved.inverse_time != now.inverse_time,
        if saved.inverse_time { 93.0 } else { 94.0 },
    );
    differs(
        saved.work_offset != now.work_offset,
        work_offset_code(saved.work_offset),
    );
    if let (Some(on), true) = (saved.tool_offset, saved.tool_offset != now.tool_offset) {
        differs(true, if on { 43.0 } else { 49.0 });
    }
    differs(
        saved.return_level != now.return_level,
        match saved.return_level {
            ir::ReturnLevel::Initial => 98.0,
            ir::ReturnLevel::R => 99.0,
        },
    );
    differs(
        saved.arc_centers != now.arc_centers,
        distance(saved.arc_centers, 90.1, 91.1),
    );
    differs(
        saved.diameter_mode != now.diameter_mode,
        if saved.diameter_mode { 7.0 } else { 8.0 },
    );
    codes
}

/// G54 … G59, G59.1 … G59.3 of the system `index` (1 = G54).
fn work_offset_code(index: u8) -> f64 {
    if index <= 6 {
        53.0 + f64::from(index)
    } else {
        59.0 + f64::from(index - 6) / 10.0
    }
}

/// The M codes whose state differs, one a line as rs274 runs them.
fn m_codes(saved: &Modes, now: &Modes) -> Vec<f64> {
    let mut codes = Vec::new();
    if saved.spindle != now.spindle {
        codes.push(match saved.spindle {
            ir::Spindle::Clockwise => 3.0,
            ir::Spindle::CounterClockwise => 4.0,
            ir::Spindle::Off => 5.0,
        });
    }
    if saved.mist != now.mist {
        codes.push(if saved.mist { 7.0 } else { 9.0 });
    }
    if saved.flood != now.flood {
        codes.push(if saved.flood { 8.0 } else { 9.0 });
    }
    codes
}
