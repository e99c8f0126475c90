//! Plain programs read a part at a time (issue 15): a program of G-code
//! words, comments and controller commands only — no parameters, no
//! expressions, no subprograms, no control flow — means the same read
//! line by line as read whole, so it is parsed and run in parts of about
//! [`CHUNK_BYTES`], each dropped before the next is read. Memory then
//! grows with the longest part, not with the program.

use super::lexer::{self, comment_end, Language, WordNumber};
use super::parser::{fast_path, parse_program_from, words_stmt};
use crate::ast::{Names, Stmt};
use crate::diagnostic::Diagnostic;
use crate::source::Locator;

/// About this many bytes of text are parsed at a time.
pub const CHUNK_BYTES: usize = 64 * 1024;

thread_local! {
    /// The size of a part on this thread; `None`: programs are read whole.
    static PART_BYTES: std::cell::Cell<Option<usize>> =
        const { std::cell::Cell::new(Some(CHUNK_BYTES)) };
}

/// Run `f` (a compile on this thread) reading plain programs in parts of
/// about `bytes`, or whole with `None` (tests compare the two).
pub fn with_part_size<T>(bytes: Option<usize>, f: impl FnOnce() -> T) -> T {
    let before = PART_BYTES.with(|p| p.replace(bytes));
    let result = f();
    PART_BYTES.with(|p| p.set(before));
    result
}

/// Whether plain programs are read in parts on this thread.
pub fn by_parts() -> bool {
    PART_BYTES.with(|p| p.get()).is_some()
}

/// The size of a part on this thread.
pub fn part_size() -> usize {
    PART_BYTES.with(|p| p.get()).unwrap_or(CHUNK_BYTES).max(1)
}

/// Whether plain G-code `text` can be read in parts: outside its comments
/// it has only one-letter words with numbers (no `#`, `[`, `=`, no names or
/// keywords), no `O` words (subprograms, o-words, program numbers), no
/// `M98`, `M99` or `G65`, and its `%` and `$` lines stand alone. Anything
/// else is read whole, by the general path.
pub fn chunkable(text: &str) -> bool {
    text.lines().all(plain_line)
}

/// One line (without its line end) of a program [`chunkable`] accepts.
pub fn plain_line(line: &str) -> bool {
    let trimmed = line.trim_start_matches([' ', '\t', '\r']);
    if trimmed.starts_with(['%', '$']) {
        return true;
    }
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            // The rest of the line is a comment (or a comment nested in
            // parentheses, which ends with its line at the latest).
            b';' => return true,
            b'(' => match comment_end(bytes, i) {
                Some(end) => i = end,
                None => return true,
            },
            b' ' | b'\t' | b'\r' => i += 1,
            // Block delete: first on its line, before a word.
            b'/' if bytes[..i].iter().all(|b| matches!(b, b' ' | b'\t')) => {
                let rest = &bytes[i + 1..];
                let word = rest.iter().find(|b| !matches!(b, b' ' | b'\t'));
                if !word.is_some_and(u8::is_ascii_alphabetic) {
                    return false;
                }
                i += 1;
            }
            b'A'..=b'Z' | b'a'..=b'z' => match plain_word(bytes, i) {
                Some(end) => i = end,
                None => return false,
            },
            _ => return false,
        }
    }
    true
}

/// The end of the word whose letter is `bytes[at]`, when it is a plain
/// word (a letter, spaces, a signed decimal number) that is none of `O`,
/// `M98`, `M99`, `G65`.
fn plain_word(bytes: &[u8], at: usize) -> Option<usize> {
    let letter = bytes[at].to_ascii_uppercase();
    if letter == b'O' {
        return None;
    }
    let number = WordNumber::after(bytes, at + 1, bytes.len());
    if !number.has_digits() {
        return None;
    }
    if !matches!(letter, b'M' | b'G') {
        return Some(number.end);
    }
    let whole = number.body().split(|&b| b == b'.').next().unwrap_or(&[]);
    let first = whole.iter().position(|&b| b != b'0').unwrap_or(whole.len());
    let calls = matches!(
        (letter, &whole[first..]),
        (b'M', b"98" | b"99") | (b'G', b"65")
    );
    (!calls).then_some(number.end)
}

/// The parts of `text` to read one after another: byte ranges that end
/// after a line end (the last at the end of the text).
pub fn chunks(text: &str) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let part = part_size();
    let mut from = 0;
    std::iter::from_fn(move || {
        if from >= text.len() {
            return None;
        }
        let want = (from + part).min(text.len());
        // A line end is one byte, never inside a character.
        let end = text.as_bytes()[want..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(text.len(), |i| want + i + 1);
        let range = from..end;
        from = end;
        Some(range)
    })
}

/// Parse the part `range` of `text` (a range [`chunks`] gave) with spans
/// in the whole text: its statements, their names, and its diagnostics.
/// A line of plain words (most of a CAM program) is built straight from
/// its bytes ([`lexer::plain_words`]); the lines between go to the lexer
/// and the parser together. A plain program means the same cut at any line
/// end, so the two give what the parser alone gives.
pub fn parse_chunk(
    text: &str,
    range: std::ops::Range<usize>,
    at: &Locator,
    language: Language,
) -> (Vec<Stmt>, Names, Vec<Diagnostic>) {
    let mut names = Names::default();
    let (mut stmts, mut diagnostics) = (Vec::new(), Vec::new());
    let mut parse = |from: usize, to: usize, stmts: &mut Vec<Stmt>| {
        if from < to {
            let (program, found) = parse_program_from(&text[..to], from, at, language, &mut names);
            stmts.extend(program.main);
            diagnostics.extend(found);
        }
    };
    if !fast_path() {
        parse(range.start, range.end, &mut stmts);
        return (stmts, names, diagnostics);
    }
    let mut words = Vec::new();
    // Lines from `waiting` on are for the parser, not yet parsed.
    let (mut waiting, mut line) = (range.start, range.start);
    let mut number = at.span(line, line).line;
    while line < range.end {
        let line_end = text.as_bytes()[line..range.end]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(range.end, |i| line + i);
        words.clear();
        if lexer::plain_words(text, line, line_end, &mut words) {
            parse(waiting, line, &mut stmts);
            if let (Some(first), Some(last)) = (words.first(), words.last()) {
                let (start, end) = (first.start as usize, last.end as usize);
                let run = (0, words.len() as u32);
                stmts.push(words_stmt(&words, run, (start, end), number, at));
            }
            waiting = (line_end + 1).min(range.end);
        }
        line = line_end + 1;
        number += 1;
    }
    parse(waiting, range.end, &mut stmts);
    (stmts, names, diagnostics)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_lines_are_words_comments_and_commands() {
        for line in [
            "G0 X1.5 Y-2 Z  0.1",
            "N10 G1 X1 F100 (a comment (nested) with # and [ ])",
            "G1 X1 ; O100 call",
            "% tape O0001",
            "$H",
            "/G1 X2",
            "  / G1 X2",
            "",
        ] {
            assert!(plain_line(line), "{line}");
        }
        for line in [
            "#1 = 2",
            "G1 X[1 + 2]",
            "O1000",
            "o100 sub",
            "M98 P100",
            "M99",
            "G65 P9010 A1",
            "IF [#1 GT 0] GOTO 10",
            "G1 X",
            "/",
            "G1 X1 / Y2",
            ":0097",
            "G1 X1.0 é",
        ] {
            assert!(!plain_line(line), "{line}");
        }
    }

    #[test]
    fn parts_end_at_line_ends_and_cover_the_text() {
        let text = "G0 X1\nG1 Y2 (é)\nG1 Z3";
        with_part_size(Some(3), || {
            let parts: Vec<_> = chunks(text).collect();
            assert_eq!(parts, vec![0..6, 6..17, 17..22]);
        });
    }
}
