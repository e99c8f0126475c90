//! Parser: tokens → AST. The only module that knows LALRPOP; the grammar
//! (`grammar/egc.lalrpop`) could be replaced by touching this file alone.
//! Besides running the grammar it turns parse errors into `SyntaxError`s and
//! splits the top level into the main program and `O…`/`M99` subprograms.
//! It must not evaluate anything.

use super::after_end;
use super::error::{ParseHint, SyntaxError, SyntaxErrorKind};
use super::language::Language;
use super::lexer::{self, Lexed};
use super::token::{Spanned, Tok};
use super::words::LexedWord;
use crate::ast::*;
use crate::diagnostic::Diagnostic;
use crate::source::{FileId, Locator, Span};
use lalrpop_util::{lalrpop_mod, ParseError};
use std::convert::Infallible;

lalrpop_mod!(
    // Generated code: its unreachable-state panics are LALRPOP's, not ours.
    #[allow(
        clippy::all,
        clippy::pedantic,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        unused_parens,
        dead_code
    )]
    grammar,
    "/egc.rs"
);

/// Parse one source file. The program is returned even when there are
/// errors (with `StmtKind::Error` where a statement could not be read), so
/// that callers can decide how far to go.
pub fn parse_program(text: &str, file: FileId) -> (Program, Vec<Diagnostic>) {
    parse_program_as(text, file, Language::Egc)
}

/// Parse one source file in `language` (plain G-code differs in comments,
/// program numbers and spaces inside words; see [`Language`]).
pub fn parse_program_as(
    text: &str,
    file: FileId,
    language: Language,
) -> (Program, Vec<Diagnostic>) {
    parse_program_at(text, &Locator::new(file, text), language)
}

/// [`parse_program_as`] with the span maker of the file (from
/// [`crate::source::Sources::locator`], so its line index is not built again).
pub fn parse_program_at(
    text: &str,
    at: &Locator,
    language: Language,
) -> (Program, Vec<Diagnostic>) {
    let mut names = Names::default();
    let (mut program, diagnostics) = parse_program_from(text, 0, at, language, &mut names);
    program.names = names;
    (program, diagnostics)
}

/// The program of `main`, with the subprograms of the `library` files
/// added (LinuxCNC's `o<name> sub` in a file of its own): each file is read
/// with the same names, so `o<name>` has one number in all of them. What a
/// library file does outside its subroutines (its closing `M2`) is not
/// run; a subroutine the main file has already is not taken again.
pub fn parse_program_files(
    main: (&str, &Locator),
    library: &[(&str, Locator)],
    language: Language,
) -> (Program, Vec<Diagnostic>) {
    let mut names = program_names(language);
    let (mut program, mut diagnostics) =
        parse_program_from(main.0, 0, main.1, language, &mut names);
    for (text, at) in library {
        let (part, more) = parse_program_from(text, 0, at, language, &mut names);
        diagnostics.extend(more);
        for sub in part.subprograms {
            if !program.subprograms.iter().any(|s| s.name == sub.name) {
                program.subprograms.push(sub);
            }
        }
    }
    program.names = names;
    (program, diagnostics)
}

/// The names a program in `language` starts with: G-code's `#1`–`#33`
/// ([`Names::name_call_parameters`]).
pub fn program_names(language: Language) -> Names {
    let mut names = Names::default();
    if language == Language::Gcode {
        names.name_call_parameters();
    }
    names
}

/// Parse `text` from the offset `from` (a line start; the lines before it
/// are not read; 0 for a whole file), with spans in the whole text,
/// interning into `names` (left empty in the program: the caller puts them
/// there). Plain G-code is read to its main program's end, and after it
/// only its subprograms ([`after_end`]).
pub fn parse_program_from(
    text: &str,
    from: usize,
    at: &Locator,
    language: Language,
    names: &mut Names,
) -> (Program, Vec<Diagnostic>) {
    // A tape is read to its closing `%` line (whole here; a caller that
    // reads in parts cuts the text there first).
    let tape = (language == Language::Gcode && at.offset(from) == 0)
        .then(|| after_end::tape_end(text, at))
        .flatten();
    if let Some((cut, note)) = tape {
        let (program, mut diagnostics) =
            parse_program_from(&text[..cut], from, at, language, names);
        diagnostics.extend(note.map(|n| n.to_diagnostic()));
        return (program, diagnostics);
    }
    let (program, problems) = parse_problems(text, from, at, language, names);
    let ended = match language {
        Language::Gcode => after_end::end_of_main(&program.main, text, at),
        Language::Egc => None,
    };
    let Some((cut, end)) = ended.filter(|&(cut, _)| after_end::has_more(&text[cut..])) else {
        return (program, drop_cascades(problems));
    };
    // Read again to the end: what the lines after it made is not kept.
    let (mut program, mut problems) = parse_problems(&text[..cut], from, at, language, names);
    let mut theirs = Vec::new();
    let mut parse = |range: std::ops::Range<usize>, names: &mut Names| {
        let (sub, found) = parse_problems(&text[..range.end], range.start, at, language, names);
        theirs.extend(found);
        sub
    };
    let (subprograms, found) = after_end::read_after_end(
        text,
        (cut, end),
        at,
        names,
        &program.subprograms,
        &mut parse,
    );
    program.subprograms.extend(subprograms);
    problems.extend(theirs);
    problems.extend(
        found
            .into_iter()
            .map(|e| Problem::new(ProblemKind::Read, e)),
    );
    problems.sort_by_key(|p| p.error.span.start);
    (program, drop_cascades(problems))
}

/// [`parse_program_from`] without the rule of the end: every line read
/// (a part of a program, or a subprogram after its end).
pub(super) fn parse_text(
    text: &str,
    from: usize,
    at: &Locator,
    language: Language,
    names: &mut Names,
) -> (Program, Vec<Diagnostic>) {
    let (program, problems) = parse_problems(text, from, at, language, names);
    (program, drop_cascades(problems))
}

/// Lex, parse and split `text` from `from`: the program and its problems,
/// sorted by where they are.
fn parse_problems(
    text: &str,
    from: usize,
    at: &Locator,
    language: Language,
    names: &mut Names,
) -> (Program, Vec<Problem>) {
    let Lexed {
        tokens,
        words,
        errors: lex_errors,
        unclosed_brace,
        call_groups,
    } = lexer::lex_from(text, from, at, names, language);
    let mut problems: Vec<Problem> = lex_errors
        .into_iter()
        .map(|e| Problem::new(ProblemKind::Read, e))
        .collect();

    let context = ErrorContext {
        at,
        language,
        text,
        names,
        call_groups: &call_groups,
        tokens: &tokens,
        words: &words,
    };
    let at_eof = |e: &ParseError<usize, Tok, Infallible>| match e {
        ParseError::UnrecognizedToken { token, .. } => token.0 >= text.len(),
        ParseError::UnrecognizedEof { .. } => true,
        _ => false,
    };
    let mut top = Vec::with_capacity(tokens.len() / 2 + 1);
    for piece in pieces(&tokens, fast_path()) {
        match piece {
            Piece::Line(start, run, end) => {
                let number = at.span(start, end).line;
                top.push(words_stmt(&words, run, (start, end), number, at));
            }
            Piece::Sub(start, name, end) => top.push(Stmt {
                kind: StmtKind::Sub(name),
                span: at.span(start, end),
            }),
            Piece::Grammar(slice) => {
                let mut recovered = Vec::new();
                let result = grammar::ProgramParser::new().parse(
                    at,
                    names,
                    &words,
                    &mut recovered,
                    slice.iter().copied().map(Ok::<_, Infallible>),
                );
                for r in recovered {
                    // The `}` the lexer adds for an unclosed block may not fit
                    // after a broken statement; the unclosed-brace error
                    // already covers it.
                    if !(unclosed_brace && at_eof(&r.error)) {
                        problems.push(context.problem(r.error));
                    }
                }
                match result {
                    Ok(stmts) => top.extend(stmts),
                    Err(e) => {
                        if !(unclosed_brace && at_eof(&e)) {
                            problems.push(context.problem(e));
                        }
                    }
                }
            }
        }
    }
    let mut structure = Vec::new();
    let program = split_subprograms(top, names, &mut structure);
    problems.extend(
        structure
            .into_iter()
            .map(|e| Problem::new(ProblemKind::Read, e)),
    );
    problems.sort_by_key(|p| p.error.span.start);
    (program, problems)
}

/// A syntax problem and where it comes from, which decides whether it is
/// only a consequence of another.
struct Problem {
    kind: ProblemKind,
    error: SyntaxError,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ProblemKind {
    /// Found reading the text (the lexer) or its structure (O…M99).
    Read,
    /// The grammar did not expect a token.
    Parse,
    /// The grammar did not expect a `}`.
    StrayBrace,
}

impl Problem {
    fn new(kind: ProblemKind, error: SyntaxError) -> Problem {
        Problem { kind, error }
    }
}

/// Keep the errors that say something new: a parse error on a line the
/// lexer already reported, or at a `}` after an earlier error (its `{` was
/// skipped while recovering), only repeats an error the user has.
fn drop_cascades(problems: Vec<Problem>) -> Vec<Diagnostic> {
    let line_of = |e: &SyntaxError| (e.span.file, e.span.line);
    let read_lines: Vec<(u32, u32)> = problems
        .iter()
        .filter(|p| p.kind == ProblemKind::Read)
        .map(|p| line_of(&p.error))
        .collect();
    let mut kept: Vec<Diagnostic> = Vec::with_capacity(problems.len());
    for p in problems {
        let parse_error = p.kind != ProblemKind::Read;
        if parse_error && read_lines.contains(&line_of(&p.error)) {
            continue;
        }
        if p.kind == ProblemKind::StrayBrace && !kept.is_empty() {
            continue;
        }
        kept.push(p.error.to_diagnostic());
    }
    kept
}

thread_local! {
    /// Tests turn the fast path off to check it builds the grammar's tree.
    static FAST_PATH: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Whether plain lines take the fast path on this thread.
pub(crate) fn fast_path() -> bool {
    FAST_PATH.with(|f| f.get())
}

/// Parse with or without the fast path for plain lines (for tests).
pub fn parse_program_with_fast_path(
    text: &str,
    file: FileId,
    fast: bool,
) -> (Program, Vec<Diagnostic>) {
    with_fast_path(fast, || parse_program(text, file))
}

/// Run `f` (a parse or a whole compile on this thread) with the fast path
/// for plain lines on or off (for tests).
pub fn with_fast_path<T>(fast: bool, f: impl FnOnce() -> T) -> T {
    let old = FAST_PATH.with(|c| c.replace(fast));
    let result = f();
    FAST_PATH.with(|c| c.set(old));
    result
}

/// A top-level statement that is one run of plain words, or a stretch of
/// tokens for the grammar.
enum Piece<'t> {
    Line(usize, (u32, u32), usize),
    /// LinuxCNC's `oN sub` alone: what the grammar builds, kept out of the
    /// stretches around it as an `O` line is (a broken block after it
    /// does not take it along).
    Sub(usize, OName, usize),
    Grammar(&'t [Spanned]),
}

/// Cut the tokens at top-level statement ends. Most lines of a CAM program
/// are one run of plain words: those are built directly, which is what the
/// grammar's `Words` rule would build, without the parser's per-token
/// work. Everything else goes to the grammar, in stretches.
fn pieces(tokens: &[Spanned], fast: bool) -> Vec<Piece<'_>> {
    let mut out = Vec::new();
    let mut depth = 0usize;
    let mut stmt_start = 0;
    let mut stretch_start = 0;
    for (i, &(start, tok, end)) in tokens.iter().enumerate() {
        match tok {
            Tok::LBrace => depth += 1,
            Tok::RBrace => depth = depth.saturating_sub(1),
            _ => {}
        }
        let last = i + 1 == tokens.len() || (depth == 0 && tokens[i + 1].1 == Tok::Term);
        if depth != 0 || !last || tok == Tok::Term {
            if tok == Tok::Term && depth == 0 {
                stmt_start = i + 1;
            }
            continue;
        }
        let piece = match tok {
            Tok::Words(first, len) => Piece::Line(start, (first, len), end),
            Tok::Sub(name) => Piece::Sub(start, name, end),
            _ => continue,
        };
        if fast && stmt_start == i {
            push_stretch(&mut out, &tokens[stretch_start..i]);
            out.push(piece);
            stretch_start = i + 1;
        }
    }
    push_stretch(&mut out, &tokens[stretch_start..]);
    out
}

/// A stretch for the grammar, without the statement ends around it.
fn push_stretch<'t>(out: &mut Vec<Piece<'t>>, mut stretch: &'t [Spanned]) {
    while let [(_, Tok::Term, _), rest @ ..] = stretch {
        stretch = rest;
    }
    while let [rest @ .., (_, Tok::Term, _)] = stretch {
        stretch = rest;
    }
    if !stretch.is_empty() {
        out.push(Piece::Grammar(stretch));
    }
}

struct ErrorContext<'a> {
    at: &'a Locator,
    language: Language,
    text: &'a str,
    names: &'a Names,
    call_groups: &'a [usize],
    tokens: &'a [Spanned],
    words: &'a [LexedWord],
}

impl ErrorContext<'_> {
    /// A parse error as a problem: a stray `}` is told apart, since after
    /// an earlier error it only means its `{` was skipped.
    fn problem(&self, e: ParseError<usize, Tok, Infallible>) -> Problem {
        let kind = match e {
            ParseError::UnrecognizedToken {
                token: (_, Tok::RBrace, _),
                ..
            }
            | ParseError::ExtraToken {
                token: (_, Tok::RBrace, _),
            } => ProblemKind::StrayBrace,
            ParseError::UnrecognizedToken { .. }
            | ParseError::ExtraToken { .. }
            | ParseError::UnrecognizedEof { .. } => ProblemKind::Parse,
            ParseError::InvalidToken { .. } | ParseError::User { .. } => ProblemKind::Read,
        };
        Problem::new(kind, self.describe(e))
    }

    fn describe(&self, e: ParseError<usize, Tok, Infallible>) -> SyntaxError {
        match e {
            ParseError::UnrecognizedToken {
                token: (l, tok, r),
                expected,
            } => {
                let (what, span) = if tok == Tok::Term {
                    ("end of statement".to_string(), self.at.span(l, l))
                } else if let Tok::Words(first, _) = tok {
                    let w = self.words[first as usize];
                    let (start, end) = (w.start as usize, w.end as usize);
                    (
                        format!("word `{}`", &self.text[start..end]),
                        self.at.span(start, end),
                    )
                } else {
                    (self.token_as_written(tok, l, r), self.at.span(l, r))
                };
                let before = self.tokens.iter().rev().find(|t| t.0 < l).map(|t| t.1);
                let wants = |t: &str| expected.iter().any(|e| e.trim_matches('"') == t);
                let mut hints = Vec::new();
                if matches!(before, Some(Tok::If | Tok::While)) {
                    hints.push(ParseHint::ConditionInParentheses);
                } else if tok == Tok::Assign && wants("==") {
                    hints.push(ParseHint::CompareWithEqEq);
                } else if tok == Tok::Else {
                    hints.push(ParseHint::ElseAfterIf);
                } else if matches!(tok, Tok::Name(_)) && wants("word") {
                    hints.push(
                        value_from_name(&self.text[l..r], self.language)
                            .unwrap_or(ParseHint::CommentSyntax(self.language)),
                    );
                } else if wants("{") && expected.len() == 1 {
                    let opener = self.tokens.iter().rev().filter(|t| t.0 < l);
                    let opener = opener
                        .take_while(|t| t.1 != Tok::Term)
                        .find(|t| matches!(t.1, Tok::If | Tok::While));
                    if let Some(t) = opener {
                        hints.push(ParseHint::BlockAfter {
                            is_if: t.1 == Tok::If,
                        });
                    }
                }
                if self.in_call_group(l) {
                    hints.push(ParseHint::CommentInCall);
                }
                let kind = SyntaxErrorKind::UnexpectedToken {
                    what,
                    expected: expected_list(&expected),
                    hints,
                };
                SyntaxError::new(kind, span)
            }
            ParseError::UnrecognizedEof { location, expected } => SyntaxError::new(
                SyntaxErrorKind::UnexpectedEnd {
                    expected: expected_list(&expected),
                },
                self.at.span(location, location),
            ),
            ParseError::ExtraToken { token: (l, tok, r) } => SyntaxError::new(
                SyntaxErrorKind::ExtraToken {
                    what: self.token_as_written(tok, l, r),
                },
                self.at.span(l, r),
            ),
            ParseError::InvalidToken { location } => SyntaxError::new(
                SyntaxErrorKind::InvalidToken,
                self.at.span(location, location + 1),
            ),
            ParseError::User { error } => match error {},
        }
    }

    /// A token as a message names it: as the program wrote it where its
    /// text is a bracket or a number (LinuxCNC's `[` is the lexer's `(`),
    /// else as [`Tok::describe`] names it.
    fn token_as_written(&self, tok: Tok, l: usize, r: usize) -> String {
        let text = self.text.get(l..r).unwrap_or("");
        let number = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit() || b == b'.');
        match tok {
            Tok::LParen | Tok::CallOpen | Tok::RParen if matches!(text, "[" | "]" | "(" | ")") => {
                format!("`{text}`")
            }
            Tok::Number(_) if number(text.trim_start_matches(['-', '+'])) => {
                format!("number `{text}`")
            }
            _ => tok.describe(self.names),
        }
    }

    fn in_call_group(&self, at: usize) -> bool {
        self.call_groups
            .iter()
            .any(|&open| open <= at && !self.text[open..at].contains('\n'))
    }
}

fn expected_list(expected: &[String]) -> String {
    let mut items: Vec<String> = expected
        .iter()
        .map(|e| {
            let e = e.trim_matches('"');
            match e {
                "word" => "a G-code word".to_string(),
                "name" | "name(" => "a name".to_string(),
                "number" => "a number".to_string(),
                "string" => "a string".to_string(),
                "X<" => "a symbolic word".to_string(),
                ">)" => "`>`".to_string(),
                "end of statement" => "end of statement".to_string(),
                other => format!("`{other}`"),
            }
        })
        .collect();
    items.dedup();
    // Where a value may start, the unary `+` (LinuxCNC's) goes unsaid; so
    // do LinuxCNC's own operator tokens, which only its brackets make, and
    // the `#` of its indirect parameters.
    if items.iter().any(|i| i == "`!`") {
        items.retain(|i| i != "`+`");
    }
    items.retain(|i| !matches!(i.as_str(), "`unary -`" | "`MOD`" | "`**`" | "`#`"));
    if items.len() > 8 {
        return "an expression or statement".to_string();
    }
    match items.len() {
        0 => "nothing".to_string(),
        1 => items.remove(0),
        _ => {
            let last = items.pop().unwrap_or_default();
            format!("{} or {}", items.join(", "), last)
        }
    }
}

/// The subprogram a statement starts: a line that holds only an `O` word
/// (its value, checked by [`program_number`] where it is used), or
/// LinuxCNC's `oN sub`.
fn program_start(stmt: &Stmt) -> Option<(Start, Span)> {
    match &stmt.kind {
        // (A sequence number may come first: `N1 O0003`.)
        StmtKind::Line(line) => match line.words.as_slice() {
            [w] | [Word { letter: b'N', .. }, w] if w.letter == b'O' => match w.value {
                WordValue::Number(n) => Some((Start::Number(n.value), w.span)),
                WordValue::Expr(_) => None,
            },
            _ => None,
        },
        StmtKind::Sub(name) => Some((Start::Name(*name), stmt.span)),
        _ => None,
    }
}

/// What starts a subprogram: an `O` word's value, or a checked name.
enum Start {
    Number(f64),
    Name(OName),
}

impl Start {
    fn name(self) -> Option<OName> {
        match self {
            Start::Number(n) => program_number(n).map(OName::Number),
            Start::Name(name) => Some(name),
        }
    }
}

/// Whether `stmt` ends the subprogram's text: an `M99` line, or an
/// `endsub`.
fn has_m99(stmt: &Stmt) -> bool {
    match &stmt.kind {
        StmtKind::Return(r) => r.ends_sub,
        StmtKind::Line(line) => line.words.iter().any(|w| {
            w.letter == b'M' && matches!(w.value, WordValue::Number(n) if n.value == 99.0)
        }),
        _ => false,
    }
}

/// Split the top level into the main program and subprograms (SPEC §2.6):
/// an `O` line (or LinuxCNC's `oN sub`) opens a subprogram that ends with
/// its `M99` (or `endsub`, which leaves a [`StmtKind::DefinitionRead`] in
/// the program around it); an `O` line at the very top whose block has no
/// `M99` numbers the main program instead.
fn split_subprograms(top: Vec<Stmt>, names: &Names, errors: &mut Vec<SyntaxError>) -> Program {
    let mut program = Program {
        main: Vec::with_capacity(top.len()),
        main_number: None,
        subprograms: Vec::new(),
        names: Names::default(),
    };
    // The program's own number: its first statement but comments.
    let first = top
        .iter()
        .position(|s| !matches!(s.kind, StmtKind::Comment(_)))
        .unwrap_or(0);
    let numbers_main =
        top.get(first).and_then(program_start).is_some() && !block_has_m99(top[first + 1..].iter());
    let mut open: Option<Subprogram> = None;
    for (index, stmt) in top.into_iter().enumerate() {
        if let Some((start, span)) = program_start(&stmt) {
            let Some(name) = start.name() else {
                errors.push(SyntaxError::new(
                    SyntaxErrorKind::InvalidProgramNumber,
                    span,
                ));
                continue;
            };
            if let Some(sub) = open.take() {
                errors.push(SyntaxError::new(
                    SyntaxErrorKind::SubprogramWithoutM99 {
                        name: sub.name.describe(names),
                        next: Some(span),
                    },
                    sub.span,
                ));
                program.subprograms.push(sub);
            }
            if index == first && numbers_main {
                program.main_number = Some(name);
                continue;
            }
            if let Some(other) = program.subprograms.iter().find(|s| s.name == name) {
                errors.push(SyntaxError::new(
                    SyntaxErrorKind::SubprogramTwice {
                        name: name.describe(names),
                        first: other.span,
                    },
                    span,
                ));
            }
            open = Some(Subprogram {
                name,
                span,
                body: Vec::new(),
            });
            continue;
        }
        match open.as_mut() {
            Some(sub) => {
                let ends = has_m99(&stmt);
                let read = match &stmt.kind {
                    StmtKind::Return(r) if r.ends_sub => Some(Stmt {
                        kind: StmtKind::DefinitionRead {
                            returns_value: r.value.is_some(),
                        },
                        span: stmt.span,
                    }),
                    _ => None,
                };
                sub.body.push(stmt);
                if ends {
                    program.subprograms.extend(open.take());
                }
                program.main.extend(read);
            }
            None => program.main.push(stmt),
        }
    }
    if let Some(sub) = open {
        errors.push(SyntaxError::new(
            SyntaxErrorKind::SubprogramWithoutM99 {
                name: sub.name.describe(names),
                next: None,
            },
            sub.span,
        ));
        program.subprograms.push(sub);
    }
    program
}

/// Does the block that starts here (up to the next `O` line) contain `M99`?
fn block_has_m99<'a>(mut rest: impl Iterator<Item = &'a Stmt>) -> bool {
    rest.try_fold(false, |_, s| {
        if program_start(s).is_some() {
            Err(false)
        } else if has_m99(s) {
            Err(true)
        } else {
            Ok(false)
        }
    })
    .unwrap_or_else(|found| found)
}

// Grammar actions: kept here so the grammar file stays declarative.

/// The statement of a line that is one run of plain words
/// (`words[run]`, from `start` to `end` on line `number` of the file):
/// what the grammar's `Words` rule builds.
fn words_stmt(
    words: &[LexedWord],
    run: (u32, u32),
    (start, end): (usize, usize),
    number: u32,
    at: &Locator,
) -> Stmt {
    let (first, len) = (run.0 as usize, run.1 as usize);
    let line = words[first..first + len]
        .iter()
        .map(|w| ast_word(w, number, at))
        .collect();
    Stmt {
        kind: StmtKind::line(line, false),
        span: at.span_on_line(number, start, end),
    }
}

/// Append the words of a run token (`Tok::Words`) to a line.
pub(crate) fn push_words(line: &mut Vec<Word>, words: &[LexedWord], run: (u32, u32), at: &Locator) {
    let (first, len) = (run.0 as usize, run.1 as usize);
    let run = &words[first..first + len];
    // A run of words never crosses a line end: one line lookup for all.
    let number = run
        .first()
        .map_or(0, |w| at.span(w.start as usize, w.end as usize).line);
    line.extend(run.iter().map(|w| ast_word(w, number, at)));
}

/// A lexed word on line `number` of the file.
fn ast_word(w: &LexedWord, number: u32, at: &Locator) -> Word {
    Word {
        letter: w.word.letter,
        value: WordValue::Number(Number {
            value: w.word.value,
            int_digits: w.word.int_digits,
            has_point: w.word.has_point,
        }),
        span: at.span_on_line(number, w.start as usize, w.end as usize),
    }
}

pub(crate) fn binary(at: &Locator, l: usize, r: usize, op: BinaryOp, a: Expr, b: Expr) -> Expr {
    Expr {
        kind: ExprKind::Binary(op, Box::new(a), Box::new(b)),
        span: at.span(l, r),
    }
}

pub(crate) fn variable(names: &Names, s: Symbol, span: Span) -> Expr {
    let kind = if names.text(s) == "PI" {
        ExprKind::Number(std::f64::consts::PI)
    } else {
        ExprKind::Var(s)
    };
    Expr { kind, span }
}

pub(crate) fn call(names: &Names, name: Symbol, args: Vec<Expr>, span: Span) -> Expr {
    let kind = match Function::from_name(names.text(name)) {
        Some(f) => ExprKind::Call(f, args),
        None => ExprKind::UnknownCall(name, args),
    };
    Expr { kind, span }
}

/// `XDd` where a word was expected: the letter of a value-taking word
/// glued to a name that starts with a capital (a name, not a comment's
/// `Move`): its value, `X<Dd>`, was meant.
fn value_from_name(text: &str, language: Language) -> Option<ParseHint> {
    let mut chars = text.chars();
    let letter = chars.next().filter(|c| "XYZABCUVWIJKRFSPQ".contains(*c))?;
    let rest = chars.as_str();
    rest.starts_with(|c: char| c.is_ascii_uppercase())
        .then(|| ParseHint::ValueFromName {
            letter,
            name: rest.to_string(),
            language,
        })
}
