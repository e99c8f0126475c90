//! The abstract syntax tree of an extended G-code program, as the parser
//! builds it. Every node carries a [`Span`]. The tree says what was written,
//! not what it means: no evaluation, no units, no modal state live here.
//! Names are interned [`Symbol`]s so that tokens and nodes allocate nothing
//! per word.

mod print;

use crate::source::Span;
use std::collections::HashMap;

/// An interned name or string literal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Symbol(pub u32);

/// The table behind [`Symbol`]s. Symbols are dense, so the evaluator can
/// keep variables in a `Vec` indexed by symbol.
#[derive(Default, Clone, Debug)]
pub struct Names {
    texts: Vec<Box<str>>,
    ids: HashMap<Box<str>, Symbol>,
    /// Comments and controller commands: text for the output, never a
    /// name, so not among the names [`Names::find`] and [`Names::iter`]
    /// see. A program read in parts drops each part's
    /// ([`Names::forget_notes`]) while its names stay.
    notes: Vec<Box<str>>,
    /// Notes kept past their part ([`Names::keep_note`]: those of a
    /// subprogram, which outlives it).
    kept: Vec<Box<str>>,
}

/// The bits that mark a [`Symbol`] as a note's, and as a kept note's.
const NOTE: u32 = 1 << 31;
const KEPT: u32 = 1 << 30;

impl Names {
    /// The text of a comment or a command, kept until
    /// [`Names::forget_notes`].
    pub fn note(&mut self, text: &str) -> Symbol {
        let s = Symbol(NOTE | self.notes.len() as u32);
        self.notes.push(text.into());
        s
    }

    /// Name G-code's `#1`–`#33`, which a call sets (LinuxCNC's `o… call`,
    /// Fanuc's `G65`) whether or not the program names them where it can
    /// read them (a `(DEBUG, #1)` reads them by text; a program read in
    /// parts may name them only further on). The parser names them first
    /// (so `o<name>` subroutines are numbered alike whole and in parts),
    /// the evaluator again for a program parsed without them.
    pub fn name_call_parameters(&mut self) {
        for k in 1..=33 {
            self.intern(&format!("#{k}"));
        }
    }

    /// Drop the notes' texts (their symbols must not be used again), but
    /// those kept.
    pub fn forget_notes(&mut self) {
        self.notes.clear();
    }

    /// The symbol of `s`'s text past [`Names::forget_notes`]: `s` itself
    /// unless it is a note.
    pub fn keep_note(&mut self, s: Symbol) -> Symbol {
        if s.0 & NOTE == 0 {
            return s;
        }
        let kept = Symbol(KEPT | self.kept.len() as u32);
        self.kept.push(self.notes[(s.0 & !NOTE) as usize].clone());
        kept
    }

    pub fn intern(&mut self, text: &str) -> Symbol {
        if let Some(&s) = self.ids.get(text) {
            return s;
        }
        let s = Symbol(self.texts.len() as u32);
        self.texts.push(text.into());
        self.ids.insert(text.into(), s);
        s
    }

    pub fn text(&self, s: Symbol) -> &str {
        match s.0 & (NOTE | KEPT) {
            0 => &self.texts[s.0 as usize],
            NOTE => &self.notes[(s.0 & !NOTE) as usize],
            _ => &self.kept[(s.0 & !KEPT) as usize],
        }
    }

    /// The symbol of `text`, if the program has it.
    pub fn find(&self, text: &str) -> Option<Symbol> {
        self.ids.get(text).copied()
    }

    pub fn len(&self) -> usize {
        self.texts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.texts.is_empty()
    }

    pub fn iter(&self) -> impl Iterator<Item = (Symbol, &str)> {
        self.texts
            .iter()
            .enumerate()
            .map(|(i, t)| (Symbol(i as u32), &**t))
    }
}

/// A parsed file: the main program and the `O…`/`M99` subprograms.
#[derive(Debug)]
pub struct Program {
    pub main: Vec<Stmt>,
    /// The `O` number written on the main program's first line, if any.
    pub main_number: Option<OName>,
    pub subprograms: Vec<Subprogram>,
    pub names: Names,
}

impl Program {
    /// The LinuxCNC `o<name>` subroutines the program calls and those it
    /// defines, by name (between `o<` and `>`): what the driver looks for
    /// in `name.ngc` files.
    pub fn named_subroutines(&self) -> (Vec<String>, Vec<String>) {
        let text = |name: OName| match name {
            OName::Named(s) => self
                .names
                .text(s)
                .strip_prefix("o<")
                .and_then(|n| n.strip_suffix('>'))
                .map(str::to_string),
            OName::Number(_) => None,
        };
        let mut calls = Vec::new();
        let bodies = std::iter::once(&self.main).chain(self.subprograms.iter().map(|s| &s.body));
        for body in bodies {
            each_stmt(body, &mut |stmt| {
                if let StmtKind::SubCall(call) = &stmt.kind {
                    calls.extend(text(call.name));
                }
            });
        }
        let subs = self
            .subprograms
            .iter()
            .filter_map(|s| text(s.name))
            .collect();
        (calls, subs)
    }
}

/// Every statement of `stmts` and of the blocks in them, in order.
fn each_stmt(stmts: &[Stmt], f: &mut impl FnMut(&Stmt)) {
    for stmt in stmts {
        f(stmt);
        match &stmt.kind {
            StmtKind::If(if_) => {
                for (_, body) in &if_.branches {
                    each_stmt(body, f);
                }
                if let Some(body) = &if_.otherwise {
                    each_stmt(body, f);
                }
            }
            StmtKind::While(w) => each_stmt(&w.body, f),
            StmtKind::Repeat(r) => each_stmt(&r.body, f),
            StmtKind::Line(_)
            | StmtKind::Lines(_)
            | StmtKind::MacroCall(_)
            | StmtKind::Assign(_)
            | StmtKind::Assigns(_)
            | StmtKind::Call { .. }
            | StmtKind::Command(_)
            | StmtKind::Comment(_)
            | StmtKind::Sub(_)
            | StmtKind::SubCall(_)
            | StmtKind::Return(_)
            | StmtKind::DefinitionRead { .. }
            | StmtKind::Goto(_)
            | StmtKind::Break(_)
            | StmtKind::Continue(_)
            | StmtKind::Error => {}
        }
    }
}

/// What names a subprogram or labels an o-word: a number (Fanuc's `O100`,
/// LinuxCNC's `o100`) or LinuxCNC's `o<name>` (its symbol's text is
/// `o<name>`, lower case, without spaces).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OName {
    Number(u32),
    Named(Symbol),
}

impl OName {
    /// As messages name a subprogram: `O100`, `o<name>`.
    pub fn describe(self, names: &Names) -> String {
        match self {
            OName::Number(n) => format!("O{n}"),
            OName::Named(s) => names.text(s).to_string(),
        }
    }

    /// As LinuxCNC writes it before its keyword: `o100`, `o<name>`.
    pub fn written(self, names: &Names) -> String {
        match self {
            OName::Number(n) => format!("o{n}"),
            OName::Named(s) => names.text(s).to_string(),
        }
    }
}

/// The number of a program or subprogram written `value` (`O100`,
/// `o100 sub`): a whole number from 0 to 99,999,999.
pub fn program_number(value: f64) -> Option<u32> {
    ((0.0..=99_999_999.0).contains(&value) && value.fract() == 0.0).then_some(value as u32)
}

#[derive(Debug)]
pub struct Subprogram {
    pub name: OName,
    /// The `O` word that opens it.
    pub span: Span,
    pub body: Vec<Stmt>,
}

#[derive(Debug, Clone)]
pub struct Stmt {
    pub kind: StmtKind,
    pub span: Span,
}

impl Stmt {
    /// `stmts` with each run of [`Lines`] as the statements the parser
    /// builds for them: a [`Line`] each, its span from its first word to
    /// its last.
    pub fn line_by_line(stmts: Vec<Stmt>) -> Vec<Stmt> {
        let mut out = Vec::with_capacity(stmts.len());
        for stmt in stmts {
            let StmtKind::Lines(lines) = &stmt.kind else {
                out.push(stmt);
                continue;
            };
            for words in lines.each_as_words() {
                let (Some(first), Some(last)) = (words.first(), words.last()) else {
                    continue;
                };
                out.push(Stmt {
                    span: first.span.to(last.span),
                    kind: StmtKind::Line(Line {
                        words,
                        block_delete: false,
                    }),
                });
            }
        }
        out
    }
}

#[derive(Debug, Clone)]
pub enum StmtKind {
    /// A line of G-code words. One line may hold several statements; see
    /// [`Line::statements`] for how it is cut.
    Line(Line),
    /// Lines of plain words in a row, as a part of a plain program (one
    /// without `GOTO`) is parsed ([`crate::syntax::chunk`]): each runs
    /// as a [`Line`].
    Lines(Box<Lines>),
    Assign(Box<Assignment>),
    /// Several assignments on one line (LinuxCNC's `#1=2 #2=[#1+1]`): every
    /// value is worked out first, with the variables as they were before
    /// the line, then all are set, in order.
    Assigns(Vec<Assignment>),
    /// A wizard or setup-directive call, in either written form.
    Call {
        name: Symbol,
        name_span: Span,
        args: Vec<Expr>,
    },
    If(Box<If>),
    While(Box<While>),
    /// LinuxCNC's `oN sub` and `o<name> sub`: the subprogram starts here.
    /// The parser moves it, to its `endsub`, into
    /// [`Program::subprograms`]; only one not at the top level stays.
    Sub(OName),
    /// LinuxCNC's `oN call [a] [b] …`: run the subprogram with `#1`, `#2`,
    /// … set to the arguments.
    SubCall(Box<SubCall>),
    /// LinuxCNC's `oN return [v]` and `oN endsub [v]`: back to the caller
    /// with the value (0 if none is given).
    Return(Box<Return>),
    /// Where an `endsub` closed a subprogram, in the program around it:
    /// rs274 sets `#<_value>` and `#<_value_returned>` as it reads the
    /// definition (the value to one ger does not know, when the `endsub`
    /// returns one: reading it then is an error).
    DefinitionRead {
        returns_value: bool,
    },
    /// LinuxCNC's `oN repeat [n] … oN endrepeat`: the body, n times.
    Repeat(Box<Repeat>),
    /// A line with Fanuc's macro call `G65 P… L… A… B…` (SPEC §2.8).
    MacroCall(Box<MacroCall>),
    /// Fanuc's `GOTO n`: go on at the line labelled `Nn` of the same
    /// program or subprogram (the target may be an expression).
    Goto(Box<Expr>),
    /// LinuxCNC's `oN break` and `oN continue`: out of, or on to the next
    /// pass of, the `while` or `do` loop labelled N around it.
    Break(OName),
    Continue(OName),
    /// A controller command line of plain G-code (grbl's `$H`), passed
    /// through as written.
    Command(Symbol),
    /// A comment of plain G-code, kept for the output.
    Comment(Symbol),
    /// A statement the parser could not read; its error is already reported.
    Error,
}

/// A `target = value` statement ([`StmtKind::Assign`]), or one of the
/// assignments of [`StmtKind::Assigns`].
#[derive(Debug, Clone)]
pub struct Assignment {
    pub target: Target,
    pub name_span: Span,
    pub value: Expr,
}

/// What an assignment sets.
#[derive(Debug, Clone)]
pub enum Target {
    Name(Symbol),
    /// LinuxCNC's and Fanuc's `#[…]` and `##1`: the numbered parameter
    /// the value names, found when the assignment runs.
    Indirect(Box<Expr>),
}

/// A LinuxCNC `o… call` ([`StmtKind::SubCall`]).
#[derive(Debug, Clone)]
pub struct SubCall {
    pub name: OName,
    pub args: Vec<Expr>,
    /// The `call` keyword, where errors of the call point.
    pub at: Span,
}

/// A LinuxCNC `return` or `endsub` ([`StmtKind::Return`]).
#[derive(Debug, Clone)]
pub struct Return {
    pub value: Option<Expr>,
    /// `endsub`, which also ends the subprogram's text.
    pub ends_sub: bool,
}

/// A LinuxCNC `repeat` loop ([`StmtKind::Repeat`]).
#[derive(Debug, Clone)]
pub struct Repeat {
    pub label: OName,
    pub count: Expr,
    pub body: Vec<Stmt>,
    /// The `repeat` keyword, where errors about the whole loop point.
    pub at: Span,
}

#[derive(Debug, Clone)]
pub struct If {
    pub branches: Vec<(Expr, Vec<Stmt>)>,
    pub otherwise: Option<Vec<Stmt>>,
}

#[derive(Debug, Clone)]
pub struct While {
    pub cond: Expr,
    pub body: Vec<Stmt>,
    /// LinuxCNC's `oN` on the loop, which its `break` and `continue` name.
    pub label: Option<OName>,
    /// LinuxCNC's `do … while`: the body runs once before the test.
    pub test_after: bool,
}

/// A line with Fanuc's `G65` ([`StmtKind::MacroCall`]). The words before
/// it are statements of their own, run first in the order written (an `N`
/// label among them is the line's, for `GOTO`); every word after it is the
/// call's: `P` names the macro, `L` repeats it, the rest are its arguments
/// (a `G` or `M` among them too: Fanuc's argument `M` is `#13`).
#[derive(Debug, Clone)]
pub struct MacroCall {
    pub before: Vec<Word>,
    /// The `G65` word.
    pub code: Word,
    pub args: Vec<Word>,
    /// Written after a block-delete `/`, as [`Line::block_delete`].
    pub block_delete: bool,
}

impl MacroCall {
    /// Every word of the line, in the order written.
    pub fn words(&self) -> impl Iterator<Item = &Word> {
        self.before
            .iter()
            .chain(std::iter::once(&self.code))
            .chain(&self.args)
    }
}

impl StmtKind {
    /// The statement a line of `words` is: a [`StmtKind::MacroCall`] from
    /// its first `G65` on, else a [`StmtKind::Line`].
    pub fn line(mut words: Vec<Word>, block_delete: bool) -> StmtKind {
        let Some(at) = words.iter().position(Word::is_macro_call) else {
            return StmtKind::Line(Line {
                words,
                block_delete,
            });
        };
        let mut args = words.split_off(at);
        let code = args.remove(0);
        StmtKind::MacroCall(Box::new(MacroCall {
            before: words,
            code,
            args,
            block_delete,
        }))
    }
}

/// The words of one G-code line, in the order written.
#[derive(Debug, Clone)]
pub struct Line {
    pub words: Vec<Word>,
    /// Written after a block-delete `/`: it runs (as on rs274 and most
    /// controllers with the switch off) and keeps its `/` in the output.
    pub block_delete: bool,
}

/// Lines of words (none written after a `/`), their words kept in one
/// vector rather than one each, and each in 24 bytes ([`PlainWord`]) rather
/// than a [`Word`]'s 40: most of a plain program, a part at a time.
#[derive(Debug, Clone, Default)]
pub struct Lines {
    /// The words of every line, one line after another.
    pub words: Vec<PlainWord>,
    /// Where each line's words end in `words`, and its line in the file.
    pub ends: Vec<LineEnd>,
    /// The file the lines are in.
    pub file: u32,
}

/// The end of a line's words in [`Lines::words`], and its (1-based) line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineEnd {
    pub end: u32,
    pub line: u32,
}

/// A word of [`Lines`]: a letter and a number written as a decimal, with
/// its span's offsets (its file and line are its line's). Nothing in it
/// needs dropping, so that a part's lines are cleared at once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlainWord {
    pub value: f64,
    pub start: u32,
    pub end: u32,
    /// Upper-case address letter.
    pub letter: u8,
    /// As [`Number`]'s.
    pub int_digits: u8,
    pub has_point: bool,
}

impl PlainWord {
    /// As [`Word::is_code`].
    pub fn is_code(&self) -> bool {
        matches!(self.letter, b'G' | b'M')
    }

    /// Its span, on `line` of `file`.
    #[inline]
    pub fn span(&self, file: u32, line: u32) -> Span {
        Span {
            file,
            line,
            start: self.start,
            end: self.end,
        }
    }

    /// The [`Word`] it is, on `line` of `file`.
    pub fn word(&self, file: u32, line: u32) -> Word {
        Word {
            letter: self.letter,
            value: WordValue::Number(Number {
                value: self.value,
                int_digits: self.int_digits,
                has_point: self.has_point,
            }),
            span: self.span(file, line),
        }
    }
}

impl Lines {
    /// The words of each line, and its line.
    pub fn each(&self) -> impl Iterator<Item = (&[PlainWord], u32)> {
        let mut start = 0;
        self.ends.iter().map(move |&LineEnd { end, line }| {
            let words = &self.words[start..end as usize];
            start = end as usize;
            (words, line)
        })
    }

    /// The words of each line as [`Word`]s (for what reads lines as the
    /// parser makes them; running them does not).
    pub fn each_as_words(&self) -> impl Iterator<Item = Vec<Word>> + '_ {
        self.each()
            .map(|(words, line)| words.iter().map(|w| w.word(self.file, line)).collect())
    }

    pub fn clear(&mut self) {
        self.words.clear();
        self.ends.clear();
    }
}

/// One statement of a [`Line`]: a G or M code with the argument words that
/// follow it, or (for the words before any G/M code) no code at all.
#[derive(Debug, Clone, Copy)]
pub struct LineStmt<'a> {
    pub code: Option<&'a Word>,
    pub args: &'a [Word],
}

impl Line {
    /// Cut the line into statements (SPEC §2.2): every G or M word starts a
    /// new statement and takes the argument words after it; words before the
    /// first G/M code form a statement of their own. `N` words are dropped.
    pub fn statements(&self) -> impl Iterator<Item = LineStmt<'_>> {
        statements(&self.words)
    }
}

/// [`statements`] of a line with one G or M code or none, found in one
/// look at its words: the statement of the words before the code (unless
/// they are only `N` words) and that of the code. `None` when the line has
/// more codes.
pub fn few_statements(words: &[Word]) -> Option<[Option<LineStmt<'_>>; 2]> {
    let mut codes = (0..words.len()).filter(|&i| words[i].is_code());
    let first = codes.next();
    if codes.next().is_some() {
        return None;
    }
    let before = &words[..first.unwrap_or(words.len())];
    let uncoded = (!before.iter().all(|w| w.letter == b'N')).then_some(LineStmt {
        code: None,
        args: before,
    });
    let coded = first.map(|at| LineStmt {
        code: Some(&words[at]),
        args: &words[at + 1..],
    });
    Some([uncoded, coded])
}

/// [`Line::statements`] of a line's words.
pub fn statements(words: &[Word]) -> impl Iterator<Item = LineStmt<'_>> {
    let mut rest = words;
    std::iter::from_fn(move || loop {
        if rest.is_empty() {
            return None;
        }
        let starts_code = rest[0].is_code();
        let (code, from) = if starts_code {
            (Some(&rest[0]), 1)
        } else {
            (None, 0)
        };
        let len = rest[from..]
            .iter()
            .position(Word::is_code)
            .unwrap_or(rest.len() - from);
        let args = &rest[from..from + len];
        rest = &rest[from + len..];
        // A line of only N words is no statement at all.
        if code.is_none() && args.iter().all(|w| w.letter == b'N') {
            continue;
        }
        return Some(LineStmt { code, args });
    })
}

#[derive(Debug, Clone)]
pub struct Word {
    /// Upper-case address letter.
    pub letter: u8,
    pub value: WordValue,
    pub span: Span,
}

impl Word {
    /// The letter of Fanuc's `,R` (the corner to the next move rounded):
    /// lower case, so that it is no address letter.
    pub const ROUND: u8 = b'r';
    /// The letter of Fanuc's `,C` (the corner chamfered).
    pub const CHAMFER: u8 = b'c';

    /// How a word's letter is written: `X`, or `,R` for [`Word::ROUND`].
    pub fn spelling(letter: u8) -> String {
        match letter {
            Word::ROUND => ",R".into(),
            Word::CHAMFER => ",C".into(),
            _ => char::from(letter).into(),
        }
    }

    /// G and M words start statements; every other letter is an argument.
    pub fn is_code(&self) -> bool {
        matches!(self.letter, b'G' | b'M')
    }

    /// Fanuc's macro call `G65`, whose words are all its arguments
    /// ([`MacroCall`]).
    pub fn is_macro_call(&self) -> bool {
        self.letter == b'G' && matches!(&self.value, WordValue::Number(n) if n.value == 65.0)
    }
}

#[derive(Debug, Clone)]
pub enum WordValue {
    /// A number written in the word: `X-.5`, `G54.1`, `P31000`.
    Number(Number),
    /// A symbolic value: `X<CenX + R>`.
    Expr(Box<Expr>),
}

/// A literal number with the facts about how it was written that Fanuc
/// semantics depend on (`M98 P31000`, `G4 P500`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Number {
    pub value: f64,
    /// Digits before the decimal point, leading zeros included.
    pub int_digits: u8,
    pub has_point: bool,
}

/// `value` as a whole number of 0 up to `u32::MAX`, if it is one.
pub fn whole_number(value: f64) -> Option<u32> {
    (value >= 0.0 && value.fract() == 0.0 && value <= f64::from(u32::MAX)).then_some(value as u32)
}

/// The value of the first `N` word of a line's `words`, where it is a
/// whole number as written (`--numbers keep`).
pub fn line_number(words: &[Word]) -> Option<u32> {
    match &words.iter().find(|w| w.letter == b'N')?.value {
        WordValue::Number(n) => whole_number(n.value),
        WordValue::Expr(_) => None,
    }
}

/// [`line_number`] of a plain-word line.
pub fn plain_line_number(words: &[PlainWord]) -> Option<u32> {
    whole_number(words.iter().find(|w| w.letter == b'N')?.value)
}

impl Number {
    /// The program number and repeat count of `M98 P<p>`, `p` this number
    /// made whole: Fanuc's `P31000` (more than four digits, no point) is
    /// three runs of program 1000.
    pub fn m98_split(&self, p: u32) -> (u32, u32) {
        match self.int_digits > 4 && !self.has_point {
            true => (p % 10_000, p / 10_000),
            false => (p, 1),
        }
    }
}

#[derive(Debug, Clone)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum ExprKind {
    Number(f64),
    Bool(bool),
    Str(Symbol),
    Var(Symbol),
    /// `#[…]`, `##1`: the numbered parameter the value names.
    Indirect(Box<Expr>),
    Unary(UnaryOp, Box<Expr>),
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
    Call(Function, Vec<Expr>),
    /// A call of a name that is no built-in function; reported by the
    /// evaluator, which knows the wizards.
    UnknownCall(Symbol, Vec<Expr>),
}

impl Expr {
    /// Change every function this expression calls by `f`.
    pub fn map_functions(&mut self, f: &impl Fn(Function) -> Function) {
        match &mut self.kind {
            ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) | ExprKind::Var(_) => {}
            ExprKind::Unary(_, e) | ExprKind::Indirect(e) => e.map_functions(f),
            ExprKind::Binary(_, a, b) => {
                a.map_functions(f);
                b.map_functions(f);
            }
            ExprKind::Call(function, args) => {
                *function = f(*function);
                args.iter_mut().for_each(|a| a.map_functions(f));
            }
            ExprKind::UnknownCall(_, args) => args.iter_mut().for_each(|a| a.map_functions(f)),
        }
    }
}

impl Target {
    /// Change every function an indirect target's number calls.
    pub fn map_functions(&mut self, f: &impl Fn(Function) -> Function) {
        if let Target::Indirect(e) = self {
            e.map_functions(f);
        }
    }
}

impl Assignment {
    /// Change every function the target and the value call.
    pub fn map_functions(&mut self, f: &impl Fn(Function) -> Function) {
        self.target.map_functions(f);
        self.value.map_functions(f);
    }
}

impl Stmt {
    /// Change the symbol of every comment and command of the statement
    /// (and of any block in it) by `f`.
    pub fn map_notes(&mut self, f: &mut impl FnMut(Symbol) -> Symbol) {
        let mut block = |stmts: &mut Vec<Stmt>| stmts.iter_mut().for_each(|s| s.map_notes(f));
        match &mut self.kind {
            StmtKind::Command(s) | StmtKind::Comment(s) => *s = f(*s),
            StmtKind::If(if_) => {
                for (_, body) in &mut if_.branches {
                    block(body);
                }
                if let Some(body) = &mut if_.otherwise {
                    block(body);
                }
            }
            StmtKind::While(w) => block(&mut w.body),
            StmtKind::Repeat(r) => block(&mut r.body),
            StmtKind::Line(_)
            | StmtKind::Lines(_)
            | StmtKind::MacroCall(_)
            | StmtKind::Assign(_)
            | StmtKind::Assigns(_)
            | StmtKind::Call { .. }
            | StmtKind::Sub(_)
            | StmtKind::SubCall(_)
            | StmtKind::Return(_)
            | StmtKind::DefinitionRead { .. }
            | StmtKind::Goto(_)
            | StmtKind::Break(_)
            | StmtKind::Continue(_)
            | StmtKind::Error => {}
        }
    }

    /// Change every function the statement (and any block in it) calls.
    pub fn map_functions(&mut self, f: &impl Fn(Function) -> Function) {
        let block = |stmts: &mut Vec<Stmt>| stmts.iter_mut().for_each(|s| s.map_functions(f));
        match &mut self.kind {
            StmtKind::Line(Line { words, .. }) => map_word_functions(words, f),
            StmtKind::MacroCall(call) => {
                map_word_functions(&mut call.before, f);
                map_word_functions(&mut call.args, f);
            }
            // Numbers only: no function to change.
            StmtKind::Lines(_) => {}
            StmtKind::Assign(a) => a.map_functions(f),
            StmtKind::Assigns(all) => all.iter_mut().for_each(|a| a.map_functions(f)),
            StmtKind::Call { args, .. } => args.iter_mut().for_each(|a| a.map_functions(f)),
            StmtKind::If(if_) => {
                for (cond, body) in &mut if_.branches {
                    cond.map_functions(f);
                    block(body);
                }
                if let Some(body) = &mut if_.otherwise {
                    block(body);
                }
            }
            StmtKind::While(w) => {
                w.cond.map_functions(f);
                block(&mut w.body);
            }
            StmtKind::Goto(target) => target.map_functions(f),
            StmtKind::SubCall(call) => call.args.iter_mut().for_each(|a| a.map_functions(f)),
            StmtKind::Return(r) => r.value.iter_mut().for_each(|v| v.map_functions(f)),
            StmtKind::Repeat(r) => {
                r.count.map_functions(f);
                block(&mut r.body);
            }
            StmtKind::Sub(_)
            | StmtKind::DefinitionRead { .. }
            | StmtKind::Break(_)
            | StmtKind::Continue(_)
            | StmtKind::Command(_)
            | StmtKind::Comment(_)
            | StmtKind::Error => {}
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnaryOp {
    Neg,
    Not,
}

/// Change every function the words' expressions call.
fn map_word_functions(words: &mut [Word], f: &impl Fn(Function) -> Function) {
    for w in words {
        if let WordValue::Expr(e) = &mut w.value {
            e.map_functions(f);
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    /// LinuxCNC's `MOD`: the remainder made non-negative (`-7 MOD 3` is 2).
    Mod,
    Pow,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
    /// LinuxCNC's word operators: numbers in, 1 or 0 out, as rs274
    /// computes them (EQ and NE equal within 0.0001; AND, OR and XOR
    /// read any non-zero number as true, and share one rank).
    NumEq,
    NumNe,
    NumLt,
    NumLe,
    NumGt,
    NumGe,
    NumAnd,
    NumOr,
    NumXor,
}

impl BinaryOp {
    pub fn symbol(self) -> &'static str {
        use BinaryOp::*;
        match self {
            Add => "+",
            Sub => "-",
            Mul => "*",
            Div => "/",
            Rem => "%",
            Mod => "MOD",
            Pow => "^",
            Eq => "==",
            Ne => "!=",
            Lt => "<",
            Le => "<=",
            Gt => ">",
            Ge => ">=",
            And => "&&",
            Or => "||",
            NumEq => "EQ",
            NumNe => "NE",
            NumLt => "LT",
            NumLe => "LE",
            NumGt => "GT",
            NumGe => "GE",
            NumAnd => "AND",
            NumOr => "OR",
            NumXor => "XOR",
        }
    }
}

/// The built-in functions of SPEC §2.4. Angles are in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Function {
    Abs,
    Sqrt,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Floor,
    Ceil,
    Round,
    Min,
    Max,
    Hypot,
    Exp,
    Ln,
    Log10,
    /// LinuxCNC's `EXISTS[#<name>]`: 1 if the parameter has a value, else 0.
    Exists,
    /// Fanuc's FIX and FUP, which round toward and away from zero
    /// (LinuxCNC's round down and up), and Fanuc's `ATAN[y]/[x]`, from 0
    /// to 360 degrees (LinuxCNC's from -180 to 180).
    FanucFix,
    FanucFup,
    FanucAtan,
}

impl Function {
    /// The functions a program can name (Fanuc's own come only from
    /// [`Function::on_fanuc`]).
    pub const ALL: [(&'static str, Function); 19] = [
        ("abs", Function::Abs),
        ("sqrt", Function::Sqrt),
        ("sin", Function::Sin),
        ("cos", Function::Cos),
        ("tan", Function::Tan),
        ("asin", Function::Asin),
        ("acos", Function::Acos),
        ("atan", Function::Atan),
        ("atan2", Function::Atan2),
        ("floor", Function::Floor),
        ("ceil", Function::Ceil),
        ("round", Function::Round),
        ("min", Function::Min),
        ("max", Function::Max),
        ("hypot", Function::Hypot),
        ("exp", Function::Exp),
        ("ln", Function::Ln),
        ("log10", Function::Log10),
        ("exists", Function::Exists),
    ];

    /// The function a Fanuc program means where LinuxCNC's reading gave
    /// `self` (the lexer reads FIX, FUP and ATAN as LinuxCNC does).
    pub fn on_fanuc(self) -> Function {
        match self {
            Function::Floor => Function::FanucFix,
            Function::Ceil => Function::FanucFup,
            Function::Atan2 => Function::FanucAtan,
            other => other,
        }
    }

    /// Function names match case-insensitively, as G-code does.
    pub fn from_name(name: &str) -> Option<Function> {
        Function::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, f)| f)
    }

    pub fn name(self) -> &'static str {
        match self {
            Function::FanucFix => return "FIX",
            Function::FanucFup => return "FUP",
            Function::FanucAtan => return "ATAN",
            _ => {}
        }
        Function::ALL
            .iter()
            .find(|(_, f)| *f == self)
            .map(|(n, _)| *n)
            .unwrap_or("?")
    }

    /// How many arguments it takes: `min` and `max` take two or more.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Function::Atan2 | Function::Hypot | Function::FanucAtan => (2, 2),
            Function::Min | Function::Max => (2, usize::MAX),
            _ => (1, 1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where a statement's words are: its code's and its arguments'.
    fn place(s: &LineStmt<'_>) -> (Option<*const Word>, *const Word, usize) {
        (
            s.code.map(|c| c as *const Word),
            s.args.as_ptr(),
            s.args.len(),
        )
    }

    /// A line with `G65` is a macro call from the `G65` on; the words
    /// before it stay the line's (its `N` label first), a second `G65`
    /// among the arguments is one of them.
    #[test]
    fn a_g65_line_is_a_macro_call_from_the_g65_on() {
        let word = |letter: u8, value: f64| Word {
            letter,
            value: WordValue::Number(Number {
                value,
                int_digits: 1,
                has_point: false,
            }),
            span: Span::default(),
        };
        let letters = |words: &[Word]| words.iter().map(|w| w.letter as char).collect::<String>();
        let line = [(b'N', 10.0), (b'G', 1.0), (b'X', 1.0), (b'G', 65.0)];
        let args = [(b'P', 9010.0), (b'M', 13.0), (b'G', 65.0), (b'A', 1.0)];
        let words = line.iter().chain(&args).map(|&(l, v)| word(l, v)).collect();
        let StmtKind::MacroCall(call) = StmtKind::line(words, true) else {
            panic!("not a macro call");
        };
        assert_eq!(letters(&call.before), "NGX");
        assert!(call.code.is_macro_call());
        assert_eq!(letters(&call.args), "PMGA");
        assert!(call.block_delete);
        assert_eq!(call.words().count(), 8);
        // G65.1 is no macro call.
        let words = vec![word(b'G', 65.1), word(b'P', 1.0)];
        assert!(matches!(StmtKind::line(words, false), StmtKind::Line(_)));
    }

    /// Every line of up to five words from G, M, N, X and F (and G65):
    /// with one code or none, [`few_statements`] cuts it as [`statements`].
    #[test]
    fn few_statements_cut_as_statements_do() {
        let word = |letter: u8, value: f64| Word {
            letter,
            value: WordValue::Number(Number {
                value,
                int_digits: 1,
                has_point: false,
            }),
            span: Span::default(),
        };
        let alphabet = [
            (b'G', 1.0),
            (b'M', 3.0),
            (b'N', 10.0),
            (b'X', 1.0),
            (b'F', 9.0),
            (b'G', 65.0),
        ];
        let (mut few, mut more) = (0, 0);
        for len in 0..=5u32 {
            for mut k in 0..alphabet.len().pow(len) {
                let words: Vec<Word> = (0..len)
                    .map(|_| {
                        let (letter, value) = alphabet[k % alphabet.len()];
                        k /= alphabet.len();
                        word(letter, value)
                    })
                    .collect();
                let all: Vec<_> = statements(&words).map(|s| place(&s)).collect();
                match few_statements(&words) {
                    Some(cut) => {
                        let got: Vec<_> = cut.iter().flatten().map(place).collect();
                        assert_eq!(got, all);
                        few += 1;
                    }
                    None => {
                        assert!(words.iter().filter(|w| w.is_code()).count() > 1);
                        more += 1;
                    }
                }
            }
        }
        assert!(few > 1000 && more > 1000, "{few} {more}");
    }
}
