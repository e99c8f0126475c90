//! Word and number lexing shared by every language: a G-code word
//! (`X-.5`, `G54.1`) and the decimal after its letter, read as
//! `str::parse` reads it without allocating, and the fast path that reads
//! a line of plain words straight from its bytes. It must not know
//! statements, expressions or what a code means.

use crate::source::Locator;

/// A G-code word as the lexer read it: `X-.5`, `G54.1`, `P31000`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WordTok {
    pub letter: u8,
    pub value: f64,
    pub int_digits: u8,
    pub has_point: bool,
}

/// A plain word with its byte range, kept in [`Lexed::words`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LexedWord {
    pub word: WordTok,
    pub start: u32,
    pub end: u32,
}

/// The words of the line `text[start..end]` (without its line end),
/// appended to `words` when it holds plain words
/// only — a letter other than `O`, then a decimal number, perhaps after
/// spaces — with spaces and tabs around them: what the lexer and the
/// parser would make of it (`Raw::Word`, or a letter and its number
/// apart), without them; a blank line has none. `false` (and `words` as
/// it was): anything else is on the line, for the lexer.
pub(crate) fn plain_words(
    text: &str,
    (start, end): (usize, usize),
    at: &Locator,
    words: &mut Vec<crate::ast::PlainWord>,
) -> bool {
    let bytes = &text.as_bytes()[..end];
    let before = words.len();
    let mut i = start;
    loop {
        while let Some(b' ' | b'\t' | b'\r' | b'\x0c') = bytes.get(i) {
            i += 1;
        }
        let Some(&letter) = bytes.get(i) else {
            break;
        };
        // What follows a number is a blank, the next word's letter, or
        // refused here.
        let number_read = match decimal_after(text, i + 1, end) {
            Some(read) if letter.is_ascii_alphabetic() && !letter.eq_ignore_ascii_case(&b'O') => {
                read
            }
            _ => {
                words.truncate(before);
                return false;
            }
        };
        let (value, int_digits, has_point, number_end) = number_read;
        words.push(crate::ast::PlainWord {
            value,
            start: at.offset(i),
            end: at.offset(number_end),
            letter: letter.to_ascii_uppercase(),
            int_digits,
            has_point,
        });
        i = number_end;
    }
    true
}

/// The decimal number after a word's letter in `text[from..end]`, read as
/// [`WordNumber::after`] finds it and [`scan_decimal`] reads it, in one
/// pass: its value, integer digits, whether it has a point, and its end.
/// `None` where [`WordNumber::is_decimal`] is false; where blanks stand
/// inside the number, `None` or an end before them (the line is then
/// the lexer's).
fn decimal_after(text: &str, from: usize, end: usize) -> Option<(f64, u8, bool, usize)> {
    // One bounds check a byte: the slice ends where the number must.
    let bytes = &text.as_bytes()[..end];
    let mut i = from;
    while let Some(b' ' | b'\t') = bytes.get(i) {
        i += 1;
    }
    let sign = i;
    let negative = bytes.get(i) == Some(&b'-');
    if let Some(b'+' | b'-') = bytes.get(i) {
        i += 1;
    }
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut point: Option<usize> = None;
    while let Some(&b) = bytes.get(i) {
        if b.is_ascii_digit() {
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
            count += 1;
        } else if b == b'.' {
            if point.is_some() {
                return None;
            }
            point = Some(count);
        } else {
            break;
        }
        i += 1;
    }
    if count == 0 {
        return None;
    }
    let int_digits = point.unwrap_or(count).min(255) as u8;
    let value = exact_decimal(mantissa, count, point, negative)
        .unwrap_or_else(|| text[sign..i].parse().unwrap_or(f64::NAN));
    Some((value, int_digits, point.is_some(), i))
}

/// The value of `count` digits read as `mantissa`, `point` of them before
/// the point, negative or not: an exact integer divided by an exact power
/// of ten, one correctly rounded operation (the value `str::parse` gives).
/// `None` beyond 15 digits, where that does not hold.
fn exact_decimal(mantissa: u64, count: usize, point: Option<usize>, negative: bool) -> Option<f64> {
    if count > 15 {
        return None;
    }
    // Exact below 10^15 either way; from `i64` it is one instruction.
    let v = mantissa as i64 as f64 / POW10[count - point.unwrap_or(count)];
    Some(if negative { -v } else { v })
}

/// Powers of ten exact in an `f64`.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The number after a word's letter, as plain G-code writes it: spaces
/// or tabs, a sign, then digits and points (`G0Z  0.1`, `X -1.5`), with
/// spaces or tabs anywhere between them (`X - 1 0 . 5` is `X-10.5`: rs274
/// reads a line without its spaces and tabs).
pub(crate) struct WordNumber<'a> {
    text: &'a str,
    /// Where its sign (or its first digit) is.
    sign: usize,
    /// Where its digits and points start, and its end (after its last
    /// digit or point; after its sign if it has none).
    digits: usize,
    pub end: usize,
    /// Its digits and its points.
    figures: usize,
    points: usize,
    /// Spaces or tabs between its sign, digits and points.
    pub spaced: bool,
}

impl WordNumber<'_> {
    /// The number in `text[from..end]`, `from` just after the letter.
    pub(crate) fn after(text: &str, from: usize, end: usize) -> WordNumber<'_> {
        let bytes = text.as_bytes();
        let blanks_from = |mut i: usize| {
            while i < end && matches!(bytes[i], b' ' | b'\t') {
                i += 1;
            }
            i
        };
        let sign = blanks_from(from);
        let digits = sign + usize::from(sign < end && matches!(bytes[sign], b'+' | b'-'));
        let (mut i, mut figures, mut points, mut spaced) = (digits, 0, 0, false);
        loop {
            let next = blanks_from(i);
            if next == end || !matches!(bytes[next], b'0'..=b'9' | b'.') {
                break;
            }
            spaced |= next > i;
            figures += 1;
            points += usize::from(bytes[next] == b'.');
            i = next + 1;
        }
        WordNumber {
            text,
            sign,
            digits,
            end: i,
            figures,
            points,
            spaced,
        }
    }

    /// Some digits and points.
    pub(crate) fn has_digits(&self) -> bool {
        self.figures > 0
    }

    /// The digits and points of the number (after its sign), spaces and
    /// tabs between them included.
    pub(crate) fn body(&self) -> &[u8] {
        &self.text.as_bytes()[self.digits..self.end]
    }

    /// A decimal number the lexer reads: a digit, and one point at most.
    pub(crate) fn is_decimal(&self) -> bool {
        self.figures > self.points && self.points <= 1
    }

    /// More than one point: a malformed number.
    pub(crate) fn has_points(&self) -> bool {
        self.points > 1
    }

    /// The sign, digits and points, without blanks.
    fn written(&self) -> std::borrow::Cow<'_, str> {
        let written = &self.text[self.sign..self.end];
        match self.spaced {
            // Rare: a copy without its blanks.
            true => written.replace([' ', '\t'], "").into(),
            false => written.into(),
        }
    }

    /// The word of `letter` and this number (a decimal).
    pub(crate) fn word(&self, letter: u8) -> WordTok {
        word_of(letter, &self.written())
    }

    /// Its value (a decimal).
    pub(crate) fn value(&self) -> f64 {
        parse_decimal(&self.written())
    }
}

/// The word written `text`: a letter, then its number.
pub(super) fn word(text: &str) -> WordTok {
    word_of(text.as_bytes()[0], &text[1..])
}

/// The word of `letter` and the number written `number` (a letter and a
/// number written apart: `G0Z  0.1`, Fanuc's `:0097`).
pub(super) fn word_of(letter: u8, number: &str) -> WordTok {
    let (value, int_digits, has_point) = scan_decimal(number);
    WordTok {
        letter: letter.to_ascii_uppercase(),
        value,
        int_digits,
        has_point,
    }
}

pub(super) fn parse_decimal(text: &str) -> f64 {
    scan_decimal(text).0
}

/// A plain decimal (`-12.5`, `.5`, `10.`) as f64, with its digits before
/// the point and whether it has one, in one pass: [`exact_decimal`] up to
/// 15 digits, at a fraction of the cost of `str::parse`, which longer
/// numbers take.
fn scan_decimal(text: &str) -> (f64, u8, bool) {
    let bytes = text.as_bytes();
    let (negative, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut point: Option<usize> = None;
    for &b in digits {
        if b.is_ascii_digit() {
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
            count += 1;
        } else if b == b'.' && point.is_none() {
            point = Some(count);
        } else {
            return (text.parse().unwrap_or(f64::NAN), 0, point.is_some());
        }
    }
    let int_digits = point.unwrap_or(count).min(255) as u8;
    let value = exact_decimal(mantissa, count, point, negative)
        .unwrap_or_else(|| text.parse().unwrap_or(f64::NAN));
    (value, int_digits, point.is_some())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `decimal_after` reads what `WordNumber::after` finds and
    /// `scan_decimal` reads, bit for bit.
    /// A number with blanks inside is for the lexer: `decimal_after`
    /// gives `None`, or stops where more of the number follows, a line
    /// [`plain_words`] refuses.
    fn reads_alike(text: &str) {
        let found = WordNumber::after(text, 0, text.len());
        let got = decimal_after(text, 0, text.len()).map(|(v, d, p, e)| (v.to_bits(), d, p, e));
        if found.spaced {
            let refused = got.is_none_or(|(_, _, _, end)| {
                let rest = text[end..].trim_start_matches([' ', '\t']);
                rest.starts_with(|c: char| c.is_ascii_digit() || c == '.')
            });
            assert!(refused, "{text:?}");
            return;
        }
        let expected = found.is_decimal().then(|| {
            let word = found.word(b'X');
            (
                word.value.to_bits(),
                word.int_digits,
                word.has_point,
                found.end,
            )
        });
        assert_eq!(got, expected, "{text:?}");
    }

    #[test]
    fn decimal_after_reads_as_the_lexer_reads() {
        for text in [
            "1",
            "-1.5",
            "+.25",
            " \t-0",
            "1.2.3",
            ".",
            "-.",
            "",
            "12345678901234567.5",
            "0.1234567890123456",
            "7X",
            "-",
            "1.",
            "007.50",
            "1 0 . 5",
            "- 1",
            "1 .",
            " 1.5 2.",
        ] {
            reads_alike(text);
        }
    }

    proptest::proptest! {
        #[test]
        fn decimal_after_reads_any_number_as_the_lexer_reads(text in r"[ \t+\-.0-9]{0,22}[XG ]?") {
            reads_alike(&text);
        }
    }

    #[test]
    fn fast_decimals_equal_std_parse() {
        for t in [
            "0",
            "1.",
            ".5",
            "-.5",
            "+2",
            "12.345",
            "-0.0001",
            "999999.999999",
            "0.1",
            "123456789012345678",
        ] {
            assert_eq!(
                parse_decimal(t).to_bits(),
                t.parse::<f64>().unwrap().to_bits(),
                "{t}"
            );
        }
    }
}
