//! What a file's bytes say before it is compiled: whether it can be
//! compiled from the file a part at a time ([`FileScan`]), how many
//! decimals its coordinates carry, its lines read again to show
//! diagnostics. Reads only from the readers it is handed.

use super::fs::FileSystem;
use super::options::Clue;
use crate::diagnostic::Diagnostic;
use crate::ir;
use crate::source::{self, FileId, BLOCK};
use crate::syntax::chunk;
use std::io::Seek;
use std::path::Path;

/// A file's whole lines as bytes, about [`chunk::CHUNK_BYTES`] of them at a
/// time (the first without a byte-order mark), for [`scan_file`].
struct RawBlocks<'a> {
    pub(super) reader: &'a mut dyn std::io::BufRead,
    pub(super) first: bool,
    block: Vec<u8>,
}

impl<'a> RawBlocks<'a> {
    pub(super) fn new(reader: &'a mut dyn std::io::BufRead) -> RawBlocks<'a> {
        RawBlocks {
            reader,
            first: true,
            block: Vec::new(),
        }
    }

    /// The lines of a file from a line after its first (no byte-order mark).
    fn after_start(reader: &'a mut dyn std::io::BufRead) -> RawBlocks<'a> {
        RawBlocks {
            first: false,
            ..RawBlocks::new(reader)
        }
    }

    /// The next lines with their line ends; `None` at the end of the file.
    pub(super) fn next(&mut self) -> std::io::Result<Option<&[u8]>> {
        self.block.clear();
        let read = read_lines(
            self.reader,
            chunk::CHUNK_BYTES,
            &mut self.first,
            &mut self.block,
        )?;
        Ok(read.then_some(&self.block[..]))
    }
}

/// Append to `bytes` the next lines of `reader`, up to the one with the
/// `want`th byte; the first lines of a file (`first`) without a byte-order
/// mark. `false` at the end of the file.
pub(super) fn read_lines(
    reader: &mut dyn std::io::BufRead,
    want: usize,
    first: &mut bool,
    bytes: &mut Vec<u8>,
) -> std::io::Result<bool> {
    let start = bytes.len();
    while bytes.len() - start < want {
        let block = reader.fill_buf()?;
        if block.is_empty() {
            break;
        }
        let take = block.len().min(want - (bytes.len() - start));
        bytes.extend_from_slice(&block[..take]);
        reader.consume(take);
    }
    if bytes.len() == start {
        return Ok(false);
    }
    if !bytes.ends_with(b"\n") {
        reader.read_until(b'\n', bytes)?;
    }
    if std::mem::take(first) {
        source::drop_bom(bytes);
    }
    Ok(true)
}

/// A program that can be compiled from a reader, a part at a time, without
/// holding its text: its decoded length and the most decimals its numbers
/// are written with ([`input_decimals`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileScan {
    pub len: usize,
    pub decimals: usize,
    /// Found from the file's first lines only ([`first_look`]; `len` is
    /// then the file's size): each part read after them is checked as it
    /// is read, and one the scan of the whole file would have answered
    /// otherwise stops the compile ([`Streamed::Rescan`]).
    pub partial: bool,
    /// What the file's first lines say of its controller ([`clue`]).
    pub clue: Option<Clue>,
    /// The O number the program starts with ([`program_number`]).
    pub program_number: Option<u32>,
}

/// The bytes at the start of a file [`clue`] looks at (with the rest of
/// the line they end in): less than a part, so that a file read in parts
/// and one read whole say the same.
const CLUE_BYTES: usize = 4096;

/// What the lines holding a file's first [`CLUE_BYTES`] say of its
/// controller.
pub fn clue(text: &str) -> Option<Clue> {
    let cut = text
        .as_bytes()
        .get(CLUE_BYTES..)
        .map_or(text.len(), |rest| {
            rest.iter()
                .position(|&b| b == b'\n')
                .map_or(text.len(), |at| CLUE_BYTES + at)
        });
    let head = text.get(..cut).unwrap_or(text);
    let lines = head.lines().map(str::trim).filter(|l| !l.is_empty());
    let tape = lines.clone().next().is_some_and(|l| l.starts_with('%'));
    let mut program_number = false;
    let mut macro_b = false;
    for line in lines {
        let bytes = line.as_bytes();
        if let [b'$', b'H' | b'h', ..] | [b'$', b'J' | b'j', b'=', ..] = bytes {
            return Some(Clue::GrblCommand);
        }
        if let [b'O' | b'o' | b':', d, ..] = bytes {
            program_number |= d.is_ascii_digit();
        }
        macro_b = macro_b || is_macro_b(line);
    }
    match (tape && program_number, macro_b) {
        (true, _) => Some(Clue::FanucTape),
        (false, true) => Some(Clue::MacroB),
        (false, false) => None,
    }
}

/// The program's own number: an `O1234` (or `:1234`) line before any
/// other words, after `%` lines and comments (a Fanuc program's head).
pub fn program_number(text: &str) -> Option<u32> {
    let lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    for line in lines {
        if line.starts_with(['%', '(', ';']) {
            continue;
        }
        let rest = line.strip_prefix(['O', 'o', ':'])?;
        let digits = rest
            .find(|c: char| !c.is_ascii_digit())
            .map_or(rest, |end| &rest[..end]);
        let after = rest[digits.len()..].trim_start();
        let alone = after.is_empty() || after.starts_with(['(', ';']);
        return (alone && !digits.is_empty())
            .then(|| digits.parse().ok())
            .flatten()
            .filter(|&n| n < 10_000);
    }
    None
}

/// A line of Fanuc's Macro B (SPEC §2.8): `IF [`, `WHILE [`, `GOTO n`
/// first (after a block delete and an N label), or a `G65` word. LinuxCNC
/// writes its control flow with o-words, so no program of its has one.
fn is_macro_b(line: &str) -> bool {
    let code: String = line
        .split(['(', ';'])
        .next()
        .unwrap_or("")
        .chars()
        .filter(|c| !c.is_ascii_whitespace())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    let body = code.trim_start_matches('/');
    let body = match body.strip_prefix('N') {
        Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit()),
        None => body,
    };
    let control = ["IF[", "WHILE[", "GOTO"]
        .iter()
        .any(|k| body.starts_with(k));
    control || has_g65(body)
}

/// A `G65` word among a line's plain words (those before any `#` or `[`).
fn has_g65(code: &str) -> bool {
    let plain = code.split(['#', '[']).next().unwrap_or("");
    let mut rest = plain;
    while let Some(at) = rest.find('G') {
        let after = &rest[at + 1..];
        let len = after
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(after.len());
        if after[..len].parse::<f64>() == Ok(65.0) {
            return true;
        }
        rest = &after[len..];
    }
    false
}

impl FileScan {
    /// Whether a file that also has numbers with `decimals` is printed as
    /// this one ([`grid_decimals`], in either units).
    pub(super) fn prints_as(&self, decimals: usize) -> bool {
        let most = self.decimals.max(decimals);
        [Some(ir::Units::Mm), Some(ir::Units::Inch)]
            .into_iter()
            .all(|units| grid_decimals(most, units) == grid_decimals(self.decimals, units))
    }
}

/// The output's decimals for an input whose numbers have `most` at most
/// (SPEC §6): as many, at least 3 for mm and 4 for inch (or units not
/// stated), at most 6.
pub(super) fn grid_decimals(most: usize, units: Option<ir::Units>) -> usize {
    let least = match units {
        Some(ir::Units::Mm) => 3,
        Some(ir::Units::Inch) | None => 4,
    };
    most.clamp(least, 6)
}

/// The bytes [`first_look`] reads of a file larger than this: its whole
/// lines up to about 256 KB (a 200,000-move program is 5 MB).
const FIRST_LOOK: u64 = 1 << 18;

/// [`scan_path`] of the file's first lines only (all of a file up to
/// [`FIRST_LOOK`] bytes): the compile then reads the file once, not twice,
/// and checks each part against the answer as it reads it. A program from
/// CAM writes its numbers with as many decimals throughout; one with more
/// further on is compiled again, after the whole scan.
pub fn first_look(fs: &dyn FileSystem, path: &Path) -> std::io::Result<Option<FileScan>> {
    first_look_within(fs, path, FIRST_LOOK)
}

/// [`first_look`] with `most` bytes for [`FIRST_LOOK`] (for the tests: the
/// first block, about 16 KB of lines, is always read).
pub fn first_look_within(
    fs: &dyn FileSystem,
    path: &Path,
    most: u64,
) -> std::io::Result<Option<FileScan>> {
    let mut reader = fs.open(path)?;
    let size = reader.seek(std::io::SeekFrom::End(0))?;
    if size <= most {
        return scan_path(fs, path);
    }
    reader.rewind()?;
    let scan = scan_blocks(RawBlocks::new(&mut reader), most as usize)?;
    Ok(scan.map(|scan| FileScan {
        len: size as usize,
        partial: true,
        ..scan
    }))
}

/// The error a [`LineReader`] stops with at a part that does not hold to
/// a [`FileScan::partial`] scan.
#[derive(Debug)]
pub(super) struct Unforeseen;

impl std::fmt::Display for Unforeseen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the file is not as its first lines said")
    }
}

impl std::error::Error for Unforeseen {}

/// Every line of the file `reader` reads, decoded as [`compile_file`]
/// decodes it (its spans are offsets into these lines): `each` is given
/// its 1-based number, its bytes (its line end included) and its text
/// without its line end. Read a part at a time: nothing but the part is
/// held.
pub fn each_line(
    reader: &mut dyn std::io::BufRead,
    each: &mut dyn FnMut(usize, std::ops::Range<usize>, &str),
) -> std::io::Result<()> {
    let mut blocks = RawBlocks::new(reader);
    let (mut number, mut start) = (1, 0);
    // After a line end (or in an empty file) an empty line follows, as in
    // a text's line index.
    let mut ended = true;
    while let Some(bytes) = blocks.next()? {
        let text = source::decode_lines(bytes.to_vec());
        for line in text.split_inclusive('\n') {
            let shown = line.strip_suffix('\n').unwrap_or(line);
            ended = shown.len() < line.len();
            let bytes = start..start + line.len();
            each(number, bytes, shown.strip_suffix('\r').unwrap_or(shown));
            number += 1;
            start += line.len();
        }
    }
    if ended {
        each(number, start..start, "");
    }
    Ok(())
}

/// The lines of file `file` that `diagnostics` show, read a part at a time
/// from `reader` (memory grows with the lines, not with the
/// file), as [`Sources::set_lines`] takes them: the lines each
/// label covers, at most 21 from its first, as the diagnostics' excerpts
/// take them ([`crate::diagnostic::render`]), and the line after each
/// (shown between two labelled lines one apart).
pub fn lines_shown(
    reader: &mut dyn std::io::BufRead,
    file: FileId,
    diagnostics: &[Diagnostic],
) -> std::io::Result<Vec<(usize, usize, String)>> {
    // Each label's first and last byte.
    let labels: Vec<(usize, usize)> = diagnostics
        .iter()
        .flat_map(|d| &d.labels)
        .filter(|label| label.file_id == file)
        .map(|label| {
            (
                label.range.start,
                label.range.end.max(label.range.start + 1) - 1,
            )
        })
        .collect();
    let mut first_lines: Vec<Option<usize>> = vec![None; labels.len()];
    let mut lines = Vec::new();
    // The line after one shown is shown too; the last line read is kept
    // (its text's room used again) for a label past the end.
    let (mut after, mut last) = (false, (0, 0, String::new()));
    each_line(reader, &mut |number, bytes, text| {
        let mut holds = false;
        for ((from, to), first) in labels.iter().zip(&mut first_lines) {
            if *from < bytes.end && bytes.start <= *to {
                holds |= *first.get_or_insert(number) + 20 >= number;
            }
        }
        if holds || std::mem::take(&mut after) {
            lines.push((number, bytes.start, text.to_string()));
        }
        after = holds;
        (last.0, last.1) = (number, bytes.start);
        last.2.clear();
        last.2.push_str(text);
    })?;
    // The last line holds every offset from its start on (the end of the
    // file, after a last line with no line end).
    let past_the_end =
        |((from, _), first): (&(usize, usize), &Option<usize>)| first.is_none() && *from >= last.1;
    let shown = lines
        .last()
        .is_some_and(|l: &(usize, usize, String)| l.0 == last.0);
    if labels.iter().zip(&first_lines).any(past_the_end) && !shown {
        lines.push(last);
    }
    Ok(lines)
}

/// Read a program through once: whether it can be compiled a part at a
/// time from a reader ([`compile_file`]): it has no NUL, control character
/// or lone CR (which [`crate::source::decode`] reports or rewrites).
/// `None`: read it whole.
pub fn scan_file(reader: &mut dyn std::io::BufRead) -> std::io::Result<Option<FileScan>> {
    scan_lines(RawBlocks::new(reader))
}

/// [`scan_file`] of the file at `path`, its two halves (cut at a line end)
/// read at the same time on two threads.
pub fn scan_path(fs: &dyn FileSystem, path: &Path) -> std::io::Result<Option<FileScan>> {
    use std::io::{BufRead, Read};
    let open = || fs.open(path);
    let mut second = open()?;
    let middle = second.seek(std::io::SeekFrom::End(0))? / 2;
    second.seek(std::io::SeekFrom::Start(middle))?;
    // The first half ends with the line the middle is on.
    let cut = middle + second.read_until(b'\n', &mut Vec::new())? as u64;
    let scan_first = move || scan_lines(RawBlocks::new(&mut open()?.take(cut)));
    let (first, second) = std::thread::scope(|scope| {
        let first = std::thread::Builder::new().spawn_scoped(scope, scan_first);
        let second = scan_lines(RawBlocks::after_start(&mut second));
        let first = match first {
            Ok(thread) => thread
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            // No second thread: one after the other.
            Err(_) => scan_first(),
        };
        (first, second)
    });
    Ok(match (first?, second?) {
        (Some(a), Some(b)) => Some(FileScan {
            len: a.len + b.len,
            decimals: a.decimals.max(b.decimals),
            partial: false,
            clue: a.clue,
            program_number: a.program_number,
        }),
        _ => None,
    })
}

/// [`scan_file`] of the lines `lines` reads.
fn scan_lines(blocks: RawBlocks<'_>) -> std::io::Result<Option<FileScan>> {
    scan_blocks(blocks, usize::MAX)
}

/// Whether whole lines of a file have no control character and no CR
/// that is not before a LF (even at the end), which is a line end to
/// `decode`: what [`scan_file`] asks of each.
pub(super) fn streamable_block(bytes: &[u8]) -> bool {
    // First one look for both (a CR before a LF is looked at again).
    // (Folded without a stop at the first: it vectorises.)
    let odd = |b: u8| b < 0x20 && b != b'\n' && b != b'\t';
    if bytes.iter().fold(false, |found, &b| found | odd(b)) {
        let control = bytes.iter().any(|&b| odd(b) && b != b'\r');
        let mut at = bytes.iter().enumerate();
        let lone_cr = at.any(|(i, &b)| b == b'\r' && bytes.get(i + 1) != Some(&b'\n'));
        if control || lone_cr {
            return false;
        }
    }
    true
}

/// [`scan_lines`] of the blocks of `blocks` until `most` bytes are read
/// (the block that passes it included).
fn scan_blocks(mut blocks: RawBlocks<'_>, most: usize) -> std::io::Result<Option<FileScan>> {
    let (mut len, mut decimals) = (0, 0);
    let mut head = None;
    let starts = blocks.first;
    while let Some(bytes) = blocks.next()? {
        if !streamable_block(bytes) {
            return Ok(None);
        }
        // Whole lines: UTF-8 as a whole, else line by line.
        let latin1;
        let text = match std::str::from_utf8(bytes) {
            Ok(text) => text,
            Err(_) => {
                latin1 = source::decode_lines(bytes.to_vec());
                &latin1
            }
        };
        decimals = decimals.max(input_decimals(text));
        if starts && head.is_none() {
            head = Some((clue(text), program_number(text)));
        }
        len += text.len();
        if len >= most {
            break;
        }
    }
    Ok(Some(FileScan {
        len,
        decimals,
        partial: false,
        clue: head.and_then(|h| h.0),
        program_number: head.and_then(|h| h.1),
    }))
}

/// The letters of coordinate words, either case: X Y Z I J K R and the
/// other axes A B C U V W.
const COORDINATE: [bool; 256] = {
    let mut table = [false; 256];
    let letters = b"XYZIJKRABCUVWxyzijkrabcuvw";
    let mut i = 0;
    while i < letters.len() {
        table[letters[i] as usize] = true;
        i += 1;
    }
    table
};

/// The most decimals any coordinate word (X Y Z I J K R, and the other
/// axes) of the source has: the digits after a point that follows a
/// coordinate letter, blanks and signs, and digits (`X-1.25`, `y .5`,
/// `X - + 1.1234`). A word inside a comment counts too, which can only add
/// precision. A block of 64 bytes at a time: its points are looked at only
/// when one has digits both `most` and `most + 1` bytes after it (one
/// after it while `most` is 0), else none has more than `most` decimals.
/// (LLVM makes the test of a block a few vector instructions; looking at
/// the digit `most` after a point as well leaves out `I2.5 J0`.)
pub(super) fn input_decimals(text: &str) -> usize {
    let bytes = text.as_bytes();
    let mut most = 0;
    let mut at = 0;
    // Each block from `at` beside the blocks `most` (at least one) and
    // `most + 1` bytes after it; again from where `most` grew.
    'blocks: while let (Some(from), Some(near), Some(far)) = (
        bytes.get(at..),
        bytes.get(at + most.max(1)..),
        bytes.get(at + most + 1..),
    ) {
        let (blocks, _) = from.as_chunks::<BLOCK>();
        let (nears, _) = near.as_chunks::<BLOCK>();
        let (fars, _) = far.as_chunks::<BLOCK>();
        for ((block, near), far) in blocks.iter().zip(nears).zip(fars) {
            if may_have_more_decimals(block, near, far) {
                let before = most;
                source::each_byte(block, b'.', |i| more_decimals(bytes, at + i, &mut most));
                if most != before {
                    at += BLOCK;
                    continue 'blocks;
                }
            }
            at += BLOCK;
        }
        break;
    }
    for p in at..bytes.len() {
        if bytes[p] == b'.' {
            more_decimals(bytes, p, &mut most);
        }
    }
    most
}

/// Whether a byte of `block` is a point with a digit at its place in
/// `near` and in `far`: folded without a stop, so that it vectorises.
fn may_have_more_decimals(block: &[u8; BLOCK], near: &[u8; BLOCK], far: &[u8; BLOCK]) -> bool {
    let digit = |b: u8| u8::from(b.wrapping_sub(b'0') < 10);
    let mut found = 0;
    for i in 0..BLOCK {
        found |= u8::from(block[i] == b'.') & digit(near[i]) & digit(far[i]);
    }
    found != 0
}

/// Make `most` the decimals of the point at `bytes[p]` if it has more and
/// is a coordinate word's. (Apart: it is seldom called, and inlined it
/// takes the registers of the loop that calls it.)
#[inline(never)]
fn more_decimals(bytes: &[u8], p: usize, most: &mut usize) {
    if !bytes.get(p + *most + 1).is_some_and(u8::is_ascii_digit) {
        return;
    }
    let decimals = bytes[p + 1..]
        .iter()
        .position(|b| !b.is_ascii_digit())
        .unwrap_or(bytes.len() - p - 1);
    if decimals > *most && in_coordinate_word(bytes, p) {
        *most = decimals;
    }
}

/// Whether the point at `bytes[p]` is a coordinate word's: before it,
/// digits, then blanks and signs, then a coordinate letter (what reading
/// forward from the letter over them would reach).
fn in_coordinate_word(bytes: &[u8], p: usize) -> bool {
    let before = &bytes[..p];
    let digits = before
        .iter()
        .rev()
        .take_while(|b| b.is_ascii_digit())
        .count();
    let before = &before[..p - digits];
    let blanks = before
        .iter()
        .rev()
        .take_while(|b| matches!(b, b' ' | b'\t' | b'+' | b'-'))
        .count();
    let before = &before[..before.len() - blanks];
    before.last().is_some_and(|&b| COORDINATE[usize::from(b)])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`input_decimals`] as one pass forward from each coordinate letter
    /// reads it: blanks and signs, digits, a point, the decimals.
    fn decimals_read_forward(text: &str) -> usize {
        let bytes = text.as_bytes();
        let (mut most, mut i) = (0, 0);
        while i < bytes.len() {
            i += 1;
            if !COORDINATE[usize::from(bytes[i - 1])] {
                continue;
            }
            while i < bytes.len() && matches!(bytes[i], b' ' | b'\t' | b'+' | b'-') {
                i += 1;
            }
            while i < bytes.len() && bytes[i].is_ascii_digit() {
                i += 1;
            }
            if i < bytes.len() && bytes[i] == b'.' {
                i += 1;
                let start = i;
                while i < bytes.len() && bytes[i].is_ascii_digit() {
                    i += 1;
                }
                most = most.max(i - start);
            }
        }
        most
    }

    proptest::proptest! {
        #[test]
        fn decimals_found_from_the_points_are_those_read_forward(
            text in r"[XxYyGgRrNn0-9 \t.+\-(\n]{0,400}"
        ) {
            proptest::prop_assert_eq!(input_decimals(&text), decimals_read_forward(&text));
        }
    }

    /// A file with a control character or a CR not before a LF is read
    /// whole (`decode` reports or rewrites them); tabs and CRLF are not.
    #[test]
    fn the_scan_refuses_control_characters_and_lone_crs() {
        for (bytes, streamed) in [
            (&b"G1 X1\tY2\r\nM30\r\n"[..], true),
            (b"G1 X1\nM30", true),
            (b"G1 X1\x01\nM30\n", false),
            (b"G1 X1\x00\nM30\n", false),
            (b"G1 X1\x0c\nM30\n", false),
            (b"G1 X1\x1f\r\nM30\r\n", false),
            (b"G1 X1\rM30\n", false),
            (b"G1 X1\r\nM30\r", false),
            (b"G1 X1\r\r\nM30\n", false),
        ] {
            let scan = scan_file(&mut &bytes[..]).ok().flatten();
            assert_eq!(scan.is_some(), streamed, "{bytes:?}");
        }
    }

    #[test]
    fn decimals_are_those_of_coordinate_words() {
        for (text, most) in [
            ("G1 X1.234 Y-0.5 Z+.25", 3),
            ("G1 F100.12345 X1.5", 1),
            ("N10.5 G1.25 P0.75", 0),
            ("X - + 1.1234", 4),
            ("X-5-3.21", 0),
            ("XX.5", 1),
            ("X1.2.345", 1),
            ("x.25 i-1.125", 3),
            ("(Y1.123456) G1 X1", 6),
            (".5 1.25", 0),
            ("X.", 0),
            ("", 0),
            ("X12345678.123456789", 9),
            ("G1 X1.5 Y2.25 (a longer line, past eight bytes) Z3.125", 3),
            ("Y1.5\nG4 P0.123456\nX.12", 2),
            ("1.23456 X-- 7.1234", 4),
        ] {
            assert_eq!(input_decimals(text), most, "{text:?}");
            assert_eq!(decimals_read_forward(text), most, "{text:?}");
        }
    }
}

#[cfg(test)]
mod clue_tests {
    use super::{clue, Clue, CLUE_BYTES};

    #[test]
    fn only_one_controllers_signs_are_clues() {
        let cases = [
            ("$H\nG21\nG0 X1\n", Some(Clue::GrblCommand)),
            ("G21\n  $J=G91 X1 F100\n", Some(Clue::GrblCommand)),
            ("%\nO1234 (PART)\nG21\n%\n", Some(Clue::FanucTape)),
            ("\n%\n:0097\nG21\n", Some(Clue::FanucTape)),
            // A `%` alone, an O word without the tape, a `$` setting.
            ("%\nG21 G0 X1\n%\n", None),
            ("O1000\nG21\nM30\n", None),
            ("$32=1\nG21\n", None),
            ("G21 (O100)\n", None),
            // Macro B: a control word first, or a G65 word.
            ("#1 = 0\nWHILE [#1 LT 3] DO1\n", Some(Clue::MacroB)),
            ("N20 IF [#1 EQ 0] GOTO 10\n", Some(Clue::MacroB)),
            ("/ goto 30\n", Some(Clue::MacroB)),
            ("G0 X1 G65 P9010 A2.\n", Some(Clue::MacroB)),
            ("%\nO1000\nG65 P9010\n", Some(Clue::FanucTape)),
            // Not Macro B: a comment, another code, LinuxCNC's o-words.
            ("(IF [#1 EQ 0] GOTO 10) G650 X1\n", None),
            ("G1 X65 G64 P0.01\n", None),
            ("o100 if [#1 EQ 0]\no100 endif\n", None),
        ];
        for (text, expected) in cases {
            assert_eq!(clue(text), expected, "{text:?}");
        }
    }

    #[test]
    fn a_program_number_heads_the_program() {
        let cases = [
            ("%\nO1234 (PART)\nG21\n", Some(1234)),
            ("(NOTE)\n:0097\nG21\n", Some(97)),
            ("G21\nO1234\n", None),
            ("O1000 G0 X1\n", None),
            ("O<sub> sub\n", None),
        ];
        for (text, expected) in cases {
            assert_eq!(super::program_number(text), expected, "{text:?}");
        }
    }

    /// A clue past the first lines is not looked at, as in a file read a
    /// part at a time.
    #[test]
    fn clues_are_in_the_first_lines_only() {
        let filler = "G1 X1 Y1\n".repeat(CLUE_BYTES / 9 + 2);
        assert_eq!(clue(&format!("{filler}$H\n")), None);
        assert_eq!(clue(&format!("$H\n{filler}")), Some(Clue::GrblCommand));
    }
}
