//! LinuxCNC's G33 (a straight feed locked to the spindle, K along the path
//! per revolution) read into an [`ir::Move`] with its `lead`, and G33.1
//! (a rigid tap there and back) into an [`ir::RigidTap`], with rs274's
//! checks, each an error at the line. It knows no target: which
//! controllers run them is the printer's question (`emit::target`).

use super::codes::error::{CodeError, CodeErrorKind as K, ThreadProblem as P};
use super::evaluator::Evaluator;
use super::state::Synced;
use super::words::WordValues;
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Motion};
use crate::source::Span;

impl Evaluator<'_> {
    /// Before the line's F is taken as a feed: rs274 refuses an F with
    /// G33 or G33.1 (`code`).
    pub(super) fn thread_feed_word(
        &self,
        w: &WordValues,
        code: &'static str,
    ) -> Result<(), Diagnostic> {
        match w.given(b'F') {
            Some(at) => Err(CodeError::new(K::Thread(P::Feed, code), at).into()),
            None => Ok(()),
        }
    }

    /// The K of a G33 or G33.1 (`code`), once the spindle turns; `at`:
    /// the code, or the line for axis words alone in its mode.
    fn lead(&self, code: &'static str, at: Span, w: &mut WordValues) -> Result<f64, Diagnostic> {
        let fail = |problem| -> Diagnostic { CodeError::new(K::Thread(problem, code), at).into() };
        let Some((lead, _)) = w.take(b'K') else {
            return Err(fail(P::NoK));
        };
        if self.modal.spindle == ir::Spindle::Off {
            return Err(fail(P::SpindleOff));
        }
        Ok(lead)
    }

    /// A G33 move (`at` the code, or the line for axis words alone in its
    /// mode), its words taken.
    pub(super) fn thread(
        &mut self,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let lead = self.lead("G33", at, w)?;
        if self.modal.comp.is_some() {
            return Err(CodeError::new(K::Thread(P::Comp, "G33"), at).into());
        }
        self.polar_words(w)?;
        let mut m = ir::Move {
            motion: Motion::Linear,
            to: ir::Axes::NONE,
            arc: None,
            corner: None,
            lead: Some(lead),
        };
        super::codes::axis_words_into(w, &mut m.to);
        self.emit(ir::Op::Move(m), span)?;
        self.synced_mode(Synced::Thread);
        Ok(())
    }

    /// A G33.1 rigid tap (`at` as for [`Self::thread`]), its words taken;
    /// I, the way out's speed-up, is kept as written.
    pub(super) fn rigid_tap(
        &mut self,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let lead = self.lead("G33.1", at, w)?;
        self.polar_words(w)?;
        let mut to = ir::Axes::NONE;
        super::codes::axis_words_into(w, &mut to);
        if to.is_empty() {
            return Err(CodeError::new(K::Thread(P::NoAxes, "G33.1"), at).into());
        }
        let speedup = w.take(b'I').map(|(i, _)| i);
        self.emit(ir::Op::RigidTap(ir::RigidTap { to, lead, speedup }), span)?;
        self.synced_mode(Synced::RigidTap);
        Ok(())
    }

    /// rs274's motion mode is now G33 or G33.1: axis words alone (with K)
    /// make another.
    fn synced_mode(&mut self, synced: Synced) {
        self.modal.motion = None;
        self.modal.spline_mode = false;
        self.modal.synced = Some(synced);
        self.cycles.kind = None;
        self.cycles.run_open = false;
    }
}
