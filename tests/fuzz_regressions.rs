//! The inputs the fuzzers found problems with (`tests/fuzz/README.md`),
//! replayed: a round trip keeps the tool path.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::compile::{compile, tool_path, CompileOptions};
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
