//! The rules of ger's own language, `.egc` (SPEC §2.3–2.7), in the one
//! lexer: whether `(` opens a comment or a group, the keywords, spaces
//! inside the words of a G-code line, a letter without its number, and
//! `P0X = 5` read as the name the user meant. It must not build syntax
//! trees.

use super::error::SyntaxErrorKind;
use super::language::Language;
use super::lexer::{find_word, Lexer, Raw, Shape};
use super::token::Tok;
use crate::ast::Function;

impl Lexer<'_> {
    /// Decide what `(` at `start` is. Returns the end of a comment to skip.
    pub(super) fn lparen(&mut self, start: usize) -> Option<usize> {
        let grouping = !self.groups.is_empty()
            || !self.syms.is_empty()
            || match self.shape {
                Shape::Empty | Shape::Code => false,
                Shape::NameHead | Shape::Keyword => true,
                Shape::Assign => !self.after_value(),
            };
        if grouping {
            let call = matches!(self.out.last(), Some(&(_, Tok::Name(_), e)) if e == start);
            self.groups.push((start, '('));
            if self.shape == Shape::NameHead {
                self.call_groups.push(start);
            }
            self.push(
                start,
                if call { Tok::CallOpen } else { Tok::LParen },
                start + 1,
            );
            return None;
        }
        match self.text[start + 1..].find(')') {
            Some(i) => Some(start + 1 + i + 1),
            None => {
                let end = self.text.len();
                self.report(
                    SyntaxErrorKind::UnclosedComment(Language::Egc),
                    start,
                    start + 1,
                );
                Some(end)
            }
        }
    }

    /// The `.egc` comments held, each a statement of its own, here.
    pub(super) fn send_held_comments(&mut self) {
        // The token that comes next starts its statement as it would
        // have without them.
        let shape = self.shape;
        for (start, symbol, end) in std::mem::take(&mut self.held_comments) {
            let at = (start, start);
            self.pending_term.get_or_insert(at);
            self.push(start, Tok::Comment(symbol), end);
            self.pending_term.get_or_insert((end, end));
        }
        self.shape = shape;
    }

    /// Is the last token the end of a value (so `(` after it is a comment)?
    pub(super) fn after_value(&self) -> bool {
        match self.out.last() {
            Some((_, Tok::Name(s), _)) => Function::from_name(self.names.text(*s)).is_none(),
            Some((_, t, _)) => matches!(
                t,
                Tok::Number(_) | Tok::Str(_) | Tok::True | Tok::False | Tok::RParen
            ),
            None => false,
        }
    }

    /// SPEC §2.2's spaces inside a word of a G-code statement, as plain
    /// G-code reads them: `G0Z  0.1`, `X - 1 0 . 5`, `X1 0.5` (rs274 reads
    /// a line without its blanks), and `X <expr>`, the symbolic word with
    /// a blank after its letter. Only where a statement is G-code words
    /// (outside groups and symbolic words): a wizard call's or directive's
    /// arguments (`Pocket 75 30 10`) and expressions stay apart. Where it
    /// took the text, the offset to go on from.
    pub(super) fn egc_spaced_word(
        &mut self,
        raw: Result<Raw, ()>,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        let words_only = matches!(self.shape, Shape::Empty | Shape::Code)
            && self.groups.is_empty()
            && self.syms.is_empty();
        if !words_only {
            return None;
        }
        match raw {
            Ok(Raw::Word) => self.spaced_number(raw, start, end),
            Ok(Raw::Letter) => {
                let line_end = self.text[start..]
                    .find('\n')
                    .map_or(self.text.len(), |i| start + i);
                let after = self.text[end..line_end].trim_start_matches([' ', '\t']);
                if after.starts_with('<') {
                    let open = line_end - after.len();
                    self.open_sym(start, '<', false);
                    let letter = self.text.as_bytes()[start].to_ascii_uppercase();
                    self.push(start, Tok::SymOpen(letter), open + 1);
                    return Some(open + 1);
                }
                self.word_after(start, line_end)
            }
            _ => None,
        }
    }

    /// A letter with no number: an address without its value, or a
    /// one-letter name in an expression.
    pub(super) fn lone_letter(&mut self, start: usize, end: usize) {
        let text = &self.text[start..end];
        let in_expression = !self.groups.is_empty()
            || !self.syms.is_empty()
            || matches!(self.shape, Shape::Assign | Shape::Keyword);
        let kind = if in_expression {
            SyntaxErrorKind::LetterAsName(text.into(), self.language)
        } else {
            SyntaxErrorKind::LetterWithoutNumber(text.into(), self.language)
        };
        self.report(kind, start, end);
    }

    pub(super) fn ident(&mut self, text: &str) -> Tok {
        const KEYWORDS: [(&str, Tok); 5] = [
            ("if", Tok::If),
            ("else", Tok::Else),
            ("while", Tok::While),
            ("true", Tok::True),
            ("false", Tok::False),
        ];
        find_word(&KEYWORDS, text).unwrap_or_else(|| Tok::Name(self.names.intern(text)))
    }

    /// `P0X = 5`: the user meant a variable, but a letter and a digit make a
    /// word. Report it and read the statement as an assignment to that name.
    pub(super) fn invalid_name(&mut self, assign_at: usize) {
        let from = self.out.get(self.stmt_start).map_or(assign_at, |t| t.0);
        let written = self.text[from..assign_at].trim_end();
        if written.is_empty()
            || !written
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'_')
        {
            return;
        }
        let letters: String = written.chars().filter(|c| !c.is_ascii_digit()).collect();
        let digits: String = written.chars().filter(|c| c.is_ascii_digit()).collect();
        let kind = SyntaxErrorKind::WordAsName {
            written: written.into(),
            respelled: (letters.len() >= 2).then(|| format!("{letters}{digits}")),
        };
        // The letters of the name were reported one by one; this says it all.
        // (Spans are in the file; a part's text starts inside it.)
        let written_span = self.span(from, assign_at);
        let (from32, to32) = (written_span.start, written_span.end);
        self.errors
            .retain(|e| e.span.start < from32 || e.span.start >= to32);
        self.report(kind, from, from + written.len());
        self.out.truncate(self.stmt_start);
        let name = self.names.intern(written);
        self.out.push((from, Tok::Name(name), from + written.len()));
        self.shape = Shape::NameHead;
    }
}
