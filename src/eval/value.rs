//! Values and expression evaluation (SPEC §2.3–2.4): numbers, booleans and
//! strings; every operator and built-in function, angles in degrees. Errors
//! are returned as [`ExprError`] with the span of the failing expression;
//! the caller reports them.

use super::degrees;
use crate::ast::{BinaryOp, Expr, ExprKind, Function, Names, Symbol, UnaryOp};
use crate::diagnostic::{error, Diagnostic, DiagnosticExt};
use crate::source::Span;
use crate::syntax::linuxcnc::{LAST_PARAMETER, RETURN_VALUE};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    Bool(bool),
    Str(Symbol),
}

impl Value {
    pub fn type_name(self) -> &'static str {
        match self {
            Value::Number(_) => "a number",
            Value::Bool(_) => "a boolean",
            Value::Str(_) => "a string",
        }
    }
}

/// Variables, indexed by symbol. `Poisoned` marks a variable whose
/// assignment failed: its uses stay silent, the error is already reported.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Slot {
    Unset,
    /// Fanuc's vacant variable (`#0`, a local no argument set): 0 in
    /// arithmetic and in GT/GE/LT/LE, but equal only to another vacant
    /// one; a word given one is left out.
    Vacant,
    Poisoned,
    /// One of rs274's predefined parameters whose value only the machine
    /// has here ([`super::predefined`]): an error where it is read.
    Machine,
    Set(Value),
}

/// The variables, by symbol, and where each numbered parameter is (for
/// `#[…]`, which finds one by its number as it runs).
#[derive(Debug)]
pub struct Vars {
    slots: Vec<Slot>,
    /// The symbol of `#n`, by n; empty when no `#[…]` was read (the lexer
    /// names every parameter when one is).
    numbered: Vec<Option<Symbol>>,
    /// Fanuc's: `#[…]` may give #0 (vacant), and variables may be vacant.
    fanuc: bool,
    /// LinuxCNC's: angles converted with rs274's long double π
    /// ([`super::degrees`]); elsewhere (`.egc`, Fanuc) as doubles.
    rs274: bool,
}

impl Vars {
    /// `fanuc`: Fanuc's variables (a `#[…]` may give #0, the vacant one;
    /// rs274 has none); `rs274`: LinuxCNC's trigonometry.
    pub fn new(slots: Vec<Slot>, names: &Names, fanuc: bool, rs274: bool) -> Vars {
        let mut vars = Vars {
            slots,
            numbered: Vec::new(),
            fanuc,
            rs274,
        };
        vars.number(names, 0);
        vars
    }

    /// Names were added to `names` from the symbol `from` on (a part of a
    /// program read in parts): their slots, each holding `first(text)`.
    pub fn grow(&mut self, names: &Names, from: usize, first: impl Fn(&str) -> Slot) {
        self.slots
            .extend(names.iter().skip(from).map(|(_, text)| first(text)));
        self.number(names, from);
    }

    /// Where the numbered parameters among the names from `from` on are,
    /// once the lexer has named them all (on the first `#[…]`).
    fn number(&mut self, names: &Names, mut from: usize) {
        if self.numbered.is_empty() {
            if names.find(&format!("#{LAST_PARAMETER}")).is_none() {
                return;
            }
            self.numbered = vec![None; LAST_PARAMETER as usize + 1];
            from = 0;
        }
        for (symbol, text) in names.iter().skip(from) {
            if let Some(n) = super::state::parameter_number(text).filter(|&n| n <= LAST_PARAMETER) {
                self.numbered[n as usize] = Some(symbol);
            }
        }
    }

    /// The numbered parameter `#[number]` names, reported at `span`.
    pub fn resolve(&self, number: &Expr, span: Span) -> Result<Symbol, ExprError> {
        let n = self::number(number, self, &|| "the parameter's number".into())?;
        self.parameter(n, span)
    }

    /// The numbered parameter `value` names (`#[value]`); as rs274, a
    /// value within 0.0001 of a whole number is that number.
    pub fn parameter(&self, value: f64, span: Span) -> Result<Symbol, ExprError> {
        let n = value.round();
        let whole = (value - n).abs() <= 1e-4;
        let lowest = u32::from(!self.fanuc);
        let found = (whole && (f64::from(lowest)..=f64::from(LAST_PARAMETER)).contains(&n))
            .then(|| self.numbered.get(n as usize).copied().flatten())
            .flatten();
        found.ok_or(ExprError::NoSuchParameter { value, span })
    }
}

impl std::ops::Deref for Vars {
    type Target = Vec<Slot>;
    fn deref(&self) -> &Vec<Slot> {
        &self.slots
    }
}

impl std::ops::DerefMut for Vars {
    fn deref_mut(&mut self) -> &mut Vec<Slot> {
        &mut self.slots
    }
}

#[derive(Debug)]
pub enum ExprError {
    Undefined {
        name: Symbol,
        span: Span,
    },
    TypeMismatch {
        expected: &'static str,
        found: &'static str,
        span: Span,
        what: String,
    },
    DivisionByZero {
        span: Span,
    },
    NotFinite {
        span: Span,
        what: String,
    },
    Arity {
        function: Function,
        given: usize,
        span: Span,
    },
    UnknownFunction {
        name: Symbol,
        span: Span,
    },
    /// `#[value]` where the value is no parameter's number.
    NoSuchParameter {
        value: f64,
        span: Span,
    },
    /// A predefined parameter only the machine knows here.
    MachineOnly {
        name: Symbol,
        span: Span,
    },
    /// Depends on a variable whose own error was already reported.
    Poisoned,
}

impl ExprError {
    /// Where it is (`None` for [`ExprError::Poisoned`]).
    pub fn span(&self) -> Option<Span> {
        match self {
            ExprError::Undefined { span, .. }
            | ExprError::TypeMismatch { span, .. }
            | ExprError::DivisionByZero { span }
            | ExprError::NotFinite { span, .. }
            | ExprError::Arity { span, .. }
            | ExprError::UnknownFunction { span, .. }
            | ExprError::NoSuchParameter { span, .. }
            | ExprError::MachineOnly { span, .. } => Some(*span),
            ExprError::Poisoned => None,
        }
    }

    /// Its wording; `from` says which parameters are the machine's.
    pub fn to_diagnostic(
        &self,
        names: &Names,
        vars: &[Slot],
        from: super::options::Flavour,
    ) -> Option<Diagnostic> {
        Some(match self {
            ExprError::Undefined { name, span } => {
                undefined_diagnostic(names.text(*name), *span, names, vars, from)
            }
            ExprError::TypeMismatch {
                expected,
                found,
                span,
                what,
            } => error(
                format!("type mismatch: {what} needs {expected}, found {found}"),
                *span,
                format!("this is {found}"),
            ),
            ExprError::DivisionByZero { span } => {
                error("division by zero", *span, "the divisor is zero here")
            }
            ExprError::NotFinite { span, what } => error(
                format!("{what} has no finite value"),
                *span,
                "the result is infinite or not a number",
            ),
            ExprError::Arity {
                function,
                given,
                span,
            } => {
                let (lo, hi) = function.arity();
                let wanted = if lo == hi {
                    format!("{lo}")
                } else {
                    format!("{lo} or more")
                };
                error(
                    format!(
                        "`{}` takes {wanted} argument(s), {given} given",
                        function.name()
                    ),
                    *span,
                    "wrong number of arguments",
                )
            }
            ExprError::UnknownFunction { name, span } => {
                let known: Vec<&str> = Function::ALL.iter().map(|(n, _)| *n).collect();
                error(
                    format!("unknown function `{}`", names.text(*name)),
                    *span,
                    "not a built-in function",
                )
                .with_note(format!("the functions are: {}", known.join(" ")))
            }
            ExprError::NoSuchParameter { value, span } => {
                let lowest = u32::from(from != super::options::Flavour::Fanuc);
                error(
                    format!("`#[{value}]` names no parameter"),
                    *span,
                    format!(
                        "a parameter's number is a whole number from {lowest} to {LAST_PARAMETER}"
                    ),
                )
            }
            ExprError::MachineOnly { name, span } => {
                let text = names.text(*name);
                let why = super::known::Param::of_name(text)
                    .map_or("ger does not know this value", |p| p.machine_only());
                error(
                    format!("`{text}` is the machine's here"),
                    *span,
                    "ger cannot know its value at this line",
                )
                .with_note(why)
            }
            ExprError::Poisoned => return None,
        })
    }
}

/// The wording of a read of a name with no value: a parameter of the
/// machine's, LinuxCNC's subroutine return value, or a name never set.
fn undefined_diagnostic(
    text: &str,
    span: Span,
    names: &Names,
    vars: &[Slot],
    from: super::options::Flavour,
) -> Diagnostic {
    let machine = super::state::parameter_number(text).is_some_and(|n| from.machine_parameter(n));
    if machine && from == super::options::Flavour::Fanuc {
        return error(
            format!("`{text}` is a variable of the machine"),
            span,
            "ger cannot know its value",
        )
        .with_help("#500–#999 keep their values on the machine and #1000 and up are system variables: set the value in the program");
    }
    if machine {
        return error(
            format!("`{text}` is a parameter of the machine's state"),
            span,
            "ger cannot know its value",
        )
        .with_help(
            "LinuxCNC keeps positions and offsets in #5001 and up; give the value in the program",
        );
    }
    if text == RETURN_VALUE {
        return error(
            format!("`{text}` is read before a subroutine returned a value"),
            span,
            "ger does not know LinuxCNC's value here",
        )
        .with_help("rs274 also sets it as it reads a subroutine's definition, to the value of its `endsub [v]` worked out there; read it after a call");
    }
    let d = error(
        format!("undefined variable `{text}`"),
        span,
        "no value has been assigned to this name",
    );
    match closest_name(text, names, vars) {
        Some(close) => d.with_help(format!("did you mean `{close}`?")),
        None => d.with_help(format!("assign it first: `{text} = …`")),
    }
}

/// The closest assigned name, for "did you mean".
fn closest_name<'a>(wanted: &str, names: &'a Names, vars: &[Slot]) -> Option<&'a str> {
    names
        .iter()
        .filter(|(s, _)| matches!(vars.get(s.0 as usize), Some(Slot::Set(_))))
        .map(|(_, text)| {
            (
                edit_distance(&wanted.to_lowercase(), &text.to_lowercase()),
                text,
            )
        })
        .filter(|&(d, text)| d <= 2.max(wanted.len() / 3) && text != wanted)
        .min_by_key(|&(d, _)| d)
        .map(|(_, text)| text)
}

pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

pub fn eval(expr: &Expr, vars: &Vars) -> Result<Value, ExprError> {
    match &expr.kind {
        ExprKind::Number(n) => Ok(Value::Number(*n)),
        ExprKind::Bool(b) => Ok(Value::Bool(*b)),
        ExprKind::Str(s) => Ok(Value::Str(*s)),
        ExprKind::Var(s) => read(vars, *s, expr.span),
        ExprKind::Indirect(e) => read(vars, vars.resolve(e, expr.span)?, expr.span),
        ExprKind::Unary(UnaryOp::Neg, e) => Ok(Value::Number(-number(e, vars, &|| "`-`".into())?)),
        ExprKind::Unary(UnaryOp::Not, e) => Ok(Value::Bool(!boolean(e, vars, &|| "`!`".into())?)),
        ExprKind::Binary(op, a, b) => binary(*op, a, b, expr.span, vars),
        ExprKind::Call(f, args) => call(*f, args, expr.span, vars),
        ExprKind::UnknownCall(name, _) => Err(ExprError::UnknownFunction {
            name: *name,
            span: expr.span,
        }),
    }
}

/// The value of the variable `name`, read at `span`.
fn read(vars: &Vars, name: Symbol, span: Span) -> Result<Value, ExprError> {
    match vars.get(name.0 as usize) {
        Some(Slot::Set(v)) => Ok(*v),
        Some(Slot::Vacant) => Ok(Value::Number(0.0)),
        Some(Slot::Poisoned) => Err(ExprError::Poisoned),
        Some(Slot::Machine) => Err(ExprError::MachineOnly { name, span }),
        _ => Err(ExprError::Undefined { name, span }),
    }
}

/// What is being evaluated, for a type error's message; only built when
/// there is an error.
pub type What<'a> = &'a dyn Fn() -> String;

pub fn number(expr: &Expr, vars: &Vars, what: What<'_>) -> Result<f64, ExprError> {
    if let Some(v) = fast_number(expr, vars) {
        return Ok(v);
    }
    match eval(expr, vars)? {
        Value::Number(n) => Ok(n),
        other => Err(ExprError::TypeMismatch {
            expected: "a number",
            found: other.type_name(),
            span: expr.span,
            what: what(),
        }),
    }
}

pub fn boolean(expr: &Expr, vars: &Vars, what: What<'_>) -> Result<bool, ExprError> {
    if let Some(b) = fast_bool(expr, vars) {
        return Ok(b);
    }
    match eval(expr, vars)? {
        Value::Bool(b) => Ok(b),
        other => Err(ExprError::TypeMismatch {
            expected: "true or false",
            found: other.type_name(),
            span: expr.span,
            what: what(),
        }),
    }
}

fn finite(value: f64, span: Span, what: impl FnOnce() -> String) -> Result<f64, ExprError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ExprError::NotFinite { span, what: what() })
    }
}

/// A variable that is vacant (Fanuc's null), written alone.
pub fn vacant(expr: &Expr, vars: &Vars) -> bool {
    // Only Fanuc's variables are ever vacant.
    if !vars.fanuc {
        return false;
    }
    let name = match &expr.kind {
        ExprKind::Var(s) => Some(*s),
        // The number may be a vacant variable's (0: `#0`).
        ExprKind::Indirect(e) => vars.resolve(e, e.span).ok(),
        _ => None,
    };
    name.is_some_and(|s| vars.get(s.0 as usize) == Some(&Slot::Vacant))
}

fn binary(op: BinaryOp, a: &Expr, b: &Expr, span: Span, vars: &Vars) -> Result<Value, ExprError> {
    let what = || format!("`{}`", op.symbol());
    // Fanuc: a vacant variable equals only another vacant one, so with
    // one on either side EQ and NE compare vacancy (1 or 0), not values.
    if matches!(op, BinaryOp::NumEq | BinaryOp::NumNe) {
        let (x, y) = (vacant(a, vars), vacant(b, vars));
        if x || y {
            return Ok(Value::Number(arithmetic(
                op,
                f64::from(u8::from(x)),
                f64::from(u8::from(y)),
            )));
        }
    }
    match op {
        BinaryOp::And => Ok(Value::Bool(
            boolean(a, vars, &what)? && boolean(b, vars, &what)?,
        )),
        BinaryOp::Or => Ok(Value::Bool(
            boolean(a, vars, &what)? || boolean(b, vars, &what)?,
        )),
        BinaryOp::Eq | BinaryOp::Ne => {
            let (x, y) = (eval(a, vars)?, eval(b, vars)?);
            let same = match (x, y) {
                (Value::Number(p), Value::Number(q)) => p == q,
                (Value::Bool(p), Value::Bool(q)) => p == q,
                (Value::Str(p), Value::Str(q)) => p == q,
                _ => {
                    return Err(ExprError::TypeMismatch {
                        expected: x.type_name(),
                        found: y.type_name(),
                        span: b.span,
                        what: what(),
                    })
                }
            };
            Ok(Value::Bool(same == (op == BinaryOp::Eq)))
        }
        _ => {
            let x = number(a, vars, &what)?;
            let y = number(b, vars, &what)?;
            match op {
                BinaryOp::Lt => Ok(Value::Bool(x < y)),
                BinaryOp::Le => Ok(Value::Bool(x <= y)),
                BinaryOp::Gt => Ok(Value::Bool(x > y)),
                BinaryOp::Ge => Ok(Value::Bool(x >= y)),
                BinaryOp::Div | BinaryOp::Rem | BinaryOp::Mod if y == 0.0 => {
                    Err(ExprError::DivisionByZero { span })
                }
                _ => Ok(Value::Number(finite(arithmetic(op, x, y), span, what)?)),
            }
        }
    }
}

fn call(f: Function, args: &[Expr], span: Span, vars: &Vars) -> Result<Value, ExprError> {
    let (lo, hi) = f.arity();
    if args.len() < lo || args.len() > hi {
        return Err(ExprError::Arity {
            function: f,
            given: args.len(),
            span,
        });
    }
    let what = || format!("`{}`", f.name());
    if f == Function::Exists {
        // Asks about the parameter, not its value.
        return match &args[0].kind {
            ExprKind::Var(s) => Ok(Value::Number(
                if matches!(vars.get(s.0 as usize), Some(Slot::Set(_) | Slot::Machine)) {
                    1.0
                } else {
                    0.0
                },
            )),
            _ => Err(ExprError::TypeMismatch {
                expected: "a parameter",
                found: "an expression",
                span: args[0].span,
                what: what(),
            }),
        };
    }
    let mut values = [0.0; 8];
    let mut rest = Vec::new();
    for (i, a) in args.iter().enumerate() {
        let v = number(a, vars, &what)?;
        match values.get_mut(i) {
            Some(slot) => *slot = v,
            None => rest.push(v),
        }
    }
    let v = apply(f, &values[..args.len().min(8)], &rest, vars.rs274);
    Ok(Value::Number(finite(v, span, || {
        format!("`{}(…)`", f.name())
    })?))
}

/// An arithmetic operator on two numbers (`+ - * / % ^`). The callers check
/// division by zero and finiteness.
fn arithmetic(op: BinaryOp, x: f64, y: f64) -> f64 {
    match op {
        BinaryOp::Add => x + y,
        BinaryOp::Sub => x - y,
        BinaryOp::Mul => x * y,
        BinaryOp::Div => x / y,
        BinaryOp::Rem => x % y,
        BinaryOp::Mod => {
            let r = x % y;
            if r < 0.0 {
                r + y.abs()
            } else {
                r
            }
        }
        BinaryOp::Pow => x.powf(y),
        // LinuxCNC's words, as the rs274 of LinuxCNC 2.9 (the reference)
        // computes them: EQ and NE within a tolerance, the others exact
        // (later versions give LE and GE the tolerance too).
        BinaryOp::NumEq => truth((x - y).abs() < LINUXCNC_EQUAL),
        BinaryOp::NumNe => truth((x - y).abs() >= LINUXCNC_EQUAL),
        BinaryOp::NumLt => truth(x < y),
        BinaryOp::NumLe => truth(x <= y),
        BinaryOp::NumGt => truth(x > y),
        BinaryOp::NumGe => truth(x >= y),
        BinaryOp::NumAnd => truth(x != 0.0 && y != 0.0),
        BinaryOp::NumOr => truth(x != 0.0 || y != 0.0),
        BinaryOp::NumXor => truth((x != 0.0) != (y != 0.0)),
        _ => f64::NAN,
    }
}

/// Two numbers LinuxCNC's EQ calls equal differ by less than this
/// (rs274's TOLERANCE_EQUAL, 0.0001 in LinuxCNC 2.9).
const LINUXCNC_EQUAL: f64 = 1e-4;

/// LinuxCNC's true and false: 1 and 0.
fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// A built-in function on its arguments (`args`, then `more` past eight),
/// angles in degrees. The arity is checked by the callers.
fn apply(f: Function, args: &[f64], more: &[f64], rs274: bool) -> f64 {
    let x = args[0];
    let y = || args.get(1).copied().unwrap_or(f64::NAN);
    if rs274 {
        // As rs274 computes them (`degrees`): the last bit can matter.
        match f {
            Function::Sin => return degrees::sin(x),
            Function::Cos => return degrees::cos(x),
            Function::Tan => return degrees::tan(x),
            Function::Asin => return degrees::to_degrees(x.asin()),
            Function::Acos => return degrees::to_degrees(x.acos()),
            Function::Atan2 => return degrees::to_degrees(x.atan2(y())),
            _ => {}
        }
    }
    match f {
        Function::Abs => x.abs(),
        Function::Sqrt => x.sqrt(),
        Function::Sin => x.to_radians().sin(),
        Function::Cos => x.to_radians().cos(),
        Function::Tan => x.to_radians().tan(),
        Function::Asin => x.asin().to_degrees(),
        Function::Acos => x.acos().to_degrees(),
        Function::Atan => x.atan().to_degrees(),
        Function::Atan2 => x.atan2(y()).to_degrees(),
        Function::FanucAtan => x.atan2(y()).to_degrees().rem_euclid(360.0),
        Function::FanucFix => x.trunc(),
        Function::FanucFup => x.signum() * x.abs().ceil(),
        Function::Floor => x.floor(),
        Function::Ceil => x.ceil(),
        Function::Round => x.round(),
        Function::Min => args
            .iter()
            .chain(more)
            .copied()
            .fold(f64::INFINITY, f64::min),
        Function::Max => args
            .iter()
            .chain(more)
            .copied()
            .fold(f64::NEG_INFINITY, f64::max),
        Function::Hypot => x.hypot(y()),
        Function::Exp => x.exp(),
        Function::Ln => x.ln(),
        Function::Log10 => x.log10(),
        // Asks about a parameter, not a number: `call` answers it.
        Function::Exists => f64::NAN,
    }
}

/// The value of a purely numeric expression, or `None` when it is not one
/// or would fail (then [`eval`] runs and says why). The hot path of loops:
/// no `Value`, no error values, the same arithmetic as [`eval`].
pub fn fast_number(expr: &Expr, vars: &Vars) -> Option<f64> {
    let v = match &expr.kind {
        // Literals and variables as they are (a literal too long for an
        // f64 is infinite, as in `eval`); what uses them checks them.
        ExprKind::Number(n) => return Some(*n),
        ExprKind::Var(s) => {
            return match vars.get(s.0 as usize) {
                Some(Slot::Set(Value::Number(n))) => Some(*n),
                _ => None,
            }
        }
        ExprKind::Indirect(e) => {
            let s = vars.parameter(fast_number(e, vars)?, e.span).ok()?;
            return match vars.get(s.0 as usize) {
                Some(Slot::Set(Value::Number(n))) => Some(*n),
                _ => None,
            };
        }
        ExprKind::Unary(UnaryOp::Neg, e) => return fast_number(e, vars).map(|v| -v),
        ExprKind::Binary(op, a, b) => {
            if !matches!(
                op,
                BinaryOp::Add
                    | BinaryOp::Sub
                    | BinaryOp::Mul
                    | BinaryOp::Div
                    | BinaryOp::Rem
                    | BinaryOp::Mod
                    | BinaryOp::Pow
                    | BinaryOp::NumEq
                    | BinaryOp::NumNe
                    | BinaryOp::NumLt
                    | BinaryOp::NumLe
                    | BinaryOp::NumGt
                    | BinaryOp::NumGe
                    | BinaryOp::NumAnd
                    | BinaryOp::NumOr
                    | BinaryOp::NumXor
            ) {
                return None;
            }
            let (x, y) = (fast_number(a, vars)?, fast_number(b, vars)?);
            if y == 0.0 && matches!(op, BinaryOp::Div | BinaryOp::Rem | BinaryOp::Mod) {
                return None;
            }
            arithmetic(*op, x, y)
        }
        ExprKind::Call(f, args) => fast_call(*f, args, vars)?,
        _ => return None,
    };
    v.is_finite().then_some(v)
}

/// [`fast_number`] of a call; apart, so that the recursion above keeps a
/// small stack frame.
#[inline(never)]
fn fast_call(f: Function, args: &[Expr], vars: &Vars) -> Option<f64> {
    let (lo, hi) = f.arity();
    // EXISTS asks about its parameter, not its value: `call` answers it.
    if f == Function::Exists || args.len() < lo || args.len() > hi || args.len() > 8 {
        return None;
    }
    let mut values = [0.0; 8];
    for (slot, a) in values.iter_mut().zip(args) {
        *slot = fast_number(a, vars)?;
    }
    Some(apply(f, &values[..args.len()], &[], vars.rs274))
}

/// The value of a condition made of comparisons of numbers, `&&`, `||`
/// and `!`, or `None` (then [`eval`] runs and says why): the hot path of
/// `while` and `if`, with the short-circuits and comparisons of [`eval`].
fn fast_bool(expr: &Expr, vars: &Vars) -> Option<bool> {
    match &expr.kind {
        ExprKind::Bool(b) => Some(*b),
        ExprKind::Var(s) => match vars.get(s.0 as usize) {
            Some(Slot::Set(Value::Bool(b))) => Some(*b),
            _ => None,
        },
        ExprKind::Unary(UnaryOp::Not, e) => fast_bool(e, vars).map(|b| !b),
        ExprKind::Binary(BinaryOp::And, a, b) => match fast_bool(a, vars)? {
            false => Some(false),
            true => fast_bool(b, vars),
        },
        ExprKind::Binary(BinaryOp::Or, a, b) => match fast_bool(a, vars)? {
            true => Some(true),
            false => fast_bool(b, vars),
        },
        ExprKind::Binary(op, a, b) => {
            let compare: fn(&f64, &f64) -> bool = match op {
                BinaryOp::Lt => f64::lt,
                BinaryOp::Le => f64::le,
                BinaryOp::Gt => f64::gt,
                BinaryOp::Ge => f64::ge,
                BinaryOp::Eq => f64::eq,
                BinaryOp::Ne => f64::ne,
                _ => return None,
            };
            Some(compare(&fast_number(a, vars)?, &fast_number(b, vars)?))
        }
        _ => None,
    }
}
