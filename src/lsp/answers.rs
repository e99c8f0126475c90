//! The editor's questions about a place in an analysed document, answered
//! from its [`Analysis`]: hover, go to definition, references, rename,
//! completion and signature help. Pure: a document's text, its analysis
//! and a place in, plain data out; no protocol and no compile here (the
//! values a hover shows are handed in, worked out only when asked).

use super::analysis::{Analysis, At, LineStarts, WizardEntry};
use super::codes;
use super::index::{first_comment, VarPlace};
use crate::eval::Seen;
use std::collections::{BTreeSet, HashMap};
use std::path::PathBuf;

/// A place in the document (`file: None`) or in another file.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    pub file: Option<PathBuf>,
    pub from: At,
    pub to: At,
}

/// Fanuc's argument letters of `G65` and the local variable each sets
/// (argument specification I).
pub const MACRO_ARGUMENTS: &[(char, u32)] = &[
    ('A', 1),
    ('B', 2),
    ('C', 3),
    ('I', 4),
    ('J', 5),
    ('K', 6),
    ('D', 7),
    ('E', 8),
    ('F', 9),
    ('H', 11),
    ('M', 13),
    ('Q', 17),
    ('R', 18),
    ('S', 19),
    ('T', 20),
    ('U', 21),
    ('V', 22),
    ('W', 23),
    ('X', 24),
    ('Y', 25),
    ('Z', 26),
];

/// A document with its analysis and its line starts.
pub struct Document<'a> {
    pub text: &'a str,
    pub analysis: &'a Analysis,
    lines: LineStarts,
}

impl<'a> Document<'a> {
    pub fn new(text: &'a str, analysis: &'a Analysis) -> Document<'a> {
        Document {
            text,
            analysis,
            lines: LineStarts::new(text),
        }
    }

    fn offset(&self, at: At) -> usize {
        self.lines.offset(self.text, at)
    }

    fn here(&self, range: &std::ops::Range<usize>) -> Target {
        Target {
            file: None,
            from: self.lines.at(self.text, range.start),
            to: self.lines.at(self.text, range.end),
        }
    }

    /// The variable named at `at`, if any: the hover then needs the
    /// values ([`super::analysis::watch_unless`]).
    pub fn var_at(&self, at: At) -> Option<&'a VarPlace> {
        self.analysis.index.var_at(self.offset(at))
    }

    fn wizard(&self, name: &str) -> Option<&'a WizardEntry> {
        self.analysis
            .wizards
            .iter()
            .find(|w| w.name.eq_ignore_ascii_case(name))
    }

    /// What to show on hovering `at`, in Markdown: a variable's value
    /// there (from `values`, by the place's offset), a call's subprogram
    /// and its first comment, a wizard's manual, a code's meaning.
    pub fn hover(&self, at: At, values: Option<&HashMap<usize, Seen>>) -> Option<String> {
        let offset = self.offset(at);
        let index = &self.analysis.index;
        if let Some(var) = index.var_at(offset) {
            let seen = values.and_then(|v| v.get(&var.at.start));
            return Some(value_text(&var.name, seen));
        }
        if let Some(call) = index.call_at(offset) {
            let comment = match index.sub(&call.key) {
                Some(sub) => Some(first_comment(self.text, sub.whole.clone())),
                None => self
                    .analysis
                    .elsewhere
                    .iter()
                    .find(|s| s.key.eq_ignore_ascii_case(&call.key))
                    .map(|s| s.comment.clone()),
            };
            return Some(match comment {
                Some(Some(c)) => format!("**{}**: {c}", call.key),
                Some(None) => format!("**{}** (no comment)", call.key),
                None => format!("**{}**: no such subprogram found", call.key),
            });
        }
        if let Some(w) = index.wizard_at(offset).and_then(|w| self.wizard(&w.name)) {
            return Some(format!("```text\n{}```", w.manual));
        }
        super::analysis::hover(self.text, at)
    }

    /// Where what is named at `at` is defined: a call's subprogram, a
    /// variable's assignments, a wizard's `.rhai` file.
    pub fn definition(&self, at: At) -> Vec<Target> {
        let offset = self.offset(at);
        let index = &self.analysis.index;
        if let Some(var) = index.var_at(offset) {
            return index
                .same_variable(var)
                .filter(|v| v.set)
                .map(|v| self.here(&v.at))
                .collect();
        }
        if let Some(call) = index.call_at(offset) {
            if let Some(sub) = index.sub(&call.key) {
                return vec![self.here(&sub.at)];
            }
            return self
                .analysis
                .elsewhere
                .iter()
                .filter(|s| s.key.eq_ignore_ascii_case(&call.key))
                .map(|s| Target {
                    file: Some(s.file.clone()),
                    from: s.from,
                    to: s.to,
                })
                .take(1)
                .collect();
        }
        let file = index
            .wizard_at(offset)
            .and_then(|w| self.wizard(&w.name))
            .and_then(|w| w.file.clone());
        let top = At { line: 0, column: 0 };
        file.map(|file| Target {
            file: Some(file),
            from: top,
            to: top,
        })
        .into_iter()
        .collect()
    }

    /// The name of the standard library's wizard called at `at`, if
    /// that is what `at` names: it has no file of its own (it is compiled
    /// into the binary), so the server writes one for the editor.
    pub fn stdlib_wizard_at(&self, at: At) -> Option<&'a str> {
        let called = self.analysis.index.wizard_at(self.offset(at))?;
        let w = self.wizard(&called.name)?;
        w.file.is_none().then_some(w.name.as_str())
    }

    /// Every place in the document naming what `at` names: a variable's
    /// reads and assignments, a subprogram and its calls, a wizard's calls.
    pub fn references(&self, at: At) -> Vec<Target> {
        let offset = self.offset(at);
        let index = &self.analysis.index;
        if let Some(var) = index.var_at(offset) {
            return index.same_variable(var).map(|v| self.here(&v.at)).collect();
        }
        let sub = index.subs.iter().find(|s| s.at.contains(&offset));
        let key = sub
            .map(|s| &s.key)
            .or_else(|| index.call_at(offset).map(|c| &c.key));
        if let Some(key) = key {
            let definition = index.sub(key).map(|s| self.here(&s.at));
            let calls = index
                .calls
                .iter()
                .filter(|c| c.key.eq_ignore_ascii_case(key));
            return definition
                .into_iter()
                .chain(calls.map(|c| self.here(&c.at)))
                .collect();
        }
        match index.wizard_at(offset) {
            Some(w) => index
                .wizard_calls
                .iter()
                .filter(|c| c.name.eq_ignore_ascii_case(&w.name))
                .map(|c| self.here(&c.at))
                .collect(),
            None => Vec::new(),
        }
    }

    /// The edits that rename the variable at `at` to `new` everywhere in
    /// its scope (a LinuxCNC sub's local: in that sub only); `Err` when `at` names none or `new` is no name.
    pub fn rename(&self, at: At, new: &str) -> Result<Vec<(Target, String)>, String> {
        let var = self
            .var_at(at)
            .ok_or("only a variable or a named parameter can be renamed")?;
        let written = &self.text[var.at.clone()];
        let new = new.trim();
        let replacement = match written.starts_with("#<") {
            true if new.starts_with("#<") => new.to_string(),
            true => format!("#<{new}>"),
            false => new.to_string(),
        };
        let bare = replacement
            .strip_prefix("#<")
            .and_then(|n| n.strip_suffix('>'))
            .unwrap_or(&replacement);
        let is_name = bare.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
            && bare.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if written.starts_with('#') && !written.starts_with("#<") || !is_name {
            return Err(format!("`{new}` is not a name this variable can take"));
        }
        Ok(self
            .analysis
            .index
            .same_variable(var)
            .map(|v| (self.here(&v.at), replacement.clone()))
            .collect())
    }

    /// What may be written at `at`: G/M codes (after a `G` or `M`),
    /// variables and named parameters the document sets that are in
    /// scope there (global, or local to the sub `at` is in), wizards.
    pub fn completion(&self, at: At) -> Vec<Completion> {
        let offset = self.offset(at);
        let before = &self.text[..offset];
        let start = before
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '#' | '<' | '.')))
            .map_or(0, |i| i + 1);
        let typed = &before[start..];
        let letter = typed.chars().next().map(|c| c.to_ascii_uppercase());
        let code_like =
            typed.len() > 1 && typed[1..].chars().all(|c| c.is_ascii_digit() || c == '.');
        let mut out = Vec::new();
        if matches!(letter, Some('G' | 'M')) && (typed.len() == 1 || code_like) {
            out.extend(
                codes::CODES
                    .iter()
                    .filter(|c| Some(c.letter as char) == letter)
                    .map(|c| Completion {
                        label: c.name(),
                        detail: c.meaning.to_string(),
                        snippet: None,
                        kind: CompletionKind::Code,
                    }),
            );
        }
        if code_like {
            return out;
        }
        let scope = self.analysis.index.scope_at(offset);
        let names: BTreeSet<&str> = self
            .analysis
            .index
            .vars
            .iter()
            .filter(|v| v.set || v.name.starts_with("#<"))
            .filter(|v| v.scope.is_none_or(|s| s == scope))
            .map(|v| v.name.as_str())
            .collect();
        out.extend(names.into_iter().map(|name| Completion {
            label: name.to_string(),
            detail: "variable".into(),
            snippet: None,
            kind: CompletionKind::Variable,
        }));
        if !typed.starts_with('#') {
            out.extend(self.analysis.wizards.iter().map(|w| Completion {
                label: w.name.clone(),
                detail: w.summary.clone(),
                snippet: Some(snippet(w)),
                kind: CompletionKind::Wizard,
            }));
        }
        out
    }

    /// The signature of the wizard or `G65` call `at` is in, and which of
    /// its parameters is being written.
    pub fn signature(&self, at: At) -> Option<Signature> {
        let offset = self.offset(at);
        let line_start = self.text[..offset].rfind('\n').map_or(0, |i| i + 1);
        let before = &self.text[line_start..offset];
        if let Some(g65) = macro_call_start(before) {
            return Some(self.macro_signature(&before[g65..]));
        }
        let trimmed = before.trim_start();
        let name_len = trimmed
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(trimmed.len());
        if name_len == trimmed.len() {
            return None;
        }
        let w = self.wizard(&trimmed[..name_len])?;
        let rest = &trimmed[name_len..];
        let active = match rest.trim_start().strip_prefix('(') {
            Some(args) => top_level(args, |c| c == ','),
            None => arguments_begun(rest),
        };
        Some(Signature {
            label: format!("{} {}", w.name, parameter_labels(w).join(" ")),
            doc: w.summary.clone(),
            parameters: parameter_labels(w),
            active: active.min(w.params.len().saturating_sub(1)),
        })
    }

    /// The signature of a `G65` call whose words after `G65` are `words`.
    fn macro_signature(&self, words: &str) -> Signature {
        let mut parameters = vec!["P".to_string(), "L".to_string()];
        parameters.extend(MACRO_ARGUMENTS.iter().map(|(l, n)| format!("{l}=#{n}")));
        let last = words
            .split_whitespace()
            .skip(1)
            .last()
            .filter(|_| !words.ends_with(char::is_whitespace));
        let letter = last
            .and_then(|w| w.chars().next())
            .map(|c| c.to_ascii_uppercase());
        let active = letter
            .and_then(|l| parameters.iter().position(|p| p.starts_with(l)))
            .unwrap_or(0);
        let program = words
            .split_whitespace()
            .find_map(|w| w.strip_prefix(['P', 'p'])?.parse::<u32>().ok());
        let doc = match program.and_then(|n| self.analysis.index.sub(&format!("O{n}"))) {
            Some(sub) => {
                let comment = first_comment(self.text, sub.whole.clone()).unwrap_or_default();
                format!("macro call of {}: {comment}", sub.key)
            }
            None => "macro call: P program, L repeats; each letter sets its local variable".into(),
        };
        Signature {
            label: format!("G65 {}", parameters.join(" ")),
            doc,
            parameters,
            active,
        }
    }
}

/// A completion offered.
#[derive(Clone, Debug, PartialEq)]
pub struct Completion {
    pub label: String,
    pub detail: String,
    /// What to insert, as an LSP snippet (`${1:width}`).
    pub snippet: Option<String>,
    pub kind: CompletionKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompletionKind {
    Code,
    Variable,
    Wizard,
}

/// A call's signature and the parameter being written.
#[derive(Clone, Debug, PartialEq)]
pub struct Signature {
    pub label: String,
    pub doc: String,
    /// Each parameter as it stands in `label`.
    pub parameters: Vec<String>,
    pub active: usize,
}

/// A hover's words on a variable's values at one place.
fn value_text(name: &str, seen: Option<&Seen>) -> String {
    match seen {
        Some(s) if s.distinct == 1 => format!("`{name}` = {} here", s.first),
        Some(s) => format!(
            "`{name}` varies here: {} values, {} … {}",
            s.distinct, s.min, s.max
        ),
        None => {
            format!("`{name}`: no value known here at compile time (not run, or the machine's)")
        }
    }
}

/// A wizard's parameters as its signature writes them (`stepdown=0`).
fn parameter_labels(w: &WizardEntry) -> Vec<String> {
    w.params
        .iter()
        .map(|(name, default)| match default {
            Some(d) => format!("[{name}={d}]"),
            None => name.clone(),
        })
        .collect()
}

/// A wizard call with its parameters without defaults as placeholders.
fn snippet(w: &WizardEntry) -> String {
    let mut s = w.name.clone();
    for (i, (name, _)) in w.params.iter().filter(|(_, d)| d.is_none()).enumerate() {
        s.push_str(&format!(" ${{{}:{name}}}", i + 1));
    }
    s
}

/// Where `G65` starts in a line's text (as a word, not in a comment).
fn macro_call_start(line: &str) -> Option<usize> {
    let code = line.split([';', '(']).next().unwrap_or_default();
    let upper = code.to_ascii_uppercase();
    upper.match_indices("G65").map(|(i, _)| i).find(|&i| {
        let after = upper[i + 3..].chars().next();
        (i == 0 || !upper.as_bytes()[i - 1].is_ascii_alphanumeric())
            && !after.is_some_and(|c| c.is_ascii_digit() || c == '.')
    })
}

/// How many of `text`'s characters outside brackets `split` is true of.
fn top_level(text: &str, split: impl Fn(char) -> bool) -> usize {
    let mut depth = 0i32;
    let mut count = 0;
    for c in text.chars() {
        match c {
            '(' | '[' | '<' => depth += 1,
            ')' | ']' | '>' => depth -= 1,
            c if depth == 0 && split(c) => count += 1,
            _ => {}
        }
    }
    count
}

/// Which argument of a wizard call written with spaces the text after
/// its name is in (0: the first).
fn arguments_begun(rest: &str) -> usize {
    let mut depth = 0i32;
    let (mut count, mut in_word) = (0usize, false);
    for c in rest.chars() {
        match c {
            '(' | '[' | '<' => depth += 1,
            ')' | ']' | '>' => depth -= 1,
            _ => {}
        }
        let space = depth == 0 && c.is_whitespace();
        if !space && !in_word {
            count += 1;
        }
        in_word = !space;
    }
    // Past a space: the next argument is begun.
    match in_word {
        true => count.saturating_sub(1),
        false => count,
    }
}
