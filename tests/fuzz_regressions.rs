//! The inputs the fuzzers found problems with (`tests/fuzz/README.md`),
//! replayed: a round trip keeps the tool path.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::driver::{compile, tool_path, CompileOptions};
use ger::source::Sources;
use std::path::Path;

fn files(dir: &str) -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz")
        .join(dir);
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    files
}

#[test]
fn found_round_trips_keep_the_tool_path() {
    let cases = files("roundtrip");
    assert!(!cases.is_empty());
    for path in cases {
        let text = std::fs::read_to_string(&path).unwrap();
        let run = |text: &str| {
            let mut sources = Sources::new();
            let file = sources.add("p.egc", text.to_string());
            let output = compile(&sources, file, &CompileOptions::default(), None).output;
            let path = tool_path(&sources, file, &CompileOptions::default(), None).0;
            (output.unwrap(), path.unwrap())
        };
        let (first, a) = run(&text);
        let (_, b) = run(&first);
        let tol = ger::toolpath::compare::Options {
            tol: 0.002,
            ..Default::default()
        };
        if let Err(d) = ger::toolpath::compare::compare(&a, &b, &tol) {
            panic!("{}: {d}\n{first}", path.display());
        }
    }
}

#[test]
fn found_inputs_give_their_diagnostic_at_once() {
    use ger::eval::{EvalOptions, Flavour};
    use ger::syntax::Language;
    use ger::wizard::{standard_library, Library, WizardEngine};
    // (file, how it is read, the error it must give): each once ran for
    // more than the fuzzer's 10 s. The first case's fix is checked here (it
    // made the error); the second's was speed only, which no test times:
    // this only keeps its diagnostics as they are. The third (a subprogram
    // calling itself with `L3`) went on past the depth limit until the
    // statement limit: its one error must be the depth's.
    let cases = [
        (
            "spiral_step_zero.egc",
            (Language::Egc, Flavour::Generic),
            "this loop never ends",
        ),
        (
            "loop_error_did_you_mean.ngc",
            (Language::Gcode, Flavour::Fanuc),
            "this loop ran more than 1000 times",
        ),
        (
            "loop_error_did_you_mean.ngc",
            (Language::Gcode, Flavour::LinuxCnc),
            "this loop ran more than 1000 times",
        ),
        (
            "recursion_with_repeats.ngc",
            (Language::Gcode, Flavour::Fanuc),
            "subprograms nested more than 64 deep",
        ),
        (
            "recursion_with_repeats.ngc",
            (Language::Gcode, Flavour::Generic),
            "subprograms nested more than 64 deep",
        ),
    ];
    for (name, (language, from), expected) in cases {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fuzz/compile_bytes")
            .join(name);
        let mut sources = Sources::new();
        // Raw bytes (Latin-1 here), decoded as `ger` decodes a file.
        let text = ger::source::decode(std::fs::read(&path).unwrap()).unwrap();
        let file = sources.add(name, text);
        let mut engine = WizardEngine::new(Library::new(standard_library(), &mut sources));
        // A low limit: should the check go, the loop stops there with
        // another message instead of running for minutes.
        let options = CompileOptions {
            eval: EvalOptions {
                max_iterations: 1000,
                ..EvalOptions::default()
            },
            input: Some(language),
            from: Some(from),
            ..CompileOptions::default()
        };
        let compiled = compile(&sources, file, &options, Some(&mut engine));
        assert!(compiled.output.is_none(), "{name}");
        if name == "recursion_with_repeats.ngc" {
            assert_eq!(compiled.diagnostics.len(), 1, "{name}");
        }
        assert!(
            compiled.diagnostics.iter().any(|d| d.message == expected),
            "{name}: {:?}",
            compiled
                .diagnostics
                .iter()
                .map(|d| &d.message)
                .collect::<Vec<_>>()
        );
    }
}
