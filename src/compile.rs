//! The driver: source text → G-code text, through the stages in order
//! (parse, expand, lowering passes, emit). It is the library's one entry
//! point for a whole compile and does no I/O.

use crate::diagnostic::{is_error, Diagnostic};
use crate::emit::{self, EmitOptions};
use crate::eval::{self, EvalOptions, WizardHost};
use crate::ir::{self, Units};
use crate::lower::{self, Pass};
use crate::source::{FileId, Sources};

/// The stages of SPEC §4, in order; `--stage NAME` stops after one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    /// The parsed program, normalised (no evaluation).
    Parse,
    Expand,
    Lower(Pass),
}

impl Stage {
    pub const ALL: [(&'static str, Stage); 6] = [
        ("parse", Stage::Parse),
        ("expand", Stage::Expand),
        ("units", Stage::Lower(Pass::Units)),
        ("polar", Stage::Lower(Pass::Polar)),
        ("offsets", Stage::Lower(Pass::Offsets)),
        ("absolute", Stage::Lower(Pass::Absolute)),
    ];

    pub fn from_name(name: &str) -> Option<Stage> {
        Stage::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, s)| s)
    }
}

#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    pub eval: EvalOptions,
    pub emit: EmitOptions,
    /// Print the program after this stage instead of the final output.
    pub stage: Option<Stage>,
}

/// The result of a compile: the text (absent when there are errors) and
/// every diagnostic, warnings included.
pub struct Compiled {
    pub output: Option<String>,
    pub diagnostics: Vec<Diagnostic>,
    /// Time spent in each stage, in order (`ger compile --timings`).
    pub timings: Vec<(&'static str, std::time::Duration)>,
}

/// Times the stages of one compile.
struct Clock {
    last: std::time::Instant,
    timings: Vec<(&'static str, std::time::Duration)>,
}

impl Clock {
    fn new() -> Clock {
        Clock {
            last: std::time::Instant::now(),
            timings: Vec::new(),
        }
    }

    fn lap(&mut self, stage: &'static str) {
        let now = std::time::Instant::now();
        self.timings.push((stage, now - self.last));
        self.last = now;
    }
}

/// Compile the file `file` of `sources`.
pub fn compile(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> Compiled {
    let mut diagnostics = Vec::new();
    let mut clock = Clock::new();
    let output = run(
        sources.text(file),
        file,
        options,
        wizards,
        &mut diagnostics,
        &mut clock,
    );
    Compiled {
        output: output.filter(|_| !diagnostics.iter().any(is_error)),
        diagnostics,
        timings: clock.timings,
    }
}

/// The stages in order; `None` when one reports an error.
fn run(
    text: &str,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    diagnostics: &mut Vec<Diagnostic>,
    clock: &mut Clock,
) -> Option<String> {
    let (program, parse_diagnostics) = crate::parser::parse_program(text, file);
    diagnostics.extend(parse_diagnostics);
    clock.lap("parse");
    if diagnostics.iter().any(is_error) {
        return None;
    }
    if options.stage == Some(Stage::Parse) {
        return Some(program.to_text());
    }
    let (ir, eval_diagnostics) = match wizards {
        Some(host) => eval::eval_program(
            &program,
            &options.eval,
            Some(&mut *host as &mut dyn WizardHost),
        ),
        None => eval::eval_program(&program, &options.eval, None),
    };
    diagnostics.extend(eval_diagnostics);
    // The tree is done with: free it before the IR passes allocate.
    drop(program);
    clock.lap("expand");
    if diagnostics.iter().any(is_error) {
        return None;
    }
    let units = output_units(&ir);
    let last = match options.stage {
        Some(Stage::Expand) => return Some(emit::emit_stage(&ir, units, text, file)),
        Some(Stage::Lower(pass)) => pass,
        _ => *Pass::ALL.last().unwrap_or(&Pass::Absolute),
    };
    let lowered = lower::run_until(ir, units, last)
        .map_err(|errors| diagnostics.extend(errors))
        .ok()?;
    clock.lap("lower");
    let output = if options.stage.is_some() {
        emit::emit_stage(&lowered, units, text, file)
    } else {
        emit::emit_program(&lowered, units, text, file, &options.emit)
    };
    clock.lap("emit");
    Some(output)
}

/// The output units (SPEC §3): `SetUnits`, else the program's first
/// G20/G21, else inch.
pub fn output_units(program: &ir::Program) -> Units {
    program.setup.units.unwrap_or_else(|| {
        program
            .stmts
            .iter()
            .find_map(|s| match s.op {
                ir::Op::Units(u) => Some(u),
                _ => None,
            })
            .unwrap_or(Units::Inch)
    })
}
