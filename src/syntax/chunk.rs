//! Programs read a part at a time (issue 15): parsed and run in parts of
//! about [`CHUNK_BYTES`], each dropped before the next is read, so memory
//! grows with the longest part, not with the program. A part of any
//! program ends outside every block, where the statement before the cut
//! is complete ([`cut_part`]); a program that calls a subprogram written
//! further on, or has a `GOTO`, is read whole. A plain program of G-code words, comments and
//! controller commands only — no parameters, no expressions, no
//! subprograms, no control flow — means the same cut at any line end
//! ([`chunkable`], [`chunks`]), and its lines of plain words are built
//! straight from their bytes ([`parse_chunk`]).

use super::after_end::end_word;
use super::gcode::comment_end;
use super::language::Language;
use super::parser::{fast_path, parse_program_from, parse_text};
use super::words::{plain_words, WordNumber};
use crate::ast::{
    LineEnd, Lines, Names, OName, PlainWord, Stmt, StmtKind, Subprogram, Word, WordValue,
};
use crate::diagnostic::Diagnostic;
use crate::source::Locator;

/// About this many bytes of text are parsed at a time. A part's syntax
/// tree (about ten times its text) stays in the processor's cache until
/// the evaluator runs it: 16 KB parts are faster than 64 KB ones (101
/// rounds in turn, the 200k-move program: 28.3 -> 27.5 ms with `-o`; 8 KB:
/// the same as 16) and take less memory (2M moves: 8.9 -> 7.7 MB).
pub const CHUNK_BYTES: usize = 16 * 1024;

thread_local! {
    /// The size of a part on this thread; `None`: programs are read whole.
    static PART_BYTES: std::cell::Cell<Option<usize>> =
        const { std::cell::Cell::new(Some(CHUNK_BYTES)) };
}

/// Run `f` (a compile on this thread) reading programs in parts of
/// about `bytes`, or whole with `None` (tests compare the two).
pub fn with_part_size<T>(bytes: Option<usize>, f: impl FnOnce() -> T) -> T {
    let before = PART_BYTES.with(|p| p.replace(bytes));
    let result = f();
    PART_BYTES.with(|p| p.set(before));
    result
}

/// Whether programs are read in parts on this thread.
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
            b'A'..=b'Z' | b'a'..=b'z' => match plain_word(line, i) {
                Some(end) => i = end,
                None => return false,
            },
            _ => return false,
        }
    }
    true
}

/// The end of the word whose letter is `line[at]`, when it is a plain
/// word (a letter, spaces, a signed decimal number without blanks inside)
/// that is none of `O`, `M98`, `M99`, `G65`.
fn plain_word(line: &str, at: usize) -> Option<usize> {
    let letter = line.as_bytes()[at].to_ascii_uppercase();
    if letter == b'O' {
        return None;
    }
    let number = WordNumber::after(line, at + 1, line.len());
    // `M 9 8` calls too: a number with blanks inside is read whole.
    if !number.has_digits() || number.spaced {
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

/// The parts a compile that cuts as it reads ([`next_cut`]) would read a
/// program that is not plain in, in order, or `None` when it would find
/// it must be read whole (but for a wizard's call, which only running it
/// shows). Every part is parsed and thrown away: tests use it to know
/// what a compile did.
pub fn cuts(text: &str, at: &Locator, language: Language) -> Option<Vec<std::ops::Range<usize>>> {
    let (mut names, mut defined) = (Names::default(), Vec::new());
    let mut found = Vec::new();
    let mut from = 0;
    while from < text.len() {
        names.forget_notes();
        match next_cut(text, from, at, language, &mut names, &mut defined) {
            Cut::Part(end, ..) => {
                found.push(from..end);
                from = end;
            }
            Cut::Grow | Cut::Whole => return None,
        }
    }
    Some(found)
}

/// The part of the text `text` held whole from `from` on ([`cut_part`],
/// grown until it ends): never [`Cut::Grow`].
pub fn next_cut(
    text: &str,
    from: usize,
    at: &Locator,
    language: Language,
    names: &mut Names,
    defined: &mut Vec<u32>,
) -> Cut {
    let mut want = part_size();
    loop {
        match cut_part(text, from, want, true, at, language, names, defined) {
            Cut::Grow => want = want.saturating_mul(2),
            cut => return cut,
        }
    }
}

/// What [`cut_part`] found.
pub enum Cut {
    /// The part ends at this offset: its statements, its subprograms and
    /// its diagnostics.
    Part(usize, Vec<Stmt>, Vec<Subprogram>, Vec<Diagnostic>),
    /// Ask again with more wanted (and, if the text is not complete, more
    /// of it).
    Grow,
    /// The program must be read whole.
    Whole,
}

/// The part of a program that is not plain starting at `from` (a line
/// start after the last cut) in `text`, about `want` bytes long, parsed
/// into `names`; `complete`: nothing follows `text` (else it ends with a
/// line end). A part ends at a line end outside every block (`while`,
/// `if`, `oN …`, `WHILE … DO`), before a line that surely starts a
/// statement of its own ([`starts_a_statement`]: a line end ends a
/// statement unless `{` or `else` follows it, across blank lines and
/// comments), and reads without a syntax error (so no
/// block, group or comment is open at the cut), or at the end of the text,
/// which then has the errors. A part may hold subprograms (`O` … `M99`,
/// LinuxCNC's `sub` … `endsub`) and call those of its own and of the parts
/// before it (`defined`, their numbers, which a part taken adds its own
/// to). A program whose part calls any other (it may be written further
/// on), defines one a part before it did, has `M99` outside a subprogram,
/// an `O` word (but the program's number, first in it) or a `GOTO` (it may
/// jump back) is read whole: those need the whole program. So is one with
/// a `G` or `M` code or a program number given by an expression (it could
/// be one of those).
#[allow(clippy::too_many_arguments)]
pub fn cut_part(
    text: &str,
    from: usize,
    want: usize,
    complete: bool,
    at: &Locator,
    language: Language,
    names: &mut Names,
    defined: &mut Vec<u32>,
) -> Cut {
    let end = match cut_after(text, from.saturating_add(want)) {
        Some(end) => end,
        None if complete => text.len(),
        None => return Cut::Grow,
    };
    let (program, diagnostics) = parse_program_from(&text[..end], from, at, language, names);
    let clean = !diagnostics.iter().any(crate::diagnostic::is_error);
    if !clean && (end < text.len() || !complete) {
        return Cut::Grow;
    }
    // The part with the main program's end is read to the end of the
    // text, as the whole program is (`parse_program_from`).
    let ends = language == Language::Gcode && end_word(&program.main).is_some();
    if ends && (end < text.len() || !complete) {
        return Cut::Grow;
    }
    let first = at.span(from, from).line == 1;
    // A part after the first that starts with an `O` line but has no
    // `M99` (the parser takes it for the program's number): a subprogram
    // that goes on past the cut.
    if program.main_number.is_some() && !first && (end < text.len() || !complete) {
        return Cut::Grow;
    }
    let own = |n: OName| program.subprograms.iter().any(|s| s.name == n);
    let known = |n: OName| own(n) || defined.contains(&defined_key(n));
    let in_subs = program.subprograms.iter().flat_map(|s| &s.body);
    if (program.main_number.is_some() && !first)
        || program
            .subprograms
            .iter()
            .any(|s| defined.contains(&defined_key(s.name)))
        || program.main.iter().any(|s| needs_whole(s, &known, false))
        || in_subs.clone().any(|s| needs_whole(s, &known, true))
    {
        return Cut::Whole;
    }
    defined.extend(program.subprograms.iter().map(|s| defined_key(s.name)));
    Cut::Part(end, program.main, program.subprograms, diagnostics)
}

/// A subprogram as `defined` (the caller's list of the parts'
/// subprograms, a `Vec<u32>` in the driver) holds it: its number, or its
/// name's symbol with the top bit set (numbers are below 10^8). To go
/// when the driver keeps a `Vec<OName>`.
fn defined_key(name: OName) -> u32 {
    match name {
        OName::Number(n) => n,
        OName::Named(s) => 1 << 31 | s.0,
    }
}

/// The first line end at or after `want` that is followed by a whole line
/// that [starts a statement](starts_a_statement) after any blank lines, if
/// `text` has one.
fn cut_after(text: &str, want: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut at = want.min(bytes.len());
    loop {
        // A line end is one byte, never inside a character.
        let end = at + bytes[at..].iter().position(|&b| b == b'\n')? + 1;
        // The statement before the cut goes on past blank lines: the line
        // that decides is the first with something on it.
        let mut line = end;
        let decides = loop {
            let next = line + bytes[line..].iter().position(|&b| b == b'\n')?;
            if !text[line..next].trim().is_empty() {
                break &text[line..next];
            }
            line = next + 1;
        };
        if starts_a_statement(decides) {
            return Some(end);
        }
        at = end;
    }
}

/// Whether `line` surely starts a statement of its own: it starts with a
/// letter, a digit, `#` or `$`, and not with `else` (in any case), which
/// the lexer joins to the statement before across line ends. A line that
/// starts otherwise (`{`, a comment, which may hide an `else` after it or
/// span lines, `%`, which the lexer skips) is no place to cut before.
fn starts_a_statement(line: &str) -> bool {
    let line = line.trim_start();
    let first = line.bytes().next().unwrap_or(b' ');
    let is_else = line
        .get(..4)
        .is_some_and(|word| word.eq_ignore_ascii_case("else"));
    (first.is_ascii_alphanumeric() || matches!(first, b'#' | b'$')) && !is_else
}

/// Whether `stmt` needs the whole program to run: a `GOTO`, an `O` word,
/// a call of a subprogram not `known`, an `M99` or a LinuxCNC `return`
/// outside a subprogram (`in_sub`), or a code or program number given by
/// an expression.
fn needs_whole(stmt: &Stmt, known: &dyn Fn(OName) -> bool, in_sub: bool) -> bool {
    let needs = |s: &Stmt| needs_whole(s, known, in_sub);
    match &stmt.kind {
        StmtKind::Goto(_) => true,
        StmtKind::Line(line) => line_needs_whole(&line.words, known, in_sub),
        StmtKind::MacroCall(call) => {
            let words: Vec<Word> = call.words().cloned().collect();
            line_needs_whole(&words, known, in_sub)
        }
        // (The parser `cut_part` reads with makes no `Lines`, only
        // `parse_lines` does: kept whole for any other caller.)
        StmtKind::Lines(lines) => lines
            .each_as_words()
            .any(|words| line_needs_whole(&words, known, in_sub)),
        StmtKind::If(f) => f
            .branches
            .iter()
            .flat_map(|(_, body)| body)
            .chain(f.otherwise.iter().flatten())
            .any(needs),
        StmtKind::While(w) => w.body.iter().any(needs),
        StmtKind::SubCall(call) => !known(call.name),
        StmtKind::Return(_) => !in_sub,
        StmtKind::Repeat(r) => r.body.iter().any(needs),
        // One the parser left in a block, where no subprogram starts.
        StmtKind::Sub(_) => true,
        StmtKind::Assign(_)
        | StmtKind::Assigns(_)
        | StmtKind::Call { .. }
        | StmtKind::Break(_)
        | StmtKind::Continue(_)
        | StmtKind::Command(_)
        | StmtKind::Comment(_)
        | StmtKind::DefinitionRead { .. }
        | StmtKind::Error => false,
    }
}

/// [`needs_whole`] of a line's words.
fn line_needs_whole(words: &[Word], known: &dyn Fn(OName) -> bool, in_sub: bool) -> bool {
    let odd = |w: &crate::ast::Word| {
        w.letter == b'O' || (w.is_code() && matches!(w.value, WordValue::Expr(_)))
    };
    words.iter().any(odd)
        || crate::ast::statements(words).any(|s| {
            let Some(WordValue::Number(code)) = s.code.map(|c| &c.value) else {
                return false;
            };
            let letter = s.code.map_or(0, |c| c.letter);
            let m98 = (letter, code.value) == (b'M', 98.0);
            match (letter, code.value) {
                (b'M', 99.0) => !in_sub,
                (b'M', 98.0) | (b'G', 65.0) => {
                    let p = s.args.iter().find(|w| w.letter == b'P');
                    let target = match p.map(|w| &w.value) {
                        Some(WordValue::Number(p)) => called(p, m98),
                        _ => None,
                    };
                    !target.map(OName::Number).is_some_and(known)
                }
                _ => false,
            }
        })
}

/// The program `M98 P<p>` (`m98`) or `G65 P<p>` calls, as the evaluator
/// reads `p`; `None` if it is not a whole number (an error there).
fn called(p: &crate::ast::Number, m98: bool) -> Option<u32> {
    let number = crate::ast::whole_number(p.value)?;
    Some(if m98 { p.m98_split(number).0 } else { number })
}

/// Parse the part `range` of the plain program `text` (a range [`chunks`]
/// gave) with spans in the whole text, interning into `names` (the
/// program's): its statements and its diagnostics.
/// A line of plain words (most of a CAM program) is built straight from
/// its bytes ([`plain_words`]); the lines between go to the lexer
/// and the parser together. A plain program means the same cut at any line
/// end, so the two give what the parser alone gives.
pub fn parse_chunk(
    text: &str,
    range: std::ops::Range<usize>,
    at: &Locator,
    language: Language,
    names: &mut Names,
) -> (Vec<Stmt>, Vec<Diagnostic>) {
    parse_lines(
        text,
        range,
        at,
        language,
        names,
        false,
        &mut Spare::default(),
    )
    .unwrap_or_default()
}

/// [`parse_chunk`] of a part not known to be plain: `None` (and nothing
/// parsed past it) at its first line that [`plain_line`] does not take.
/// A line of plain words is plain unless it calls (`M98`, `M99`, `G65`,
/// which [`plain_word`] refuses); only the other lines are looked at again.
/// Lines of plain words in a row are kept in vectors from `spare` (those of
/// parts run before, [`recycle`]) while it has any. `None` too for a part
/// with the program's end (`M2`, `M30`), which [`cut_part`] reads.
pub fn parse_plain_chunk(
    text: &str,
    range: std::ops::Range<usize>,
    at: &Locator,
    language: Language,
    names: &mut Names,
    spare: &mut Spare,
) -> Option<(Vec<Stmt>, Vec<Diagnostic>)> {
    parse_lines(text, range, at, language, names, true, spare)
}

/// Emptied [`Lines`] of parts that have run, for the parts to come: their
/// vectors are then not allocated and freed again for every part.
#[derive(Debug, Default)]
pub struct Spare {
    runs: Vec<Lines>,
    /// The room for words they have, in all.
    room: usize,
}

impl Spare {
    /// The most room for words kept, in all: 65,536 words, 1.6 MB (a part
    /// of 16 KB of CAM lines has about 2,500).
    const MOST_ROOM: usize = 1 << 16;

    fn pop(&mut self) -> Lines {
        let run = self.runs.pop().unwrap_or_default();
        self.room -= run.words.capacity();
        run
    }

    /// Keep `run`, emptied, unless that would keep more than the most room.
    fn push(&mut self, mut run: Lines) {
        let room = run.words.capacity();
        if self.room + room <= Self::MOST_ROOM {
            run.clear();
            self.room += room;
            self.runs.push(run);
        }
    }

    pub fn clear(&mut self) {
        *self = Spare::default();
    }
}

/// The lines of words of `stmts` (a part that has run), into `spare` for
/// [`parse_plain_chunk`].
pub fn recycle(stmts: Vec<Stmt>, spare: &mut Spare) {
    for stmt in stmts {
        if let StmtKind::Lines(run) = stmt.kind {
            spare.push(*run);
        }
    }
}

/// Whether a word, a letter and its value, may call a subprogram
/// (`M98`, `M99`, `G65`, however written): the words [`plain_word`]
/// refuses, and some more (`M-98`).
fn may_call(word: &PlainWord) -> bool {
    let value = word.value;
    // The whole part of the value, without its sign: 98 or 99, or 65.
    match word.letter {
        b'M' => (98.0..100.0).contains(&value.abs()),
        b'G' => (65.0..66.0).contains(&value.abs()),
        _ => false,
    }
}

fn parse_lines(
    text: &str,
    range: std::ops::Range<usize>,
    at: &Locator,
    language: Language,
    names: &mut Names,
    check: bool,
    spare: &mut Spare,
) -> Option<(Vec<Stmt>, Vec<Diagnostic>)> {
    let (mut stmts, mut diagnostics) = (Vec::new(), Vec::new());
    let mut parse = |from: usize, to: usize, stmts: &mut Vec<Stmt>| {
        if from < to {
            let (program, found) = parse_text(&text[..to], from, at, language, names);
            // A part of a plain program has no subprogram.
            debug_assert!(program.subprograms.is_empty());
            stmts.extend(program.main);
            diagnostics.extend(found);
        }
    };
    if !fast_path() {
        if check && !text[range.clone()].lines().all(plain_line) {
            return None;
        }
        parse(range.start, range.end, &mut stmts);
        return (!check || end_word(&stmts).is_none()).then_some((stmts, diagnostics));
    }
    // The lines of plain words since the last line for the parser.
    let mut run = spare.pop();
    // Lines from `waiting` on are for the parser, not yet parsed.
    let (mut waiting, mut line) = (range.start, range.start);
    let mut number = at.span(line, line).line;
    // The line ends, from the part's line index (a start is after one).
    let starts = at.line_starts();
    let mut after = starts[starts.partition_point(|&s| s as usize <= line)..].iter();
    while line < range.end {
        let line_end = after
            .next()
            .map_or(range.end, |&s| (s as usize - 1).min(range.end));
        let before = run.words.len();
        if plain_words(text, (line, line_end), at, &mut run.words) {
            if check && run.words[before..].iter().any(may_call) {
                spare.push(run);
                return None;
            }
            if waiting < line {
                // The lines before this one go first: the run up to them,
                // then they; this line starts the next run.
                if !run.ends.is_empty() {
                    let mut next = spare.pop();
                    next.words.extend(run.words.drain(before..));
                    end_run(&mut stmts, std::mem::replace(&mut run, next), at, spare);
                }
                parse(waiting, line, &mut stmts);
            }
            let end = run.words.len() as u32;
            if run.ends.last().map_or(0, |e| e.end) < end {
                run.ends.push(LineEnd { end, line: number });
            }
            waiting = (line_end + 1).min(range.end);
        } else if check && !plain_line(&text[line..line_end]) {
            spare.push(run);
            return None;
        }
        line = line_end + 1;
        number += 1;
    }
    end_run(&mut stmts, run, at, spare);
    parse(waiting, range.end, &mut stmts);
    // The part with the program's end is read by the parser to the end of
    // the text ([`cut_part`]), as the whole program is.
    (!check || end_word(&stmts).is_none()).then_some((stmts, diagnostics))
}

/// The statement of a run of lines of plain words, if it has any; its span
/// from its first word to its last.
fn end_run(stmts: &mut Vec<Stmt>, mut run: Lines, at: &Locator, spare: &mut Spare) {
    match (run.words.first(), run.words.last(), run.ends.first()) {
        (Some(first), Some(last), Some(line)) => {
            run.file = at.file() as u32;
            let span = first.span(run.file, line.line);
            stmts.push(Stmt {
                span: span.to(last.span(run.file, line.line)),
                kind: StmtKind::Lines(Box::new(run)),
            })
        }
        _ => spare.push(run),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part read as plain (`compile_file`) is parsed as plain exactly
    /// when its every line is plain (what a scan of the file said before
    /// it was read) and it has no program end, and then as `parse_chunk`
    /// parses it; with the fast path and without.
    fn reads_as_plain(text: &str) {
        let at = Locator::new(0, text);
        // A part with the program's end is read by `cut_part`, not as plain.
        let (read, _) = parse_chunk(
            text,
            0..text.len(),
            &at,
            Language::Gcode,
            &mut Names::default(),
        );
        let plain = text.lines().all(plain_line) && end_word(&read).is_none();
        for fast in [true, false] {
            crate::syntax::parser::with_fast_path(fast, || {
                let range = 0..text.len();
                let mut names = Names::default();
                let got = parse_plain_chunk(
                    text,
                    range.clone(),
                    &at,
                    Language::Gcode,
                    &mut names,
                    &mut Spare::default(),
                );
                assert_eq!(got.is_some(), plain, "{text:?} (fast path: {fast})");
                if let Some((stmts, found)) = got {
                    let mut names = Names::default();
                    let (all, all_found) =
                        parse_chunk(text, range, &at, Language::Gcode, &mut names);
                    assert_eq!(format!("{stmts:?}"), format!("{all:?}"), "{text:?}");
                    assert_eq!(found.len(), all_found.len(), "{text:?}");
                }
            });
        }
    }

    /// Lines of plain words in a row are one statement; a line for the
    /// parser between them ends it, and comes between it and the next.
    #[test]
    fn lines_in_a_row_are_one_statement() {
        let text = "G1 X1\nG1 X2\n\n(c)\nG1 X3\n\nG1 X4\n(d)\n";
        let at = Locator::new(0, text);
        let range = 0..text.len();
        let (stmts, _) = parse_chunk(text, range, &at, Language::Gcode, &mut Names::default());
        let kinds: Vec<String> = stmts
            .iter()
            .map(|s| match &s.kind {
                StmtKind::Lines(lines) => {
                    let ends: Vec<u32> = lines.ends.iter().map(|e| e.end).collect();
                    format!("lines {ends:?}")
                }
                StmtKind::Comment(_) => "comment".to_string(),
                other => format!("{other:?}"),
            })
            .collect();
        assert_eq!(
            kinds,
            ["lines [2, 4]", "comment", "lines [2, 4]", "comment"]
        );
        // Spans from the first word of a run to its last.
        assert_eq!((stmts[0].span.start, stmts[0].span.end), (0, 11));
        assert_eq!((stmts[2].span.start, stmts[2].span.end), (17, 29));
    }

    /// Runs kept for the parts to come: emptied, with room for at most
    /// [`Spare::MOST_ROOM`] words in all.
    #[test]
    fn spare_runs_are_empty_and_bounded() {
        let parse = |text: &str| {
            let at = Locator::new(0, text);
            let range = 0..text.len();
            parse_chunk(text, range, &at, Language::Gcode, &mut Names::default()).0
        };
        let mut spare = Spare::default();
        // Runs of two lines between comments.
        recycle(parse(&"G1 X1 Y2\nG0 Z5\n(c)\n".repeat(3000)), &mut spare);
        assert_eq!(spare.runs.len(), 3000);
        let room: usize = spare.runs.iter().map(|r| r.words.capacity()).sum();
        assert_eq!(spare.room, room);
        assert!(room <= Spare::MOST_ROOM);
        assert!(spare
            .runs
            .iter()
            .all(|r| r.words.is_empty() && r.ends.is_empty()));
        // A run with more room than that is not kept.
        let mut spare = Spare::default();
        recycle(parse(&"G1 X1 Y2 Z3\n".repeat(30_000)), &mut spare);
        assert!(spare.runs.is_empty() && spare.room == 0);
        // Taken back, a run's room is no longer counted.
        recycle(parse("G1 X1\n"), &mut spare);
        assert_eq!(spare.runs.len(), 1);
        let run = spare.pop();
        assert_eq!((spare.runs.len(), spare.room), (0, 0));
        assert!(run.words.capacity() > 0);
    }

    #[test]
    fn a_part_is_plain_when_its_every_line_is() {
        for text in [
            "G1 X1.5 Y2\nG0 Z5\nM30\n",
            "G1 X1 (a comment)\n%\n$H\n/G1 X2\r\nG1 Y1",
            "G1 X1\nM98 P100\nG1 X2\n",
            "G1 X1\nM-98 P100\n",
            "m0099.5\n",
            "M97\nM100\nG64 P0.01\nG66\nG64.5\n",
            "G1 X1\nG65 P9010 A1\n",
            "G65.9 P1\n",
            "G1 X1\n#1 = 2\nG1 X#1\n",
            "G1 X1\no100 sub\nG1 X2\no100 endsub\n",
            "G1 X1\nG1 X\n",
            "G1 X1.2.3\n",
            "",
        ] {
            reads_as_plain(text);
        }
    }

    proptest::proptest! {
        #[test]
        fn a_part_is_plain_when_its_every_line_is_any_part(
            lines in proptest::collection::vec(r"[GMOgmoXxPp0-9 \t.+\-(;%/#=]{0,16}", 0..5)
        ) {
            reads_as_plain(&lines.join("\n"));
        }
    }

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

    /// The parts of `text` (G-code) at the smallest part size: how many,
    /// or `None` when it must be read whole.
    fn parts_of(text: &str) -> Option<usize> {
        let at = Locator::new(0, text);
        with_part_size(Some(1), || cuts(text, &at, Language::Gcode)).map(|c| c.len())
    }

    #[test]
    fn a_subprogram_is_kept_for_the_parts_after_it() {
        let sub = "o<dip> sub\nG1 Z-1 F100\n(down)\nG0 Z1\no<dip> endsub\n";
        let fanuc_sub = "O0100\nG1 Z-1 F100\nM99\n";
        let main = "G0 X1\n#1 = 2\nG0 X#1\n";
        // Defined before its calls, in a part of its own: cut.
        let before = format!("G21\n{sub}{main}o<dip> call\n{main}o<dip> call\nM2\n");
        assert!(parts_of(&before).is_some_and(|n| n > 4), "{before}");
        let repeated = format!("G21\n{fanuc_sub}{main}M98 P30100\n{main}M98 P100 L2\nM30\n");
        assert!(parts_of(&repeated).is_some_and(|n| n > 4), "{repeated}");
        for whole in [
            // Called before it is written.
            format!("G21\n{main}o<dip> call\n{sub}M2\n"),
            format!("G21\n{main}M98 P100\nM30\n{fanuc_sub}"),
            // `P30100` is three runs of O0100, not O30100.
            format!("G21\nO30100\nG0 X1\nM99\n{main}M98 P30100\nM30\n"),
            // Written twice (an error the whole read reports).
            format!("G21\n{fanuc_sub}{main}{fanuc_sub}M30\n"),
            // The program number given by an expression, `M99` in the
            // main program, a `GOTO`, an `O` word after the first line.
            format!("G21\n{fanuc_sub}{main}M98 P#1\nM30\n"),
            format!("G21\n{main}M99\n"),
            format!("G21\nN10 {main}GOTO 10\nM30\n"),
            format!("G21\n{main}O1\n{main}M30\n"),
        ] {
            assert_eq!(parts_of(&whole), None, "{whole}");
        }
    }

    #[test]
    fn no_part_ends_before_the_else_of_its_if() {
        // The `else` after blank lines, comments (a line may go on after
        // one) and `%` lines still belongs to the if.
        for between in [
            "\n// the other side\n(also)\n",
            "; note ",
            "(c) ",
            "%\n",
            "\n \n",
        ] {
            let text = format!(
                "G0 X0\nif (1 > 0) {{\n  G0 X1\n}}\n{between}else {{\n  G0 X2\n}}\nG0 X3\n"
            );
            let at = Locator::new(0, &text);
            let cuts = with_part_size(Some(1), || cuts(&text, &at, Language::Egc)).unwrap();
            let (close, other) = (text.find("}\n").unwrap(), text.find("else").unwrap());
            assert!(cuts.len() >= 2, "{cuts:?}");
            for range in &cuts {
                let inside = (close..other).contains(&range.end);
                assert!(!inside, "{between:?}: {range:?} in {cuts:?}");
            }
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
