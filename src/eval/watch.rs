//! The values variables had where the program reads and sets them, for
//! the editor's hover ("`Count` = 12 here", "varies: 3 values, 0 … 12"):
//! recorded only when a caller asks ([`super::watch_program`]); a compile
//! carries no watch and pays one `None` test per statement. It records;
//! it must not change what the program does.

use super::evaluator::Evaluator;
use super::value::{Slot, Value};
use crate::ast::{self, Expr, ExprKind, Symbol};
use crate::source::Span;

impl Evaluator<'_> {
    /// The variables `stmt` reads, as they are before it runs (the
    /// statements of its blocks are watched as they run).
    pub(super) fn watch_reads(&mut self, stmt: &ast::Stmt) {
        use ast::StmtKind as K;
        match &stmt.kind {
            K::Line(line) => {
                for w in &line.words {
                    if let ast::WordValue::Expr(e) = &w.value {
                        self.watch_expr(e);
                    }
                }
            }
            K::MacroCall(call) => {
                for w in call.words() {
                    if let ast::WordValue::Expr(e) = &w.value {
                        self.watch_expr(e);
                    }
                }
            }
            K::Assign(a) => self.watch_assignment(a),
            K::Assigns(all) => all.iter().for_each(|a| self.watch_assignment(a)),
            K::Call { args, .. } => args.iter().for_each(|a| self.watch_expr(a)),
            K::If(if_) => if_.branches.iter().for_each(|(c, _)| self.watch_expr(c)),
            K::SubCall(call) => call.args.iter().for_each(|a| self.watch_expr(a)),
            K::Return(r) => r.value.iter().for_each(|v| self.watch_expr(v)),
            K::Repeat(r) => self.watch_expr(&r.count),
            K::Goto(target) => self.watch_expr(target),
            // A `while`'s condition is watched before each test.
            K::While(_)
            | K::Lines(_)
            | K::Sub(_)
            | K::DefinitionRead { .. }
            | K::Break(_)
            | K::Continue(_)
            | K::Command(_)
            | K::Comment(_)
            | K::Error => {}
        }
    }

    fn watch_assignment(&mut self, a: &ast::Assignment) {
        self.watch_expr(&a.value);
        if let ast::Target::Indirect(e) = &a.target {
            self.watch_expr(e);
        }
    }

    /// The value `name` was set to, at the place that names it.
    pub(super) fn watch_set(&mut self, name: Symbol, at: Span) {
        self.watch_var(name, at);
    }

    /// Each variable `e` reads, at its place.
    pub(super) fn watch_expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Var(s) => self.watch_var(*s, e.span),
            ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
            ExprKind::Indirect(inner) | ExprKind::Unary(_, inner) => self.watch_expr(inner),
            ExprKind::Binary(_, a, b) => {
                self.watch_expr(a);
                self.watch_expr(b);
            }
            ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => {
                args.iter().for_each(|a| self.watch_expr(a))
            }
        }
    }

    fn watch_var(&mut self, name: Symbol, at: Span) {
        let value = match self.vars.get(name.0 as usize) {
            Some(Slot::Set(Value::Number(n))) => *n,
            Some(Slot::Set(Value::Bool(b))) => f64::from(u8::from(*b)),
            _ => return,
        };
        if let Some(watch) = &mut self.watch {
            watch.note(at, value);
        }
    }
}

/// A sink that drops what it is given: a watched run makes no output.
pub(super) struct Nowhere;

impl crate::ir::Sink for Nowhere {
    fn start(&mut self, _: &crate::ir::Start) {}
    fn batch(&mut self, batch: &mut Vec<crate::ir::Stmt>) {
        batch.clear();
    }
}
