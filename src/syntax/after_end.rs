//! What rs274 does not read (SPEC §2.8): the lines after a plain
//! program's end, a line of the main program's top level with `M2` or
//! `M30`. LinuxCNC's files keep notes in prose there; Fanuc's programs
//! keep their subprograms there (`O1000` … `M99`), and rs274 finds an
//! `o<name> sub` there when a call looks for it. So after the end only
//! subprograms are read, each as it would be anywhere; every other line
//! is left unread, with one note saying so, and a `%` line ends the
//! reading. A tape (a program that starts with a `%` alone on its line)
//! ends at its next such line, M2/M30 or not ([`Tape`], [`tape_end`]: the callers that
//! read in parts cut the text there). One function reads the rest of a
//! program from its end, whatever part of it is being read
//! ([`super::chunk`] reads the part with the end to the end of the text),
//! so a program means the same read whole or in parts. It must not evaluate anything: an `M2`
//! inside a block or a subprogram ends nothing here.

use super::error::{SyntaxError, SyntaxErrorKind};
use super::linuxcnc::OWord;
use crate::ast::{Names, Program, Stmt, StmtKind, Subprogram, WordValue};
use crate::source::{Locator, Span};

/// Where the main program of `main` (a plain program's top-level
/// statements, in order) ends: the offset just past the line of its first
/// `M2` or `M30` not written after a block delete (which may not run),
/// and that word's span. `None`: it has none.
pub(super) fn end_of_main(main: &[Stmt], text: &str, at: &Locator) -> Option<(usize, Span)> {
    let word = end_word(main)?;
    // Offsets in `text`: the word's less the part's base.
    let end = (word.end as usize).checked_sub(at.offset(0) as usize)?;
    let cut = text
        .get(end..)?
        .find('\n')
        .map_or(text.len(), |i| end + i + 1);
    Some((cut, word))
}

/// The span of the `M2` or `M30` that ends the main program of `main`
/// ([`end_of_main`]).
pub(super) fn end_word(main: &[Stmt]) -> Option<Span> {
    let is_end = |letter: u8, value: f64| letter == b'M' && (value == 2.0 || value == 30.0);
    main.iter().find_map(|stmt| match &stmt.kind {
        StmtKind::Line(line) if !line.block_delete => line
            .words
            .iter()
            .find(|w| matches!(w.value, WordValue::Number(n) if is_end(w.letter, n.value)))
            .map(|w| w.span),
        StmtKind::Lines(lines) => lines.each().find_map(|(words, line)| {
            let w = words.iter().find(|w| is_end(w.letter, w.value))?;
            Some(w.span(lines.file, line))
        }),
        _ => None,
    })
}

/// Whether the text after a program's end, `rest`, needs reading: it has
/// a line that is neither blank nor a `%` line before its first `%` line.
pub(super) fn has_more(rest: &str) -> bool {
    rest.lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with('%'))
        .any(|l| !l.is_empty())
}

/// The subprograms written in `text` from `from` (the line after the
/// program's end, the `M2`/`M30` at `end`) on, each parsed alone by
/// `parse` (its range of `text`) as it would be anywhere, and the problems
/// found besides theirs: one written twice, and one note for the other
/// lines but blank lines and comments, which are not read. `before`: the subprograms the program has
/// already.
pub(super) fn read_after_end(
    text: &str,
    (from, end): (usize, Span),
    at: &Locator,
    names: &mut Names,
    before: &[Subprogram],
    parse: &mut dyn FnMut(std::ops::Range<usize>, &mut Names) -> Program,
) -> (Vec<Subprogram>, Vec<SyntaxError>) {
    let (mut subprograms, mut problems) = (Vec::<Subprogram>::new(), Vec::new());
    let mut unread: Option<(Span, usize)> = None;
    let mut line_start = from;
    while line_start < text.len() {
        let line_end = next_line(text, line_start);
        let line = text[line_start..line_end].trim();
        let sub_end = match start_of_subprogram(line) {
            // Blank lines and comments (Fanuc's between its subprograms)
            // say nothing that is lost.
            _ if code_of(line).is_empty() => None,
            _ if line.starts_with('%') => break,
            Some(start) => Some(end_of_subprogram(text, line_end, &start)),
            None => {
                match &mut unread {
                    Some((_, lines)) => *lines += 1,
                    None => {
                        let written = &text[line_start..line_end];
                        let start = line_start + written.len() - written.trim_start().len();
                        unread = Some((at.span(start, start + line.len()), 1));
                    }
                }
                None
            }
        };
        let Some(sub_end) = sub_end else {
            line_start = line_end;
            continue;
        };
        let program = parse(line_start..sub_end, names);
        for sub in program.subprograms {
            let first = before
                .iter()
                .chain(&subprograms)
                .find(|s| s.name == sub.name);
            if let Some(first) = first {
                let name = sub.name.describe(names);
                let kind = SyntaxErrorKind::SubprogramTwice {
                    name,
                    first: first.span,
                };
                problems.push(SyntaxError::new(kind, sub.span));
            }
            subprograms.push(sub);
        }
        line_start = sub_end;
    }
    if let Some((first, lines)) = unread {
        let kind = SyntaxErrorKind::NotReadAfterEnd { lines, end };
        problems.push(SyntaxError::new(kind, first));
    }
    (subprograms, problems)
}

/// A tape (SPEC §2.8): a program whose first line with anything on it is
/// a `%` alone ends at the next line that is a `%` alone, where rs274 and
/// Fanuc stop reading. Fed a program's lines in order, it says which
/// closes the tape. A `%` line with text (`% LED on`, which some posts
/// write as a comment; rs274 refuses it) closes nothing, nor does a `%`
/// in a program that does not start with one: both are skipped, as they
/// always were.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Tape {
    /// No line with anything on it yet.
    #[default]
    Unknown,
    Open,
    NotATape,
    Closed,
}

impl Tape {
    /// The next line of the program (without its line end): whether it
    /// closes the tape (nothing from its start on is read).
    pub fn closes(&mut self, line: &str) -> bool {
        let line = line.trim_start_matches('\u{feff}').trim();
        match *self {
            Tape::Unknown if line.is_empty() => false,
            Tape::Unknown if line == "%" => {
                *self = Tape::Open;
                false
            }
            Tape::Unknown => {
                *self = Tape::NotATape;
                false
            }
            Tape::Open if line == "%" => {
                *self = Tape::Closed;
                true
            }
            _ => false,
        }
    }

    /// Whether no line to come can close it.
    pub fn decided(self) -> bool {
        matches!(self, Tape::NotATape | Tape::Closed)
    }
}

/// The lines after a tape's end that would have said something: not
/// blank, not only a comment or a `%` line; counted as they are read.
#[derive(Clone, Copy, Debug, Default)]
pub struct Unread {
    first: Option<Span>,
    lines: usize,
}

impl Unread {
    /// The whole lines of `text` from `from` on, placed in the file by `at`.
    pub fn add(&mut self, text: &str, from: usize, at: &Locator) {
        let mut start = from;
        while start < text.len() {
            let end = next_line(text, start);
            let written = &text[start..end];
            let line = written.trim();
            if !code_of(line).is_empty() && !line.starts_with('%') {
                self.lines += 1;
                let from = start + written.len() - written.trim_start().len();
                self.first
                    .get_or_insert_with(|| at.span(from, from + line.len()));
            }
            start = end;
        }
    }

    /// The note at the first line not read, the tape closed at `end`; none
    /// when every line after it is blank, a comment or a `%` line.
    pub fn note(self, end: Span) -> Option<SyntaxError> {
        let first = self.first?;
        let kind = SyntaxErrorKind::NotReadAfterTape {
            lines: self.lines,
            end,
        };
        Some(SyntaxError::new(kind, first))
    }
}

/// Where the tape of `text`, a program from its first line, ends
/// ([`Tape`]): the start of its closing `%` line, and the note for the
/// lines after it ([`Unread`]). `None`: it is not a tape, or not closed.
pub fn tape_end(text: &str, at: &Locator) -> Option<(usize, Option<SyntaxError>)> {
    let mut tape = Tape::default();
    let mut start = 0;
    while start < text.len() && !tape.decided() {
        let end = next_line(text, start);
        if tape.closes(&text[start..end]) {
            let percent = start + text[start..end].find('%').unwrap_or(0);
            let mut unread = Unread::default();
            unread.add(text, end, at);
            return Some((start, unread.note(at.span(percent, percent + 1))));
        }
        start = end;
    }
    None
}

/// The offset just past the line that starts at `start`.
fn next_line(text: &str, start: usize) -> usize {
    text[start..]
        .find('\n')
        .map_or(text.len(), |i| start + i + 1)
}

/// How a subprogram written after the end starts.
enum Start {
    /// LinuxCNC's `o<name> sub` or `oN sub`: its label, as compared.
    Named(String),
    /// Fanuc's `O1000` (or `:1000`) alone on its line.
    Numbered,
}

/// The subprogram `line` (trimmed) starts, if it starts one: after an
/// optional `N` label, an o-word and `sub`, or an `O` number alone (a
/// comment may follow either).
fn start_of_subprogram(line: &str) -> Option<Start> {
    let line = without_label(line);
    let (label, rest) = o_label(line)?;
    let rest = rest.trim_start();
    if let Some(after) = keyword(rest, OWord::Sub) {
        return ends_here(after).then_some(Start::Named(label));
    }
    let numbered = label.bytes().all(|b| b.is_ascii_digit()) && !label.is_empty();
    (numbered && ends_here(rest)).then_some(Start::Numbered)
}

/// Where the subprogram that starts just before `from` ends: past its
/// `endsub` line (LinuxCNC) or its `M99` line (Fanuc); the end of the text
/// if it never does (its parse then says so).
fn end_of_subprogram(text: &str, from: usize, start: &Start) -> usize {
    let mut line_start = from;
    while line_start < text.len() {
        let line_end = next_line(text, line_start);
        let line = text[line_start..line_end].trim();
        let ends = match start {
            Start::Named(name) => o_label(without_label(line)).is_some_and(|(label, rest)| {
                label == *name && keyword(rest.trim_start(), OWord::EndSub).is_some()
            }),
            Start::Numbered => has_m99(line),
        };
        if ends {
            return line_end;
        }
        line_start = line_end;
    }
    text.len()
}

/// `line` without an `N` label and the blanks after it.
fn without_label(line: &str) -> &str {
    match line.strip_prefix(['N', 'n']) {
        Some(rest) if rest.starts_with(|c: char| c.is_ascii_digit()) => rest
            .trim_start_matches(|c: char| c.is_ascii_digit() || c == '.')
            .trim_start(),
        _ => line,
    }
}

/// An o-word's label (`<name>` in lower case without blanks, or its
/// digits, `:` as Fanuc's `O`) and the text after it.
fn o_label(line: &str) -> Option<(String, &str)> {
    let rest = line.strip_prefix(['o', 'O', ':'])?.trim_start();
    if let Some(named) = rest.strip_prefix('<') {
        let close = named.find('>')?;
        let label: String = named[..close]
            .chars()
            .filter(|c| !c.is_whitespace())
            .flat_map(char::to_lowercase)
            .collect();
        return Some((format!("<{label}>"), &named[close + 1..]));
    }
    // Blanks may stand between its digits (`o 1 0 0`), as rs274 reads it.
    let digits = rest
        .find(|c: char| !(c.is_ascii_digit() || c == ' ' || c == '\t'))
        .unwrap_or(rest.len());
    let number: String = rest[..digits].split_whitespace().collect();
    let number = number.trim_start_matches('0');
    let read = rest[..digits].trim_end().len();
    (read > 0).then(|| (number.to_string(), &rest[read..]))
}

/// The text after the o-word keyword `word` at the start of `text`, as
/// rs274 spells it (`end sub`), if it is there as a whole word.
fn keyword(text: &str, word: OWord) -> Option<&str> {
    OWord::spelled(text)
        .filter(|&(spelled, _)| spelled == word)
        .map(|(_, taken)| &text[taken..])
}

/// Nothing but blanks or a comment in `rest`.
fn ends_here(rest: &str) -> bool {
    let rest = rest.trim_start();
    rest.is_empty() || rest.starts_with(['(', ';'])
}

/// A line without its comments and blanks, in upper case.
fn code_of(line: &str) -> String {
    let mut code = String::with_capacity(line.len());
    let mut depth = 0usize;
    for c in line.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            c if depth == 0 && !c.is_whitespace() => code.push(c.to_ascii_uppercase()),
            _ => {}
        }
    }
    code
}

/// Whether a line has the word `M99` outside its comments (`M99`, `m099`,
/// `M 99`).
fn has_m99(line: &str) -> bool {
    let code = code_of(line);
    code.match_indices('M').any(|(at, _)| {
        let digits: String = code[at + 1..]
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect();
        digits.parse::<f64>() == Ok(99.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subprograms_are_told_from_notes() {
        assert!(
            matches!(start_of_subprogram("o<on_abort> sub"), Some(Start::Named(n)) if n == "<on_abort>")
        );
        assert!(
            matches!(start_of_subprogram("O< On Abort >SUB (x)"), Some(Start::Named(n)) if n == "<onabort>")
        );
        assert!(matches!(start_of_subprogram("N10 o100 sub"), Some(Start::Named(n)) if n == "100"));
        assert!(matches!(
            start_of_subprogram("O1000"),
            Some(Start::Numbered)
        ));
        assert!(matches!(
            start_of_subprogram(":0097 (PART)"),
            Some(Start::Numbered)
        ));
        for note in [
            "o<x> subtract",
            "On abort, the sub runs",
            "O2 sensor",
            "(o<x> sub)",
            "; o<x> sub",
            "EMC_ABORT_TASK_EXEC_ERROR = 1,",
            "o<x> endsub",
        ] {
            assert!(start_of_subprogram(note).is_none(), "{note}");
        }
    }

    #[test]
    fn m99_is_a_word_outside_comments() {
        assert!(has_m99("M99"));
        assert!(has_m99("N20 m 099 (back)"));
        assert!(!has_m99("(M99) G1 X1"));
        assert!(!has_m99("G1 X1 ; M99"));
        assert!(!has_m99("M990"));
    }

    #[test]
    fn a_tape_is_closed_by_its_next_percent_line_only() {
        let closing = |text: &str| {
            let mut tape = Tape::default();
            text.lines().position(|line| tape.closes(line))
        };
        assert_eq!(closing("%\nG0 X1\n% LED on\nG0 X2\n%\n"), Some(4));
        assert_eq!(closing("\n  \n\u{feff}%\nG0 X1\n  %\n"), Some(4));
        assert_eq!(closing("% tape\nG0 X1\n%\n"), None);
        assert_eq!(closing("(c)\n%\nG0 X1\n%\n"), None);
        assert_eq!(closing("G0 X1\n%\nG0 X2\n%\n"), None);
        assert_eq!(closing("%\nG0 X1\n"), None);
    }

    #[test]
    fn what_follows_a_tape_is_counted_but_comments_and_percent_lines() {
        let text = "%\nG0 X1\n%\n\n(c) ; d\nG0 X2\n%\nnotes\n";
        let (cut, note) = tape_end(text, &Locator::new(0, text)).unwrap();
        assert_eq!(&text[cut..cut + 2], "%\n");
        let note = note.unwrap();
        assert_eq!((note.span.line, note.span.start), (6, 19));
        assert!(matches!(
            note.kind,
            SyntaxErrorKind::NotReadAfterTape { lines: 2, .. }
        ));
        let text = "%\nG0 X1\n%\n(c)\n%\n";
        assert!(tape_end(text, &Locator::new(0, text)).unwrap().1.is_none());
    }

    #[test]
    fn more_is_read_only_before_a_tape_end() {
        assert!(!has_more("\n  \n%\nnotes\n"));
        assert!(has_more("\n(note)\n%\n"));
        assert!(!has_more(""));
    }
}
