//! A program read a part at a time: from a text held whole, or from a
//! file's lines as the evaluator asks for them. Each part is parsed once;
//! a part that needs the whole program stops the reading ([`Whole`]).

use super::scan::{input_decimals, streamable_block};
use super::scan::{read_lines, FileScan, Unforeseen};
use crate::ast::Names;
use crate::diagnostic::{is_error, Diagnostic};
use crate::eval;
use crate::source::{self, FileId, Locator};
use crate::syntax::{chunk, Language, Tape, Unread};
use std::time::{Duration, Instant};

/// Where the parts of a program come from.
pub(super) enum PartSource<'a> {
    /// Ranges of a text held whole.
    Text {
        text: &'a str,
        at: &'a Locator,
        ranges: Box<dyn Iterator<Item = std::ops::Range<usize>> + 'a>,
    },
    /// A program that is not plain, held whole, cut as it is read
    /// ([`chunk::next_cut`]: each part parsed once, where it is cut).
    TextCut {
        text: &'a str,
        at: &'a Locator,
        from: usize,
        /// The subprograms of the parts read ([`chunk::cut_part`]).
        defined: Vec<u32>,
    },
    /// Lines read from a file as they are needed (its text is never
    /// held), as plain G-code, until a part is not
    /// ([`chunk::parse_plain_chunk`]): then a [`PartSource::Program`].
    Reader(LineReader<'a>),
    /// A program that is not plain, read from a file a part at a time.
    Program(ProgramReader<'a>),
    /// Only while one source gives way to another.
    Done,
}

/// A program read a part at a time ([`chunk`]): each part is parsed
/// when the evaluator asks for it. After a syntax error nothing more is
/// run, but every part is still read, so that all syntax errors are found.
pub(super) struct Parts<'a> {
    pub(super) source: PartSource<'a>,
    pub(super) diagnostics: Vec<Diagnostic>,
    pub(super) broken: bool,
    pub(super) time: Duration,
    /// The first read error; the program stops there.
    pub(super) read_error: Option<std::io::Error>,
    /// A part needs the whole program; nothing more is read.
    pub(super) whole: bool,
    /// Emptied runs of lines of plain words, for the lines to come
    /// ([`chunk::recycle`]).
    pub(super) spare: chunk::Spare,
    /// The note for what follows a tape's end, when the text read was cut
    /// there ([`crate::syntax::tape_end`]).
    pub(super) tape_note: Option<Diagnostic>,
}

impl<'a> Parts<'a> {
    pub(super) fn new(source: PartSource<'a>) -> Parts<'a> {
        Parts {
            source,
            diagnostics: Vec::new(),
            broken: false,
            time: Duration::ZERO,
            read_error: None,
            whole: false,
            spare: chunk::Spare::default(),
            tape_note: None,
        }
    }

    /// The note for what follows a tape's end, once every part is read:
    /// the text's, or the file's, found as its lines were read.
    pub(super) fn take_tape_note(&mut self) -> Option<Diagnostic> {
        let lines = match &mut self.source {
            PartSource::Reader(lines) => Some(lines),
            PartSource::Program(program) => Some(&mut program.lines),
            _ => None,
        };
        let from_file = lines.and_then(|l| l.tape_note.take());
        self.tape_note.take().or(from_file)
    }

    /// The statements of a part that has run: their runs of lines are
    /// kept for the parts to come while those are read as plain (no other
    /// source takes them).
    pub(super) fn recycle(&mut self, ran: Vec<crate::ast::Stmt>) {
        match self.source {
            PartSource::Reader(_) | PartSource::Text { .. } => chunk::recycle(ran, &mut self.spare),
            _ => self.spare.clear(),
        }
    }

    /// The next part to run; `None` at the end, or after a syntax error
    /// (the rest is read for its errors).
    pub(super) fn next(&mut self, language: Language, names: &mut Names) -> Option<eval::Part> {
        loop {
            let started = Instant::now();
            let (stmts, subprograms, found) = self.parse_next(language, names)?;
            self.time += started.elapsed();
            self.broken |= found.iter().any(is_error);
            self.diagnostics.extend(found);
            if !self.broken {
                return Some((stmts, subprograms));
            }
        }
    }

    /// The next part, parsed; none after a read error.
    fn parse_next(&mut self, language: Language, names: &mut Names) -> Option<Parsed> {
        if self.read_error.is_some() {
            return None;
        }
        // A plain program has no subprogram.
        let no_subprograms = |(stmts, diagnostics)| (stmts, Vec::new(), diagnostics);
        match &mut self.source {
            PartSource::Text { text, at, ranges } => {
                let range = ranges.next()?;
                let (start, spare) = (range.start, &mut self.spare);
                match chunk::parse_plain_chunk(text, range, at, language, names, spare) {
                    Some(parsed) => Some(no_subprograms(parsed)),
                    None => {
                        // The program's end: this part and the rest are
                        // cut where the program allows ([`chunk::cut_part`]).
                        self.source = PartSource::TextCut {
                            text,
                            at,
                            from: start,
                            defined: Vec::new(),
                        };
                        self.parse_next(language, names)
                    }
                }
            }
            PartSource::Reader(reader) => match reader.next_part() {
                Ok(Some((text, at))) => {
                    let range = 0..text.len();
                    let spare = &mut self.spare;
                    match chunk::parse_plain_chunk(&text, range, &at, language, names, spare) {
                        Some(parsed) => Some(no_subprograms(parsed)),
                        None => {
                            // Not plain: this part and the rest are cut
                            // where the program allows (what was parsed of
                            // it is thrown away; nothing of it has run).
                            let PartSource::Reader(reader) =
                                std::mem::replace(&mut self.source, PartSource::Done)
                            else {
                                return None;
                            };
                            let program = ProgramReader::resume(reader, language, text, &at);
                            self.source = PartSource::Program(program);
                            self.parse_next(language, names)
                        }
                    }
                }
                Ok(None) => None,
                Err(e) => {
                    self.read_error = Some(e);
                    None
                }
            },
            PartSource::Done => None,
            PartSource::TextCut { .. } | PartSource::Program(_) if self.whole => None,
            PartSource::TextCut { text, from, .. } if *from >= text.len() => None,
            PartSource::TextCut {
                text,
                at,
                from,
                defined,
            } => {
                match chunk::next_cut(text, *from, at, language, names, defined) {
                    chunk::Cut::Part(end, stmts, subprograms, diagnostics) => {
                        *from = end;
                        Some((stmts, subprograms, diagnostics))
                    }
                    // (`next_cut` never asks to grow: the text is all there.)
                    chunk::Cut::Grow | chunk::Cut::Whole => {
                        self.whole = true;
                        None
                    }
                }
            }
            PartSource::Program(reader) => match reader.next_part(names) {
                Ok(Some(Ok(parsed))) => Some(parsed),
                Ok(Some(Err(Whole))) => {
                    self.whole = true;
                    None
                }
                Ok(None) => None,
                Err(e) => {
                    self.read_error = Some(e);
                    None
                }
            },
        }
    }
}

/// Whole lines of a program, read from a file about
/// [`chunk::CHUNK_BYTES`] at a time and decoded as [`source::decode`]
/// decodes the whole file (a file [`scan_file`] accepted: no NUL, control
/// character or lone CR, so the two agree).
pub(super) struct LineReader<'a> {
    pub(super) reader: &'a mut dyn std::io::BufRead,
    pub(super) file: FileId,
    /// No part read yet (the first may start with a byte-order mark).
    pub(super) first: bool,
    /// Where the next part starts in the decoded file, and its lines before.
    base: usize,
    lines_before: usize,
    /// A [`FileScan::partial`] scan each part is checked against.
    pub(super) check: Option<FileScan>,
    /// Whether a part's decimals are checked against it too: they only
    /// decide how the output is printed (not for a tool path's moves).
    pub(super) printed: bool,
    /// Whether the program is a tape, and closed ([`Tape`]); the decoded
    /// text and lines given out so far, to place what follows its end.
    tape: Tape,
    given: usize,
    lines_given: usize,
    /// The note for what follows a tape's end, once the file is read.
    pub(super) tape_note: Option<Diagnostic>,
}

impl<'a> LineReader<'a> {
    /// The lines of a program in `language` (only plain G-code may be a
    /// tape).
    pub(super) fn new(
        reader: &'a mut dyn std::io::BufRead,
        (file, language): (FileId, Language),
        scan: FileScan,
    ) -> LineReader<'a> {
        LineReader {
            reader,
            file,
            first: true,
            base: 0,
            lines_before: 0,
            check: scan.partial.then_some(scan),
            printed: true,
            tape: match language {
                Language::Gcode => Tape::Unknown,
                Language::Egc => Tape::NotATape,
            },
            given: 0,
            lines_given: 0,
            tape_note: None,
        }
    }

    /// The next part's text and span maker; `None` at the end of the file.
    /// A part is the lines up to the one with its [`chunk::part_size`]th
    /// byte.
    fn next_part(&mut self) -> std::io::Result<Option<(String, Locator)>> {
        let Some(text) = self.next_lines(chunk::part_size())? else {
            return Ok(None);
        };
        let at = Locator::part(self.file, &text, self.base, self.lines_before);
        self.base += text.len();
        self.lines_before += at.line_ends();
        Ok(Some((text, at)))
    }

    /// The next lines, up to the one with the `part`th byte, decoded;
    /// `None` at the end of the file. Read in blocks.
    /// With a [`FileScan::partial`] scan (`check`), each is checked first
    /// as the whole scan would have read it: `Err(`[`Unforeseen`]`)`.
    /// A tape ([`Tape`]) ends at its closing `%` line: nothing from it on
    /// is given; the rest of the file is read for the note.
    fn next_lines(&mut self, part: usize) -> std::io::Result<Option<String>> {
        if self.tape == Tape::Closed {
            return Ok(None);
        }
        let Some(mut text) = self.decoded_lines(part)? else {
            return Ok(None);
        };
        if !self.tape.decided() {
            let mut start = 0;
            while start < text.len() && !self.tape.decided() {
                let end = text[start..]
                    .find('\n')
                    .map_or(text.len(), |i| start + i + 1);
                if self.tape.closes(&text[start..end]) {
                    self.tape_closed(&text, start)?;
                    text.truncate(start);
                    break;
                }
                start = end;
            }
        }
        self.given += text.len();
        self.lines_given += text.bytes().filter(|&b| b == b'\n').count();
        Ok(Some(text))
    }

    /// The tape closes at `text[close..]`'s line: the rest of the file is
    /// read for the note on what is not.
    fn tape_closed(&mut self, text: &str, close: usize) -> std::io::Result<()> {
        let at = Locator::part(self.file, text, self.given, self.lines_given);
        let percent = close + text[close..].find('%').unwrap_or(0);
        let end = at.span(percent, percent + 1);
        let after = text[close..]
            .find('\n')
            .map_or(text.len(), |i| close + i + 1);
        let mut unread = Unread::default();
        unread.add(text, after, &at);
        let (mut base, mut lines) = (self.given + text.len(), self.lines_given + at.line_ends());
        while let Some(more) = self.decoded_lines(chunk::part_size())? {
            let at = Locator::part(self.file, &more, base, lines);
            unread.add(&more, 0, &at);
            base += more.len();
            lines += at.line_ends();
        }
        self.tape_note = unread.note(end).map(|n| n.to_diagnostic());
        Ok(())
    }

    /// The next lines, decoded and checked ([`Self::next_lines`]).
    fn decoded_lines(&mut self, part: usize) -> std::io::Result<Option<String>> {
        let mut bytes = Vec::with_capacity(part + 256);
        if !read_lines(self.reader, part, &mut self.first, &mut bytes)? {
            return Ok(None);
        }
        let unforeseen = || Err(std::io::Error::other(Unforeseen));
        if self.check.is_some() && !streamable_block(&bytes) {
            return unforeseen();
        }
        let text = source::decode_lines(bytes);
        match self.check {
            Some(scan) if self.printed && !scan.prints_as(input_decimals(&text)) => unforeseen(),
            _ => Ok(Some(text)),
        }
    }
}

/// A part's statements and diagnostics.
type Parsed = (
    Vec<crate::ast::Stmt>,
    Vec<crate::ast::Subprogram>,
    Vec<Diagnostic>,
);

/// The program must be read whole ([`chunk::cut_part`]).
pub(super) struct Whole;

/// The parts of a program that is not plain, read from a file as they are
/// needed ([`chunk::cut_part`]): the text from the last cut on is held
/// until the next.
pub(super) struct ProgramReader<'a> {
    pub(super) lines: LineReader<'a>,
    pub(super) language: Language,
    /// The text read from the last cut on, and where it is in the file.
    pub(super) text: String,
    base: usize,
    lines_before: usize,
    /// The file has been read to its end.
    read_all: bool,
    /// The subprograms of the parts read ([`chunk::cut_part`]).
    pub(super) defined: Vec<u32>,
}

impl<'a> ProgramReader<'a> {
    pub(super) fn new(lines: LineReader<'a>, language: Language) -> ProgramReader<'a> {
        ProgramReader {
            lines,
            language,
            text: String::new(),
            base: 0,
            lines_before: 0,
            read_all: false,
            defined: Vec::new(),
        }
    }

    /// Go on from a part `lines` gave as plain (`text`, placed by `at`),
    /// which is not: it is the text read from the last cut on.
    fn resume(
        lines: LineReader<'a>,
        language: Language,
        text: String,
        at: &Locator,
    ) -> ProgramReader<'a> {
        ProgramReader {
            base: lines.base - text.len(),
            lines_before: lines.lines_before - at.line_ends(),
            text,
            ..ProgramReader::new(lines, language)
        }
    }

    /// The next part, parsed into `names`: its statements and diagnostics,
    /// or `Err` if the program must be read whole; `None` at the end of the
    /// file.
    fn next_part(&mut self, names: &mut Names) -> std::io::Result<Option<Result<Parsed, Whole>>> {
        let mut want = chunk::part_size();
        loop {
            while !self.read_all && self.text.len() < want.saturating_mul(2) {
                match self.lines.next_lines(want)? {
                    Some(more) => self.text.push_str(&more),
                    None => self.read_all = true,
                }
            }
            if self.text.is_empty() {
                return Ok(None);
            }
            let (file, complete) = (self.lines.file, self.read_all);
            let at = Locator::part(file, &self.text, self.base, self.lines_before);
            let cut = chunk::cut_part(
                &self.text,
                0,
                want,
                complete,
                &at,
                self.language,
                names,
                &mut self.defined,
            );
            match cut {
                chunk::Cut::Grow => want = want.saturating_mul(2),
                chunk::Cut::Part(end, stmts, subprograms, diagnostics) => {
                    self.base += end;
                    self.lines_before += self.text[..end].bytes().filter(|&b| b == b'\n').count();
                    self.text.drain(..end);
                    return Ok(Some(Ok((stmts, subprograms, diagnostics))));
                }
                chunk::Cut::Whole => return Ok(Some(Err(Whole))),
            }
        }
    }
}
