//! The AST printed back as normalised source (`ger compile --stage parse`):
//! one statement per line as the parser cut them, expressions fully
//! parenthesised so precedence is visible. A teaching aid and the parser's
//! golden-test format; it must not evaluate anything.

use super::*;
use std::fmt::Write;

impl Program {
    pub fn to_text(&self) -> String {
        let mut p = AstPrinter {
            names: &self.names,
            out: String::new(),
            depth: 0,
        };
        if let Some(n) = self.main_number {
            p.line(&format!("{} (main)", n.describe(p.names)));
        }
        p.block(&self.main);
        for sub in &self.subprograms {
            p.line(&sub.name.describe(p.names));
            p.depth += 1;
            p.block(&sub.body);
            p.depth -= 1;
        }
        p.out
    }
}

struct AstPrinter<'a> {
    names: &'a Names,
    out: String,
    depth: usize,
}

impl AstPrinter<'_> {
    fn line(&mut self, text: &str) {
        for _ in 0..self.depth {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn block(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            self.stmt(s);
        }
    }

    /// A line of words, a statement of it to a line.
    fn words(&mut self, words: &[Word], block_delete: bool) {
        for s in crate::ast::statements(words) {
            let words: Vec<String> = s
                .code
                .into_iter()
                .chain(s.args)
                .map(|w| self.word(w))
                .collect();
            let slash = if block_delete { "/" } else { "" };
            self.line(&format!("{slash}{}", words.join(" ")));
        }
    }

    fn stmt(&mut self, stmt: &Stmt) {
        match &stmt.kind {
            StmtKind::Line(line) => self.words(&line.words, line.block_delete),
            StmtKind::MacroCall(call) => {
                self.words(&call.before, call.block_delete);
                let words: Vec<String> = std::iter::once(&call.code)
                    .chain(&call.args)
                    .map(|w| self.word(w))
                    .collect();
                let slash = if call.block_delete { "/" } else { "" };
                self.line(&format!("{slash}{}", words.join(" ")));
            }
            StmtKind::Lines(lines) => lines
                .each_as_words()
                .for_each(|words| self.words(&words, false)),
            StmtKind::Assign(a) => {
                let text = self.assignment(a);
                self.line(&text);
            }
            StmtKind::Assigns(all) => {
                let parts: Vec<String> = all.iter().map(|a| self.assignment(a)).collect();
                self.line(&parts.join(" "));
            }
            StmtKind::Call { name, args, .. } => {
                let args: Vec<String> = args.iter().map(|a| self.expr(a)).collect();
                let text = format!("{}({})", self.names.text(*name), args.join(", "));
                self.line(&text);
            }
            StmtKind::If(if_) => self.if_block(if_),
            StmtKind::While(w) => self.while_block(w),
            StmtKind::Break(label) => self.line(&format!("{} break", label.written(self.names))),
            StmtKind::Continue(label) => {
                self.line(&format!("{} continue", label.written(self.names)))
            }
            StmtKind::Return(r) => {
                let keyword = if r.ends_sub { "endsub" } else { "return" };
                let text = match &r.value {
                    Some(v) => format!("{keyword} [{}]", self.expr(v)),
                    None => keyword.to_string(),
                };
                self.line(&text)
            }
            StmtKind::DefinitionRead { .. } => {}
            StmtKind::Repeat(r) => {
                let head = format!(
                    "{} repeat [{}] {{",
                    r.label.written(self.names),
                    self.expr(&r.count)
                );
                self.line(&head);
                self.nested(&r.body);
                self.line("}");
            }
            StmtKind::Sub(name) => self.line(&format!("{} sub", name.written(self.names))),
            StmtKind::SubCall(call) => {
                let mut text = format!("{} call", call.name.written(self.names));
                for arg in &call.args {
                    text.push_str(&format!(" [{}]", self.expr(arg)));
                }
                self.line(&text)
            }
            StmtKind::Goto(target) => {
                let text = format!("GOTO {}", self.expr(target));
                self.line(&text)
            }
            StmtKind::Error => self.line("<error>"),
            StmtKind::Comment(c) => {
                let text = format!("({})", self.names.text(*c));
                self.line(&text)
            }
            StmtKind::Command(c) => {
                let text = self.names.text(*c).to_string();
                self.line(&text)
            }
        }
    }

    /// `if … { } else if … { } else { }`.
    fn if_block(&mut self, if_: &If) {
        let If {
            branches,
            otherwise,
        } = if_;
        for (i, (cond, body)) in branches.iter().enumerate() {
            let head = if i == 0 { "if" } else { "} else if" };
            let text = format!("{head} {} {{", self.expr(cond));
            self.line(&text);
            self.nested(body);
        }
        if let Some(body) = otherwise {
            self.line("} else {");
            self.nested(body);
        }
        self.line("}");
    }

    /// `while … { }`, or LinuxCNC's `do { } while …`, with its label.
    fn while_block(&mut self, w: &While) {
        let While {
            cond,
            body,
            label,
            test_after,
        } = w;
        let label = label.map_or(String::new(), |n| format!("{} ", n.written(self.names)));
        let cond = self.expr(cond);
        if *test_after {
            self.line(&format!("{label}do {{"));
            self.nested(body);
            self.line(&format!("}} while {cond}"));
        } else {
            self.line(&format!("{label}while {cond} {{"));
            self.nested(body);
            self.line("}");
        }
    }

    fn nested(&mut self, body: &[Stmt]) {
        self.depth += 1;
        self.block(body);
        self.depth -= 1;
    }

    fn word(&self, w: &Word) -> String {
        match &w.value {
            WordValue::Number(n) => format!("{}{}", Word::spelling(w.letter), n.value),
            WordValue::Expr(e) => format!("{}<{}>", Word::spelling(w.letter), self.expr(e)),
        }
    }

    fn expr(&self, e: &Expr) -> String {
        let mut s = String::new();
        self.write_expr(&mut s, e);
        s
    }

    fn assignment(&self, a: &Assignment) -> String {
        format!("{} = {}", self.target(&a.target), self.expr(&a.value))
    }

    fn target(&self, target: &Target) -> String {
        match target {
            Target::Name(name) => self.names.text(*name).to_string(),
            Target::Indirect(e) => format!("#[{}]", self.expr(e)),
        }
    }

    fn write_expr(&self, s: &mut String, e: &Expr) {
        match &e.kind {
            ExprKind::Number(n) => {
                let _ = write!(s, "{n}");
            }
            ExprKind::Bool(b) => {
                let _ = write!(s, "{b}");
            }
            ExprKind::Str(sym) => {
                let _ = write!(s, "\"{}\"", self.names.text(*sym));
            }
            ExprKind::Var(sym) => s.push_str(self.names.text(*sym)),
            ExprKind::Indirect(inner) => {
                s.push_str("#[");
                self.write_expr(s, inner);
                s.push(']');
            }
            ExprKind::Unary(op, inner) => {
                s.push_str(match op {
                    UnaryOp::Neg => "(-",
                    UnaryOp::Not => "(!",
                });
                self.write_expr(s, inner);
                s.push(')');
            }
            ExprKind::Binary(op, a, b) => {
                s.push('(');
                self.write_expr(s, a);
                let _ = write!(s, " {} ", op.symbol());
                self.write_expr(s, b);
                s.push(')');
            }
            ExprKind::Call(f, args) => self.write_call(s, f.name(), args),
            ExprKind::UnknownCall(name, args) => self.write_call(s, self.names.text(*name), args),
        }
    }

    fn write_call(&self, s: &mut String, name: &str, args: &[Expr]) {
        s.push_str(name);
        s.push('(');
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            self.write_expr(s, a);
        }
        s.push(')');
    }
}
