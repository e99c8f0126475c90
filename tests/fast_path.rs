//! The parser's fast path for plain lines must build exactly the tree the
//! grammar builds: compare both on every program in the test corpus.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::syntax::egc::parse_program_with_fast_path;
use std::path::Path;

#[test]
fn fast_path_builds_the_grammars_tree() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for dir in [
        "tests/cases/parse",
        "tests/cases/syntax",
        "tests/oracle/eval",
        "tests/oracle/lower",
        "examples",
    ] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "egc") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let (fast, fast_errors) = parse_program_with_fast_path(&text, 0, true);
            let (slow, slow_errors) = parse_program_with_fast_path(&text, 0, false);
            if !slow_errors.is_empty() || !fast_errors.is_empty() {
                // A broken program's tree is never used; its first error is.
                let first = |e: &[ger::diagnostic::Diagnostic]| format!("{:?}", e.first());
                assert_eq!(
                    first(&fast_errors),
                    first(&slow_errors),
                    "{}",
                    path.display()
                );
                checked += 1;
                continue;
            }
            assert_eq!(fast.to_text(), slow.to_text(), "{}", path.display());
            // Spans too: the N numbers of the output come from them.
            let spans = |p: &ger::ast::Program| p.main.iter().map(|s| s.span).collect::<Vec<_>>();
            assert_eq!(spans(&fast), spans(&slow), "{}", path.display());
            checked += 1;
        }
    }
    assert!(checked > 100, "only {checked} programs found");
}
