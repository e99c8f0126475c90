//! Lowering: IR → simpler IR, one pass per stage of SPEC §4, applied in a
//! fixed order by [`run_until`]. Each pass is a function
//! `fn run(ir::Program) -> Result<ir::Program, Vec<Diagnostic>>` in its own
//! file and can be stopped after (`--stage NAME`). Passes never see the
//! AST and never print.
//!
//! Order: units → polar → offsets → absolute. Polar runs before offsets
//! (SPEC §4 lists it after): a G90 polar point is relative to the program
//! zero, so it must become a Cartesian program point before the offsets
//! pass folds the program zero away. The result is the same tool path.

mod absolute;
mod offsets;
mod polar;
mod units;

use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::ir;
use crate::source::Span;

/// The lowering passes, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Pass {
    Units,
    Polar,
    Offsets,
    Absolute,
}

impl Pass {
    pub const ALL: [Pass; 4] = [Pass::Units, Pass::Polar, Pass::Offsets, Pass::Absolute];

    pub fn name(self) -> &'static str {
        match self {
            Pass::Units => "units",
            Pass::Polar => "polar",
            Pass::Offsets => "offsets",
            Pass::Absolute => "absolute",
        }
    }

    fn run(
        self,
        program: ir::Program,
        output_units: ir::Units,
    ) -> Result<ir::Program, Vec<Diagnostic>> {
        match self {
            Pass::Units => units::run(program, output_units),
            Pass::Polar => polar::run(program),
            Pass::Offsets => offsets::run(program),
            Pass::Absolute => absolute::run(program),
        }
    }
}

/// Run every pass up to and including `last`.
pub fn run_until(
    mut program: ir::Program,
    output_units: ir::Units,
    last: Pass,
) -> Result<ir::Program, Vec<Diagnostic>> {
    for pass in Pass::ALL {
        program = pass.run(program, output_units)?;
        if pass == last {
            break;
        }
    }
    Ok(program)
}

/// Collects the diagnostics of one pass; the pass goes on after an error
/// where it can, so one run reports every independent problem.
#[derive(Default)]
struct Errors(Vec<Diagnostic>);

impl Errors {
    fn push(&mut self, d: Diagnostic) {
        if self.0.len() < 50 {
            self.0.push(d);
        }
    }

    fn finish(self, program: ir::Program) -> Result<ir::Program, Vec<Diagnostic>> {
        if self.0.is_empty() {
            Ok(program)
        } else {
            Err(self.0)
        }
    }
}

/// `what` (a move, G92, …) needs the position of an axis no move has set.
fn unknown_position(span: Span, axis: usize, what: &str) -> Diagnostic {
    let letter = ['X', 'Y', 'Z'][axis];
    error(
        format!("{what} needs the current {letter} position, which is not known"),
        span,
        format!("no move has set {letter} yet"),
    )
    .with_help(format!("move to an absolute {letter} position first"))
}
