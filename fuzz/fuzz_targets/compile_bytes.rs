//! Arbitrary bytes as a program, read as `.egc`, as plain G-code and as
//! Fanuc Macro B (plain G-code `--from fanuc`): ger must not panic, hang
//! or run out of memory; it either compiles them or reports errors.
#![no_main]

use ger::driver::{compile, CompileOptions};
use ger::eval::{EvalOptions, Flavour};
use ger::source::{decode, Sources};
use ger::syntax::Language;
use ger::wizard::{standard_library, Library, WizardEngine};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = decode(bytes.to_vec()) else { return };
    let mut sources = Sources::new();
    let file = sources.add("fuzz.egc", text);
    let mut engine = WizardEngine::new(Library::new(standard_library(), &mut sources));
    // Small limits keep each run short; the limits themselves are tested.
    let options = CompileOptions {
        eval: EvalOptions {
            max_iterations: 10_000,
            max_statements: 100_000,
            ..EvalOptions::default()
        },
        ..CompileOptions::default()
    };
    let readings = [
        (Language::Egc, Flavour::Generic),
        (Language::Gcode, Flavour::LinuxCnc),
        (Language::Gcode, Flavour::Fanuc),
    ];
    for (language, from) in readings {
        let options = CompileOptions {
            input: Some(language),
            from: Some(from),
            ..options.clone()
        };
        let compiled = compile(&sources, file, &options, Some(&mut engine));
        // Every diagnostic renders (long lines windowed, spans inside the text).
        let _ = ger::diagnostic::render(&sources, &compiled.diagnostics);
    }
});
