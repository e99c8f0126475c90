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
        each_read(stmt, &mut |name, at| self.watch_var(name, at));
    }

    /// The value `name` was set to, at the place that names it.
    pub(super) fn watch_set(&mut self, name: Symbol, at: Span) {
        self.watch_var(name, at);
    }

    /// Each variable `e` reads, at its place.
    pub(super) fn watch_expr(&mut self, e: &Expr) {
        each_read_in(e, &mut |name, at| self.watch_var(name, at));
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

/// Each variable `stmt` reads, at its place, before it runs (not those of
/// the statements of its blocks, nor a `while`'s condition, read before
/// each test).
pub(super) fn each_read(stmt: &ast::Stmt, f: &mut dyn FnMut(Symbol, Span)) {
    use ast::StmtKind as K;
    let mut words = |words: &mut dyn Iterator<Item = &ast::Word>| {
        for w in words {
            if let ast::WordValue::Expr(e) = &w.value {
                each_read_in(e, f);
            }
        }
    };
    match &stmt.kind {
        K::Line(line) => words(&mut line.words.iter()),
        K::MacroCall(call) => words(&mut call.words()),
        K::Assign(a) => assignment_reads(a, f),
        K::Assigns(all) => all.iter().for_each(|a| assignment_reads(a, f)),
        K::Call { args, .. } => args.iter().for_each(|a| each_read_in(a, f)),
        K::If(if_) => if_.branches.iter().for_each(|(c, _)| each_read_in(c, f)),
        K::SubCall(call) => call.args.iter().for_each(|a| each_read_in(a, f)),
        K::Return(r) => r.value.iter().for_each(|v| each_read_in(v, f)),
        K::Repeat(r) => each_read_in(&r.count, f),
        K::Goto(target) => each_read_in(target, f),
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

fn assignment_reads(a: &ast::Assignment, f: &mut dyn FnMut(Symbol, Span)) {
    each_read_in(&a.value, f);
    if let ast::Target::Indirect(e) = &a.target {
        each_read_in(e, f);
    }
}

/// Each variable `e` reads, at its place.
pub(super) fn each_read_in(e: &Expr, f: &mut dyn FnMut(Symbol, Span)) {
    match &e.kind {
        ExprKind::Var(s) => f(*s, e.span),
        ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        ExprKind::Indirect(inner) | ExprKind::Unary(_, inner) => each_read_in(inner, f),
        ExprKind::Binary(_, a, b) => {
            each_read_in(a, f);
            each_read_in(b, f);
        }
        ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => {
            args.iter().for_each(|a| each_read_in(a, f))
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
