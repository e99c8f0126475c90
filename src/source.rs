//! Source files and spans. A [`Span`] is a file id, the 1-based line of its
//! start and a byte range; every AST node and IR statement carries one, so
//! an output line's N number needs no lookup. Input bytes become text here
//! ([`decode`]): UTF-8, else Latin-1 per line, and binary input is refused.
//! This module does no I/O: callers hand it the bytes they have read.

use std::sync::Arc;

/// Index of a file in [`Sources`].
pub type FileId = usize;

/// A byte range in one source file, with the line it starts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub file: u32,
    /// 1-based line of `start` (0 for spans made up by the compiler).
    pub line: u32,
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(file: FileId, line: u32, start: usize, end: usize) -> Span {
        Span {
            file: file as u32,
            line,
            start: start as u32,
            end: end as u32,
        }
    }

    pub fn file_id(self) -> FileId {
        self.file as FileId
    }

    /// The smallest span covering both (they must be in the same file).
    pub fn to(self, other: Span) -> Span {
        let first = if other.start < self.start {
            other
        } else {
            self
        };
        Span {
            file: self.file,
            line: first.line,
            start: first.start,
            end: self.end.max(other.end),
        }
    }

    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// Every file the compiler has read: the part program, subroutine files
/// and any wizard scripts whose diagnostics must be shown.
#[derive(Default)]
pub struct Sources {
    files: Vec<SourceFile>,
}

pub struct SourceFile {
    pub name: String,
    pub text: String,
    /// Shared with the parser's [`Locator`]: built once per file.
    lines: Arc<LineIndex>,
    /// Only some lines of the file are held (`text` is them one after
    /// another): those its diagnostics show ([`Sources::set_lines`]).
    some_lines: Option<Vec<HeldLine>>,
}

/// A line of a file held alone: its 1-based number, where it starts in
/// the file, and where its text is in the [`SourceFile`]'s.
struct HeldLine {
    number: usize,
    start: usize,
    text: std::ops::Range<usize>,
}

impl Sources {
    pub fn new() -> Sources {
        Sources::default()
    }

    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        let text = text.into();
        self.files.push(SourceFile {
            name: name.into(),
            lines: Arc::new(LineIndex::new(&text)),
            text,
            some_lines: None,
        });
        self.files.len() - 1
    }

    /// The span maker of a file, on the line index built when it was added.
    pub fn locator(&self, file: FileId) -> Locator {
        Locator {
            file,
            lines: self
                .files
                .get(file)
                .map_or_else(|| Arc::new(LineIndex::new("")), |f| Arc::clone(&f.lines)),
            base: 0,
            lines_before: 0,
        }
    }

    /// Give `file` its text (a file compiled from a reader, read again to
    /// show its diagnostics).
    pub fn set_text(&mut self, file: FileId, text: String) {
        if let Some(f) = self.files.get_mut(file) {
            f.lines = Arc::new(LineIndex::new(&text));
            f.text = text;
            f.some_lines = None;
        }
    }

    /// Give `file` some of its lines only (a file compiled from a reader,
    /// read again for the lines its diagnostics show: memory grows with
    /// them, not with the file): each its 1-based number, the byte offset
    /// it starts at, and its text without its line end, in order.
    pub fn set_lines(&mut self, file: FileId, lines: Vec<(usize, usize, String)>) {
        let Some(f) = self.files.get_mut(file) else {
            return;
        };
        let (mut text, mut held) = (String::new(), Vec::with_capacity(lines.len()));
        for (number, start, line) in lines {
            let at = text.len();
            text.push_str(&line);
            held.push(HeldLine {
                number,
                start,
                text: at..text.len(),
            });
            text.push('\n');
        }
        f.lines = Arc::new(LineIndex::new(""));
        f.text = text;
        f.some_lines = Some(held);
    }

    pub fn text(&self, file: FileId) -> &str {
        self.files.get(file).map_or("", |f| f.text.as_str())
    }

    pub fn name(&self, file: FileId) -> &str {
        self.files.get(file).map_or("?", |f| f.name.as_str())
    }

    pub fn get(&self, file: FileId) -> Option<&SourceFile> {
        self.files.get(file)
    }
}

impl SourceFile {
    /// The byte range of a 1-based line, without its line end.
    pub fn line_range(&self, line: usize) -> std::ops::Range<usize> {
        self.lines.range(line, &self.text)
    }

    /// 1-based line of a byte offset. Of a file with some lines held, the
    /// last held line that starts at or before it.
    pub fn line_of(&self, offset: usize) -> usize {
        match &self.some_lines {
            Some(held) => {
                let after = held.partition_point(|l| l.start <= offset);
                held.get(after.wrapping_sub(1)).map_or(1, |l| l.number)
            }
            None => self.lines.line(offset as u32),
        }
    }

    /// A 1-based line: the byte offset it starts at in the file, and its
    /// text without its line end (empty for a line not held).
    pub fn line_text(&self, line: usize) -> (usize, &str) {
        match &self.some_lines {
            Some(held) => held
                .iter()
                .find(|l| l.number == line)
                .map_or((0, ""), |l| (l.start, &self.text[l.text.clone()])),
            None => {
                let range = self.line_range(line);
                (range.start, &self.text[range])
            }
        }
    }
}

/// Makes the spans of one file: byte ranges with their line. The text it
/// is given may be a part of the file (read a part at a time): offsets in
/// it are then moved by the part's place.
pub struct Locator {
    file: FileId,
    lines: Arc<LineIndex>,
    /// Where the text starts in the file, and the lines before it.
    base: usize,
    lines_before: usize,
}

impl Locator {
    pub fn new(file: FileId, text: &str) -> Locator {
        Locator::part(file, text, 0, 0)
    }

    /// For `text`, the part of the file `file` that starts at byte `base`
    /// after `lines_before` lines.
    pub fn part(file: FileId, text: &str, base: usize, lines_before: usize) -> Locator {
        Locator {
            file,
            lines: Arc::new(LineIndex::new(text)),
            base,
            lines_before,
        }
    }

    pub fn file(&self) -> FileId {
        self.file
    }

    /// How many line ends the text has.
    pub fn line_ends(&self) -> usize {
        self.lines.line_ends()
    }

    /// Where each line of the text starts: 0, then after each line end.
    pub fn line_starts(&self) -> &[u32] {
        &self.lines.starts
    }

    pub fn span(&self, start: usize, end: usize) -> Span {
        let line = self.lines_before + self.lines.line(start as u32);
        self.span_on_line(line as u32, start, end)
    }

    /// Where the text's byte `at` is in the file.
    #[inline]
    pub fn offset(&self, at: usize) -> u32 {
        (self.base + at) as u32
    }

    /// [`Locator::span`] when its (1-based) line in the file is known.
    pub fn span_on_line(&self, line: u32, start: usize, end: usize) -> Span {
        Span::new(self.file, line, self.base + start, self.base + end)
    }
}

/// The bytes the scans test at once: a bit each in a `u64` ([`marks_of`]).
pub(crate) const BLOCK: usize = 64;

/// Call `found` with the offset of every `byte` in `bytes`, in order, a
/// block of [`BLOCK`] bytes at a time ([`marks_of`]).
#[inline]
pub(crate) fn each_byte(bytes: &[u8], byte: u8, mut found: impl FnMut(usize)) {
    let (blocks, rest) = bytes.as_chunks::<BLOCK>();
    let mut at = 0;
    for block in blocks {
        let mut marks = marks_of(block, byte);
        while marks != 0 {
            found(at + marks.trailing_zeros() as usize);
            marks &= marks - 1;
        }
        at += BLOCK;
    }
    for (i, &b) in rest.iter().enumerate() {
        if b == byte {
            found(at + i);
        }
    }
}

/// A bit for each byte of `block` that is `byte`, the first the lowest.
/// The comparison is a loop LLVM makes vector instructions (a 1 or a 0 a
/// byte); each eight of those bytes are gathered into eight bits by one
/// multiplication: the byte `i` (0 or 1) times the multiplier's byte `7 -
/// i` (`0x80 >> (7 - i)`) lands on bit `i` of the top byte, and no sum
/// carries.
#[inline]
fn marks_of(block: &[u8; BLOCK], byte: u8) -> u64 {
    let mut ones = [0u8; BLOCK];
    for (one, &b) in ones.iter_mut().zip(block) {
        *one = u8::from(b == byte);
    }
    let (eights, _) = ones.as_chunks::<8>();
    let mut marks = 0;
    for (k, eight) in eights.iter().enumerate() {
        let gathered = u64::from_le_bytes(*eight).wrapping_mul(0x0102_0408_1020_4080) >> 56;
        marks |= gathered << (8 * k);
    }
    marks
}

/// Line starts of one text.
pub struct LineIndex {
    starts: Vec<u32>,
}

impl LineIndex {
    pub fn new(text: &str) -> LineIndex {
        // Room for lines of 16 bytes: most programs' lines are longer.
        let mut starts = Vec::with_capacity(text.len() / 16 + 1);
        starts.push(0);
        // A block of 64 bytes at a time: a line is about a third of one.
        each_byte(text.as_bytes(), b'\n', |at| starts.push(at as u32 + 1));
        LineIndex { starts }
    }

    /// How many line ends the text has.
    pub fn line_ends(&self) -> usize {
        self.starts.len() - 1
    }

    /// 1-based line of a byte offset.
    pub fn line(&self, offset: u32) -> usize {
        match self.starts.binary_search(&offset) {
            Ok(i) => i + 1,
            Err(i) => i,
        }
    }

    /// The byte range of a 1-based line, without its `\n` (or `\r\n`).
    pub fn range(&self, line: usize, text: &str) -> std::ops::Range<usize> {
        let i = line.saturating_sub(1).min(self.starts.len() - 1);
        let start = self.starts[i] as usize;
        let mut end = self
            .starts
            .get(i + 1)
            .map_or(text.len(), |&s| s as usize - 1);
        if end > start && text.as_bytes().get(end - 1) == Some(&b'\r') {
            end -= 1;
        }
        start..end.max(start)
    }
}

/// Why bytes are not a program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotText {
    /// A NUL byte at this offset: a binary file.
    Nul(usize),
    /// Control bytes no text editor writes, at this offset.
    Control(usize),
}

/// The text of a source file: UTF-8 as it is; a line that is not UTF-8 is
/// read as Latin-1 (old controllers and editors write it), so a comment
/// with `°` survives. A byte-order mark is dropped, a lone CR (old Mac
/// line ends) becomes LF, and a DOS end-of-file `^Z` with anything after
/// it is dropped, as are NUL bytes that only pad the file's end (a
/// transfer in blocks leaves them). NUL bytes elsewhere or other control
/// characters mean the file is not text: refused before any parsing.
/// Every span refers to this text.
pub fn decode(mut bytes: Vec<u8>) -> Result<String, NotText> {
    drop_bom(&mut bytes);
    if let Some(eof) = bytes.iter().position(|&b| b == 0x1a) {
        if bytes[eof + 1..].iter().all(|b| b.is_ascii_whitespace()) {
            bytes.truncate(eof);
        }
    }
    // One pass: a NUL anywhere says "binary" before any other control
    // byte, unless it starts the padding of a text's end.
    let (mut control, mut padding) = (None, None);
    for (at, &b) in bytes.iter().enumerate() {
        match b {
            0 if is_padding(&bytes, at) => {
                padding = Some(at);
                break;
            }
            0 => return Err(NotText::Nul(at)),
            b'\n' | b'\r' | b'\t' | 0x0c => {}
            _ if b < 0x20 => {
                control.get_or_insert(at);
            }
            _ => {}
        }
    }
    if let Some(pad) = padding {
        bytes.truncate(pad);
    }
    if let Some(at) = control {
        return Err(NotText::Control(at));
    }
    // A lone CR is a line end (same length: offsets do not move).
    if bytes.contains(&b'\r') {
        for i in 0..bytes.len() {
            if bytes[i] == b'\r' && bytes.get(i + 1) != Some(&b'\n') {
                bytes[i] = b'\n';
            }
        }
    }
    Ok(decode_lines(bytes))
}

/// Whether the NUL at `at` only pads the end of a text: NULs and blanks
/// from it on, and text before it (a file of NULs alone is no program).
fn is_padding(bytes: &[u8], at: usize) -> bool {
    bytes[at..]
        .iter()
        .all(|&b| b == 0 || b.is_ascii_whitespace())
        && bytes[..at].iter().any(|b| !b.is_ascii_whitespace())
}

/// Clean bytes as text: UTF-8 when they all are, else each line as UTF-8
/// or Latin-1 ([`decode_line`]).
pub fn decode_lines(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| {
        let bytes = e.into_bytes();
        let mut text = String::with_capacity(bytes.len() + bytes.len() / 8);
        for line in bytes.split_inclusive(|&b| b == b'\n') {
            text.push_str(&decode_line(line));
        }
        text
    })
}

/// The UTF-8 byte-order mark, dropped where a file starts with it.
pub const BOM: &[u8] = b"\xef\xbb\xbf";

/// Drop the byte-order mark `bytes` (a file's start) begins with, if any.
pub fn drop_bom(bytes: &mut Vec<u8>) {
    if bytes.starts_with(BOM) {
        bytes.drain(..BOM.len());
    }
}

/// One line as UTF-8, else as Latin-1 ([`decode`]'s rule for each line).
pub fn decode_line(line: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(line) {
        Ok(s) => std::borrow::Cow::Borrowed(s),
        Err(_) => std::borrow::Cow::Owned(line.iter().map(|&b| b as char).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact for every byte next to every other, in the blocks and in
    /// the rest after them.
    #[test]
    fn each_byte_finds_exactly_the_bytes_equal() {
        for byte in 0..=255u8 {
            for other in 0..=255u8 {
                let eight = [
                    other,
                    byte,
                    other ^ 0x80,
                    byte,
                    0,
                    255,
                    byte.wrapping_add(1),
                    other,
                ];
                // Two blocks, and seven bytes after them.
                let bytes: Vec<u8> = eight.iter().copied().cycle().take(64 * 2 + 7).collect();
                let mut found = Vec::new();
                each_byte(&bytes, byte, |at| found.push(at));
                let expected: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] == byte).collect();
                assert_eq!(found, expected, "{byte} {other}");
            }
        }
    }

    #[test]
    fn line_starts_are_after_every_line_end() {
        let mut random = crate::test_random::Random::new(0x9e37_79b9_7f4a_7c15);
        for len in 0..200 {
            // Bytes next to `\n` in value too (`\x0b`, `\x09`, `\x8a`).
            let text: String = (0..len)
                .map(|_| ['\n', '\x0b', '\t', 'a', '\u{8a}', ' '][random.below(6) as usize])
                .collect();
            let expected: Vec<u32> = std::iter::once(0)
                .chain(
                    text.bytes()
                        .enumerate()
                        .filter(|&(_, b)| b == b'\n')
                        .map(|(i, _)| i as u32 + 1),
                )
                .collect();
            assert_eq!(LineIndex::new(&text).starts, expected, "{text:?}");
        }
    }

    #[test]
    fn latin1_lines_survive_and_utf8_stays() {
        let bytes = b"G0 X1 (25\xb0)\nG1 Y2 (\xc3\xa9)\n";
        assert_eq!(decode(bytes.to_vec()).unwrap(), "G0 X1 (25°)\nG1 Y2 (é)\n");
    }

    #[test]
    fn cr_line_ends_and_bom() {
        assert_eq!(
            decode(b"\xef\xbb\xbfG0\rG1\r\nG2".to_vec()).unwrap(),
            "G0\nG1\r\nG2"
        );
    }

    #[test]
    fn binary_is_refused_and_ctrl_z_ends_the_file() {
        assert_eq!(decode(b"G0\x00X1".to_vec()), Err(NotText::Nul(2)));
        assert_eq!(decode(b"G0 X1\n\x1a".to_vec()).unwrap(), "G0 X1\n");
        assert_eq!(decode(b"G0\x01".to_vec()), Err(NotText::Control(2)));
    }

    /// NUL bytes that only pad the end of a text go (a real file: `%`, the
    /// program, `%`, then NULs); with text after them, or none before,
    /// the file is still not text.
    #[test]
    fn nul_padding_at_the_end_is_dropped() {
        let padded = b"%\nG0 X1\nM30\n%\n\x00\x00".to_vec();
        assert_eq!(decode(padded).unwrap(), "%\nG0 X1\nM30\n%\n");
        assert_eq!(decode(b"G0 X1\n\x00\n\x00 ".to_vec()).unwrap(), "G0 X1\n");
        assert_eq!(decode(b"G0 X1\n\x00\x00G1".to_vec()), Err(NotText::Nul(6)));
        assert_eq!(decode(b"\n\x00\x00".to_vec()), Err(NotText::Nul(1)));
    }

    #[test]
    fn line_ranges_drop_line_ends() {
        let text = "ab\r\ncd\nef";
        let index = LineIndex::new(text);
        assert_eq!(&text[index.range(1, text)], "ab");
        assert_eq!(&text[index.range(2, text)], "cd");
        assert_eq!(&text[index.range(3, text)], "ef");
        assert_eq!(index.line(5), 2);
    }
}
