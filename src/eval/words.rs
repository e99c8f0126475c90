//! The words of one statement by letter ([`WordValues`]), read by the
//! code, cycle and compensation modules. A table and a mask: it must not
//! know what a letter means.

use crate::ast;
use crate::source::Span;

/// Values of the words of one statement, by letter: a presence mask and
/// the values, with the index of each word for its span and spelling.
/// Cheap to start empty: the table is the last statement's (only the
/// letters present in the mask are ever read), not made and cleared anew.
pub(super) struct WordValues<'w> {
    present: u32,
    pub(super) table: Box<WordTable>,
    words: &'w [ast::Word],
}

/// A value and a word index for every letter.
#[derive(Default)]
pub(super) struct WordTable {
    values: [f64; SLOTS],
    index: [u16; SLOTS],
}

/// A slot for each letter, for LinuxCNC's polar words `@` and `^`, and
/// for Fanuc's corner words `,R` and `,C`.
const SLOTS: usize = 30;

/// The slot of a word's letter (`A`..`Z`, then `@`, `^`, `,R`, `,C`).
fn slot(letter: u8) -> usize {
    match letter {
        b'@' => 26,
        b'^' => 27,
        ast::Word::ROUND => 28,
        ast::Word::CHAMFER => 29,
        _ => usize::from(letter - b'A'),
    }
}

/// The letter of a slot, as [`slot`] numbers them.
fn letter_of(slot: u32) -> u8 {
    match slot {
        26 => b'@',
        27 => b'^',
        28 => ast::Word::ROUND,
        29 => ast::Word::CHAMFER,
        _ => b'A' + slot as u8,
    }
}

impl<'w> WordValues<'w> {
    pub(super) fn new(words: &'w [ast::Word], table: Box<WordTable>) -> Self {
        WordValues {
            present: 0,
            table,
            words,
        }
    }

    pub(super) fn bit(letter: u8) -> u32 {
        1 << slot(letter)
    }

    /// The span of the word already given for `letter`, if any.
    pub(super) fn given(&self, letter: u8) -> Option<Span> {
        self.has(letter)
            .then(|| self.words[self.table.index[slot(letter)] as usize].span)
    }

    pub(super) fn set(&mut self, letter: u8, value: f64, word_index: usize) {
        let i = slot(letter);
        self.present |= Self::bit(letter);
        self.table.values[i] = value;
        self.table.index[i] = word_index.min(u16::MAX as usize) as u16;
    }

    pub(super) fn take(&mut self, letter: u8) -> Option<(f64, Span)> {
        self.take_number(letter).map(|(v, s, _)| (v, s))
    }

    /// The value, its span, and how it was written (`P31000`, `P0.5`).
    pub(super) fn take_number(&mut self, letter: u8) -> Option<(f64, Span, ast::Number)> {
        if !self.has(letter) {
            return None;
        }
        self.present &= !Self::bit(letter);
        let i = slot(letter);
        let word = &self.words[self.table.index[i] as usize];
        let written = match &word.value {
            ast::WordValue::Number(n) => *n,
            ast::WordValue::Expr(_) => ast::Number {
                value: self.table.values[i],
                int_digits: 0,
                has_point: true,
            },
        };
        Some((self.table.values[i], word.span, written))
    }

    /// The value alone, taken (no span or spelling to look up).
    pub(super) fn take_value(&mut self, letter: u8) -> Option<f64> {
        if !self.has(letter) {
            return None;
        }
        self.present &= !Self::bit(letter);
        Some(self.table.values[slot(letter)])
    }

    /// The value given for `letter` (present), left in place.
    pub(super) fn table_value(&self, letter: u8) -> f64 {
        self.table.values[slot(letter)]
    }

    /// LinuxCNC's polar words `@` and `^` replaced by the X and Y they
    /// make, each spanned at the polar word that gave it.
    pub(super) fn polar_to_xy(&mut self, x: f64, y: f64) {
        let at = |w: &Self, l: u8| w.has(l).then(|| w.table.index[slot(l)]);
        let (radius, angle) = (at(self, b'@'), at(self, b'^'));
        for (letter, value, index) in [(b'X', x, radius.or(angle)), (b'Y', y, angle.or(radius))] {
            if let Some(index) = index {
                self.set(letter, value, usize::from(index));
            }
        }
        self.present &= !(Self::bit(b'@') | Self::bit(b'^'));
    }

    pub(super) fn has(&self, letter: u8) -> bool {
        self.present & Self::bit(letter) != 0
    }

    /// Any of `letters` given (a constant list: its mask folds away).
    pub(super) fn has_any(&self, letters: &[u8]) -> bool {
        let mask = letters.iter().fold(0, |mask, &l| mask | Self::bit(l));
        self.present & mask != 0
    }

    pub(super) fn remaining(&self) -> impl Iterator<Item = (u8, Span)> + '_ {
        let mut left = self.present;
        std::iter::from_fn(move || {
            if left == 0 {
                return None;
            }
            let letter = letter_of(left.trailing_zeros());
            left &= left - 1;
            self.given(letter).map(|s| (letter, s))
        })
    }
}
