//! Cutter compensation blocks (G40, G41/G42 [D], G41.1/G42.1 D): the
//! radius they name and what may not happen while compensation is on
//! (rs274's rules). The geometry is the comp pass's (`lower/comp.rs`).

use super::evaluator::Evaluator;
use super::words::WordValues;
use crate::diagnostic::{error, Diagnostic, DiagnosticExt, Located, Wording};
use crate::ir::{self, CompRadius, Op, Side};
use crate::source::Span;

impl Evaluator<'_> {
    /// G41/G42 (`t` 410/420) or G41.1/G42.1 (411/421).
    pub(super) fn comp_on(
        &mut self,
        t: u32,
        at: Span,
        w: &mut WordValues,
    ) -> Result<Op, CompBlockError> {
        let name = match t {
            410 => "G41",
            420 => "G42",
            411 => "G41.1",
            _ => "G42.1",
        };
        if let Some((_, since)) = self.modal.comp {
            return Err(CompBlockError::new(
                CompBlockErrorKind::AlreadyOn { code: name, since },
                at,
            ));
        }
        if self.modal.plane == ir::Plane::YZ {
            return Err(CompBlockError::new(
                CompBlockErrorKind::PlaneYz { code: name },
                at,
            ));
        }
        let side = if t == 410 || t == 411 {
            Side::Left
        } else {
            Side::Right
        };
        let radius = match (t, w.take(b'D')) {
            (410 | 420, None) => CompRadius::LoadedTool,
            (410 | 420, Some((d, dspan))) => {
                if d < 0.0 || (d - d.round()).abs() > 1e-4 || d > 99_999.0 {
                    return Err(CompBlockError::new(
                        CompBlockErrorKind::DNotATool { code: name },
                        dspan,
                    ));
                }
                match d.round() as u32 {
                    0 => CompRadius::LoadedTool,
                    n => CompRadius::Tool(n),
                }
            }
            (_, Some((d, _))) => CompRadius::Diameter(d),
            (_, None) => {
                return Err(CompBlockError::new(
                    CompBlockErrorKind::NoDiameter { code: name },
                    at,
                ))
            }
        };
        Ok(Op::Comp { side, radius })
    }

    /// What may not happen under compensation: an error naming it, with
    /// the line that turned compensation on.
    pub(super) fn check_under_comp(&self, op: &Op, span: Span) -> Result<(), CompBlockError> {
        let Some((_, since)) = self.modal.comp else {
            return Ok(());
        };
        let what = match op {
            Op::ChangeTool => "a tool change",
            Op::Cycle(_) => "a canned cycle",
            Op::Home { .. } => "G28/G30",
            Op::MachineMove(_) => "a G53 move",
            Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::CancelPosition => "a change of work offset",
            Op::ToolLength { .. } | Op::CancelToolLength => "a change of tool length offset",
            Op::Plane(p) if *p != self.modal.plane => "a change of plane",
            Op::Polar(true) => "polar coordinates (G16)",
            Op::PathControl(_) => "a change of path control (G61, G61.1, G64)",
            Op::Spline(_) => "a spline (G5, G5.1)",
            Op::RigidTap(_) => "a rigid tap (G33.1)",
            _ => return Ok(()),
        };
        Err(CompBlockError::new(
            CompBlockErrorKind::UnderComp { what, since },
            span,
        ))
    }
}

/// What a compensation block, or a block under compensation, gets wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum CompBlockErrorKind {
    /// G41/G42 again; where compensation was turned on.
    AlreadyOn {
        code: &'static str,
        since: Span,
    },
    PlaneYz {
        code: &'static str,
    },
    /// G41/G42 D that is not a tool number.
    DNotATool {
        code: &'static str,
    },
    /// G41.1/G42.1 without its diameter.
    NoDiameter {
        code: &'static str,
    },
    /// What may not happen under compensation; where it was turned on.
    UnderComp {
        what: &'static str,
        since: Span,
    },
}

/// What goes wrong, and where: see [`CompBlockErrorKind`].
pub type CompBlockError = Located<CompBlockErrorKind>;

impl Wording for CompBlockErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        match self {
            CompBlockErrorKind::AlreadyOn { code, since } => error(
                format!("{code} while cutter compensation is on"),
                at,
                "compensation is already on",
            )
            .with_secondary(*since, "turned on here")
            .with_help("turn it off with G40 first, also to change sides"),
            CompBlockErrorKind::PlaneYz { code } => error(
                format!("{code} in the YZ plane (G19)"),
                at,
                "compensation works in G17 (XY) and G18 (XZ)",
            ),
            CompBlockErrorKind::DNotATool { code } => error(
                format!("{code} D must be a tool number"),
                at,
                "D names a tool of the tool table (LinuxCNC), a whole number",
            )
            .with_help("G41.1 D… takes the cutter's diameter instead"),
            CompBlockErrorKind::NoDiameter { code } => error(
                format!("{code} without D"),
                at,
                "D gives the cutter's diameter",
            ),
            CompBlockErrorKind::UnderComp { what, since } => error(
                format!("{what} under cutter compensation"),
                at,
                "not allowed while compensation is on",
            )
            .with_secondary(*since, "compensation turned on here")
            .with_help("turn compensation off with G40 before it"),
        }
    }
}
