//! Fanuc's Macro B control words in plain G-code, read as the `.egc`
//! tokens they mean (SPEC §2.8): `WHILE [c] DOm … ENDm` is a `while`
//! block; `IF [c] THEN #1 = 2` and `IF [c] GOTO n` are an `if` whose block
//! is the rest of the line; `GOTO n` is a jump to the line labelled `Nn`.
//! A label before a control word or an assignment (`N20 IF …`,
//! `N30 #1 = 2`) is a statement of its own, so that `GOTO` finds it.
//!
//! None of these words can be G-code (`IF` is no I word, `DO1` no D word),
//! so they are read in any plain program; `--from fanuc` gives them
//! Fanuc's vacant variables and macro calls in the evaluator.

use super::error::SyntaxErrorKind;
use super::lexer::{Lexer, Raw, Shape};
use super::token::Tok;
use super::words::WordNumber;
use crate::ast::Word;

impl Lexer<'_> {
    /// Fanuc's corner words `,R` (round) and `,C` (chamfer) at `start`
    /// (the comma), outside any bracket: a word whose letter is
    /// [`Word::ROUND`] or [`Word::CHAMFER`]; where the text goes on. No
    /// other language ger reads writes a comma between words, so they are
    /// read in any plain program.
    pub(super) fn corner_word(&mut self, start: usize, end: usize) -> Option<usize> {
        if !self.groups.is_empty() || !self.syms.is_empty() {
            return None;
        }
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let after = self.text[end..line_end].trim_start_matches([' ', '\t']);
        let at = line_end - after.len();
        let letter = match after.as_bytes().first()?.to_ascii_uppercase() {
            b'R' => Word::ROUND,
            b'C' => Word::CHAMFER,
            _ => return None,
        };
        let number = WordNumber::after(self.text, at + 1, line_end);
        if !number.is_decimal() {
            return self.expression_word_of(letter, start, at + 1);
        }
        let mut word = number.word(b'R');
        word.letter = letter;
        self.push_word(word, start, number.end);
        Some(number.end)
    }

    /// A Macro B word at `start..end`: where the text goes on, if it was
    /// one.
    pub(super) fn fanuc(
        &mut self,
        raw: &Result<Raw, ()>,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        if *raw != Ok(Raw::Ident) {
            return None;
        }
        let text = &self.text[start..end];
        let (word, digits) = text.split_at(
            text.find(|c: char| c.is_ascii_digit())
                .unwrap_or(text.len()),
        );
        // Any other word (`EQ`, `sin`, a name) is not Macro B's: nothing
        // more to look at.
        const KEYWORDS: [&str; 6] = ["WHILE", "IF", "GOTO", "END", "DO", "THEN"];
        let word = KEYWORDS
            .into_iter()
            .find(|k| k.eq_ignore_ascii_case(word))?;
        let head = self.statement_head();
        match (word, head) {
            ("WHILE" | "IF", Some(None)) if digits.is_empty() => {
                self.end_label(start);
                let tok = if word == "IF" { Tok::If } else { Tok::While };
                self.push(start, tok, end);
            }
            ("GOTO", Some(None)) => {
                self.end_label(start);
                self.goto(digits, start, end);
            }
            ("END", Some(None)) if !digits.is_empty() => {
                self.end_label(start);
                let number: u32 = digits.parse().unwrap_or(0);
                match self.fanuc_loops.pop() {
                    Some(open) if open == number => {
                        if let Some(tok) = self.close_brace(start, end) {
                            self.push(start, tok, end);
                        }
                    }
                    open => {
                        let kind = SyntaxErrorKind::EndMismatch { end: number, open };
                        self.report(kind, start, end);
                        self.fanuc_loops.extend(open);
                    }
                }
            }
            ("DO", Some(Some(Tok::While))) if !digits.is_empty() && self.after_condition() => {
                let number: u32 = digits.parse().unwrap_or(0);
                self.fanuc_loops.push(number);
                if let Some(tok) = self.open_brace(start, end) {
                    self.push(start, tok, end);
                }
            }
            ("THEN" | "GOTO", Some(Some(Tok::If)))
                if self.after_condition() && (word == "GOTO" || digits.is_empty()) =>
            {
                // The block is the rest of the line.
                if let Some(tok) = self.open_brace(start, end) {
                    self.push(start, tok, end);
                }
                self.close_at_line_end = true;
                if word == "GOTO" {
                    self.goto(digits, start, end);
                }
            }
            _ => return None,
        }
        Some(end)
    }

    /// `GOTO`, and its label when written without a space (`GOTO10`).
    fn goto(&mut self, digits: &str, start: usize, end: usize) {
        self.push(start, Tok::Goto, end);
        if !digits.is_empty() {
            let label: f64 = digits.parse().unwrap_or(0.0);
            self.push(start + 4, Tok::Number(label), end);
        }
    }

    /// What the current statement starts with: `Some(None)` when nothing
    /// (or only an N label) has been read, `Some(Some(tok))` for a
    /// keyword, `None` for anything else.
    fn statement_head(&self) -> Option<Option<Tok>> {
        // A statement ended and the next has not started.
        if self.pending_term.is_some() {
            return Some(None);
        }
        let tokens = &self.out[self.stmt_start.min(self.out.len())..];
        match tokens.first().map(|t| t.1) {
            None => Some(None),
            Some(Tok::Words(..)) if tokens.len() == 1 && self.only_labels(tokens[0].1) => {
                Some(None)
            }
            Some(tok @ (Tok::If | Tok::While)) => Some(Some(tok)),
            _ => None,
        }
    }

    /// The last token closed the condition's `[ ]`.
    fn after_condition(&self) -> bool {
        matches!(self.out.last(), Some((_, Tok::RParen, _))) && self.groups.is_empty()
    }

    /// A run of words that are all N labels.
    fn only_labels(&self, run: Tok) -> bool {
        let Tok::Words(first, len) = run else {
            return false;
        };
        let words = self.words.get(first as usize..(first + len) as usize);
        words.is_some_and(|w| w.iter().all(|w| w.word.letter == b'N'))
    }

    /// Before a control word or an assignment: an N label read so far is a
    /// statement of its own (`N20 IF …`), so that a `GOTO` finds it.
    pub(super) fn end_label(&mut self, start: usize) {
        if self.pending_term.is_some() {
            return;
        }
        let tokens = &self.out[self.stmt_start.min(self.out.len())..];
        if tokens.len() == 1 && self.only_labels(tokens[0].1) {
            self.pending_term = Some((start, start));
            self.shape = Shape::Empty;
        }
    }
}
