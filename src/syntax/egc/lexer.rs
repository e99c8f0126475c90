//! Lexer: source text → tokens. logos finds the raw tokens; this module adds
//! what G-code needs and a regular lexer cannot see: whether `(` opens a
//! comment or a group, which `>` closes a symbolic word `X<…>`, `%` lines,
//! and newlines that only continue a statement (before `{` or `else`).
//! It must not build syntax trees or know what a G code means.

use super::error::{SyntaxError, SyntaxErrorKind};
use crate::ast::{BinaryOp, Function, Names, Symbol};
use crate::source::{Locator, Span};
use logos::Logos;

mod fanuc;

#[derive(Logos, Clone, Copy, Debug, PartialEq)]
#[logos(skip r"[ \t\r\f]+")]
enum Raw {
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

/// Which language a file is in (SPEC §2.8): ger's own, or plain G-code as
/// CAM and people write it, where `;` starts a comment, `( … )` is always a
/// comment (nested parentheses included), `:0097` is a program number and a
/// word may have spaces between its letter and number (`G0Z  0.1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Language {
    #[default]
    Egc,
    Gcode,
}

impl Language {
    /// `.egc` is ger's language; every other file is plain G-code.
    pub fn of_file(name: &str) -> Language {
        let lower = name.to_ascii_lowercase();
        if lower.ends_with(".egc") || name == "<stdin>" {
            Language::Egc
        } else {
            Language::Gcode
        }
    }
}

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

/// The tokens the parser sees. `Copy` and allocation-free: names and strings
/// are interned, and a run of plain words is one token.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tok {
    /// Consecutive plain words of one statement: `words[first..first+len]`.
    /// One token per run keeps the parser's work per line small.
    Words(u32, u32),
    /// `X<`: a symbolic word's letter and opening bracket.
    SymOpen(u8),
    /// The `>` that closes a symbolic word.
    SymClose,
    Name(Symbol),
    Number(f64),
    Str(Symbol),
    /// A controller command line of plain G-code (grbl's `$H`), whole.
    Command(Symbol),
    /// A comment of plain G-code, kept for the output; it ends the line
    /// it was on and is its own statement after it.
    Comment(Symbol),
    If,
    Else,
    While,
    /// Fanuc's `GOTO`.
    Goto,
    /// LinuxCNC's and Fanuc's `#` before `#1` or `[…]`: the parameter
    /// whose number is that value.
    Hash,
    /// LinuxCNC's `oN` before `while` or `do`: the loop's label, which a
    /// `break` or `continue` names.
    Loop(u32),
    /// LinuxCNC's `oN do`: a loop tested at its end.
    Do,
    /// LinuxCNC's `oN break` and `oN continue`, with the loop's label.
    Break(u32),
    Continue(u32),
    True,
    False,
    /// `(` that opens a group.
    LParen,
    /// `(` written directly after a name: a call `name(…)`.
    CallOpen,
    RParen,
    LBrace,
    RBrace,
    Comma,
    /// End of statement: newline or `;` (runs collapse into one).
    Term,
    Assign,
    EqEq,
    NotEq,
    Lt,
    Le,
    Gt,
    Ge,
    AndAnd,
    OrOr,
    Bang,
    Plus,
    Minus,
    Star,
    Slash,
    Percent,
    Caret,
    /// LinuxCNC's `MOD`, `**` and unary minus (their own meanings).
    Mod,
    PowLeft,
    NegTight,
    /// LinuxCNC's relational and logical word operators (`GT`, `AND`, …),
    /// which work on numbers.
    Word(BinaryOp),
}

impl Tok {
    /// How the token reads in an error message.
    pub fn describe(&self, names: &Names) -> String {
        match self {
            Tok::Words(_, _) => "a G-code word".into(),
            Tok::SymOpen(l) => format!("`{}<`", *l as char),
            Tok::SymClose => "`>`".into(),
            Tok::Name(s) => format!("name `{}`", names.text(*s)),
            Tok::Number(_) => "number".into(),
            Tok::Str(_) => "a string".into(),
            Tok::Command(_) => "a controller command".into(),
            Tok::Comment(_) => "a comment".into(),
            Tok::Term => "end of statement".into(),
            Tok::Word(op) => format!("`{}`", op.symbol()),
            other => format!("`{}`", other.text()),
        }
    }

    fn text(&self) -> &'static str {
        match self {
            Tok::If => "if",
            Tok::Goto => "GOTO",
            Tok::Hash => "#",
            Tok::Loop(_) => "o-word",
            Tok::Do => "do",
            Tok::Break(_) => "break",
            Tok::Continue(_) => "continue",
            Tok::Else => "else",
            Tok::While => "while",
            Tok::True => "true",
            Tok::False => "false",
            Tok::LParen | Tok::CallOpen => "(",
            Tok::RParen => ")",
            Tok::LBrace => "{",
            Tok::RBrace => "}",
            Tok::Comma => ",",
            Tok::Assign => "=",
            Tok::EqEq => "==",
            Tok::NotEq => "!=",
            Tok::Lt => "<",
            Tok::Le => "<=",
            Tok::Gt | Tok::SymClose => ">",
            Tok::Ge => ">=",
            Tok::AndAnd => "&&",
            Tok::OrOr => "||",
            Tok::Bang => "!",
            Tok::Plus => "+",
            Tok::Minus => "-",
            Tok::Star => "*",
            Tok::Slash => "/",
            Tok::Percent => "%",
            Tok::Caret => "^",
            Tok::Mod => "MOD",
            Tok::PowLeft => "**",
            Tok::NegTight => "-",
            _ => "?",
        }
    }
}

pub type Spanned = (usize, Tok, usize);

/// The name of a LinuxCNC subroutine as written between `o<` and `>`:
/// without surrounding spaces, in lower case (its file is `name.ngc`).
pub fn subroutine_name(written: &str) -> String {
    written.trim().to_ascii_lowercase()
}

/// Why the text after a `#` is not a parameter ger reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotAParameter {
    /// `#<` with no `>` on its line.
    Unclosed,
    /// No number or `<name>`: `#[…]`, `##1` (indirect), or nothing.
    NoName,
}

/// A LinuxCNC parameter read from `rest`, the text after its `#`: the
/// name of its symbol (`#<name>` without case or spaces, as LinuxCNC
/// ignores them; `#12` without leading zeros) and the bytes of `rest` it
/// takes.
pub fn parameter_name(rest: &str) -> Result<(String, usize), NotAParameter> {
    if let Some(inner) = rest.strip_prefix('<') {
        let close = inner
            .find(['>', '\n'])
            .filter(|&i| inner[i..].starts_with('>'))
            .ok_or(NotAParameter::Unclosed)?;
        let name: String = inner[..close]
            .chars()
            .filter(|c| !c.is_whitespace())
            .flat_map(char::to_lowercase)
            .collect();
        return Ok((format!("#<{name}>"), close + 2));
    }
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    if digits == 0 {
        return Err(NotAParameter::NoName);
    }
    let number = rest[..digits].trim_start_matches('0');
    let number = if number.is_empty() { "0" } else { number };
    Ok((format!("#{number}"), digits))
}

/// The last numbered parameter, LinuxCNC's (#5601: rs274 has 5602 from
/// #0, which is not one); a `#[…]` beyond it is an error.
pub const LAST_PARAMETER: u32 = 5601;
/// Tokens in one statement. Expressions are trees the evaluator walks
/// recursively, so their size is bounded where they are read; real
/// statements are far shorter.
pub const MAX_STATEMENT_TOKENS: usize = 1000;
/// `{` blocks nested inside each other.
pub const MAX_BLOCK_DEPTH: usize = 64;
/// Arguments of an `o… call`: a subroutine reads them as `#1` to `#30`.
pub const MAX_CALL_ARGUMENTS: u32 = 30;

/// What the current statement looks like so far; decides what `(` means.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Shape {
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

pub fn lex(text: &str, at: &Locator, names: &mut Names) -> Lexed {
    lex_from(text, 0, at, names, Language::Egc)
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
struct OpenSym {
    start: usize,
    /// `<` (`.egc`) or `[`.
    bracket: char,
    /// The group depth it was opened at.
    depth: usize,
    /// It closes with the group opened after it (`X#[…]`).
    with_group: bool,
}

struct Lexer<'a> {
    text: &'a str,
    /// Where reading starts (a line start; [`lex_from`]).
    from: usize,
    language: Language,
    at: &'a Locator,
    names: &'a mut Names,
    out: Vec<Spanned>,
    words: Vec<LexedWord>,
    errors: Vec<SyntaxError>,
    unclosed_brace: bool,
    call_groups: Vec<usize>,
    shape: Shape,
    /// Index in `out` where the current statement starts.
    stmt_start: usize,
    /// Open groups, innermost last: where each opened, and its bracket
    /// (`(`, or LinuxCNC's and Fanuc's `[`).
    groups: Vec<(usize, char)>,
    /// Open symbolic words, innermost last.
    syms: Vec<OpenSym>,
    braces: Vec<usize>,
    /// A statement end seen but not yet emitted: dropped if `{` or `else`
    /// comes next, so braces and `else` may start a new line.
    pending_term: Option<(usize, usize)>,
    /// Comments of the current line (plain G-code), sent after it.
    line_comments: Vec<(usize, Symbol, usize)>,
    /// The current statement passed `MAX_STATEMENT_TOKENS`: its remaining
    /// tokens are dropped.
    too_long: bool,
    /// Blocks nested too deep: the rest of the file is not read.
    stopped: bool,
    /// A LinuxCNC `if`/`while` line: its block opens at the line's end.
    block_at_line_end: bool,
    /// Group depths of LinuxCNC `ATAN[` calls still at their first argument.
    atan_groups: Vec<usize>,
    /// An `o… call` line being read.
    pending_call: Option<PendingCall>,
    /// The labels of open `oN do` loops, innermost last.
    do_labels: Vec<f64>,
    /// An `oN repeat` line: its counter, and where `repeat` is.
    pending_repeat: Option<(Symbol, usize, usize)>,
    /// An `oN return` or `oN endsub` line being read.
    pending_return: Option<PendingReturn>,
    /// Inside a LinuxCNC `oN sub` … `oN endsub` (a part holds its
    /// subroutines whole: [`super::chunk::cut_part`]).
    in_sub: bool,
    /// The `oN while [c]` that ends a do loop, and Fanuc's `IF [c] THEN`
    /// and `IF [c] GOTO n`: the block closes at the line's end.
    close_at_line_end: bool,
    /// Fanuc's open `WHILE … DOm` loops: their m, innermost last.
    fanuc_loops: Vec<u32>,
    /// `#0`…`#LAST_PARAMETER` are all named (a `#[…]` was read).
    every_parameter_named: bool,
}

/// The program numbers given to LinuxCNC's named subroutines (`o<name>`).
pub const NAMED_SUB_BASE: u32 = 90_000_000;

/// An `o… call` line: its subroutine, the arguments so far, where `call` is.
#[derive(Clone, Copy, Debug)]
struct PendingCall {
    number: f64,
    args: u32,
    at: (usize, usize),
}

/// An `oN return` or `oN endsub` line: where its keyword is, whether a
/// value (`[…]`) was read, and whether the return is at the top of its
/// subroutine (an `M99` there would end the subroutine's text).
#[derive(Clone, Copy, Debug)]
struct PendingReturn {
    at: (usize, usize),
    value: bool,
    top: bool,
    /// `endsub`, which also ends the definition.
    end: bool,
}

/// LinuxCNC's value of the last subroutine's return, and whether it
/// returned one: set by every `return` and `endsub` (0 without a value),
/// read-only to the program.
pub const RETURN_VALUE: &str = "#<_value>";
pub const VALUE_RETURNED: &str = "#<_value_returned>";
/// What [`RETURN_VALUE`] is set to where ger does not know its value: rs274
/// also sets it while it reads a subroutine's definition, to the value of
/// its `endsub [v]` worked out there (with the subroutine's own names read
/// as 0), which ger does not reproduce. Reading it then is an error.
pub const UNKNOWN_RETURN: &str = "#<_value:unknown>";

impl<'a> Lexer<'a> {
    fn new(text: &'a str, from: usize, at: &'a Locator, names: &'a mut Names) -> Lexer<'a> {
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
            too_long: false,
            stopped: false,
            block_at_line_end: false,
            atan_groups: Vec::new(),
            pending_call: None,
            do_labels: Vec::new(),
            pending_repeat: None,
            pending_return: None,
            in_sub: false,
            close_at_line_end: false,
            fanuc_loops: Vec::new(),
            every_parameter_named: false,
        }
    }

    fn span(&self, start: usize, end: usize) -> Span {
        self.at.span(start, end)
    }

    fn report(&mut self, kind: SyntaxErrorKind, start: usize, end: usize) {
        let span = self.span(start, end);
        self.errors.push(SyntaxError::new(kind, span));
    }

    fn run(mut self) -> Lexed {
        let mut raw = Raw::lexer(self.text);
        raw.bump(self.from);
        while let Some(result) = raw.next() {
            let range = raw.span();
            let (start, end) = (range.start, range.end);
            if self.language == Language::Gcode {
                if let Some(skip_to) = self.plain_gcode(result, start, end) {
                    raw.bump(skip_to.saturating_sub(end));
                    continue;
                }
            }
            let Ok(tok) = result else {
                let ch = self.text[start..].chars().next().unwrap_or('?');
                self.report(
                    SyntaxErrorKind::UnknownCharacter(ch),
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
                        // A comment: skip past its `)` (or to the end).
                        raw.bump(close - end);
                    }
                }
                _ => self.token(tok, start, end),
            }
        }
        self.finish()
    }

    /// The rules of plain G-code that differ from `.egc`, for the raw token
    /// at `start..end`: where it took the text, the offset to go on from.
    fn plain_gcode(&mut self, raw: Result<Raw, ()>, start: usize, end: usize) -> Option<usize> {
        if let Some(skip_to) = self.fanuc(&raw, start, end) {
            return Some(skip_to);
        }
        if let Some(skip_to) = self.linuxcnc(raw, start, end) {
            return Some(skip_to);
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
                let number = format!("O{}", &self.text[start + 1..digits]);
                self.push_word(word(&number), start, digits);
                Some(digits)
            }
            // `G0Z  0.1`: spaces between a letter and its number.
            Ok(Raw::Letter) => {
                let number = WordNumber::after(self.text.as_bytes(), end, line_end);
                if !number.is_decimal() {
                    return None;
                }
                let compact = format!("{}{}", &self.text[start..end], &self.text[number.range()]);
                self.push_word(word(&compact), start, number.end);
                Some(number.end)
            }
            _ => None,
        }
    }

    /// LinuxCNC's parameters and expressions in plain G-code, read as the
    /// `.egc` tokens they mean: `#<name>` and `#1` are names, `[ ]` groups
    /// (`X[…]` and `X#1` are symbolic words, `sin[…]` a call), `EQ`…`LE`,
    /// `AND`, `OR`, `MOD` and `**` operators; `O100 sub`/`endsub`/`call`
    /// become `O100`/`M99`/`M98 P100`. Where it took the text, the offset
    /// to go on from.
    fn linuxcnc(&mut self, raw: Result<Raw, ()>, start: usize, end: usize) -> Option<usize> {
        let rest = &self.text[start..];
        match raw {
            Err(()) if rest.starts_with('#') => {
                if self.groups.is_empty() && self.syms.is_empty() {
                    self.end_label(start);
                }
                Some(self.parameter(start))
            }
            Err(()) if rest.starts_with('[') => Some(self.open_bracket(start)),
            Err(())
                if rest.starts_with(']') && self.atan_groups.last() == Some(&self.groups.len()) =>
            {
                Some(self.atan_comma(start))
            }
            Err(()) if rest.starts_with(']') => Some(self.close_bracket(start)),
            Ok(Raw::Star) if self.text[end..].starts_with('*') => {
                self.push(start, Tok::PowLeft, end + 1);
                Some(end + 1)
            }
            // A minus where a value starts, inside brackets: LinuxCNC's
            // unary minus, which takes only the value right after it.
            Ok(Raw::Minus)
                if (!self.groups.is_empty() || !self.syms.is_empty())
                    && self
                        .out
                        .last()
                        .is_some_and(|&(_, tok, _)| expects_value(tok)) =>
            {
                self.push(start, Tok::NegTight, end);
                Some(end)
            }
            Ok(Raw::Letter) => self.expression_word(start, end),
            Ok(Raw::Ident) => self.linuxcnc_ident(start, end),
            Ok(Raw::SymOpen) if rest.starts_with(['o', 'O']) && self.first_on_line(start) => {
                self.named_o_word(start)
            }
            _ => None,
        }
    }

    /// A `[` at `start`: a group, a function's arguments, or the next
    /// argument of an `o… call`; where to go on.
    fn open_bracket(&mut self, start: usize) -> usize {
        if self.groups.is_empty() && self.syms.is_empty() {
            if let Some(pending) = &mut self.pending_call {
                // The next argument of an `o… call`.
                pending.args += 1;
                let name = format!("#<call:{}>", pending.args);
                if self.out.len() > self.stmt_start {
                    self.pending_term = Some((start, start));
                    self.shape = Shape::Empty;
                }
                let symbol = self.names.intern(&name);
                self.push(start, Tok::Name(symbol), start);
                self.push(start, Tok::Assign, start);
            } else if let Some(pending) = self.pending_return.as_mut().filter(|r| !r.value) {
                // The value of an `oN return [v]` or `oN endsub [v]`.
                pending.value = true;
                let symbol = self.names.intern(RETURN_VALUE);
                self.push(start, Tok::Name(symbol), start);
                self.push(start, Tok::Assign, start);
            }
        }
        let call = matches!(self.out.last(), Some(&(_, Tok::Name(n), e))
            if self.text[e..start].trim().is_empty()
                && Function::from_name(self.names.text(n)).is_some());
        if call {
            if let Some((_, Tok::Name(n), e)) = self.out.last_mut() {
                // LinuxCNC's `ATAN[y]/[x]` is atan2(y, x).
                if self.names.text(*n).eq_ignore_ascii_case("atan") {
                    *n = self.names.intern("atan2");
                    self.atan_groups.push(self.groups.len() + 1);
                }
                *e = start;
            }
        }
        self.groups.push((start, '['));
        let tok = if call { Tok::CallOpen } else { Tok::LParen };
        self.push(start, tok, start + 1);
        start + 1
    }

    /// `ATAN[y]/[x]`: the `]/[` between its arguments, read as a comma;
    /// where to go on.
    fn atan_comma(&mut self, start: usize) -> usize {
        self.atan_groups.pop();
        let after = self.text[start + 1..].trim_start();
        let Some(second) = after
            .strip_prefix('/')
            .map(str::trim_start)
            .filter(|a| a.starts_with('['))
        else {
            self.report(SyntaxErrorKind::AtanOneArgument, start, start + 1);
            self.groups.pop();
            self.push(start, Tok::RParen, start + 1);
            return start + 1;
        };
        let open = self.text.len() - second.len();
        self.push(start, Tok::Comma, open + 1);
        open + 1
    }

    /// A symbolic word starts at `start` with `bracket` (`<`, `[`);
    /// `with_group`: it ends where the group opened next does (`X#[…]`),
    /// not with its own `]` or `>`.
    fn open_sym(&mut self, start: usize, bracket: char, with_group: bool) {
        let depth = self.groups.len();
        self.syms.push(OpenSym {
            start,
            bracket,
            depth,
            with_group,
        });
    }

    /// A `]` at `start`: the end of a symbolic word or of a group.
    fn close_bracket(&mut self, start: usize) -> usize {
        match self.syms.last() {
            Some(sym) if sym.depth == self.groups.len() => {
                self.syms.pop();
                self.push(start, Tok::SymClose, start + 1);
            }
            _ if self.groups.pop().is_some() => {
                self.push(start, Tok::RParen, start + 1);
                // `X#[…]`: the word ends with the group.
                let depth = self.groups.len();
                if self
                    .syms
                    .last()
                    .is_some_and(|s| s.with_group && s.depth == depth)
                {
                    self.syms.pop();
                    self.push(start + 1, Tok::SymClose, start + 1);
                }
            }
            _ => self.report(SyntaxErrorKind::UnmatchedBracket, start, start + 1),
        }
        start + 1
    }

    /// `X[…]`, `X#1`, `Z-#2`: a word whose value is an expression. Where
    /// it took the text, the offset to go on from.
    fn expression_word(&mut self, start: usize, end: usize) -> Option<usize> {
        let after = self.text[end..].trim_start_matches([' ', '\t']);
        let at = self.text.len() - after.len();
        let letter = self.text.as_bytes()[start].to_ascii_uppercase();
        if after.starts_with('[') {
            self.open_sym(start, '[', false);
            self.push(start, Tok::SymOpen(letter), at + 1);
            Some(at + 1)
        } else if after.starts_with('#') || after.starts_with("-#") {
            // `Z-#2` is the parameter's negative, as rs274 reads it.
            self.push(start, Tok::SymOpen(letter), end);
            let minus = usize::from(after.starts_with('-'));
            if minus == 1 {
                self.push(at, Tok::NegTight, at + 1);
            }
            let name_end = self.parameter(at + minus);
            let bracket = self.text[name_end..].starts_with('[');
            if bracket && matches!(self.out.last(), Some((_, Tok::Hash, _))) {
                // `X#[…]`: the word ends where the group does.
                self.open_sym(start, '[', true);
            } else {
                self.push(name_end, Tok::SymClose, name_end);
            }
            Some(name_end)
        } else {
            None
        }
    }

    /// A word of letters: an operator inside brackets, FIX or FUP, or an
    /// o-word's keyword.
    fn linuxcnc_ident(&mut self, start: usize, end: usize) -> Option<usize> {
        let text = &self.text[start..end];
        if let Some(tok) = self.operator(text) {
            self.push(start, tok, end);
            return Some(end);
        }
        if let Some(taken) = self.operator_then_number(start, end) {
            return Some(taken);
        }
        // LinuxCNC's FIX and FUP round down and up.
        let rounding = [("fix", "floor"), ("fup", "ceil")]
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(text));
        if let Some((_, name)) = rounding {
            if self.text[end..].trim_start().starts_with('[') {
                let symbol = self.names.intern(name);
                self.push(start, Tok::Name(symbol), end);
                return Some(end);
            }
        }
        self.o_word(text, start, end)
    }

    /// An operator written against the number after it, inside brackets
    /// (`[#1EQ1]`, `[#2GT0.5]`: rs274 and Fanuc read them so): the
    /// operator, then the number; where they end.
    fn operator_then_number(&mut self, start: usize, end: usize) -> Option<usize> {
        let text = &self.text[start..end];
        let digits = text.find(|c: char| c.is_ascii_digit())?;
        let tok = self.operator(&text[..digits])?;
        if !text[digits..].bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        // The number may go on past what the lexer took: `1.5`.
        let bytes = self.text.as_bytes();
        let mut number_end = end;
        if bytes.get(number_end) == Some(&b'.') {
            number_end += 1;
            while bytes.get(number_end).is_some_and(u8::is_ascii_digit) {
                number_end += 1;
            }
        }
        let number = parse_decimal(&self.text[start + digits..number_end]);
        self.push(start, tok, start + digits);
        self.push(start + digits, Tok::Number(number), number_end);
        Some(number_end)
    }

    /// `o<name>`: a named subroutine, given a number of its own.
    fn named_o_word(&mut self, start: usize) -> Option<usize> {
        let rest = &self.text[start..];
        let close = rest
            .find(['>', '\n'])
            .filter(|&i| rest[i..].starts_with('>'))?;
        // Numbered by its name's symbol: the same in every file read with
        // the same names (a subroutine in a file of its own).
        let name = subroutine_name(&rest[2..close]);
        let symbol = self.names.intern(&format!("o<{name}>"));
        let number = format!("O{}", NAMED_SUB_BASE + symbol.0);
        self.push_word(word(&number), start, start + close + 1);
        Some(start + close + 1)
    }

    /// `#<name>` or `#123` at `start`, pushed as a name; or the `#` of an
    /// indirect parameter (`##1`, `#[…]`), pushed as [`Tok::Hash`] before
    /// the parameter or the `[` it reads. Where it ends.
    fn parameter(&mut self, mut start: usize) -> usize {
        loop {
            match parameter_name(&self.text[start + 1..]) {
                Ok((name, used)) => {
                    let end = start + 1 + used;
                    let symbol = self.names.intern(&name);
                    self.push(start, Tok::Name(symbol), end);
                    return end;
                }
                Err(NotAParameter::Unclosed) => {
                    self.report(SyntaxErrorKind::UnclosedParameter, start, start + 2);
                    return start + 2;
                }
                Err(NotAParameter::NoName) => {
                    let after = self.text[start + 1..].trim_start_matches([' ', '\t']);
                    let next = self.text.len() - after.len();
                    // `# 1`: rs274 reads a line without its spaces.
                    if let (true, Ok((name, used))) = (next > start + 1, parameter_name(after)) {
                        let symbol = self.names.intern(&name);
                        self.push(start, Tok::Name(symbol), next + used);
                        return next + used;
                    }
                    if !after.starts_with(['#', '[']) {
                        self.report(SyntaxErrorKind::NotAParameter, start, start + 1);
                        return start + 1;
                    }
                    self.push(start, Tok::Hash, start + 1);
                    self.name_every_parameter();
                    if after.starts_with('[') {
                        return next;
                    }
                    start = next;
                }
            }
        }
    }

    /// Every numbered parameter a `#[…]` may reach gets its name (once):
    /// the evaluator finds a computed parameter by its name.
    fn name_every_parameter(&mut self) {
        if !self.every_parameter_named {
            self.every_parameter_named = true;
            for n in 0..=LAST_PARAMETER {
                self.names.intern(&format!("#{n}"));
            }
        }
    }

    /// LinuxCNC's word operators, inside brackets.
    fn operator(&self, text: &str) -> Option<Tok> {
        if self.groups.is_empty() && self.syms.is_empty() {
            return None;
        }
        const OPERATORS: [(&str, Tok); 10] = [
            ("EQ", Tok::Word(BinaryOp::NumEq)),
            ("NE", Tok::Word(BinaryOp::NumNe)),
            ("GT", Tok::Word(BinaryOp::NumGt)),
            ("GE", Tok::Word(BinaryOp::NumGe)),
            ("LT", Tok::Word(BinaryOp::NumLt)),
            ("LE", Tok::Word(BinaryOp::NumLe)),
            ("AND", Tok::Word(BinaryOp::NumAnd)),
            ("OR", Tok::Word(BinaryOp::NumOr)),
            ("XOR", Tok::Word(BinaryOp::NumXor)),
            ("MOD", Tok::Mod),
        ];
        find_word(&OPERATORS, text)
    }

    /// The LinuxCNC o-word keyword after the O word of this line: `sub`,
    /// `endsub` and `call` become `O100`, `M99` and `M98 P100`; `if`,
    /// `elseif`, `else`, `endif`, `while`, `endwhile` become `.egc` blocks
    /// (the O word is only their label).
    fn o_word(&mut self, text: &str, start: usize, end: usize) -> Option<usize> {
        let keyword = OWord::from_text(text)?;
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        // The keyword must come right after its O word, the last token.
        let count = self.words.len();
        let right_after = matches!(self.out.last(), Some(&(_, Tok::Words(first, len), _))
            if (first + len) as usize == count);
        let last = self
            .words
            .last_mut()
            .filter(|w| right_after && w.word.letter == b'O' && w.start as usize >= line_start)?;
        let number = last.word.value;
        // O numbers are whole and below 2^32 (named ones included).
        let label = number as u32;
        match keyword {
            OWord::Sub => self.in_sub = true,
            // `#<_value> = [v]`, `#<_value_returned> = 1` (or both 0),
            // then `M99`: written at the line's end.
            OWord::EndSub | OWord::Return => {
                self.drop_label();
                let top = keyword == OWord::Return && self.braces.is_empty();
                if keyword == OWord::EndSub {
                    self.in_sub = false;
                } else if !self.in_sub {
                    self.report(SyntaxErrorKind::ReturnOutsideSub, start, end);
                    return Some(end);
                }
                self.pending_return = Some(PendingReturn {
                    at: (start, end),
                    value: false,
                    top,
                    end: keyword == OWord::EndSub,
                });
            }
            OWord::Call => {
                // `#<call:k> = [arg]` for each argument, `#<call> = count`,
                // then `M98 P100`: written at the line's end.
                self.drop_label();
                self.pending_call = Some(PendingCall {
                    number,
                    args: 0,
                    at: (start, end),
                });
            }
            // `oN do … oN while [c]`: `do { … } while (c)`.
            OWord::Do => {
                self.drop_label();
                self.push(start, Tok::Loop(label), end);
                self.push(start, Tok::Do, end);
                self.block_at_line_end = true;
                self.do_labels.push(number);
            }
            OWord::Break | OWord::Continue => {
                self.drop_label();
                let tok = if keyword == OWord::Break {
                    Tok::Break(label)
                } else {
                    Tok::Continue(label)
                };
                self.push(start, tok, end);
            }
            // `oN repeat [n] … oN endrepeat`: `#<repeat:N> = [n]; while
            // (#<repeat:N> >= 1) { #<repeat:N> = #<repeat:N> - 1 … }`.
            OWord::Repeat => {
                self.drop_label();
                let count = self.names.intern(&format!("#<repeat:{number}>"));
                self.push(start, Tok::Name(count), end);
                self.push(start, Tok::Assign, end);
                self.pending_repeat = Some((count, start, end));
            }
            OWord::EndRepeat => {
                self.drop_label();
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
            }
            OWord::While if self.do_labels.last() == Some(&number) => {
                self.drop_label();
                self.do_labels.pop();
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
                self.push(start, Tok::While, end);
            }
            OWord::While => {
                self.drop_label();
                self.push(start, Tok::Loop(label), end);
                self.push(start, Tok::While, end);
                self.block_at_line_end = true;
            }
            OWord::If => {
                self.drop_label();
                self.push(start, Tok::If, end);
                self.block_at_line_end = true;
            }
            OWord::ElseIf | OWord::Else => {
                self.drop_label();
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
                self.push(start, Tok::Else, end);
                if keyword == OWord::ElseIf {
                    self.push(start, Tok::If, end);
                    self.block_at_line_end = true;
                } else if let Some(tok) = self.open_brace(start, end) {
                    self.push(start, tok, end);
                }
            }
            OWord::EndIf | OWord::EndWhile => {
                self.drop_label();
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
            }
        }
        Some(end)
    }

    /// The end of an `o… call` line: the argument count, then the call.
    fn end_call(&mut self, call: PendingCall) {
        let (start, end) = call.at;
        if call.args > MAX_CALL_ARGUMENTS {
            self.report(
                SyntaxErrorKind::TooManyArguments(MAX_CALL_ARGUMENTS),
                start,
                end,
            );
        }
        if self.out.len() > self.stmt_start {
            self.pending_term = Some((start, start));
            self.shape = Shape::Empty;
        }
        let marker = self.names.intern("#<call>");
        self.push(start, Tok::Name(marker), end);
        self.push(start, Tok::Assign, end);
        self.push(start, Tok::Number(call.args as f64), end);
        self.pending_term = Some((start, start));
        self.shape = Shape::Empty;
        self.push_word(word("M98"), start, end);
        // With a point: `P90000000` would be Fanuc's count-and-number form.
        let number = format!("P{}.", call.number);
        self.push_word(word(&number), start, end);
    }

    /// The end of an `oN return` or `oN endsub` line: the value (0 if none
    /// was given) and whether there was one, then `M99`; at the top of a
    /// subroutine, in a block that always runs (`M99` there would end the
    /// subroutine's text).
    fn end_return(&mut self, pending: PendingReturn) {
        let (start, end) = pending.at;
        // Each a statement of its own, after the value's if one was read.
        let statement = |lexer: &mut Self, toks: &[Tok]| {
            lexer.pending_term = Some((start, start));
            lexer.shape = Shape::Empty;
            for &tok in toks {
                lexer.push(start, tok, end);
            }
        };
        let value = self.names.intern(RETURN_VALUE);
        let returned = self.names.intern(VALUE_RETURNED);
        if !pending.value {
            statement(self, &[Tok::Name(value), Tok::Assign, Tok::Number(0.0)]);
        }
        let given = f64::from(u8::from(pending.value));
        statement(
            self,
            &[Tok::Name(returned), Tok::Assign, Tok::Number(given)],
        );
        if pending.top {
            statement(self, &[Tok::If, Tok::LParen, Tok::Number(1.0), Tok::RParen]);
            if let Some(tok) = self.open_brace(start, end) {
                self.push(start, tok, end);
            }
        }
        statement(self, &[]);
        self.push_word(word("M99"), start, end);
        if pending.top {
            self.pending_term = Some((start, start));
            if let Some(tok) = self.close_brace(start, end) {
                self.push(start, tok, end);
            }
        }
        // After the definition, in the program around it: rs274 sets both
        // as it reads the `endsub` line (the value as [`UNKNOWN_RETURN`]
        // says).
        if pending.end {
            let after = match pending.value {
                true => Tok::Name(self.names.intern(UNKNOWN_RETURN)),
                false => Tok::Number(0.0),
            };
            statement(self, &[Tok::Name(value), Tok::Assign, after]);
            statement(
                self,
                &[Tok::Name(returned), Tok::Assign, Tok::Number(given)],
            );
        }
    }

    /// Nothing but blanks before `start` on its line.
    fn first_on_line(&self, start: usize) -> bool {
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        self.text[line_start..start].trim().is_empty()
    }

    /// Drop the O word just read: it only labels a block.
    fn drop_label(&mut self) {
        self.words.pop();
        let index = self.words.len() as u32;
        if let Some((_, Tok::Words(first, len), _)) = self.out.last_mut() {
            if *first + *len == index + 1 {
                *len -= 1;
                if *len == 0 {
                    self.out.pop();
                }
            }
        }
        if self.out.len() <= self.stmt_start {
            self.shape = Shape::Empty;
        }
    }

    /// A `( … )` comment of plain G-code, which may hold parentheses of its
    /// own; it ends with its line. Returns where the text goes on.
    fn nested_comment(&mut self, start: usize, line_end: usize) -> usize {
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
    fn keep_comment(&mut self, start: usize, end: usize) {
        let text = self.text[start..end].trim();
        if text.is_empty() {
            return;
        }
        let symbol = self.names.note(text);
        self.line_comments.push((start, symbol, end));
    }

    /// The comments of the line that ends here, each a statement of its own.
    fn flush_comments(&mut self, at: (usize, usize)) {
        for (start, symbol, end) in std::mem::take(&mut self.line_comments) {
            self.pending_term.get_or_insert(at);
            self.push(start, Tok::Comment(symbol), end);
        }
        self.pending_term.get_or_insert(at);
    }

    /// A word the plain G-code rules read, as `Raw::Word` would be.
    fn push_word(&mut self, word: WordTok, start: usize, end: usize) {
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

    fn finish(mut self) -> Lexed {
        let eof = self.text.len();
        self.assignments_after_words(eof);
        if !self.line_comments.is_empty() {
            self.flush_comments((eof, eof));
        }
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

    /// Decide what `(` at `start` is. Returns the end of a comment to skip.
    fn lparen(&mut self, start: usize) -> Option<usize> {
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

    /// Is the last token the end of a value (so `(` after it is a comment)?
    fn after_value(&self) -> bool {
        match self.out.last() {
            Some((_, Tok::Name(s), _)) => Function::from_name(self.names.text(*s)).is_none(),
            Some((_, t, _)) => matches!(
                t,
                Tok::Number(_) | Tok::Str(_) | Tok::True | Tok::False | Tok::RParen
            ),
            None => false,
        }
    }

    fn token(&mut self, raw: Raw, start: usize, end: usize) {
        let text = &self.text[start..end];
        let tok = match raw {
            Raw::LineComment if self.language == Language::Gcode => {
                // Read as a comment, as in `.egc`, but not silently.
                self.report(SyntaxErrorKind::SlashCommentInGcode, start, start + 2);
                return;
            }
            Raw::LineComment | Raw::LParen => return,
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
                if let (Shape::NameHead, Some(&(at, Tok::Name(name), name_end))) =
                    (self.shape, self.out.last())
                {
                    let text = self.names.text(name);
                    if text == RETURN_VALUE || text == VALUE_RETURNED {
                        let kind = SyntaxErrorKind::ReadOnlyParameter(text.to_string());
                        self.report(kind, at, name_end);
                    }
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
    fn newline_in_group(&mut self, start: usize, end: usize) {
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

    /// A line of plain G-code with words and parameter assignments
    /// (`#1=5 G1 X#1`): rs274 reads every word and value with the
    /// parameters as they were before the line and sets them after it, so
    /// the words become a statement of their own, followed by the
    /// assignments. Any other mix is left for the parser to report.
    fn assignments_after_words(&mut self, at: usize) {
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

    /// A line end or `;`: the statement ends (and a plain program's
    /// comments of the line follow it).
    fn statement_end(&mut self, start: usize, end: usize) {
        if let Some(&OpenSym { start, bracket, .. }) = self.syms.first() {
            self.unclosed_sym(start, bracket);
        }
        self.assignments_after_words(start);
        if let Some(call) = self.pending_call.take() {
            self.end_call(call);
        }
        if let Some(pending) = self.pending_return.take() {
            self.end_return(pending);
        }
        if let Some((count, at, at_end)) = self.pending_repeat.take() {
            self.pending_term = Some((at, at));
            self.shape = Shape::Empty;
            for tok in [
                Tok::While,
                Tok::LParen,
                Tok::Name(count),
                Tok::Ge,
                Tok::Number(1.0),
                Tok::RParen,
            ] {
                self.push(at, tok, at_end);
            }
            if let Some(tok) = self.open_brace(at, at_end) {
                self.push(at, tok, at_end);
            }
            self.pending_term = Some((at, at));
            for tok in [
                Tok::Name(count),
                Tok::Assign,
                Tok::Name(count),
                Tok::Minus,
                Tok::Number(1.0),
            ] {
                self.push(at, tok, at_end);
            }
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

    /// A letter with no number: an address without its value, or a
    /// one-letter name in an expression.
    fn lone_letter(&mut self, start: usize, end: usize) {
        let text = &self.text[start..end];
        let in_expression = !self.groups.is_empty()
            || !self.syms.is_empty()
            || matches!(self.shape, Shape::Assign | Shape::Keyword);
        let kind = if in_expression {
            SyntaxErrorKind::LetterAsName(text.into())
        } else {
            SyntaxErrorKind::LetterWithoutNumber(text.into())
        };
        self.report(kind, start, end);
    }

    /// `{`, unless blocks are nested too deep (then the rest is not read).
    fn open_brace(&mut self, start: usize, end: usize) -> Option<Tok> {
        if self.braces.len() >= MAX_BLOCK_DEPTH {
            self.report(SyntaxErrorKind::BlocksTooDeep(MAX_BLOCK_DEPTH), start, end);
            self.stopped = true;
            return None;
        }
        self.braces.push(start);
        Some(Tok::LBrace)
    }

    /// `}`, if a block is open.
    fn close_brace(&mut self, start: usize, end: usize) -> Option<Tok> {
        if self.braces.pop().is_none() {
            self.report(SyntaxErrorKind::UnmatchedBrace, start, end);
            return None;
        }
        Some(Tok::RBrace)
    }

    fn ident(&mut self, text: &str) -> Tok {
        const KEYWORDS: [(&str, Tok); 5] = [
            ("if", Tok::If),
            ("else", Tok::Else),
            ("while", Tok::While),
            ("true", Tok::True),
            ("false", Tok::False),
        ];
        find_word(&KEYWORDS, text).unwrap_or_else(|| Tok::Name(self.names.intern(text)))
    }

    fn push(&mut self, start: usize, tok: Tok, end: usize) {
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

    fn alone_on_line(&self, start: usize, end: usize) -> bool {
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = self.text[end..]
            .find('\n')
            .map_or(self.text.len(), |i| end + i);
        self.text[line_start..start].trim().is_empty() && self.text[end..line_end].trim().is_empty()
    }

    /// The symbolic word opened at `open` with `bracket` is not closed.
    fn unclosed_sym(&mut self, open: usize, bracket: char) {
        // From the letter to its bracket (`X<`, `X [`, `X#[`).
        let end = self.text[open + 1..]
            .find(bracket)
            .map_or(open + 2, |i| open + 2 + i);
        let kind = SyntaxErrorKind::UnclosedSymbolicWord(bracket);
        self.report(kind, open, end);
        self.syms.clear();
    }

    /// `P0X = 5`: the user meant a variable, but a letter and a digit make a
    /// word. Report it and read the statement as an assignment to that name.
    fn invalid_name(&mut self, assign_at: usize) {
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

/// The token a word of `table` stands for, matched without case.
/// Whether a value must come after `tok` (an operator, an opening
/// bracket, a comma): a minus after it is LinuxCNC's unary minus, and a
/// line end after it inside parentheses does not end the statement.
fn expects_value(tok: Tok) -> bool {
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

/// The keywords of LinuxCNC's o-words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OWord {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Repeat,
    EndRepeat,
    Break,
    Continue,
}

impl OWord {
    fn from_text(text: &str) -> Option<OWord> {
        const KEYWORDS: [(&str, OWord); 15] = [
            ("sub", OWord::Sub),
            ("endsub", OWord::EndSub),
            ("call", OWord::Call),
            ("return", OWord::Return),
            ("if", OWord::If),
            ("elseif", OWord::ElseIf),
            ("else", OWord::Else),
            ("endif", OWord::EndIf),
            ("while", OWord::While),
            ("endwhile", OWord::EndWhile),
            ("do", OWord::Do),
            ("repeat", OWord::Repeat),
            ("endrepeat", OWord::EndRepeat),
            ("break", OWord::Break),
            ("continue", OWord::Continue),
        ];
        find_word(&KEYWORDS, text)
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

/// The entry of `table` whose word is `text`, in either case.
fn find_word<T: Copy>(table: &[(&str, T)], text: &str) -> Option<T> {
    table
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(text))
        .map(|&(_, t)| t)
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
/// `None` where [`WordNumber::is_decimal`] is false.
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
/// or tabs, a sign, then digits and points (`G0Z  0.1`, `X -1.5`).
pub(crate) struct WordNumber<'a> {
    bytes: &'a [u8],
    /// Where its sign (or its first digit) is.
    sign: usize,
    /// Where its digits and points start, and its end.
    digits: usize,
    pub end: usize,
    points: usize,
}

impl WordNumber<'_> {
    /// The number in `bytes[from..end]`, `from` just after the letter.
    pub(crate) fn after(bytes: &[u8], from: usize, end: usize) -> WordNumber<'_> {
        let mut i = from;
        while i < end && matches!(bytes[i], b' ' | b'\t') {
            i += 1;
        }
        let sign = i;
        if i < end && matches!(bytes[i], b'+' | b'-') {
            i += 1;
        }
        let (digits, mut points) = (i, 0);
        while i < end && matches!(bytes[i], b'0'..=b'9' | b'.') {
            points += usize::from(bytes[i] == b'.');
            i += 1;
        }
        WordNumber {
            bytes,
            sign,
            digits,
            end: i,
            points,
        }
    }

    /// The sign and digits, without the blanks before them.
    pub(crate) fn range(&self) -> std::ops::Range<usize> {
        self.sign..self.end
    }

    /// Some digits and points.
    pub(crate) fn has_digits(&self) -> bool {
        self.end > self.digits
    }

    /// The digits and points of the number (after its sign).
    pub(crate) fn body(&self) -> &[u8] {
        &self.bytes[self.digits..self.end]
    }

    /// A decimal number the lexer reads: a digit, and one point at most.
    pub(crate) fn is_decimal(&self) -> bool {
        self.has_digits() && self.body() != b"." && self.points <= 1
    }
}

fn word(text: &str) -> WordTok {
    let (value, int_digits, has_point) = scan_decimal(&text[1..]);
    WordTok {
        letter: text.as_bytes()[0].to_ascii_uppercase(),
        value,
        int_digits,
        has_point,
    }
}

fn parse_decimal(text: &str) -> f64 {
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
    fn reads_alike(text: &str) {
        let found = WordNumber::after(text.as_bytes(), 0, text.len());
        let expected = found.is_decimal().then(|| {
            let (v, digits, point) = scan_decimal(&text[found.range()]);
            (v.to_bits(), digits, point, found.end)
        });
        let got = decimal_after(text, 0, text.len()).map(|(v, d, p, e)| (v.to_bits(), d, p, e));
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
        assert_eq!(kinds("G1 X1 (cut)").len(), 1);
        assert!(kinds("A_ = (1 + 2)").contains(&Tok::LParen));
        assert_eq!(kinds("Depth = 5 (mm)").len(), 3);
        assert!(kinds("holesLine(1, 2)").contains(&Tok::CallOpen));
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

    #[test]
    fn sym_close_only_at_its_depth() {
        let toks = kinds("G0 X<(Ab > 1) + 2>");
        assert!(toks.contains(&Tok::Gt));
        assert_eq!(toks.last(), Some(&Tok::SymClose));
    }
}
