//! The problems of reading a program's text, as data: what the lexer, the
//! grammar and the O…M99 split find, each a kind and the span it points
//! at. [`SyntaxError::to_diagnostic`] is the one place their wording
//! lives; the code that finds a problem decides its kind, never its words.

use super::language::Language;
use crate::diagnostic::{error, note, warning, Diagnostic, DiagnosticExt, Located, Wording};
use crate::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub enum SyntaxErrorKind {
    /// A character no token starts with, in a file of `Language`.
    UnknownCharacter(char, Language),
    /// A group (`(` in `.egc`, `[` in G-code: `bracket`) still open when
    /// its line ended (`on_its_line`) or when the file ended.
    UnclosedParen {
        on_its_line: bool,
        bracket: char,
    },
    /// `)` with no group open.
    UnmatchedParen,
    /// LinuxCNC's `]` with no `[` open.
    UnmatchedBracket,
    /// Fanuc's `ENDm` that closes no `DOm`: its m, and the open loop's.
    EndMismatch {
        end: u32,
        open: Option<u32>,
    },
    /// `{` never closed.
    UnclosedBrace,
    /// `}` with no block open.
    UnmatchedBrace,
    /// `X<` whose `>` never comes on its line.
    /// `X<…` (`.egc`) or `X[…`, `X#[…` (LinuxCNC, Fanuc) without its
    /// closing bracket on the line; the opening bracket.
    UnclosedSymbolicWord(char),
    /// `( … )` with no `)`: plain G-code's ends with its line, `.egc`'s
    /// at the next `)`.
    UnclosedComment(Language),
    UnterminatedString,
    /// A number with more than one decimal point, as written.
    MalformedNumber(String),
    /// `//` in plain G-code, read as a comment (a warning).
    SlashCommentInGcode,
    /// A single letter where an expression wants a name.
    LetterAsName(String, Language),
    /// A letter with no number where a word belongs.
    LetterWithoutNumber(String, Language),
    /// `P0X = 5`: a word where a name was meant, and the name it could be
    /// (its letters, then its digits), if it has two letters.
    WordAsName {
        written: String,
        respelled: Option<String>,
    },
    /// `{` blocks nested deeper than the limit: the rest is not read.
    BlocksTooDeep(usize),
    /// A statement of more tokens than the limit: the rest is dropped.
    StatementTooLong(usize),
    /// `#<` with no `>` on its line.
    UnclosedParameter,
    /// A `#` followed by no number, `<name>`, `#` or `[`.
    NotAParameter,
    /// `ATAN[y]` without its `/[x]`.
    AtanOneArgument,
    /// An o-word `return` outside a subroutine.
    ReturnOutsideSub,
    /// An assignment to a parameter only a subroutine's return sets.
    ReadOnlyParameter(String),
    /// An `o… call` with more arguments than a subroutine takes.
    TooManyArguments(u32),
    /// The grammar did not expect a token: the token as the message names
    /// it, what it expected instead, and hints that fit the tokens around.
    UnexpectedToken {
        what: String,
        expected: String,
        hints: Vec<ParseHint>,
    },
    /// The text ended where the grammar expected `expected`.
    UnexpectedEnd {
        expected: String,
    },
    /// A token after a complete program.
    ExtraToken {
        what: String,
    },
    /// LALRPOP's own lexer's error; ger's tokens should never make it.
    InvalidToken,
    /// An O number that is not a whole number from 0 to 99999999.
    InvalidProgramNumber,
    /// Subprogram `name` (`O100`, `o<name>`) has no M99 before the next
    /// program (`next`) or the end of the file.
    SubprogramWithoutM99 {
        name: String,
        next: Option<Span>,
    },
    /// Subprogram `name` again; where it was first.
    SubprogramTwice {
        name: String,
        first: Span,
    },
    /// Lines after the main program's end (the `M2`/`M30` at `end`) that
    /// are not subprograms: not read (a note, at the first).
    NotReadAfterEnd {
        lines: usize,
        end: Span,
    },
    /// Lines after a tape's closing `%` (at `end`; the program started
    /// with `%`): not read (a note, at the first).
    NotReadAfterTape {
        lines: usize,
        end: Span,
    },
}

/// Why a parse error may have happened, read from the tokens around it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParseHint {
    /// Right after `if` or `while`.
    ConditionInParentheses,
    /// `=` where `==` would fit.
    CompareWithEqEq,
    /// `else` not after an `if` block.
    ElseAfterIf,
    /// A name where a word was expected: likely a comment's text.
    CommentSyntax(Language),
    /// A word letter glued to a name (`XDd`): the name's value was meant,
    /// `X<Dd>` (`.egc`) or `X#<Dd>` (plain G-code).
    ValueFromName {
        letter: char,
        name: String,
        language: Language,
    },
    /// No `{` after the condition of an `if` (true) or a `while` (false).
    BlockAfter { is_if: bool },
    /// Inside a wizard call's `( … )`, which groups.
    CommentInCall,
}

/// What goes wrong, and where: see [`SyntaxErrorKind`].
pub type SyntaxError = Located<SyntaxErrorKind>;

impl Wording for SyntaxErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        use SyntaxErrorKind::*;
        match self {
            UnknownCharacter(ch, language) => error(
                format!("unexpected character `{}`", ch.escape_default()),
                at,
                "ger does not know this character",
            )
            .with_help(match language {
                Language::Egc => "comments are written `( … )` on G-code lines or `// …` anywhere",
                Language::Gcode => "comments are written `( … )` or after `;`",
            }),
            UnclosedParen {
                on_its_line,
                bracket,
            } => {
                let (name, close) = match bracket {
                    '[' => ("bracket", ']'),
                    _ => ("parenthesis", ')'),
                };
                let when = if *on_its_line {
                    "is not closed on its line"
                } else {
                    "is never closed"
                };
                error(
                    format!("unclosed `{bracket}`"),
                    at,
                    format!("this {name} {when}"),
                )
                .with_help(format!("add the matching `{close}`"))
            }
            UnmatchedParen => error("unmatched `)`", at, "no `(` is open here"),
            UnmatchedBracket => error("unmatched `]`", at, "no `[` is open here"),
            EndMismatch { end, open } => match open {
                Some(open) => error(
                    format!("END{end} closes the loop DO{open}"),
                    at,
                    format!("the innermost open loop is DO{open}"),
                )
                .with_help("close loops in the opposite order: `WHILE [..] DO1 … WHILE [..] DO2 … END2 … END1`"),
                None => error(format!("END{end} without a DO{end}"), at, "no WHILE loop is open here"),
            },
            UnclosedBrace => error("unclosed `{`", at, "this block is never closed")
                .with_help("add the matching `}`"),
            UnmatchedBrace => error("unmatched `}`", at, "no block is open here")
                .with_help("remove it, or add the `{` that opens the block"),
            UnclosedSymbolicWord('<') => error(
                "unclosed `<` in a symbolic word",
                at,
                "this `<` is never closed",
            )
            .with_help("a symbolic word is written `X<expression>`, all on one line"),
            UnclosedSymbolicWord(open) => error(
                format!("unclosed `{open}` in a word's expression"),
                at,
                format!("this `{open}` is never closed"),
            )
            .with_help("a word's expression is written `X[expression]`, all on one line"),
            UnclosedComment(Language::Gcode) => error(
                "unclosed comment",
                at,
                "this comment is not closed on its line",
            )
            .with_help("a `( … )` comment ends with a `)` on the same line"),
            UnclosedComment(Language::Egc) => {
                error("unclosed comment", at, "this comment is never closed")
                    .with_help("a `( … )` comment ends at the next `)`; add one")
            }
            UnterminatedString => error(
                "unterminated string",
                at,
                "this string has no closing `\"`",
            )
            .with_help("strings end on the line they start on"),
            SlashCommentInGcode => warning(
                "`//` read as a comment in plain G-code",
                at,
                "the rest of the line is not read",
            )
            .with_note("`//` comments are ger's `.egc` language; LinuxCNC refuses them")
            .with_help("write the comment as `( … )` or after `;`"),
            MalformedNumber(text) => error(
                format!("malformed number `{text}`"),
                at,
                "more than one decimal point",
            )
            .with_help("a number has at most one `.`: `1.25`, `.5`, `10.`"),
            LetterAsName(text, language) => error(
                format!("`{text}` is not a variable name"),
                at,
                "a single letter is a G-code address, not a name",
            )
            .with_help(match language {
                Language::Egc => format!(
                    "a variable name needs at least two characters: `{text}{text}`, `{text}_`"
                ),
                Language::Gcode => "a parameter is written `#1` or `#<name>`".to_string(),
            }),
            LetterWithoutNumber(text, language) => error(
                format!("`{text}` without a number"),
                at,
                "a word needs a number after its letter",
            )
            .with_help(match language {
                Language::Egc => format!(
                    "write `{u}10` or `{u}<expression>` (a negative one: `{u}<-expression>`)",
                    u = text.to_ascii_uppercase()
                ),
                Language::Gcode => format!(
                    "write `{u}10`, `{u}#1`, `{u}#<name>` or `{u}[expression]`",
                    u = text.to_ascii_uppercase()
                ),
            }),
            WordAsName { written, respelled } => {
                let d = error(
                    format!("`{written}` is not a valid variable name"),
                    at,
                    "a letter followed by a number is a G-code word",
                )
                .with_note("a name starts with two letters, or a letter and `_`");
                match respelled {
                    Some(name) => d.with_help(format!("try `{name}`")),
                    None => d,
                }
            }
            BlocksTooDeep(limit) => error(
                format!("blocks nested more than {limit} deep"),
                at,
                "this block is too deep",
            )
            .with_help("the rest of the file was not read; flatten the nesting"),
            StatementTooLong(limit) => error(
                format!("statement longer than {limit} tokens"),
                at,
                "the statement is cut here",
            )
            .with_help("split the expression with intermediate variables"),
            UnclosedParameter => error(
                "unclosed parameter name",
                at,
                "`#<` starts a name that ends with `>`",
            ),
            NotAParameter => error(
                "`#` names no parameter",
                at,
                "a parameter is `#123`, `#<name>`, `##1` or `#[expression]`",
            ),
            AtanOneArgument => error(
                "ATAN needs two arguments",
                at,
                "LinuxCNC writes `ATAN[y]/[x]`",
            ),
            ReturnOutsideSub => error(
                "`return` outside a subroutine",
                at,
                "it returns from an `o… sub`; the program ends with M2 or M30",
            ),
            ReadOnlyParameter(name) => error(
                format!("`{name}` cannot be set"),
                at,
                "a subroutine's `return [value]` or `endsub [value]` sets it",
            ),
            TooManyArguments(limit) => error(
                format!("more than {limit} arguments"),
                at,
                format!("a subroutine takes #1 to #{limit}"),
            ),
            UnexpectedToken {
                what,
                expected,
                hints,
            } => hints.iter().fold(
                error(format!("unexpected {what}"), at, format!("expected {expected}")),
                |d, hint| d.with_help(hint_text(hint)),
            ),
            UnexpectedEnd { expected } => error(
                "unexpected end of file",
                at,
                format!("expected {expected}"),
            ),
            ExtraToken { what } => error(
                format!("unexpected {what}"),
                at,
                "nothing more was expected here",
            ),
            InvalidToken => error("invalid token", at, "not understood"),
            InvalidProgramNumber => error(
                "invalid program number",
                at,
                "an O number is a whole number from 0 to 99999999",
            ),
            SubprogramWithoutM99 { name, next } => {
                let label = match next {
                    Some(_) => "this subprogram is not closed",
                    None => "this subprogram is never closed",
                };
                let d = error(format!("subprogram {name} has no M99"), at, label);
                match next {
                    Some(next) => d.with_secondary(*next, "the next program starts here"),
                    None => d,
                }
                .with_help("end every subprogram with `M99`")
            }
            SubprogramTwice { name, first } => error(
                format!("{name} is defined twice"),
                at,
                "second definition",
            )
            .with_secondary(*first, "first definition"),
            NotReadAfterEnd { lines, end } => note(
                match lines {
                    1 => "1 line after the program's end is not read".to_string(),
                    n => format!("{n} lines after the program's end are not read"),
                },
                at,
                "from here on, only subprograms are read",
            )
            .with_secondary(*end, "the program ends here")
            .with_note(
                "rs274 reads nothing after M2/M30 but the subprograms a call looks for, \
                 and Fanuc keeps its subprograms there",
            ),
            NotReadAfterTape { lines, end } => note(
                match lines {
                    1 => "1 line after the tape's end is not read".to_string(),
                    n => format!("{n} lines after the tape's end are not read"),
                },
                at,
                "not read",
            )
            .with_secondary(*end, "the tape ends here")
            .with_note(
                "a program that starts with a `%` line ends at its next `%` line: \
                 rs274 and Fanuc controls read nothing after it",
            ),
        }
    }
}

fn hint_text(hint: &ParseHint) -> String {
    match hint {
        ParseHint::ConditionInParentheses => {
            "conditions are written in parentheses: `while (i < 3) { … }`".to_string()
        }
        ParseHint::CompareWithEqEq => "to compare two values write `==`; `=` assigns".to_string(),
        ParseHint::ElseAfterIf => "`else` must follow the `}` of an `if` block".to_string(),
        ParseHint::CommentSyntax(Language::Egc) => {
            "comments are written `( … )` or `// …`".to_string()
        }
        ParseHint::CommentSyntax(Language::Gcode) => {
            "comments are written `( … )` or after `;`".to_string()
        }
        ParseHint::ValueFromName {
            letter,
            name,
            language: Language::Egc,
        } => format!("a word takes a variable's value in angle brackets: write `{letter}<{name}>`"),
        ParseHint::ValueFromName {
            letter,
            name,
            language: Language::Gcode,
        } => format!("a word takes a parameter's value: write `{letter}#<{name}>`"),
        ParseHint::BlockAfter { is_if: true } => {
            "an `if` runs a block: `{` on the line of the condition, `}` after the body: `if (Count > 0) { G0 X1 }`".to_string()
        }
        ParseHint::BlockAfter { is_if: false } => {
            "a `while` runs a block: `{` on the line of the condition, `}` after the body: `while (Count < 3) { Count = Count + 1 }`".to_string()
        }
        ParseHint::CommentInCall => {
            "in a wizard call `( … )` groups an expression; write comments with `//`".to_string()
        }
    }
}
