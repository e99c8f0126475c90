//! What goes wrong with a wizard call: its script, its declaration, its
//! arguments, or the run. As data with one wording function.

use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub enum WizardErrorKind {
    /// Rhai's message; the span is the script's line.
    DoesNotCompile { message: String },
    /// The declaration's problem at its line; the span is the call.
    BadDeclaration { line: Span, message: String },
    /// The arguments do not fit the declaration; how it is called.
    WrongArguments { message: String, usage: String },
    /// The script raised an error at `raised`; the span is the call.
    Failed { message: String, raised: Span },
}

#[derive(Clone, Debug, PartialEq)]
pub struct WizardError {
    /// The wizard's name.
    pub wizard: String,
    pub kind: WizardErrorKind,
    pub span: Span,
}

impl WizardError {
    pub fn new(wizard: &str, kind: WizardErrorKind, span: Span) -> WizardError {
        WizardError {
            wizard: wizard.to_string(),
            kind,
            span,
        }
    }

    /// One line for a wizard that called this one (its Rhai error).
    pub fn summary(&self) -> String {
        let name = &self.wizard;
        match &self.kind {
            WizardErrorKind::DoesNotCompile { message } => {
                format!("wizard `{name}` does not compile: {message}")
            }
            WizardErrorKind::BadDeclaration { message, .. } => {
                format!("wizard `{name}` has a bad declaration: {message}")
            }
            WizardErrorKind::WrongArguments { message, usage } => format!("{usage}: {message}"),
            WizardErrorKind::Failed { message, .. } => {
                format!("wizard `{name}` failed: {message}")
            }
        }
    }

    pub fn to_diagnostic(&self) -> Diagnostic {
        let (name, at) = (&self.wizard, self.span);
        match &self.kind {
            WizardErrorKind::DoesNotCompile { message } => error(
                format!("wizard script `{name}` does not compile"),
                at,
                message,
            ),
            WizardErrorKind::BadDeclaration { line, message } => error(
                format!("wizard `{name}` has a bad declaration"),
                at,
                "called here",
            )
            .with_secondary(*line, message),
            WizardErrorKind::WrongArguments { message, usage } => {
                error(format!("wrong arguments for wizard `{name}`"), at, message)
                    .with_note(format!("usage: {usage}"))
            }
            WizardErrorKind::Failed { message, raised } => error(
                format!("wizard `{name}` failed: {message}"),
                at,
                "called here",
            )
            .with_secondary(*raised, "raised here"),
        }
    }
}
