//! LinuxCNC's language in plain G-code (SPEC §2.8), in the one lexer:
//! `#1` and `#<name>` parameters, `[ ]` groups and symbolic words, word
//! operators (`EQ`, `AND`, `MOD`, `**`), FIX/FUP/ATAN, and the o-words.
//! It must not build syntax trees.

use super::error::SyntaxErrorKind;
use super::lexer::{expects_value, find_word, Lexer, PendingCall, Raw, Shape};
use super::token::Tok;
use super::words::{parse_decimal, WordNumber};
use crate::ast::{BinaryOp, Function, OName};

/// The name of a LinuxCNC subroutine as written between `o<` and `>`:
/// without its blanks (rs274 reads a line without them: `o<a b>` is
/// `o<ab>`), in lower case (its file is `name.ngc`).
pub fn subroutine_name(written: &str) -> String {
    written
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_lowercase()
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

/// Arguments of an `o… call`: a subroutine reads them as `#1` to `#30`.
pub const MAX_CALL_ARGUMENTS: u32 = 30;

/// LinuxCNC's value of the last subroutine's return, and whether it
/// returned one: set by every `return` and `endsub` (0 without a value),
/// read-only to the program.
pub const RETURN_VALUE: &str = "#<_value>";
pub const VALUE_RETURNED: &str = "#<_value_returned>";

/// The keywords of LinuxCNC's o-words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum OWord {
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

/// An o-word's label as read: the value of its `O` word (checked where
/// it must name a program), or `o<name>`.
#[derive(Clone, Copy, Debug)]
enum Label {
    Number(f64),
    Named(OName),
}

impl Label {
    /// As a loop's label (`o1.5 while` is loop 1, as the label was read).
    fn as_loop(self) -> OName {
        match self {
            Label::Number(n) => OName::Number(n as u32),
            Label::Named(name) => name,
        }
    }
}

impl OWord {
    /// The keyword spelled at the start of `text`, as rs274 reads it from
    /// a line without its blanks: letters with spaces or tabs between
    /// them (`s u b`, `end sub`, `else if`), the first of its keywords in
    /// its order that they start with; with the length of `text` it
    /// takes. A letter or digit right after the keyword's last letter
    /// makes it none (`endsubx`, `sub1`: rs274 refuses those).
    pub(super) fn spelled(text: &str) -> Option<(OWord, usize)> {
        // rs274's order: `elseif` before `else`.
        const KEYWORDS: [(&str, OWord); 15] = [
            ("sub", OWord::Sub),
            ("endsub", OWord::EndSub),
            ("call", OWord::Call),
            ("do", OWord::Do),
            ("while", OWord::While),
            ("repeat", OWord::Repeat),
            ("if", OWord::If),
            ("elseif", OWord::ElseIf),
            ("else", OWord::Else),
            ("endif", OWord::EndIf),
            ("break", OWord::Break),
            ("continue", OWord::Continue),
            ("endwhile", OWord::EndWhile),
            ("endrepeat", OWord::EndRepeat),
            ("return", OWord::Return),
        ];
        // Each letter (in lower case) and the offset just past it.
        let bytes = text.as_bytes();
        let mut letters = [(0u8, 0usize); 9];
        let (mut count, mut i) = (0, 0);
        while count < letters.len() {
            while let Some(b' ' | b'\t') = bytes.get(i) {
                i += 1;
            }
            match bytes.get(i) {
                Some(b) if b.is_ascii_alphabetic() => {
                    letters[count] = (b.to_ascii_lowercase(), i + 1)
                }
                _ => break,
            }
            count += 1;
            i += 1;
        }
        let letters = &letters[..count];
        let (keyword, taken) = KEYWORDS.iter().find_map(|&(k, word)| {
            let spelled = letters.iter().map(|l| l.0).take(k.len());
            (letters.len() >= k.len() && spelled.eq(k.bytes()))
                .then(|| (word, letters[k.len() - 1].1))
        })?;
        let joined = bytes
            .get(taken)
            .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_');
        (!joined).then_some((keyword, taken))
    }
}

impl Lexer<'_> {
    /// LinuxCNC's parameters and expressions in plain G-code, read as the
    /// `.egc` tokens they mean: `#<name>` and `#1` are names, `[ ]` groups
    /// (`X[…]` and `X#1` are symbolic words, `sin[…]` a call), `EQ`…`LE`,
    /// `AND`, `OR`, `MOD` and `**` operators; the o-words are read by
    /// [`Self::o_word`]. Where it took the text, the offset to go on from.
    pub(super) fn linuxcnc(
        &mut self,
        raw: Result<Raw, ()>,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        if matches!(raw, Ok(Raw::Letter | Raw::Ident)) {
            if let Some(taken) = self.o_word(start) {
                return Some(taken);
            }
        }
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
            // `o <name>`: rs274 drops the blanks before the `<` too.
            Ok(Raw::Letter)
                if rest.starts_with(['o', 'O'])
                    && rest[1..].trim_start_matches([' ', '\t']).starts_with('<')
                    && self.first_on_line(start) =>
            {
                self.named_o_word(start)
            }
            Ok(Raw::Letter) => self.expression_word(start, end),
            Ok(Raw::Caret) | Err(())
                if rest.starts_with(['@', '^'])
                    && self.groups.is_empty()
                    && self.syms.is_empty() =>
            {
                self.polar_word(start)
            }
            Ok(Raw::Ident) => self.linuxcnc_ident(start, end),
            Ok(Raw::SymOpen) if rest.starts_with(['o', 'O']) && self.first_on_line(start) => {
                self.named_o_word(start)
            }
            _ => None,
        }
    }

    /// A `[` at `start`: a group, a function's arguments, or the next
    /// argument of an `o… call`; where to go on.
    pub(super) fn open_bracket(&mut self, start: usize) -> usize {
        if self.groups.is_empty() && self.syms.is_empty() {
            if let Some(pending) = &mut self.pending_call {
                // The next argument of an `o… call`.
                pending.args += 1;
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
    pub(super) fn atan_comma(&mut self, start: usize) -> usize {
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

    /// A `]` at `start`: the end of a symbolic word or of a group.
    pub(super) fn close_bracket(&mut self, start: usize) -> usize {
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

    /// `X[…]`, `X#1`, `Z-#2`, `Z-[…]`: a word whose value is an expression. Where
    /// it took the text, the offset to go on from.
    pub(super) fn expression_word(&mut self, start: usize, end: usize) -> Option<usize> {
        let letter = self.text.as_bytes()[start].to_ascii_uppercase();
        self.expression_word_of(letter, start, end)
    }

    /// [`Self::expression_word`] of a word whose letter is `letter`
    /// (Fanuc's `,R[#1]` is spelled with two characters).
    pub(super) fn expression_word_of(
        &mut self,
        letter: u8,
        start: usize,
        end: usize,
    ) -> Option<usize> {
        let after = self.text[end..].trim_start_matches([' ', '\t']);
        let at = self.text.len() - after.len();
        // After a minus (and blanks: `X - #1`), the value it negates.
        let negated = after
            .strip_prefix('-')
            .map(|r| r.trim_start_matches([' ', '\t']));
        if after.starts_with('[') {
            self.open_sym(start, '[', false);
            self.push(start, Tok::SymOpen(letter), at + 1);
            Some(at + 1)
        } else if after.starts_with('#') || negated.is_some_and(|r| r.starts_with('#')) {
            // `Z-#2` is the parameter's negative, as rs274 reads it.
            self.push(start, Tok::SymOpen(letter), end);
            let hash = match negated {
                Some(rest) => {
                    self.push(at, Tok::NegTight, at + 1);
                    self.text.len() - rest.len()
                }
                None => at,
            };
            let name_end = self.parameter(hash);
            let bracket = self.text[name_end..].starts_with('[');
            if bracket && matches!(self.out.last(), Some((_, Tok::Hash, _))) {
                // `X#[…]`: the word ends where the group does.
                self.open_sym(start, '[', true);
            } else {
                self.push(name_end, Tok::SymClose, name_end);
            }
            Some(name_end)
        } else if let Some(group) = negated.filter(|r| r.starts_with('[')) {
            // `X-[#1*2]`: the group's negative; the word ends with it.
            self.push(start, Tok::SymOpen(letter), end);
            self.push(at, Tok::NegTight, at + 1);
            self.open_sym(start, '[', true);
            Some(self.text.len() - group.len())
        } else {
            None
        }
    }

    /// `@1.5`, `^[360/17]`: a polar word (radius or angle), a word whose
    /// letter is the sign; where to go on.
    fn polar_word(&mut self, start: usize) -> Option<usize> {
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let number = WordNumber::after(self.text, start + 1, line_end);
        if number.is_decimal() {
            let word = number.word(self.text.as_bytes()[start]);
            self.push_word(word, start, number.end);
            return Some(number.end);
        }
        self.expression_word(start, start + 1)
    }

    /// A word of letters: an operator inside brackets, FIX or FUP, or an
    /// o-word's keyword.
    pub(super) fn linuxcnc_ident(&mut self, start: usize, end: usize) -> Option<usize> {
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
        None
    }

    /// An operator written against the number after it, inside brackets
    /// (`[#1EQ1]`, `[#2GT0.5]`: rs274 and Fanuc read them so): the
    /// operator, then the number; where they end.
    pub(super) fn operator_then_number(&mut self, start: usize, end: usize) -> Option<usize> {
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

    /// `o<name>` (or `o <name>`): a named subroutine or loop label, which the keyword
    /// after it takes ([`Self::take_label`]).
    pub(super) fn named_o_word(&mut self, start: usize) -> Option<usize> {
        let rest = &self.text[start..];
        let open = rest.find('<')?;
        let close = rest
            .find(['>', '\n'])
            .filter(|&i| rest[i..].starts_with('>'))?;
        let name = subroutine_name(&rest[open + 1..close]);
        let symbol = self.names.intern(&format!("o<{name}>"));
        self.push(start, Tok::OName(OName::Named(symbol)), start + close + 1);
        Some(start + close + 1)
    }

    /// `#<name>` or `#123` at `start`, pushed as a name; or the `#` of an
    /// indirect parameter (`##1`, `#[…]`), pushed as [`Tok::Hash`] before
    /// the parameter or the `[` it reads. Where it ends.
    pub(super) fn parameter(&mut self, mut start: usize) -> usize {
        loop {
            if let Some(end) = self.spaced_parameter(start) {
                return end;
            }
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

    /// `#1 2` at `start`, a parameter's number with blanks inside, pushed
    /// as its name (`#12`: rs274 reads a line without its blanks); where
    /// it ends.
    fn spaced_parameter(&mut self, start: usize) -> Option<usize> {
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let number = WordNumber::after(self.text, start + 1, line_end);
        let written = &self.text[start + 1..number.end];
        if !number.spaced
            || !written
                .bytes()
                .all(|b| matches!(b, b'0'..=b'9' | b' ' | b'\t'))
        {
            return None;
        }
        let digits = written.replace([' ', '\t'], "");
        let (name, _) = parameter_name(&digits).ok()?;
        let symbol = self.names.intern(&name);
        self.push(start, Tok::Name(symbol), number.end);
        Some(number.end)
    }

    /// Every numbered parameter a `#[…]` may reach gets its name (once):
    /// the evaluator finds a computed parameter by its name.
    pub(super) fn name_every_parameter(&mut self) {
        if !self.every_parameter_named {
            self.every_parameter_named = true;
            for n in 0..=LAST_PARAMETER {
                self.names.intern(&format!("#{n}"));
            }
        }
    }

    /// LinuxCNC's word operators, inside brackets.
    pub(super) fn operator(&self, text: &str) -> Option<Tok> {
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

    /// The LinuxCNC o-word keyword at `start`, after the o-word of this
    /// line, spelled as rs274 reads it ([`OWord::spelled`]): `sub`,
    /// `call`, `return`, `endsub` and `repeat` become their own tokens;
    /// `if`, `elseif`, `else`, `endif`, `while`, `endwhile`, `do`, `break`
    /// and `continue` become `.egc` blocks and jumps (the o-word only
    /// labels them).
    pub(super) fn o_word(&mut self, start: usize) -> Option<usize> {
        let (keyword, taken) = OWord::spelled(&self.text[start..])?;
        let end = start + taken;
        let (label, (o_start, o_end)) = self.take_label(start)?;
        // rs274 runs an o-word after a block-delete `/` as any other.
        if self.out.len() == self.stmt_start + 1
            && matches!(self.out.last(), Some(&(_, Tok::Slash, _)))
        {
            self.out.pop();
            self.shape = Shape::Empty;
        }
        // Sub and call name a program: a whole number in range.
        let name = |lexer: &mut Self| match label {
            Label::Named(name) => Some(name),
            Label::Number(n) => {
                let number = crate::ast::program_number(n);
                if number.is_none() {
                    let kind = SyntaxErrorKind::InvalidProgramNumber;
                    lexer.report(kind, o_start, o_end);
                }
                number.map(OName::Number)
            }
        };
        match keyword {
            OWord::Sub => {
                self.in_sub = true;
                if let Some(name) = name(self) {
                    self.new_statement(o_start);
                    self.push(o_start, Tok::Sub(name), o_end);
                }
            }
            OWord::EndSub | OWord::Return => {
                let ends_sub = keyword == OWord::EndSub;
                if ends_sub {
                    self.in_sub = false;
                } else if !self.in_sub {
                    self.report(SyntaxErrorKind::ReturnOutsideSub, start, end);
                    return Some(end);
                }
                // The evaluator sets them by name: named whether or not the
                // program reads them.
                self.names.intern(RETURN_VALUE);
                self.names.intern(VALUE_RETURNED);
                self.new_statement(start);
                self.push(start, Tok::Return(ends_sub), end);
            }
            OWord::Call => {
                if let Some(name) = name(self) {
                    self.new_statement(start);
                    self.push(start, Tok::SubCall(name), end);
                }
                self.pending_call = Some(PendingCall {
                    args: 0,
                    at: (start, end),
                });
            }
            _ => self.o_block(keyword, label.as_loop(), start, end),
        }
        Some(end)
    }

    /// The o-word keywords of blocks and jumps, with their loop's label.
    fn o_block(&mut self, keyword: OWord, label: OName, start: usize, end: usize) {
        match keyword {
            // `oN do … oN while [c]`: `do { … } while (c)`.
            OWord::Do => {
                self.push(start, Tok::Loop(label), end);
                self.push(start, Tok::Do, end);
                self.block_at_line_end = true;
                self.do_labels.push(label);
            }
            OWord::Break => self.push(start, Tok::Break(label), end),
            OWord::Continue => self.push(start, Tok::Continue(label), end),
            // `oN repeat [n] … oN endrepeat`: its block opens at the
            // line's end and closes at `endrepeat`.
            OWord::Repeat => {
                self.push(start, Tok::Repeat(label), end);
                self.block_at_line_end = true;
            }
            OWord::While if self.do_labels.last() == Some(&label) => {
                self.do_labels.pop();
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
                self.push(start, Tok::While, end);
            }
            OWord::While => {
                self.push(start, Tok::Loop(label), end);
                self.push(start, Tok::While, end);
                self.block_at_line_end = true;
            }
            OWord::If => {
                self.push(start, Tok::If, end);
                self.block_at_line_end = true;
            }
            OWord::ElseIf | OWord::Else => {
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
            _ => {
                // `endif`, `endwhile`, `endrepeat`.
                if let Some(tok) = self.close_brace(start, end) {
                    self.push(start, tok, end);
                }
            }
        }
    }

    /// The o-word before the keyword at `start`, taken out of the stream:
    /// the `O` word right before it on its line, or the `o<name>` token;
    /// with its span. `None` (nothing taken) if there is none.
    fn take_label(&mut self, start: usize) -> Option<(Label, (usize, usize))> {
        if let Some(&(o_start, Tok::OName(name), o_end)) = self.out.last() {
            self.out.pop();
            if self.out.len() <= self.stmt_start {
                self.shape = Shape::Empty;
            }
            return Some((Label::Named(name), (o_start, o_end)));
        }
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        // The keyword must come right after its O word, the last token.
        let count = self.words.len();
        let right_after = matches!(self.out.last(), Some(&(_, Tok::Words(first, len), _))
            if (first + len) as usize == count);
        let last = self
            .words
            .last()
            .filter(|w| right_after && w.word.letter == b'O' && w.start as usize >= line_start)?;
        let found = (
            Label::Number(last.word.value),
            (last.start as usize, last.end as usize),
        );
        self.drop_label();
        Some(found)
    }

    /// A line that is only `o<name>` names a program, as a line that is
    /// only `O100` does: a subprogram starts there (and is reported if no
    /// `M99` or `endsub` ends it).
    pub(super) fn lone_o_name(&mut self) {
        if self.pending_term.is_none() && self.out.len() == self.stmt_start + 1 {
            if let Some((_, tok, _)) = self.out.last_mut() {
                if let Tok::OName(name) = *tok {
                    *tok = Tok::Sub(name);
                }
            }
        }
    }

    /// A statement ends before the one that starts at `at`, unless none
    /// has started.
    fn new_statement(&mut self, at: usize) {
        if self.out.len() > self.stmt_start {
            self.pending_term = Some((at, at));
            self.shape = Shape::Empty;
        }
    }

    /// The end of an `o… call` line: no more arguments than a
    /// subprogram reads.
    pub(super) fn end_call(&mut self, call: PendingCall) {
        let (start, end) = call.at;
        if call.args > MAX_CALL_ARGUMENTS {
            self.report(
                SyntaxErrorKind::TooManyArguments(MAX_CALL_ARGUMENTS),
                start,
                end,
            );
        }
    }

    /// Drop the O word just read: it only labels a block.
    pub(super) fn drop_label(&mut self) {
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

    /// An assignment to LinuxCNC's return value, which the program may
    /// only read: the name just read is the statement's first token.
    pub(super) fn read_only_target(&mut self) {
        if let Some(&(at, Tok::Name(name), name_end)) = self.out.last() {
            let text = self.names.text(name);
            if text == RETURN_VALUE || text == VALUE_RETURNED {
                let kind = SyntaxErrorKind::ReadOnlyParameter(text.to_string());
                self.report(kind, at, name_end);
            }
        }
    }
}
