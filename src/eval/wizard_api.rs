//! The boundary between the evaluator and the wizard engine: what a
//! wizard call is handed ([`WizardHost`], [`WizardCall`]) and what a
//! wizard may do to the program being built ([`WizardContext`],
//! [`MachineState`]). Interfaces only: it must not know how the evaluator
//! or the engine implements them.

use super::value::Value;
use crate::ast::{self, Names};
use crate::diagnostic::Diagnostic;
use crate::ir;
use crate::source::Span;

/// What a wizard call is handed to; implemented by the wizard engine. The
/// evaluator only knows this interface.
pub trait WizardHost {
    /// Run wizard `name` (already known not to be a directive). Returns
    /// `None` if no wizard has that name.
    fn call(
        &mut self,
        name: &str,
        args: &[Value],
        call: &WizardCall<'_>,
        ctx: &mut dyn WizardContext,
    ) -> Option<Result<(), Vec<Diagnostic>>>;

    /// Is there a wizard of this name (matched case-insensitively)?
    fn has(&self, name: &str) -> bool;

    /// Names of every wizard known, for "did you mean".
    fn names(&self) -> Vec<String>;
}

/// Where a wizard was called, for its diagnostics.
pub struct WizardCall<'a> {
    pub span: Span,
    pub arg_spans: &'a [Span],
    pub names: &'a Names,
}

/// What a wizard may do to the program being built.
pub trait WizardContext {
    /// Run one parsed line of extended G-code as if written at the call.
    fn run_line(&mut self, line: &ast::Program) -> Result<(), Vec<Diagnostic>>;
    fn emit(&mut self, op: ir::Op) -> Result<(), Diagnostic>;
    fn state(&self) -> MachineState;
}

/// The machine state a wizard can read.
#[derive(Clone, Copy, Debug)]
pub struct MachineState {
    /// Last commanded position in program coordinates (`None` before the
    /// first move that sets the axis).
    pub position: [Option<f64>; 3],
    /// G91 is on at the call.
    pub incremental: bool,
    /// G16 is on at the call.
    pub polar: bool,
    /// G90.1 is on at the call.
    pub absolute_centers: bool,
    /// G93 is on at the call.
    pub inverse_time: bool,
    pub units: Option<ir::Units>,
    pub tool: u32,
    pub tool_diameter: f64,
    /// The loaded tool's included angle if it is a vee (`SetTool … "vee60"`).
    pub tool_angle: Option<f64>,
    /// The feed per minute in effect (`None` before an F, or under G93).
    pub feed: Option<f64>,
}
