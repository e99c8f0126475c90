//! Lexer: source text → tokens, for every language. logos finds the raw
//! tokens; this module keeps the statement being read (its shape, open
//! groups, symbolic words and blocks) and the rules `.egc` and plain
//! G-code share. Each language's own rules are methods in its module
//! (`egc`, `gcode`, `linuxcnc`, `fanuc`), which `run` and `token` call.
//! It must not build syntax trees or know what a G code means.

use super::error::{SyntaxError, SyntaxErrorKind};
use super::language::Language;
use super::token::{Spanned, Tok};
use super::words::{parse_decimal, word, LexedWord, WordTok};
use crate::ast::{Names, OName, Symbol};
use crate::source::{Locator, Span};
use logos::Logos;

#[derive(Logos, Clone, Copy, Debug, PartialEq)]
#[logos(skip r"[ \t\r\f]+")]
pub(super) enum Raw {
    #[regex(r"[A-Za-z][+-]?([0-9]+\.?[0-9]*|\.[0-9]+)")]
    Word,
    #[regex(r"[A-Za-z][+-]?[0-9]*\.[0-9]*\.[0-9.]*")]
    #[regex(r"[0-9]*\.[0-9]*\.[0-9.]*")]
    BadNumber,
    #[regex(r"[A-Za-z]<")]
    SymOpen,
    #[regex(r"[A-Za-z][A-Za-z_][A-Za-z0-9_]*")]
    Ident,
    #[regex(r"[A-Za-z]")]
    Letter,
    #[regex(r"[0-9]+\.?[0-9]*|\.[0-9]+")]
    Number,
    #[regex(r#""[^"\n]*""#, allow_greedy = true)]
    Str,
    #[regex(r#""[^"\n]*"#, allow_greedy = true)]
    OpenStr,
    #[regex(r"//[^\n]*", allow_greedy = true)]
    LineComment,
    #[token("\n")]
    Newline,
    #[token(";")]
    Semi,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token(",")]
    Comma,
    #[token("=")]
    Assign,
    #[token("==")]
    EqEq,
    #[token("!=")]
    NotEq,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("&&")]
    AndAnd,
    #[token("||")]
    OrOr,
    #[token("!")]
    Bang,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("%")]
    Percent,
    #[token("^")]
    Caret,
}

/// Tokens in one statement. Expressions are trees the evaluator walks
/// recursively, so their size is bounded where they are read; real
/// statements are far shorter.
pub const MAX_STATEMENT_TOKENS: usize = 1000;

/// `{` blocks nested inside each other.
pub const MAX_BLOCK_DEPTH: usize = 64;

/// What the current statement looks like so far; decides what `(` means.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Shape {
    /// Nothing yet: a `(` here is a comment.
    Empty,
    /// Starts with a G-code word: `(` is a comment.
    Code,
    /// Starts with a name: a wizard call, `(` groups.
    NameHead,
    /// `name =`: `(` groups, except right after a complete value.
    Assign,
    /// `if`, `while`, `else`: `(` groups.
    Keyword,
}

/// Tokens of one file plus the errors found while lexing.
pub struct Lexed {
    pub tokens: Vec<Spanned>,
    pub words: Vec<LexedWord>,
    pub errors: Vec<SyntaxError>,
    /// A `{` was never closed: the lexer closed it at the end of the file.
    pub unclosed_brace: bool,
    /// Where `(` groups opened in wizard calls (offsets in the text read,
    /// not spans: a part starts inside its file); a parse error inside one
    /// gets a hint that comments there are written with `//`.
    pub call_groups: Vec<usize>,
}

/// The tokens of `text` in `language` from the offset `from` (a line
/// start), with spans in the whole text: the earlier lines are not read.
pub fn lex_from(
    text: &str,
    from: usize,
    at: &Locator,
    names: &mut Names,
    language: Language,
) -> Lexed {
    let mut lexer = Lexer::new(text, from, at, names);
    lexer.language = language;
    lexer.run()
}

/// A symbolic word being read (`X<…>`, `X[…]`, `X#[…]`).
pub(super) struct OpenSym {
    pub(super) start: usize,
    /// `<` (`.egc`) or `[`.
    pub(super) bracket: char,
    /// The group depth it was opened at.
    pub(super) depth: usize,
    /// It closes with the group opened after it (`X#[…]`).
    pub(super) with_group: bool,
}

pub(super) struct Lexer<'a> {
    pub(super) text: &'a str,
    /// Where reading starts (a line start; [`lex_from`]).
    pub(super) from: usize,
    pub(super) language: Language,
    pub(super) at: &'a Locator,
    pub(super) names: &'a mut Names,
    pub(super) out: Vec<Spanned>,
    pub(super) words: Vec<LexedWord>,
    pub(super) errors: Vec<SyntaxError>,
    pub(super) unclosed_brace: bool,
    pub(super) call_groups: Vec<usize>,
    pub(super) shape: Shape,
    /// Index in `out` where the current statement starts.
    pub(super) stmt_start: usize,
    /// Open groups, innermost last: where each opened, and its bracket
    /// (`(`, or LinuxCNC's and Fanuc's `[`).
    pub(super) groups: Vec<(usize, char)>,
    /// Open symbolic words, innermost last.
    pub(super) syms: Vec<OpenSym>,
    pub(super) braces: Vec<usize>,
    /// A statement end seen but not yet emitted: dropped if `{` or `else`
    /// comes next, so braces and `else` may start a new line.
    pub(super) pending_term: Option<(usize, usize)>,
    /// Comments of the current line, sent after it.
    pub(super) line_comments: Vec<(usize, Symbol, usize)>,
    /// `.egc` comments of lines read, sent before the next token that
    /// does not go on with a statement (`{`, `else`), so that a comment
    /// between `if (c)` and its `{` or between `}` and `else` lands
    /// inside the block.
    pub(super) held_comments: Vec<(usize, Symbol, usize)>,
    /// The current statement passed `MAX_STATEMENT_TOKENS`: its remaining
    /// tokens are dropped.
    pub(super) too_long: bool,
    /// Blocks nested too deep: the rest of the file is not read.
    pub(super) stopped: bool,
    /// A LinuxCNC `if`/`while` line: its block opens at the line's end.
    pub(super) block_at_line_end: bool,
    /// Group depths of LinuxCNC `ATAN[` calls still at their first argument.
    pub(super) atan_groups: Vec<usize>,
    /// An `o… call` line being read.
    pub(super) pending_call: Option<PendingCall>,
    /// The labels of open `oN do` loops, innermost last.
    pub(super) do_labels: Vec<OName>,
    /// Inside a LinuxCNC `oN sub` … `oN endsub` (a part holds its
    /// subroutines whole: [`super::chunk::cut_part`]).
    pub(super) in_sub: bool,
    /// The `oN while [c]` that ends a do loop, and Fanuc's `IF [c] THEN`
    /// and `IF [c] GOTO n`: the block closes at the line's end.
    pub(super) close_at_line_end: bool,
    /// Fanuc's open `WHILE … DOm` loops: their m, innermost last.
    pub(super) fanuc_loops: Vec<u32>,
    /// `#0`…`#LAST_PARAMETER` are all named (a `#[…]` was read).
    pub(super) every_parameter_named: bool,
}

/// Whether a value must come after `tok` (an operator, an opening
/// bracket, a comma): a minus after it is LinuxCNC's unary minus, and a
/// line end after it inside parentheses does not end the statement.
pub(super) fn expects_value(tok: Tok) -> bool {
    matches!(
        tok,
        Tok::LParen
            | Tok::CallOpen
            | Tok::SymOpen(_)
            | Tok::Comma
            | Tok::Plus
            | Tok::Minus
            | Tok::Star
            | Tok::Slash
            | Tok::Percent
            | Tok::Caret
            | Tok::Mod
            | Tok::PowLeft
            | Tok::NegTight
            | Tok::EqEq
            | Tok::NotEq
            | Tok::Lt
            | Tok::Le
            | Tok::Gt
            | Tok::Ge
            | Tok::AndAnd
            | Tok::OrOr
            | Tok::Bang
            | Tok::Word(_)
    )
}

/// The entry of `table` whose word is `text`, in either case.
pub(super) fn find_word<T: Copy>(table: &[(&str, T)], text: &str) -> Option<T> {
    table
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(text))
        .map(|&(_, t)| t)
}

/// An `o… call` line: its arguments so far, and where `call` is.
#[derive(Clone, Copy, Debug)]
pub(super) struct PendingCall {
    pub(super) args: u32,
    pub(super) at: (usize, usize),
}

impl<'a> Lexer<'a> {
    pub(super) fn new(
        text: &'a str,
        from: usize,
        at: &'a Locator,
        names: &'a mut Names,
    ) -> Lexer<'a> {
        let from = from.min(text.len());
        let read = text.len() - from;
        Lexer {
            text,
            from,
            language: Language::Egc,
            at,
            names,
            // Generous: untouched capacity costs no memory, regrowing copies.
            out: Vec::with_capacity(read / 4),
            words: Vec::with_capacity(read / 3),
            errors: Vec::new(),
            unclosed_brace: false,
            call_groups: Vec::new(),
            shape: Shape::Empty,
            stmt_start: 0,
            groups: Vec::new(),
            syms: Vec::new(),
            braces: Vec::new(),
            pending_term: None,
            line_comments: Vec::new(),
            held_comments: Vec::new(),
            too_long: false,
            stopped: false,
            block_at_line_end: false,
            atan_groups: Vec::new(),
            pending_call: None,
            do_labels: Vec::new(),
            in_sub: false,
            close_at_line_end: false,
            fanuc_loops: Vec::new(),
            every_parameter_named: false,
        }
    }

    pub(super) fn span(&self, start: usize, end: usize) -> Span {
        self.at.span(start, end)
    }

    pub(super) fn report(&mut self, kind: SyntaxErrorKind, start: usize, end: usize) {
        let span = self.span(start, end);
        self.errors.push(SyntaxError::new(kind, span));
    }

    pub(super) fn run(mut self) -> Lexed {
        let mut raw = Raw::lexer(self.text);
        raw.bump(self.from);
        while let Some(result) = raw.next() {
            let range = raw.span();
            let (start, end) = (range.start, range.end);
            let taken = match self.language {
                Language::Gcode => self.plain_gcode(result, start, end),
                Language::Egc => self.egc_spaced_word(result, start, end),
            };
            if let Some(skip_to) = taken {
                raw.bump(skip_to.saturating_sub(end));
                continue;
            }
            let Ok(tok) = result else {
                let ch = self.text[start..].chars().next().unwrap_or('?');
                self.report(
                    SyntaxErrorKind::UnknownCharacter(ch, self.language),
                    start,
                    start + ch.len_utf8(),
                );
                continue;
            };
            if self.stopped {
                break;
            }
            match tok {
                Raw::LParen => {
                    if let Some(close) = self.lparen(start) {
                        // A comment: kept for the output, and skipped
                        // past its `)` (or to the end).
                        let inner = close - usize::from(self.text[..close].ends_with(')'));
                        self.keep_comment(start + 1, inner);
                        raw.bump(close - end);
                    }
                }
                _ => self.token(tok, start, end),
            }
        }
        self.finish()
    }

    /// A word the plain G-code rules read, as `Raw::Word` would be.
    pub(super) fn push_word(&mut self, word: WordTok, start: usize, end: usize) {
        let index = self.words.len() as u32;
        self.words.push(LexedWord {
            word,
            start: start as u32,
            end: end as u32,
        });
        if self.pending_term.is_none() {
            if let Some((_, Tok::Words(first, len), run_end)) = self.out.last_mut() {
                if *first + *len == index {
                    *len += 1;
                    *run_end = end;
                    return;
                }
            }
        }
        self.push(start, Tok::Words(index, 1), end);
    }

    pub(super) fn finish(mut self) -> Lexed {
        let eof = self.text.len();
        self.assignments_after_words(eof);
        self.lone_o_name();
        if !self.line_comments.is_empty() {
            self.flush_comments((eof, eof));
        }
        self.send_held_comments();
        if let Some(&OpenSym { start, bracket, .. }) = self.syms.first() {
            self.unclosed_sym(start, bracket);
        }
        if let Some(&(open, bracket)) = self.groups.first() {
            self.report(
                SyntaxErrorKind::UnclosedParen {
                    on_its_line: false,
                    bracket,
                },
                open,
                open + 1,
            );
            self.groups.clear();
            self.push(eof, Tok::RParen, eof);
        }
        let open_braces = std::mem::take(&mut self.braces);
        for &open in open_braces.iter().rev() {
            // After a too-deep block the rest was not read: not unclosed.
            if self.stopped {
                self.push(eof, Tok::RBrace, eof);
                continue;
            }
            self.unclosed_brace = true;
            self.report(SyntaxErrorKind::UnclosedBrace, open, open + 1);
            self.push(eof, Tok::RBrace, eof);
        }
        Lexed {
            tokens: self.out,
            words: self.words,
            errors: self.errors,
            unclosed_brace: self.unclosed_brace,
            call_groups: self.call_groups,
        }
    }

    pub(super) fn token(&mut self, raw: Raw, start: usize, end: usize) {
        let text = &self.text[start..end];
        let tok = match raw {
            Raw::LineComment if self.language == Language::Gcode => {
                // Read as a comment, as in `.egc`, but not silently.
                self.report(SyntaxErrorKind::SlashCommentInGcode, start, start + 2);
                return;
            }
            Raw::LineComment => {
                // `.egc`'s `//` comment, kept for the output.
                self.keep_comment(start + 2, end);
                return;
            }
            Raw::LParen => return,
            Raw::Newline if !self.groups.is_empty() => return self.newline_in_group(start, end),
            Raw::Newline | Raw::Semi => return self.statement_end(start, end),
            Raw::Word => {
                self.push_word(word(text), start, end);
                return;
            }
            Raw::BadNumber => {
                self.report(SyntaxErrorKind::MalformedNumber(text.into()), start, end);
                return;
            }
            Raw::SymOpen => {
                self.open_sym(start, '<', false);
                Tok::SymOpen(text.as_bytes()[0].to_ascii_uppercase())
            }
            Raw::Ident => self.ident(text),
            Raw::Letter => return self.lone_letter(start, end),
            Raw::Number => Tok::Number(parse_decimal(text)),
            Raw::Str => Tok::Str(self.names.intern(&text[1..text.len() - 1])),
            Raw::OpenStr => {
                self.report(SyntaxErrorKind::UnterminatedString, start, end);
                return;
            }
            Raw::RParen => {
                // A `)` closes only a `(`: in G-code, where `(` starts a
                // comment, no group (`X#[1)]` is a typo).
                if self.groups.last().is_none_or(|&(_, open)| open != '(') {
                    self.report(SyntaxErrorKind::UnmatchedParen, start, end);
                    return;
                }
                self.groups.pop();
                Tok::RParen
            }
            Raw::LBrace => match self.open_brace(start, end) {
                Some(tok) => tok,
                None => return,
            },
            Raw::RBrace => match self.close_brace(start, end) {
                Some(tok) => tok,
                None => return,
            },
            Raw::Gt => match self.syms.last() {
                Some(sym) if sym.depth == self.groups.len() => {
                    self.syms.pop();
                    Tok::SymClose
                }
                _ => Tok::Gt,
            },
            Raw::Percent if self.alone_on_line(start, end) => return,
            Raw::Assign => {
                if self.shape == Shape::Code {
                    self.invalid_name(start);
                }
                if self.shape == Shape::NameHead {
                    self.read_only_target();
                }
                Tok::Assign
            }
            Raw::Comma => Tok::Comma,
            Raw::EqEq => Tok::EqEq,
            Raw::NotEq => Tok::NotEq,
            Raw::Lt => Tok::Lt,
            Raw::Le => Tok::Le,
            Raw::Ge => Tok::Ge,
            Raw::AndAnd => Tok::AndAnd,
            Raw::OrOr => Tok::OrOr,
            Raw::Bang => Tok::Bang,
            Raw::Plus => Tok::Plus,
            Raw::Minus => Tok::Minus,
            Raw::Star => Tok::Star,
            Raw::Slash => Tok::Slash,
            Raw::Percent => Tok::Percent,
            Raw::Caret => Tok::Caret,
        };
        self.push(start, tok, end);
    }

    /// A line end inside parentheses: the line goes on after `,`, `(` or an
    /// operator; otherwise the `(` was never closed.
    pub(super) fn newline_in_group(&mut self, start: usize, end: usize) {
        let continues = self
            .out
            .last()
            .is_some_and(|&(_, tok, _)| expects_value(tok));
        if continues {
            return;
        }
        let (open, bracket) = self.groups[0];
        self.report(
            SyntaxErrorKind::UnclosedParen {
                on_its_line: true,
                bracket,
            },
            open,
            open + 1,
        );
        self.groups.clear();
        self.syms.clear();
        self.pending_term.get_or_insert((start, end));
        self.shape = Shape::Empty;
    }

    /// A line end or `;`: the statement ends (and a plain program's
    /// comments of the line follow it).
    pub(super) fn statement_end(&mut self, start: usize, end: usize) {
        if let Some(&OpenSym { start, bracket, .. }) = self.syms.first() {
            self.unclosed_sym(start, bracket);
        }
        self.assignments_after_words(start);
        self.lone_o_name();
        if let Some(call) = self.pending_call.take() {
            self.end_call(call);
        }
        if std::mem::take(&mut self.block_at_line_end) {
            if let Some(tok) = self.open_brace(start, end) {
                self.push(start, tok, start);
            }
        }
        if std::mem::take(&mut self.close_at_line_end) {
            self.pending_term = Some((start, start));
            if let Some(tok) = self.close_brace(start, end) {
                self.push(start, tok, start);
            }
        }
        self.pending_term.get_or_insert((start, end));
        self.flush_comments((start, end));
        self.shape = Shape::Empty;
    }

    /// `{`, unless blocks are nested too deep (then the rest is not read).
    pub(super) fn open_brace(&mut self, start: usize, end: usize) -> Option<Tok> {
        if self.braces.len() >= MAX_BLOCK_DEPTH {
            self.report(SyntaxErrorKind::BlocksTooDeep(MAX_BLOCK_DEPTH), start, end);
            self.stopped = true;
            return None;
        }
        self.braces.push(start);
        Some(Tok::LBrace)
    }

    /// `}`, if a block is open.
    pub(super) fn close_brace(&mut self, start: usize, end: usize) -> Option<Tok> {
        if self.braces.pop().is_none() {
            self.report(SyntaxErrorKind::UnmatchedBrace, start, end);
            return None;
        }
        Some(Tok::RBrace)
    }

    pub(super) fn push(&mut self, start: usize, tok: Tok, end: usize) {
        if !self.held_comments.is_empty()
            && !matches!(tok, Tok::LBrace | Tok::Else | Tok::Comment(_))
        {
            self.send_held_comments();
        }
        if self.pending_term.is_some() || matches!(tok, Tok::LBrace | Tok::RBrace) {
            self.too_long = false;
        } else if self.out.len() - self.stmt_start >= MAX_STATEMENT_TOKENS {
            if !self.too_long {
                self.report(
                    SyntaxErrorKind::StatementTooLong(MAX_STATEMENT_TOKENS),
                    start,
                    end,
                );
                self.too_long = true;
            }
            return;
        }
        if let Some((ts, te)) = self.pending_term.take() {
            let continues = matches!(tok, Tok::LBrace | Tok::Else);
            let after_term = matches!(self.out.last(), None | Some((_, Tok::Term, _)));
            if !continues && !after_term {
                self.out.push((ts, Tok::Term, te));
            }
            self.stmt_start = self.out.len();
        }
        self.shape = match (self.shape, &tok) {
            (_, Tok::LBrace | Tok::RBrace) => Shape::Empty,
            (Shape::Empty, Tok::Name(_)) => Shape::NameHead,
            (Shape::Empty, Tok::If | Tok::While | Tok::Else | Tok::Loop(_) | Tok::Do) => {
                Shape::Keyword
            }
            (Shape::Empty, _) => Shape::Code,
            (Shape::NameHead, Tok::Assign) if self.out.len() == self.stmt_start + 1 => {
                Shape::Assign
            }
            (shape, _) => shape,
        };
        self.out.push((start, tok, end));
        if matches!(tok, Tok::LBrace | Tok::RBrace) {
            self.stmt_start = self.out.len();
        }
    }

    /// Nothing but blanks before `start` on its line.
    pub(super) fn first_on_line(&self, start: usize) -> bool {
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        self.text[line_start..start].trim().is_empty()
    }

    pub(super) fn alone_on_line(&self, start: usize, end: usize) -> bool {
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = self.text[end..]
            .find('\n')
            .map_or(self.text.len(), |i| end + i);
        self.text[line_start..start].trim().is_empty() && self.text[end..line_end].trim().is_empty()
    }

    /// A symbolic word starts at `start` with `bracket` (`<`, `[`);
    /// `with_group`: it ends where the group opened next does (`X#[…]`),
    /// not with its own `]` or `>`.
    pub(super) fn open_sym(&mut self, start: usize, bracket: char, with_group: bool) {
        let depth = self.groups.len();
        self.syms.push(OpenSym {
            start,
            bracket,
            depth,
            with_group,
        });
    }

    /// The symbolic word opened at `open` with `bracket` is not closed.
    pub(super) fn unclosed_sym(&mut self, open: usize, bracket: char) {
        // From the letter to its bracket (`X<`, `X [`, `X#[`).
        let end = self.text[open + 1..]
            .find(bracket)
            .map_or(open + 2, |i| open + 2 + i);
        let kind = SyntaxErrorKind::UnclosedSymbolicWord(bracket);
        self.report(kind, open, end);
        self.syms.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lex(text: &str, at: &Locator, names: &mut Names) -> Lexed {
        lex_from(text, 0, at, names, Language::Egc)
    }
    use crate::syntax::error::SyntaxErrorKind;

    #[test]
    fn a_line_goes_on_inside_parentheses_after_an_operator() {
        let mut names = Names::default();
        let src = "Aa = (1 +\n2)\nG0 X<Aa>\n";
        let lexed = lex(src, &Locator::new(0, src), &mut names);
        assert!(lexed.errors.is_empty(), "{:?}", lexed.errors);
        let src = "Aa = (1\n2)\n";
        let lexed = lex(src, &Locator::new(0, src), &mut names);
        assert_eq!(
            lexed.errors[0].kind,
            SyntaxErrorKind::UnclosedParen {
                on_its_line: true,
                bracket: '('
            }
        );
    }

    fn kinds(src: &str) -> Vec<Tok> {
        let mut names = Names::default();
        lex(src, &Locator::new(0, src), &mut names)
            .tokens
            .into_iter()
            .map(|t| t.1)
            .collect()
    }

    #[test]
    fn compact_words_split() {
        let mut names = Names::default();
        let lexed = lex(
            "N10G01X1.5Y-.5F100",
            &Locator::new(0, "N10G01X1.5Y-.5F100"),
            &mut names,
        );
        assert_eq!(lexed.tokens.len(), 1);
        assert_eq!(lexed.words.len(), 5);
        let y = lexed.words[3];
        assert_eq!((y.word.letter, y.word.value), (b'Y', -0.5));
        assert_eq!((y.start, y.end), (10, 14));
    }

    #[test]
    fn paren_is_comment_on_code_lines_and_group_in_expressions() {
        // A comment is kept, a statement of its own after its line's.
        let comment = |t: &Tok| matches!(t, Tok::Comment(_));
        let cut = kinds("G1 X1 (cut)");
        assert_eq!(cut.len(), 3);
        assert!(matches!(cut[0], Tok::Words(..)) && cut[1] == Tok::Term && comment(&cut[2]));
        assert!(kinds("A_ = (1 + 2)").contains(&Tok::LParen));
        let mm = kinds("Depth = 5 (mm)");
        assert_eq!(mm.len(), 5);
        assert!(comment(&mm[4]) && !mm.contains(&Tok::LParen));
        assert!(kinds("holesLine(1, 2)").contains(&Tok::CallOpen));
    }

    #[test]
    fn an_egc_comment_before_a_brace_or_else_goes_into_the_block_after_it() {
        // `if (c) // x` then `{`, `} // y` then `else`: the comments wait
        // for the block's first statement; no statement end comes between
        // the condition and its `{`, nor between `}` and `else`.
        let toks = kinds("if (Ab) // x\n{\nG1 X1\n} // y\nelse {\nG1 X2 // z\n}\n");
        let at = |t: Tok| toks.iter().position(|u| *u == t).unwrap();
        let comments: Vec<usize> = (0..toks.len())
            .filter(|&i| matches!(toks[i], Tok::Comment(_)))
            .collect();
        assert_eq!(comments.len(), 3, "{toks:?}");
        assert!(comments[0] > at(Tok::LBrace), "{toks:?}");
        assert!(comments[1] > at(Tok::Else), "{toks:?}");
        assert!(!toks
            .windows(2)
            .any(|w| w[0] == Tok::Term && matches!(w[1], Tok::LBrace | Tok::Else)));
    }

    #[test]
    fn newline_before_brace_or_else_continues() {
        let toks = kinds("if (Ab)\n{\nG1 X1\n}\nelse\n{ G1 X2 }\n");
        assert!(!toks
            .windows(2)
            .any(|w| w[0] == Tok::Term && w[1] == Tok::LBrace));
        assert!(!toks
            .windows(2)
            .any(|w| w[0] == Tok::Term && w[1] == Tok::Else));
    }

    #[test]
    fn sym_close_only_at_its_depth() {
        let toks = kinds("G0 X<(Ab > 1) + 2>");
        assert!(toks.contains(&Tok::Gt));
        assert_eq!(toks.last(), Some(&Tok::SymClose));
    }
}
