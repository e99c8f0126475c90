//! The tokens the grammar reads, shared by every language's rules: what
//! the lexer hands the parser. It must not know how they are found.

use crate::ast::{BinaryOp, Names, OName, Symbol};

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
    /// LinuxCNC's `o<name>`, read before its keyword takes it: left in
    /// the stream only when no keyword follows (a syntax error).
    OName(OName),
    /// LinuxCNC's `oN` before `while` or `do`: the loop's label, which a
    /// `break` or `continue` names.
    Loop(OName),
    /// LinuxCNC's `oN do`: a loop tested at its end.
    Do,
    /// LinuxCNC's `oN break` and `oN continue`, with the loop's label.
    Break(OName),
    Continue(OName),
    /// LinuxCNC's `oN sub`: a subprogram starts.
    Sub(OName),
    /// LinuxCNC's `oN call`; its arguments follow, each in `[ ]`.
    SubCall(OName),
    /// LinuxCNC's `oN return` (false) and `oN endsub` (true); a value in
    /// `[ ]` may follow.
    Return(bool),
    /// LinuxCNC's `oN repeat`: its count in `[ ]`, then its block.
    Repeat(OName),
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
            Tok::Loop(_) | Tok::OName(_) => "o-word",
            Tok::Sub(_) => "sub",
            Tok::SubCall(_) => "call",
            Tok::Return(false) => "return",
            Tok::Return(true) => "endsub",
            Tok::Repeat(_) => "repeat",
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
