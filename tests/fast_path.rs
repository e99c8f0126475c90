//! The parser's fast path for plain lines must build exactly the tree the
//! grammar builds: compare both on every program in the test corpus.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use ger::syntax::parse_program_with_fast_path;
use std::path::Path;

mod support;

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

/// A plain program read in parts builds its lines of plain words straight
/// from their bytes (`lexer::plain_words`); the parts must be what the
/// lexer and parser build, spans and all, on every plain program of the
/// repository (and, in a test of its own, of `../shared/real`).
#[test]
fn plain_word_lines_are_what_the_parser_builds() {
    let (checked, lines) = plain_word_lines(support::Corpus::Own, true);
    assert!(checked > 30, "only {checked} plain programs found");
    assert!(lines > 1_000, "only {lines} lines");
}

/// [`plain_word_lines_are_what_the_parser_builds`] on `../shared/real`.
#[test]
#[cfg_attr(not(shared_real), ignore = "../shared/real absent")]
fn plain_word_lines_are_what_the_parser_builds_on_shared_real() {
    let (checked, lines) = plain_word_lines(support::Corpus::SharedReal, false);
    assert!(
        checked > 10 && lines > 10_000,
        "{checked} programs, {lines} lines"
    );
}

/// The fast path against the parser on the plain programs of `corpus`
/// (and on lines near its edge, with `edges`): how many programs and
/// lines were compared.
fn plain_word_lines(corpus: support::Corpus, edges: bool) -> (usize, usize) {
    use ger::source::{Locator, Sources};
    use ger::syntax::chunk::{chunks, parse_chunk, with_part_size};
    use ger::syntax::parser::with_fast_path;
    use ger::syntax::Language;
    let (mut checked, mut lines) = (0, 0);
    // Lines near the edge of the fast path, one program read in parts.
    let edge_lines = "G 1 X - 1\nx+.5y-.5 f 100\nG1X1.5.3\nN10G1X1\n  \t\x0c\r\nG1 X1e5\nGX1\nX.\n\
                 G1 X1 (c)\nX1-2\nD01\nDO1\ng0z  0.1\r\nX12345678901234567.5\n/G1 X2\n$H\n\
                 % tape\nM3S1000\nG1 X1;c\nX1 Y\nG 0 1 X 1 0 . 5\nX1 0.5.\nX1 .5 Y- 2\tF1\t0\n";
    let mut plain = match edges {
        true => vec![("edges".to_string(), edge_lines.to_string())],
        false => Vec::new(),
    };
    plain.extend(
        support::plain_programs(corpus)
            .into_iter()
            .map(|(path, text)| (path.display().to_string(), text)),
    );
    for (name, text) in plain {
        let mut sources = Sources::new();
        let file = sources.add(name.clone(), String::new());
        let at = Locator::new(file, &text);
        // Parts of about 200 bytes: lines of words among the others.
        let ranges: Vec<_> = with_part_size(Some(200), || chunks(&text).collect());
        for range in &ranges {
            let parse = |fast| {
                with_fast_path(fast, || {
                    let mut names = ger::ast::Names::default();
                    let (stmts, diagnostics) =
                        parse_chunk(&text, range.clone(), &at, Language::Gcode, &mut names);
                    // Lines in a row are kept together: compared line by line.
                    let stmts = ger::ast::Stmt::line_by_line(stmts);
                    format!("{stmts:?}\n{diagnostics:?}")
                })
            };
            let (fast, slow) = (parse(true), parse(false));
            assert_eq!(fast, slow, "{name} at {range:?}");
        }
        lines += text.lines().count();
        checked += 1;
    }
    (checked, lines)
}
