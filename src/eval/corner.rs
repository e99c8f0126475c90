//! Fanuc's corner words on a G1, G2 or G3: `,R` (the corner to the next
//! move rounded) and `,C` (chamfered), taken from a statement's words and
//! checked where the evaluator alone can see the mistake (both on one
//! line, a size of 0 or less, a move that is not a G1, G2 or G3). It must
//! not cut the corner: that needs the next move, and the corners pass
//! does it.

use super::codes::error::{CodeError, CodeErrorKind as K};
use super::words::WordValues;
use crate::ast::Word;
use crate::diagnostic::Diagnostic;
use crate::ir::{self, Motion};
use crate::source::Span;

/// The corner words of `w`, taken: the corner and the word's span.
pub(super) fn take_corner(w: &mut WordValues) -> Result<Option<(ir::Corner, Span)>, Diagnostic> {
    let round = w.take(Word::ROUND);
    let chamfer = w.take(Word::CHAMFER);
    let (corner, size, at, letter) = match (round, chamfer) {
        (None, None) => return Ok(None),
        (Some(_), Some((_, at))) => return Err(CodeError::new(K::RoundAndChamfer, at).into()),
        (Some((r, at)), None) => (ir::Corner::Round(r), r, at, Word::ROUND),
        (None, Some((c, at))) => (ir::Corner::Chamfer(c), c, at, Word::CHAMFER),
    };
    if size.is_nan() || size <= 0.0 {
        return Err(CodeError::new(K::CornerSize(Word::spelling(letter)), at).into());
    }
    Ok(Some((corner, at)))
}

/// The error for corner words on a move of `motion` that is not a G1, G2
/// or G3 (`machine`: under G53), if any.
pub(super) fn check_motion(motion: Motion, machine: bool, at: Span) -> Result<(), Diagnostic> {
    let what = match motion {
        _ if machine => "a G53 move",
        Motion::Linear | Motion::ArcCw | Motion::ArcCcw => return Ok(()),
        Motion::Rapid => "a rapid (G0)",
    };
    Err(CodeError::new(K::CornerNotOnG1(what), at).into())
}
