//! The options of one compile: which stages run, how the input is read
//! and how the output is written. Validated here, in the library
//! ([`CompileOptions::validate`]), so no caller can run a compile the
//! command line would refuse. Knows nothing of files or of the stages' code.

use crate::emit::{EmitOptions, Target, MOST_DECIMALS};
use crate::eval::{self, Chosen, EvalOptions};
use crate::lower;
use crate::source::FileId;
use crate::syntax::Language;

/// The stages of SPEC §4, in order; `--stage NAME` stops after one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    /// The parsed program, normalised (no evaluation).
    Parse,
    Expand,
    /// After the pass of this index in [`lower::PASSES`].
    Lower(usize),
    /// The final program as `--arcs fit` prints it (`fit-r` if chosen),
    /// each fitted arc naming the source lines it replaces.
    Fit,
}

impl Stage {
    /// Every stage name, in order.
    pub fn names() -> impl Iterator<Item = &'static str> {
        ["parse", "expand"]
            .into_iter()
            .chain(lower::PASSES.iter().map(|p| p.name))
            .chain(["fit"])
    }

    pub fn from_name(name: &str) -> Option<Stage> {
        match name.to_ascii_lowercase().as_str() {
            "parse" => Some(Stage::Parse),
            "expand" => Some(Stage::Expand),
            "fit" => Some(Stage::Fit),
            _ => lower::pass_index(name).map(Stage::Lower),
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    pub eval: EvalOptions,
    /// The source language (`--input`); `None`: from the file name.
    pub input: Option<crate::syntax::Language>,
    /// `--from`; `None`: from the file name (`.ngc` is LinuxCNC's).
    pub from: Option<eval::Flavour>,
    pub emit: EmitOptions,
    pub lower: lower::LowerOptions,
    /// Print the program after this stage instead of the final output.
    pub stage: Option<Stage>,
    /// Files of LinuxCNC subroutines (`o<name> sub` … `endsub`) the
    /// program calls but does not hold; the caller found and read them.
    pub library: Vec<FileId>,
    /// The machine's travel (`[machine]` of `ger.toml`): each move is
    /// checked against it (`driver::travel`).
    pub travel: Option<super::travel::Travel>,
}

impl CompileOptions {
    /// The language of the file `name`: `--input`, else its name's.
    pub fn language(&self, name: &str) -> Language {
        self.input.unwrap_or_else(|| Language::of_file(name))
    }

    /// Whose meaning holds for the file `name` whose first lines say
    /// `clue`, and why (SPEC §1): `--from`, else a `.ngc` file is
    /// LinuxCNC's, else the `--target`'s controller, else the clue, else
    /// generic. A `.egc` program is generic.
    pub(super) fn flavour(&self, name: &str, clue: Option<Clue>) -> (eval::Flavour, Chosen) {
        use eval::Flavour as F;
        if let Some(from) = self.from {
            return (from, Chosen::Flag);
        }
        // ger's own language means the same whatever the target.
        if self.language(name) != Language::Gcode {
            return (F::Generic, Chosen::Nothing);
        }
        if F::of_file(name) == F::LinuxCnc {
            return (F::LinuxCnc, Chosen::FileName);
        }
        match (self.emit.target, clue) {
            (Target::Grbl, _) => (F::Grbl, Chosen::Target),
            (Target::LinuxCnc, _) => (F::LinuxCnc, Chosen::Target),
            (Target::Fanuc, _) => (F::Fanuc, Chosen::Target),
            (Target::Generic, Some(Clue::GrblCommand)) => (F::Grbl, Chosen::GrblCommand),
            (Target::Generic, Some(Clue::FanucTape)) => (F::Fanuc, Chosen::FanucTape),
            (Target::Generic, Some(Clue::MacroB)) => (F::Fanuc, Chosen::MacroB),
            (Target::Generic, None) => (F::Generic, Chosen::Nothing),
        }
    }

    /// The evaluator's options for a file in `language` read as `from`.
    pub(super) fn eval_options(
        &self,
        (from, chosen): (eval::Flavour, Chosen),
        language: Language,
    ) -> EvalOptions {
        EvalOptions {
            from,
            chosen,
            plain: language == Language::Gcode,
            ..self.eval.clone()
        }
    }
}

/// A sign in a file's first lines that only one controller's programs
/// carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clue {
    /// A line starting `$H` or `$J=`: grbl's homing or jog command.
    GrblCommand,
    /// A `%` line first and a line `O1234` (or `:1234`): a Fanuc tape.
    FanucTape,
    /// A line of Fanuc's Macro B: `IF [`, `WHILE [`, `GOTO`, `G65`.
    MacroB,
}

/// Options no compile can run with: the command line's usage errors,
/// refused by the library for every caller.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    #[error("--tolerance must be positive and --decimals at most 9")]
    ToleranceOrDecimals,
    #[error("--cycles keep needs a controller with canned cycles: --target fanuc or linuxcnc")]
    CyclesKeptWithout,
    #[error("--comp keep needs a controller that compensates: --target fanuc or linuxcnc")]
    CompKeptWithout,
}

/// Whether a `--tolerance` (or `ger.toml`'s `tolerance`) is one a compile
/// can run with: a positive number.
pub fn usable_tolerance(tolerance: f64) -> bool {
    tolerance.is_finite() && tolerance > 0.0
}

impl CompileOptions {
    /// Whether a compile can run with these options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let emit = &self.emit;
        if emit.tolerance.is_some_and(|t| !usable_tolerance(t))
            || emit.decimals.is_some_and(|d| d > MOST_DECIMALS)
        {
            return Err(OptionError::ToleranceOrDecimals);
        }
        let keeps_cycles_and_comp = matches!(emit.target, Target::Fanuc | Target::LinuxCnc);
        if self.lower.keep_cycles && !keeps_cycles_and_comp {
            return Err(OptionError::CyclesKeptWithout);
        }
        if self.lower.keep_comp && !keeps_cycles_and_comp {
            return Err(OptionError::CompKeptWithout);
        }
        Ok(())
    }
}

#[cfg(test)]
mod flavour_tests {
    use super::{Clue, CompileOptions};
    use crate::emit::Target;
    use crate::eval::{Chosen, Flavour};

    /// SPEC §1's order: `--from`, a `.ngc` name, the target, a clue,
    /// nothing; a `.egc` program is generic whatever the target.
    #[test]
    fn whose_meaning_without_from() {
        let with = |from: Option<Flavour>, target| {
            let mut options = CompileOptions {
                from,
                ..CompileOptions::default()
            };
            options.emit.target = target;
            options
        };
        let grbl_tape = Some(Clue::GrblCommand);
        let cases = [
            (
                with(Some(Flavour::Fanuc), Target::Grbl),
                "a.ngc",
                grbl_tape,
                (Flavour::Fanuc, Chosen::Flag),
            ),
            (
                with(None, Target::Grbl),
                "a.ngc",
                None,
                (Flavour::LinuxCnc, Chosen::FileName),
            ),
            (
                with(None, Target::Grbl),
                "a.nc",
                Some(Clue::FanucTape),
                (Flavour::Grbl, Chosen::Target),
            ),
            (
                with(None, Target::Fanuc),
                "a.nc",
                grbl_tape,
                (Flavour::Fanuc, Chosen::Target),
            ),
            (
                with(None, Target::LinuxCnc),
                "a.tap",
                None,
                (Flavour::LinuxCnc, Chosen::Target),
            ),
            (
                with(None, Target::Generic),
                "a.gcode",
                grbl_tape,
                (Flavour::Grbl, Chosen::GrblCommand),
            ),
            (
                with(None, Target::Generic),
                "a.nc",
                Some(Clue::FanucTape),
                (Flavour::Fanuc, Chosen::FanucTape),
            ),
            (
                with(None, Target::Generic),
                "a.nc",
                Some(Clue::MacroB),
                (Flavour::Fanuc, Chosen::MacroB),
            ),
            (
                with(None, Target::Generic),
                "a.nc",
                None,
                (Flavour::Generic, Chosen::Nothing),
            ),
            (
                with(None, Target::Fanuc),
                "a.egc",
                None,
                (Flavour::Generic, Chosen::Nothing),
            ),
        ];
        for (options, name, clue, expected) in cases {
            assert_eq!(options.flavour(name, clue), expected, "{name} {clue:?}");
        }
    }
}
