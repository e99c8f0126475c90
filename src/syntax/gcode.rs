//! The rules of plain G-code (SPEC §2.8) in the one lexer: `;` and
//! nested `( … )` comments kept for the output, `%` lines, grbl's `$`
//! commands, Fanuc's `:0097`, spaces inside a word (which `.egc`'s
//! G-code lines share), and a line's parameter assignments set after its
//! words. The LinuxCNC and Fanuc rules are tried first. It must not build
//! syntax trees.

use super::error::SyntaxErrorKind;
use super::language::Language;
use super::lexer::{Lexer, Raw};
use super::token::{Spanned, Tok};
use super::words::{word_of, WordNumber};

impl Lexer<'_> {
    /// The rules of plain G-code that differ from `.egc`, for the raw token
    /// at `start..end`: where it took the text, the offset to go on from.
    pub(super) fn plain_gcode(
        &mut self,
        raw: Result<Raw, ()>,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        if let Some(skip_to) = self.fanuc(&raw, start, end) {
            return Some(skip_to);
        }
        if raw == Ok(Raw::Comma) {
            if let Some(skip_to) = self.corner_word(start, end) {
                return Some(skip_to);
            }
        }
        if let Some(skip_to) = self.linuxcnc(raw, start, end) {
            return Some(skip_to);
        }
        if matches!(raw, Ok(Raw::Word | Raw::Number)) {
            return self.spaced_number(raw, start, end);
        }
        // Words, numbers and line ends (nearly every token) are as in
        // `.egc`: decided before the line is looked at.
        let dollar_or_colon = raw.is_err() && self.text[start..].starts_with(['$', ':']);
        if !matches!(
            raw,
            Ok(Raw::Semi | Raw::LParen | Raw::Percent | Raw::Letter)
        ) && !dollar_or_colon
        {
            return None;
        }
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let first_on_line = || {
            let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
            self.text[line_start..start].trim().is_empty()
        };
        match raw {
            // `;` to the end of the line is a comment.
            Ok(Raw::Semi) => {
                self.keep_comment(start + 1, line_end);
                Some(line_end)
            }
            Ok(Raw::LParen) => {
                let end = self.nested_comment(start, line_end);
                let inner_end = if self.text[..end].ends_with(')') {
                    end - 1
                } else {
                    end
                };
                self.keep_comment(start + 1, inner_end);
                Some(end)
            }
            // `%` starts and ends a tape; text after it is a note.
            Ok(Raw::Percent) if first_on_line() => Some(line_end),
            // grbl's `$H`, `$X`, `$$`: a command to the controller.
            Err(()) if self.text[start..].starts_with('$') && first_on_line() => {
                let command = self.text[start..line_end].trim_end();
                let symbol = self.names.note(command);
                self.push(start, Tok::Command(symbol), start + command.len());
                Some(line_end)
            }
            // Fanuc's `:0097` is the program number `O0097`.
            Err(()) if first_on_line() => {
                let digits = self.text[start + 1..line_end]
                    .find(|c: char| !c.is_ascii_digit())
                    .map_or(line_end, |i| start + 1 + i);
                if digits == start + 1 {
                    return None;
                }
                let number = word_of(b'O', &self.text[start + 1..digits]);
                self.push_word(number, start, digits);
                Some(digits)
            }
            // `G0Z  0.1`: spaces between a letter and its number.
            Ok(Raw::Letter) => self.word_after(start, line_end),
            _ => None,
        }
    }

    /// The word whose letter is at `start`, its number read to `line_end`
    /// at the latest, with any blanks inside it (`G 0 1`, `X - 1 0 . 5`);
    /// where the text goes on. A number of two points is an error; no
    /// number, `None`.
    pub(super) fn word_after(&mut self, start: usize, line_end: usize) -> Option<usize> {
        let number = WordNumber::after(self.text, start + 1, line_end);
        if number.has_points() {
            let written = self.text[start..number.end].to_string();
            self.report(SyntaxErrorKind::MalformedNumber(written), start, number.end);
        } else if number.is_decimal() {
            let word = number.word(self.text.as_bytes()[start]);
            self.push_word(word, start, number.end);
        } else {
            return None;
        }
        Some(number.end)
    }

    /// A word or a number (`raw`) at `start..end` that goes on after
    /// blanks (`X1 0.5`, `#1 = 2 5`): rs274 reads a line without its
    /// blanks, so it is read to its last digit or point; where the text
    /// goes on. Any other: `None`, as the lexer found it.
    pub(super) fn spaced_number(
        &mut self,
        raw: Result<Raw, ()>,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        let bytes = self.text.as_bytes();
        let mut next = end;
        while let Some(b' ' | b'\t') = bytes.get(next) {
            next += 1;
        }
        let goes_on = next > end
            && bytes
                .get(next)
                .is_some_and(|b| b.is_ascii_digit() || *b == b'.');
        if !goes_on {
            return None;
        }
        let line_end = self.text[next..]
            .find('\n')
            .map_or(self.text.len(), |i| next + i);
        if raw == Ok(Raw::Word) {
            return self.word_after(start, line_end);
        }
        let number = WordNumber::after(self.text, start, line_end);
        if number.has_points() {
            let written = self.text[start..number.end].to_string();
            self.report(SyntaxErrorKind::MalformedNumber(written), start, number.end);
        } else {
            self.push(start, Tok::Number(number.value()), number.end);
        }
        Some(number.end)
    }

    /// A `( … )` comment of plain G-code, which may hold parentheses of its
    /// own; it ends with its line. Returns where the text goes on.
    pub(super) fn nested_comment(&mut self, start: usize, line_end: usize) -> usize {
        if let Some(end) = comment_end(&self.text.as_bytes()[..line_end], start) {
            return end;
        }
        self.report(
            SyntaxErrorKind::UnclosedComment(Language::Gcode),
            start,
            start + 1,
        );
        line_end
    }

    /// Keep the text of a comment to send after its line.
    pub(super) fn keep_comment(&mut self, start: usize, end: usize) {
        let text = self.text[start..end].trim();
        if text.is_empty() {
            return;
        }
        let symbol = self.names.note(text);
        self.line_comments.push((start, symbol, end));
    }

    /// The comments of the line that ends here, each a statement of its
    /// own (`.egc`'s held for the next token: `Lexer::held_comments`).
    pub(super) fn flush_comments(&mut self, at: (usize, usize)) {
        if self.language == Language::Egc {
            self.held_comments.append(&mut self.line_comments);
            self.pending_term.get_or_insert(at);
            return;
        }
        for (start, symbol, end) in std::mem::take(&mut self.line_comments) {
            self.pending_term.get_or_insert(at);
            self.push(start, Tok::Comment(symbol), end);
        }
        self.pending_term.get_or_insert(at);
    }

    /// A line of plain G-code with words and parameter assignments
    /// (`#1=5 G1 X#1`): rs274 reads every word and value with the
    /// parameters as they were before the line and sets them after it, so
    /// the words become a statement of their own, followed by the
    /// assignments. Any other mix is left for the parser to report.
    pub(super) fn assignments_after_words(&mut self, at: usize) {
        if self.language != Language::Gcode || self.pending_term.is_some() {
            return;
        }
        let tokens = &self.out[self.stmt_start.min(self.out.len())..];
        if !tokens.iter().any(|t| t.1 == Tok::Assign) {
            return;
        }
        let mut words = Vec::new();
        let mut assignments = Vec::new();
        let mut i = 0;
        while i < tokens.len() {
            // Where an assignment's target ends: a name, or `#[…]`/`##1`.
            let target = match tokens[i].1 {
                Tok::Name(_) => Some(i + 1),
                Tok::Hash => value_end(tokens, i),
                _ => None,
            };
            let assigned = target.filter(|&t| matches!(tokens.get(t), Some((_, Tok::Assign, _))));
            let end = match (assigned, tokens[i].1) {
                (Some(t), _) => {
                    let Some(end) = value_end(tokens, t + 1) else {
                        return;
                    };
                    assignments.push(i..end);
                    end
                }
                (None, Tok::Words(..)) => {
                    words.push(i..i + 1);
                    i + 1
                }
                (None, Tok::SymOpen(_)) => {
                    let Some(end) = closing(tokens, i, |t| t == Tok::SymClose) else {
                        return;
                    };
                    words.push(i..end);
                    end
                }
                _ => return,
            };
            i = end;
        }
        if words.is_empty() || assignments.is_empty() {
            return;
        }
        let mut reordered: Vec<Spanned> = words
            .into_iter()
            .flat_map(|r| &tokens[r])
            .copied()
            .collect();
        reordered.push((at, Tok::Term, at));
        reordered.extend(assignments.into_iter().flat_map(|r| &tokens[r]).copied());
        let from = self.stmt_start;
        self.out.truncate(from);
        self.out.extend(reordered);
    }
}

/// Where the value of an assignment that starts at `tokens[i]` ends: one
/// value, as rs274 reads it (a number, a parameter, `[…]`, a function's
/// call, after any signs and `#`s).
fn value_end(tokens: &[Spanned], mut i: usize) -> Option<usize> {
    while matches!(
        tokens.get(i)?.1,
        Tok::Minus | Tok::Plus | Tok::NegTight | Tok::Hash
    ) {
        i += 1;
    }
    match tokens.get(i)?.1 {
        Tok::Name(_) if matches!(tokens.get(i + 1), Some((_, Tok::CallOpen, _))) => {
            closing(tokens, i + 1, |t| t == Tok::RParen)
        }
        Tok::Number(_) | Tok::Name(_) => Some(i + 1),
        Tok::LParen => closing(tokens, i, |t| t == Tok::RParen),
        _ => None,
    }
}

/// The end (one past) of the bracket that opens at `tokens[open]`,
/// counting every group and symbolic word between.
fn closing(tokens: &[Spanned], open: usize, closes: impl Fn(Tok) -> bool) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &(_, tok, _)) in tokens.iter().enumerate().skip(open) {
        match tok {
            Tok::LParen | Tok::CallOpen | Tok::SymOpen(_) => depth += 1,
            Tok::RParen | Tok::SymClose => depth -= 1,
            _ => {}
        }
        if depth == 0 {
            return closes(tok).then_some(k + 1);
        }
    }
    None
}

/// Where the plain G-code comment that opens at `bytes[open]` ends (one
/// past the `)` that closes it, counting nested ones), or `None` when it
/// runs to the end of `bytes` (its line).
pub fn comment_end(bytes: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &b) in bytes.iter().enumerate().skip(open) {
        match b {
            b'(' => depth += 1,
            b')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(k + 1);
                }
            }
            _ => {}
        }
    }
    None
}
