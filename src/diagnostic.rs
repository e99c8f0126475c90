//! Diagnostics: the one place that knows codespan-reporting. Every stage
//! turns its own error enum into a [`Diagnostic`] with `to_diagnostic()`;
//! this module builds and renders them. It does no I/O: rendering returns a
//! `String` that the CLI prints.

use crate::source::{Sources, Span};
use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity};
use codespan_reporting::term;

pub type Diagnostic = CsDiagnostic<usize>;

/// An error with a primary label at `span`.
pub fn error(
    message: impl std::fmt::Display,
    span: Span,
    label: impl std::fmt::Display,
) -> Diagnostic {
    CsDiagnostic::error()
        .with_message(message)
        .with_labels(vec![
            Label::primary(span.file, span.range()).with_message(label)
        ])
}

/// A warning with a primary label at `span`.
pub fn warning(
    message: impl std::fmt::Display,
    span: Span,
    label: impl std::fmt::Display,
) -> Diagnostic {
    CsDiagnostic::warning()
        .with_message(message)
        .with_labels(vec![
            Label::primary(span.file, span.range()).with_message(label)
        ])
}

/// Builder helpers shared by every stage's `to_diagnostic()`.
pub trait DiagnosticExt {
    fn with_secondary(self, span: Span, label: impl std::fmt::Display) -> Self;
    fn with_help(self, help: impl std::fmt::Display) -> Self;
}

impl DiagnosticExt for Diagnostic {
    fn with_secondary(mut self, span: Span, label: impl std::fmt::Display) -> Self {
        self.labels
            .push(Label::secondary(span.file, span.range()).with_message(label));
        self
    }

    fn with_help(mut self, help: impl std::fmt::Display) -> Self {
        self.notes.push(format!("help: {}", help));
        self
    }
}

pub fn is_error(d: &Diagnostic) -> bool {
    matches!(d.severity, Severity::Error | Severity::Bug)
}

/// Render diagnostics as codespan's plain-text report (no colour, so that the
/// output is byte-for-byte reproducible in golden tests).
pub fn render(sources: &Sources, diagnostics: &[Diagnostic]) -> String {
    let config = term::Config::default();
    let mut out = String::new();
    for d in diagnostics {
        if term::emit_to_string(&mut out, &config, sources.files(), d).is_err() {
            out.push_str(&format!("error: {}\n", d.message));
        }
    }
    out
}
