//! Codegen: IR → G-code text (SPEC §6). Prints the program after any stage
//! (`--stage`), and the final output with its target, numbering, decimals
//! and arc format. In parts: [`number`] formats numbers, `printer` writes
//! lines and spells statements, `target` holds each controller family's
//! rules, `stage` and `program` decide what is printed.
//!
//! It must not change what the program does: every choice here is about
//! spelling, except the final rounding, which it makes consistent (arc
//! centres are printed relative to the start as printed).

mod fit;
pub mod number;
mod printer;
mod program;
mod stage;
mod target;

pub use program::ProgramPrinter;
pub use stage::StagePrinter;
pub use target::{Target, Unrunnable, Why};

/// The most decimals the output takes: a nanometre, and the output's grid
/// stays within an i64.
pub const MOST_DECIMALS: usize = 9;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Numbering {
    /// N = the source line that produced the output line.
    #[default]
    Source,
    /// N10, N20, …
    Seq,
    /// The program's own N words: on the first output line of a line that
    /// has one, the first time it runs (see [`ir::Stmt::number`]).
    ///
    /// [`ir::Stmt::number`]: crate::ir::Stmt::number
    Keep,
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ArcFormat {
    #[default]
    Ij,
    R,
    Lines,
    /// Chains of lines that lie on an arc written as that arc (I/J).
    Fit,
    /// [`ArcFormat::Fit`], the arcs (fitted or not) written as `R` does.
    FitR,
}

impl ArcFormat {
    /// Whether chains of lines are fitted.
    pub fn fits(self) -> bool {
        matches!(self, ArcFormat::Fit | ArcFormat::FitR)
    }

    /// Whether arcs are written with R where it is exact enough.
    pub fn writes_r(self) -> bool {
        matches!(self, ArcFormat::R | ArcFormat::FitR)
    }
}

#[derive(Clone, Debug)]
pub struct EmitOptions {
    pub numbering: Numbering,
    /// The output flavour (`--target`).
    pub target: Target,
    pub arcs: ArcFormat,
    /// Decimals; `None`: 3 for mm, 4 for inch.
    pub decimals: Option<usize>,
    /// Chord tolerance for `--arcs lines` and `--arcs fit`, in output
    /// units; `None`: 0.001 for lines, 0.005 mm or 0.0002 in to fit.
    pub tolerance: Option<f64>,
    /// Program number for targets that want one.
    pub program_number: u32,
}

impl Default for EmitOptions {
    fn default() -> Self {
        EmitOptions {
            numbering: Numbering::Source,
            target: Target::Generic,
            arcs: ArcFormat::Ij,
            decimals: None,
            tolerance: None,
            program_number: 1,
        }
    }
}
