//! The names of one document and where they are, from its syntax tree:
//! each variable's reads and assignments, each subprogram and the calls
//! of it (`M98 P…`, `G65 P…`, `o… call`), each wizard call. What hover,
//! go to definition, references, rename and completion look things up
//! in. Byte offsets into the document's text; no protocol, no evaluation.
//!
//! Scopes as the evaluator keeps them (`eval/state.rs`'s `CallScope`):
//! in a LinuxCNC `o… sub`, `#1`–`#30` and the named parameters that do
//! not start with `_` are the sub's own; the main program's (and a
//! Fanuc `O` block's, which shares its caller's) are another scope; every
//! other name is global.

use crate::ast::{self, Expr, ExprKind, Names, OName, Stmt, StmtKind, WordValue};
use crate::syntax::Language;

/// A byte range of the document.
pub type Bytes = std::ops::Range<usize>;

/// A variable named at a place: read, or set by an assignment.
#[derive(Clone, Debug, PartialEq)]
pub struct VarPlace {
    /// As the program's names have it (`Count`, `#<depth>`, `#1`).
    pub name: String,
    pub at: Bytes,
    pub set: bool,
    /// The scope it is local to ([`Index::scope_at`]); `None`: global.
    pub scope: Option<usize>,
}

/// A subprogram the document defines.
#[derive(Clone, Debug, PartialEq)]
pub struct SubPlace {
    /// `O100` or `o<name>` ([`OName::describe`]).
    pub key: String,
    /// Its `O` word (or `o…` word).
    pub at: Bytes,
    /// Its opening line to the end of its body.
    pub whole: Bytes,
}

/// A call of a subprogram: the word that names it.
#[derive(Clone, Debug, PartialEq)]
pub struct CallPlace {
    pub key: String,
    pub at: Bytes,
}

/// A wizard (or directive) call: its name.
#[derive(Clone, Debug, PartialEq)]
pub struct WizardPlace {
    pub name: String,
    pub at: Bytes,
}

/// Every name of a document and its places.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Index {
    pub vars: Vec<VarPlace>,
    pub subs: Vec<SubPlace>,
    pub calls: Vec<CallPlace>,
    pub wizard_calls: Vec<WizardPlace>,
    /// The LinuxCNC subs' bodies, each a scope of its own (numbered from
    /// 1 in this order; 0 is the main program's).
    pub scopes: Vec<Bytes>,
}

impl Index {
    /// The index of `text` read as `language`.
    pub fn of(text: &str, language: Language) -> Index {
        let (program, _) = crate::syntax::parse_program_as(text, 0, language);
        Index::of_program(&program, text)
    }

    /// The index of `program`, parsed from `text`.
    pub fn of_program(program: &ast::Program, text: &str) -> Index {
        let mut index = Index::default();
        let names = &program.names;
        index.scoped(&program.main, 0, names, text);
        for sub in &program.subprograms {
            let end = sub.body.last().map_or(sub.span.end, |s| s.span.end);
            let whole = sub.span.start as usize..end as usize;
            index.subs.push(SubPlace {
                key: sub.name.describe(names),
                at: sub.span.start as usize..sub.span.end as usize,
                whole: whole.clone(),
            });
            let scope = match opens_a_sub(text, sub.span.end as usize) {
                true => {
                    index.scopes.push(whole);
                    index.scopes.len()
                }
                false => 0,
            };
            index.scoped(&sub.body, scope, names, text);
        }
        index.vars.sort_by_key(|v| v.at.start);
        index
    }

    /// The names of `body`, the local ones in `scope`.
    fn scoped(&mut self, body: &[Stmt], scope: usize, names: &Names, text: &str) {
        let from = self.vars.len();
        self.stmts(body, names, text);
        for var in &mut self.vars[from..] {
            var.scope = is_local(&var.name).then_some(scope);
        }
    }

    /// The scope the byte `offset` is in: a LinuxCNC sub's (from 1), else
    /// the main program's (0).
    pub fn scope_at(&self, offset: usize) -> usize {
        self.scopes
            .iter()
            .position(|s| s.contains(&offset))
            .map_or(0, |i| i + 1)
    }

    /// The places of the variable `var` names: those of its name in its
    /// scope.
    pub fn same_variable<'a>(&'a self, var: &'a VarPlace) -> impl Iterator<Item = &'a VarPlace> {
        self.vars
            .iter()
            .filter(move |v| v.name == var.name && v.scope == var.scope)
    }

    fn stmts(&mut self, stmts: &[Stmt], names: &Names, text: &str) {
        for stmt in stmts {
            self.stmt(stmt, names, text);
        }
    }

    fn stmt(&mut self, stmt: &Stmt, names: &Names, text: &str) {
        match &stmt.kind {
            StmtKind::Line(line) => self.words(&line.words, names),
            StmtKind::Lines(lines) => {
                for words in lines.each_as_words() {
                    self.words(&words, names);
                }
            }
            StmtKind::MacroCall(call) => {
                self.words(&call.before, names);
                self.words(&call.args, names);
                self.macro_call(call, names);
            }
            StmtKind::Assign(a) => self.assignment(a, names),
            StmtKind::Assigns(all) => all.iter().for_each(|a| self.assignment(a, names)),
            StmtKind::Call {
                name,
                name_span,
                args,
            } => {
                self.wizard_calls.push(WizardPlace {
                    name: names.text(*name).to_string(),
                    at: name_span.start as usize..name_span.end as usize,
                });
                args.iter().for_each(|a| self.expr(a, names));
            }
            StmtKind::If(if_) => {
                for (cond, body) in &if_.branches {
                    self.expr(cond, names);
                    self.stmts(body, names, text);
                }
                if let Some(body) = &if_.otherwise {
                    self.stmts(body, names, text);
                }
            }
            StmtKind::While(w) => {
                self.expr(&w.cond, names);
                self.stmts(&w.body, names, text);
            }
            StmtKind::Repeat(r) => {
                self.expr(&r.count, names);
                self.stmts(&r.body, names, text);
            }
            StmtKind::SubCall(call) => {
                if let Some(at) = o_word_before(text, call.at.start as usize) {
                    self.calls.push(CallPlace {
                        key: call.name.describe(names),
                        at,
                    });
                }
                call.args.iter().for_each(|a| self.expr(a, names));
            }
            StmtKind::Return(r) => r.value.iter().for_each(|v| self.expr(v, names)),
            StmtKind::Goto(target) => self.expr(target, names),
            StmtKind::Sub(_)
            | StmtKind::DefinitionRead { .. }
            | StmtKind::Break(_)
            | StmtKind::Continue(_)
            | StmtKind::Command(_)
            | StmtKind::Comment(_)
            | StmtKind::Error => {}
        }
    }

    fn assignment(&mut self, a: &ast::Assignment, names: &Names) {
        match &a.target {
            ast::Target::Name(name) => self.vars.push(VarPlace {
                name: names.text(*name).to_string(),
                at: a.name_span.start as usize..a.name_span.end as usize,
                set: true,
                scope: None,
            }),
            ast::Target::Indirect(e) => self.expr(e, names),
        }
        self.expr(&a.value, names);
    }

    /// A line's words: the variables its values read, and its calls.
    fn words(&mut self, words: &[ast::Word], names: &Names) {
        for w in words {
            if let WordValue::Expr(e) = &w.value {
                self.expr(e, names);
            }
        }
        for s in ast::statements(words) {
            let Some(code) = s.code else { continue };
            let WordValue::Number(n) = code.value else {
                continue;
            };
            if code.letter != b'M' || n.value != 98.0 {
                continue;
            }
            if let Some((number, at)) = program_word(s.args) {
                let program = number.m98_split(number.value as u32).0;
                self.calls.push(CallPlace {
                    key: OName::Number(program).describe(names),
                    at,
                });
            }
        }
    }

    /// Fanuc's `G65 P…`: a call of the program its `P` names.
    fn macro_call(&mut self, call: &ast::MacroCall, names: &Names) {
        if let Some((number, at)) = program_word(&call.args) {
            self.calls.push(CallPlace {
                key: OName::Number(number.value as u32).describe(names),
                at,
            });
        }
    }

    fn expr(&mut self, e: &Expr, names: &Names) {
        match &e.kind {
            ExprKind::Var(s) => self.vars.push(VarPlace {
                name: names.text(*s).to_string(),
                at: e.span.start as usize..e.span.end as usize,
                set: false,
                scope: None,
            }),
            ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
            ExprKind::Indirect(inner) | ExprKind::Unary(_, inner) => self.expr(inner, names),
            ExprKind::Binary(_, a, b) => {
                self.expr(a, names);
                self.expr(b, names);
            }
            ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => {
                args.iter().for_each(|a| self.expr(a, names))
            }
        }
    }

    /// The variable place at byte `offset`.
    pub fn var_at(&self, offset: usize) -> Option<&VarPlace> {
        self.vars.iter().find(|v| v.at.contains(&offset))
    }

    /// The call at byte `offset`.
    pub fn call_at(&self, offset: usize) -> Option<&CallPlace> {
        self.calls.iter().find(|c| c.at.contains(&offset))
    }

    /// The wizard call at byte `offset`.
    pub fn wizard_at(&self, offset: usize) -> Option<&WizardPlace> {
        self.wizard_calls.iter().find(|w| w.at.contains(&offset))
    }

    /// The subprogram named `key`.
    pub fn sub(&self, key: &str) -> Option<&SubPlace> {
        self.subs.iter().find(|s| s.key.eq_ignore_ascii_case(key))
    }
}

/// Whether a variable of this name is local to its call's scope:
/// LinuxCNC's `#1`–`#30` and named parameters without a leading `_`.
fn is_local(name: &str) -> bool {
    match crate::eval::parameter_number(name) {
        Some(k) => (1..=30).contains(&k),
        None => name.starts_with("#<") && !name.starts_with("#<_"),
    }
}

/// Whether the o-word ending at byte `end` opens a LinuxCNC `sub` (not
/// a Fanuc `O` block, which shares its caller's variables).
/// Blanks count for nothing in G-code: `o100 s u b` opens one too.
fn opens_a_sub(text: &str, end: usize) -> bool {
    let rest = text.get(end..).unwrap_or_default();
    let line = rest.lines().next().unwrap_or_default();
    let mut letters = line.chars().filter(|c| !c.is_whitespace());
    let keyword: String = letters.by_ref().take(3).collect();
    keyword.eq_ignore_ascii_case("sub")
        && !letters
            .next()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The `P` word of `words` when it is a whole number written as one,
/// and its place.
fn program_word(words: &[ast::Word]) -> Option<(ast::Number, Bytes)> {
    let p = words.iter().find(|w| w.letter == b'P')?;
    match &p.value {
        WordValue::Number(n) if ast::whole_number(n.value).is_some() => {
            Some((*n, p.span.start as usize..p.span.end as usize))
        }
        _ => None,
    }
}

/// The o-word (`o100`, `o<name>`) written before the keyword at byte
/// `keyword` on its line.
fn o_word_before(text: &str, keyword: usize) -> Option<Bytes> {
    let line_start = text.get(..keyword)?.rfind('\n').map_or(0, |i| i + 1);
    let before = text[line_start..keyword].trim_end();
    let start = match before.ends_with('>') {
        true => before.rfind('<')?.checked_sub(1)?,
        false => before.rfind(['o', 'O'])?,
    };
    Some(line_start + start..line_start + before.len())
}

/// The first comment of the lines of `range` in `text`: `( … )`, `; …` or
/// `// …`, its text trimmed.
pub fn first_comment(text: &str, range: Bytes) -> Option<String> {
    let from = text[..range.start.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let to = range.end.min(text.len());
    text.get(from..to)?.lines().find_map(comment_of)
}

fn comment_of(line: &str) -> Option<String> {
    let starts = [line.find('('), line.find(';'), line.find("//")];
    let start = starts.into_iter().flatten().min()?;
    let rest = &line[start..];
    let body = if let Some(inner) = rest.strip_prefix('(') {
        inner.rfind(')').map_or(inner, |end| &inner[..end])
    } else if let Some(inner) = rest.strip_prefix("//") {
        inner
    } else {
        &rest[1..]
    };
    let body = body.trim();
    (!body.is_empty()).then(|| body.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variables_subprograms_and_calls_are_found_with_their_places() {
        let text = "Depth = 2\nG1 Z<-Depth> F100\nPocket 20 10 Depth\nM98 P100\nM30\n\
                    O100 (DRILL THE PATTERN)\nG0 X1\nM99\n";
        let index = Index::of(text, Language::Egc);
        let places: Vec<_> = index
            .vars
            .iter()
            .map(|v| (v.name.as_str(), &text[v.at.clone()], v.set))
            .collect();
        assert_eq!(
            places,
            [
                ("Depth", "Depth", true),
                ("Depth", "Depth", false),
                ("Depth", "Depth", false)
            ]
        );
        assert_eq!(index.subs.len(), 1, "{index:?}");
        assert_eq!(index.subs[0].key, "O100");
        let call = &index.calls[0];
        assert_eq!(
            (call.key.as_str(), &text[call.at.clone()]),
            ("O100", "P100")
        );
        assert_eq!(&text[index.wizard_calls[0].at.clone()], "Pocket");
        assert_eq!(
            first_comment(text, index.subs[0].whole.clone()).as_deref(),
            Some("DRILL THE PATTERN")
        );
    }

    #[test]
    fn linuxcnc_named_parameters_and_o_calls() {
        let text = "#<depth> = 3\no<drill> call [#<depth>]\nM2\no<drill> sub\n; drills one hole\nG0 X#1\no<drill> endsub\n";
        let index = Index::of(text, Language::Gcode);
        let places: Vec<_> = index.vars.iter().map(|v| &text[v.at.clone()]).collect();
        assert_eq!(places, ["#<depth>", "#<depth>", "#1"], "{index:?}");
        let call = &index.calls[0];
        assert_eq!(
            (call.key.as_str(), &text[call.at.clone()]),
            ("o<drill>", "o<drill>")
        );
        let sub = index.sub("o<drill>").unwrap();
        assert_eq!(
            first_comment(text, sub.whole.clone()).as_deref(),
            Some("drills one hole")
        );
        // `#1` in the sub is its own; `#<depth>` the main program's.
        let scopes: Vec<_> = index.vars.iter().map(|v| v.scope).collect();
        assert_eq!(scopes, [Some(0), Some(0), Some(1)]);
    }

    #[test]
    fn a_sub_spelled_with_blanks_has_its_own_scope() {
        // rs274 reads `o100 s u b` as `o100 sub`; `o100 subx` is no sub.
        for sub in ["s u b", "SUB (a comment)"] {
            let text = format!("#1 = 2\no100 call\nM2\no100 {sub}\nG0 X#1\no100 endsub\n");
            let index = Index::of(&text, Language::Gcode);
            let scopes: Vec<_> = index.vars.iter().map(|v| v.scope).collect();
            assert_eq!(scopes, [Some(0), Some(1)], "{text}");
        }
        assert!(!opens_a_sub("o100 subx\n", 4));
        assert!(!opens_a_sub("o100 s u b_1\n", 4));
        assert!(opens_a_sub("o100 s u b\n", 4));
    }

    #[test]
    fn a_fanuc_o_block_shares_its_callers_scope_and_globals_have_none() {
        let text = "#1 = 2
#<_g> = 1
M98 P100
M30
O100
G0 X#1
M99
";
        let index = Index::of(text, Language::Gcode);
        let scopes: Vec<_> = index
            .vars
            .iter()
            .map(|v| (v.name.as_str(), v.scope))
            .collect();
        assert_eq!(scopes, [("#1", Some(0)), ("#<_g>", None), ("#1", Some(0))]);
        assert!(index.scopes.is_empty());
    }
}
