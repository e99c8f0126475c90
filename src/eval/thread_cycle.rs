//! LinuxCNC's G76 threading cycle (under `--from linuxcnc`) made the G0
//! and G33 moves rs274 makes of it (`convert_threading_cycle`): passes
//! at a growing depth along the drive line, then the spring passes at
//! full depth, each tapered in and out where E and L say, then a rapid to
//! the cycle's end. A lathe cycle, but nothing in it but straight moves
//! and G33, which ger writes for every target that has G33. Knows no
//! target and no pass: the moves go out as the program's own would, in
//! its distance mode.

use super::codes::error::{CodeError, CodeErrorKind as K, ThreadCycleProblem as P};
use super::evaluator::Evaluator;
use super::state::Synced;
use super::words::WordValues;
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Axis, Motion};
use crate::source::Span;

/// The most passes one G76 makes (a J tiny beside K, or a large R,
/// makes rs274 run on for ever).
const MAX_PASSES: f64 = 100_000.0;

/// The G76 words, checked, lengths in the program's units (radii).
struct Thread {
    pitch: f64,
    /// The thread's peak from the drive line (I, signed), the first
    /// cut's depth beyond it (J) and the full depth (K).
    peak: f64,
    first: f64,
    full: f64,
    /// Q in radians, turned round when the thread runs towards +Z.
    angle: f64,
    spring: i64,
    degression: f64,
    /// E, signed along Z as the thread runs; 0 without a taper.
    taper: f64,
    taper_pitch: f64,
    entry_taper: bool,
    exit_taper: bool,
}

/// Where one pass goes: X on the drive line side (`x`), Z at the start
/// and at the end.
struct Pass {
    x_out: f64,
    x_in: f64,
    x_crest: f64,
    z_start: f64,
    z_end: f64,
}

impl Evaluator<'_> {
    /// A G76 line (`at` the code, or the line for axis words alone in
    /// its mode), its words taken.
    pub(super) fn threading_cycle(
        &mut self,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let fail = |problem| -> Diagnostic { CodeError::new(K::ThreadCycle(problem), at).into() };
        let mut to = ir::Axes::NONE;
        super::codes::axis_words_into(w, &mut to);
        if let Some((axis, _)) = to
            .iter()
            .find(|(a, _)| !matches!(a, Axis::X | Axis::Y | Axis::Z))
        {
            return Err(fail(P::OtherAxis(axis.letter() as char)));
        }
        let thread = self.thread_words(w, at)?;
        if to.is_empty() {
            return Err(fail(P::NoAxes));
        }
        if self.modal.spindle == ir::Spindle::Off {
            return Err(fail(P::SpindleOff));
        }
        if self.modal.comp.is_some() {
            return Err(fail(P::Comp));
        }
        let [x, y, z] = [0, 1, 2].map(|i| self.predefined.here[i]);
        let (Some(x), Some(z)) = (x, z) else {
            let axis = if x.is_none() { 'X' } else { 'Z' };
            return Err(fail(P::UnknownStart(axis)));
        };
        let distance = self.modal.distance;
        let end = |axis: Axis, from: Option<f64>| match (to.get(axis), distance) {
            (Some(v), ir::Distance::Absolute) => Some(v),
            (Some(v), ir::Distance::Incremental) => from.map(|p| p + v),
            (None, _) => from,
        };
        let end_z = end(Axis::Z, Some(z)).unwrap_or(z);
        let thread = thread.along(end_z > z);
        let passes = thread.passes();
        if passes > MAX_PASSES {
            return Err(fail(P::TooManyPasses(passes)));
        }
        let mut cut = Cut {
            ev: self,
            at: [x, z],
            span,
        };
        cut.passes(&thread, x, z, end_z)?;
        let final_end = [end(Axis::X, Some(x)), end(Axis::Y, y), Some(end_z)];
        cut.rapid_to(&to, final_end)?;
        self.modal.motion = None;
        self.modal.spline_mode = false;
        self.modal.synced = Some(Synced::ThreadCycle);
        self.cycles.kind = None;
        self.cycles.run_open = false;
        Ok(())
    }

    /// P, I, J, K, Q, H, R, E, L taken and checked as rs274 checks them
    /// (I, J, K halved under G7).
    fn thread_words(&self, w: &mut WordValues, at: Span) -> Result<Thread, Diagnostic> {
        let fail = |problem| -> Diagnostic { CodeError::new(K::ThreadCycle(problem), at).into() };
        let mut required = |letter: u8| {
            w.take(letter)
                .map(|(v, _)| v)
                .ok_or_else(|| fail(P::Missing(letter as char)))
        };
        let pitch = required(b'P')?;
        let [i, j, k] = [required(b'I')?, required(b'J')?, required(b'K')?];
        let mut whole = |letter: u8| -> Result<Option<i64>, Diagnostic> {
            match w.take(letter) {
                Some((v, span)) if v.fract() != 0.0 => {
                    Err(CodeError::new(K::ThreadCycle(P::NotWhole(letter as char)), span).into())
                }
                Some((v, _)) => Ok(Some(v as i64)),
                None => Ok(None),
            }
        };
        let spring = whole(b'H')?.unwrap_or(0);
        let flags = whole(b'L')?.unwrap_or(0).max(0);
        let angle = w
            .take(b'Q')
            .map_or(0.0, |(q, _)| if q == -1.0 { 0.0 } else { q });
        let degression = w.take(b'R').map_or(1.0, |(r, _)| r.max(1.0));
        let taper = w.take(b'E').map_or(0.0, |(e, _)| e.max(0.0));
        if i == 0.0 {
            return Err(fail(P::IZero));
        }
        if j <= 0.0 {
            return Err(fail(P::JNotPositive));
        }
        if k <= j {
            return Err(fail(P::KNotAboveJ));
        }
        let half = if self.modal.diameter_mode { 0.5 } else { 1.0 };
        let full = (k * half).abs();
        let taper_pitch = match taper > 0.0 {
            true => pitch * taper.hypot(full) / taper,
            false => pitch,
        };
        Ok(Thread {
            pitch,
            peak: i * half,
            first: (j * half).abs(),
            full,
            angle: angle.to_radians(),
            spring,
            degression,
            taper,
            taper_pitch,
            entry_taper: flags & 1 != 0,
            exit_taper: flags & 2 != 0,
        })
    }
}

impl Thread {
    /// Towards +Z the compound angle and the taper turn round.
    fn along(mut self, towards_plus_z: bool) -> Thread {
        if towards_plus_z {
            self.angle = -self.angle;
            self.taper = -self.taper;
        }
        self
    }

    /// How many passes the cycle makes before its full-depth ones: the
    /// depth after pass n is the peak + J n^(1/R), up to the peak + K.
    fn passes(&self) -> f64 {
        (self.full / self.first).powf(self.degression) + self.spring.max(0) as f64
    }

    /// The X of a depth beyond the drive line: towards the axis for an
    /// external thread, away for an internal one (I > 0).
    fn x_at(&self, drive_line: f64, depth: f64) -> f64 {
        match self.peak > 0.0 {
            true => drive_line + depth,
            false => drive_line - depth,
        }
    }
}

/// The moves of one G76, written as the program writes its own.
struct Cut<'e, 'a> {
    ev: &'e mut Evaluator<'a>,
    /// Where the last move left the tool: X, Z.
    at: [f64; 2],
    span: Span,
}

impl Cut<'_, '_> {
    /// Every pass, as `convert_threading_cycle` orders them.
    fn passes(&mut self, t: &Thread, x: f64, z: f64, end_z: f64) -> Result<(), Diagnostic> {
        let peak = t.peak.abs();
        let end_depth = t.full + peak;
        let target_z = end_z + t.full * t.angle.tan();
        let pass_at = |depth: f64| {
            let zoff = (depth - peak) * t.angle.tan();
            Pass {
                x_out: t.x_at(x, depth - end_depth),
                x_in: t.x_at(x, depth),
                x_crest: t.x_at(x, depth - t.full),
                z_start: z - zoff,
                z_end: target_z - zoff,
            }
        };
        let mut depth = peak + t.first;
        let mut n = 1.0_f64;
        while depth < end_depth {
            self.pass(t, &pass_at(depth))?;
            n += 1.0;
            depth = peak + t.first * n.powf(1.0 / t.degression);
        }
        for _ in 0..t.spring + 1 {
            self.pass(t, &pass_at(end_depth))?;
        }
        Ok(())
    }

    /// One pass: back to its start, in (tapered or at a rapid), along,
    /// out (tapered or at a rapid).
    fn pass(&mut self, t: &Thread, p: &Pass) -> Result<(), Diagnostic> {
        self.go(None, p.x_out, p.z_start)?;
        if t.taper != 0.0 && t.entry_taper {
            self.go(Some(t.taper_pitch), p.x_crest, p.z_start)?;
            self.go(Some(t.taper_pitch), p.x_in, p.z_start - t.taper)?;
        } else {
            self.go(None, p.x_in, p.z_start)?;
        }
        if t.taper != 0.0 && t.exit_taper {
            self.go(Some(t.pitch), p.x_in, p.z_end + t.taper)?;
            self.go(Some(t.taper_pitch), p.x_crest, p.z_end)?;
        } else {
            self.go(Some(t.pitch), p.x_in, p.z_end)?;
        }
        self.go(None, p.x_out, p.z_end)
    }

    /// A rapid (`lead` none) or a G33 to X, Z, in the distance mode.
    fn go(&mut self, lead: Option<f64>, x: f64, z: f64) -> Result<(), Diagnostic> {
        let mut to = ir::Axes::NONE;
        for (axis, v, from) in [(Axis::X, x, self.at[0]), (Axis::Z, z, self.at[1])] {
            to.set(axis, self.written(v, from));
        }
        self.at = [x, z];
        let motion = if lead.is_some() {
            Motion::Linear
        } else {
            Motion::Rapid
        };
        self.emit(motion, lead, to)
    }

    /// The cycle's last rapid: to its X, Y, Z (those not given stay).
    fn rapid_to(&mut self, given: &ir::Axes, end: [Option<f64>; 3]) -> Result<(), Diagnostic> {
        let mut to = ir::Axes::NONE;
        let from = [
            Some(self.at[0]),
            self.ev.predefined.here[1],
            Some(self.at[1]),
        ];
        for (i, axis) in [Axis::X, Axis::Y, Axis::Z].into_iter().enumerate() {
            // rs274 writes every axis; only a changed one matters here.
            if let (Some(v), Some(p)) = (end[i], from[i]) {
                to.set(axis, self.written(v, p));
            } else if let Some(v) = given.get(axis) {
                to.set(axis, v);
            }
        }
        self.emit(Motion::Rapid, None, to)
    }

    /// `v` as the program's distance mode writes it, from `from`.
    fn written(&self, v: f64, from: f64) -> f64 {
        match self.ev.modal.distance {
            ir::Distance::Absolute => v,
            ir::Distance::Incremental => v - from,
        }
    }

    fn emit(&mut self, motion: Motion, lead: Option<f64>, to: ir::Axes) -> Result<(), Diagnostic> {
        let m = ir::Move {
            motion,
            to,
            arc: None,
            corner: None,
            lead,
        };
        self.ev.emit(ir::Op::Move(m), self.span)
    }
}
