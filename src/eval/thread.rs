//! LinuxCNC's G33 (a straight feed locked to the spindle, K along the path
//! per revolution) read into an [`ir::Move`] with its `lead`, with rs274's
//! checks, each an error at the line. It knows no target: which
//! controllers run G33 is the printer's question (`emit::target`).

use super::codes::error::{CodeError, CodeErrorKind as K, ThreadProblem as P};
use super::evaluator::Evaluator;
use super::words::WordValues;
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Motion};
use crate::source::Span;

impl Evaluator<'_> {
    /// Before the line's F is taken as a feed: rs274 refuses an F with G33.
    pub(super) fn thread_feed_word(&self, w: &WordValues) -> Result<(), Diagnostic> {
        match w.given(b'F') {
            Some(at) => Err(CodeError::new(K::Thread(P::Feed), at).into()),
            None => Ok(()),
        }
    }

    /// A G33 move (`at` the code, or the line for axis words alone in its
    /// mode), its words taken.
    pub(super) fn thread(
        &mut self,
        at: Span,
        w: &mut WordValues,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let fail =
            |problem, span| -> Diagnostic { CodeError::new(K::Thread(problem), span).into() };
        let Some((lead, _)) = w.take(b'K') else {
            return Err(fail(P::NoK, at));
        };
        if self.modal.spindle == ir::Spindle::Off {
            return Err(fail(P::SpindleOff, at));
        }
        if self.modal.comp.is_some() {
            return Err(fail(P::Comp, at));
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
        // rs274's motion mode is now G33: axis words alone (with K) thread.
        self.modal.motion = None;
        self.modal.spline_mode = false;
        self.modal.thread_mode = true;
        self.cycles.kind = None;
        self.cycles.run_open = false;
        Ok(())
    }
}
