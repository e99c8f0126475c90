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
    sources: &mut Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> Compiled {
    let mut clock = Clock::new();
    let text = sources.text(file).to_string();
    let (program, mut diagnostics) = crate::parser::parse_program(&text, file);
    clock.lap("parse");
    if diagnostics.iter().any(is_error) || options.stage == Some(Stage::Parse) {
        let output = (!diagnostics.iter().any(is_error)).then(|| program.to_text());
        return Compiled {
            output,
            diagnostics,
            timings: clock.timings,
        };
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
        return Compiled {
            output: None,
            diagnostics,
            timings: clock.timings,
        };
    }
    let units = output_units(&ir);
    if options.stage == Some(Stage::Expand) {
        return Compiled {
            output: Some(emit::emit_stage(&ir, units, &text, file)),
            diagnostics,
            timings: clock.timings,
        };
    }
    let last = match options.stage {
        Some(Stage::Lower(pass)) => pass,
        _ => *Pass::ALL.last().unwrap_or(&Pass::Absolute),
    };
    let lowered = match lower::run_until(ir, units, last) {
        Ok(program) => program,
        Err(errors) => {
            diagnostics.extend(errors);
            return Compiled {
                output: None,
                diagnostics,
                timings: clock.timings,
            };
        }
    };
    clock.lap("lower");
    let output = if options.stage.is_some() {
        emit::emit_stage(&lowered, units, &text, file)
    } else {
        emit::emit_program(&lowered, units, &text, file, &options.emit)
    };
    clock.lap("emit");
    Compiled {
        output: Some(output),
        diagnostics,
        timings: clock.timings,
    }
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
