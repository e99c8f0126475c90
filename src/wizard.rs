//! Wizards (SPEC §5): Rhai scripts that emit statements. One sandboxed
//! engine per compile; a script sees the small API of `stdlib/README.md`
//! and nothing else (no files, network, processes, `import` or `eval`).
//! What a script emits is collected as typed actions and replayed into the
//! evaluator through [`WizardContext`], so it goes through every stage like
//! hand-written code. This module knows Rhai; the evaluator does not.

pub mod declaration;
mod error;

use crate::diagnostic::{Diagnostic, DiagnosticExt};
use crate::eval::value::Value;
use crate::eval::{MachineState, WizardCall, WizardContext, WizardHost};
use crate::ir::{self, Arc, ArcGeometry, Axes, Axis, Motion, Op};
use crate::source::{FileId, Sources, Span};
use declaration::Declaration;
use error::{WizardError, WizardErrorKind};
use rhai::{Array, Dynamic, Engine, EvalAltResult, NativeCallContext, Position, Scope, AST};
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

mod stdlib {
    include!(concat!(env!("OUT_DIR"), "/stdlib.rs"));
}

/// Limits of the sandbox (documented in `stdlib/README.md`).
const MAX_OPERATIONS: u64 = 50_000_000;
const MAX_CALL_LEVELS: usize = 32;
const MAX_STRING: usize = 10_000;
const MAX_ARRAY: usize = 100_000;
const MAX_STATEMENTS: usize = 1_000_000;
const MAX_WIZARD_DEPTH: usize = 16;

/// A script found by discovery (the CLI reads the folders).
pub struct WizardSource {
    pub name: String,
    pub text: String,
    /// Where it came from, for `ger wizards`: a path or `stdlib`.
    pub origin: String,
}

/// The standard library, compiled into the binary. Files whose name starts
/// with `_` are not wizards (`_prelude.rhai`).
pub fn standard_library() -> Vec<WizardSource> {
    stdlib::STDLIB
        .iter()
        .filter(|(name, _)| !name.starts_with('_'))
        .map(|(name, text)| WizardSource {
            name: name.to_string(),
            text: text.to_string(),
            origin: "stdlib".to_string(),
        })
        .collect()
}

pub struct Wizard {
    pub name: String,
    pub origin: String,
    pub file: FileId,
    pub declaration: Result<Declaration, declaration::DeclarationError>,
    /// Compiled on first use.
    ast: RefCell<Option<Result<Rc<AST>, WizardError>>>,
    text: String,
}

impl Wizard {
    /// Its signature and one-line summary (`ger wizards`).
    pub fn described(&self) -> (String, String) {
        match &self.declaration {
            Ok(d) => (d.signature(&self.name), d.summary().to_string()),
            Err(e) => (
                self.name.clone(),
                format!("(bad declaration, line {}: {})", e.line, e.message),
            ),
        }
    }

    /// Its signature, where it comes from, its doc and each parameter:
    /// what `ger wizards NAME` prints and the editor's hover shows.
    pub fn manual(&self) -> String {
        let (signature, _) = self.described();
        let mut out = format!("{signature}    [{}]\n\n", self.origin);
        let Ok(d) = &self.declaration else {
            return out;
        };
        for line in &d.doc {
            out.push_str(line);
            out.push('\n');
        }
        if !d.params.is_empty() {
            out.push('\n');
        }
        for p in &d.params {
            let default = p
                .default
                .as_ref()
                .map_or(String::new(), |d| format!(" (default {d})"));
            out.push_str(&format!("  {:<12} {}{default}\n", p.name, p.doc));
        }
        out
    }
}

/// Every wizard found, by lower-case name; earlier sources win.
#[derive(Default)]
pub struct Library {
    wizards: Vec<Wizard>,
    index: HashMap<String, usize>,
}

impl Library {
    /// Build the library from sources in priority order (user folders first,
    /// the standard library last). Each script is added to `sources` so its
    /// diagnostics can be shown.
    pub fn new(found: Vec<WizardSource>, sources: &mut Sources) -> Library {
        let mut lib = Library::default();
        for s in found {
            let key = s.name.to_lowercase();
            if lib.index.contains_key(&key) {
                continue;
            }
            let file = sources.add(
                if s.origin == "stdlib" {
                    format!("stdlib/{}.rhai", s.name)
                } else {
                    s.origin.clone()
                },
                s.text.clone(),
            );
            lib.index.insert(key, lib.wizards.len());
            lib.wizards.push(Wizard {
                declaration: declaration::parse(&s.text),
                name: s.name,
                origin: s.origin,
                file,
                ast: RefCell::new(None),
                text: s.text,
            });
        }
        lib
    }

    pub fn get(&self, name: &str) -> Option<&Wizard> {
        self.index
            .get(&name.to_lowercase())
            .map(|&i| &self.wizards[i])
    }

    pub fn iter(&self) -> impl Iterator<Item = &Wizard> {
        let mut v: Vec<&Wizard> = self.wizards.iter().collect();
        v.sort_by_key(|w| w.name.to_lowercase());
        v.into_iter()
    }
}

/// What a script asked for, in order.
enum Action {
    Op(Op),
    /// A `gcode()` line, parsed when the script gave it.
    Line(crate::ast::Program),
}

/// The state a running script shares with the API functions.
#[derive(Default)]
struct Session {
    actions: Vec<Action>,
    position: [Option<f64>; 3],
    incremental: bool,
    units: Option<ir::Units>,
    tool: u32,
    tool_diameter: f64,
    tool_angle: Option<f64>,
    /// The feed per minute in effect, as `feed()` changes it.
    feed: Option<f64>,
    /// Wizards running, innermost last.
    stack: Vec<String>,
}

type RhaiResult<T> = Result<T, Box<EvalAltResult>>;

fn fail<T>(message: impl Into<String>) -> RhaiResult<T> {
    Err(Box::new(EvalAltResult::ErrorRuntime(
        Dynamic::from(message.into()),
        Position::NONE,
    )))
}

fn number(d: &Dynamic, what: &str) -> RhaiResult<f64> {
    let value = if let Ok(f) = d.as_float() {
        f
    } else if let Ok(i) = d.as_int() {
        i as f64
    } else {
        return fail(format!("{what} must be a number, not {}", d.type_name()));
    };
    if !ir::is_length(value) {
        return fail(format!(
            "{what} is out of range: {value:e} (numbers must be between -{} and {})",
            ir::MAX_LENGTH,
            ir::MAX_LENGTH
        ));
    }
    Ok(value)
}

impl Session {
    fn push(&mut self, action: Action) -> RhaiResult<()> {
        if self.actions.len() >= MAX_STATEMENTS {
            return fail(format!(
                "the wizard emitted more than {MAX_STATEMENTS} statements"
            ));
        }
        if let Action::Op(Op::Move(m)) = &action {
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                if let Some(v) = m.to.get(axis) {
                    let axis = axis.index();
                    self.position[axis] = if self.incremental {
                        self.position[axis].map(|p| p + v)
                    } else {
                        Some(v)
                    };
                }
            }
        }
        self.actions.push(action);
        Ok(())
    }

    fn motion(&mut self, motion: Motion, to: Axes, center: Option<ir::Center>) -> RhaiResult<()> {
        let arc = center.map(|c| Arc {
            geometry: ArcGeometry::Center(c),
            turns: 1,
        });
        self.push(Action::Op(Op::Move(ir::Move {
            motion,
            to,
            arc,
            corner: None,
            lead: None,
        })))
    }
}

/// The wizard engine: one per compile. Its Rhai engine is built at the
/// first wizard call (a third of a millisecond: most programs call none).
pub struct WizardEngine {
    engine: std::cell::OnceCell<Engine>,
    library: Rc<Library>,
    session: Rc<RefCell<Session>>,
}

impl WizardEngine {
    pub fn new(library: Library) -> WizardEngine {
        WizardEngine {
            engine: std::cell::OnceCell::new(),
            library: Rc::new(library),
            session: Rc::new(RefCell::new(Session::default())),
        }
    }

    fn engine(&self) -> &Engine {
        self.engine
            .get_or_init(|| rhai_engine(&self.session, &self.library))
    }

    pub fn library(&self) -> &Library {
        &self.library
    }
}

/// A Rhai engine with the wizard API and its limits.
fn rhai_engine(session: &Rc<RefCell<Session>>, library: &Rc<Library>) -> Engine {
    let mut engine = Engine::new();
    engine
        .set_max_operations(MAX_OPERATIONS)
        .set_max_call_levels(MAX_CALL_LEVELS)
        .set_max_string_size(MAX_STRING)
        .set_max_array_size(MAX_ARRAY)
        .set_max_map_size(MAX_ARRAY)
        .set_max_expr_depths(64, 32)
        .set_module_resolver(rhai::module_resolvers::DummyModuleResolver::new());
    engine.disable_symbol("eval");
    engine.on_print(|_| {});
    engine.on_debug(|_, _, _| {});
    register_api(&mut engine, session, library);
    register_prelude(&mut engine);
    engine
}

/// The API of `stdlib/README.md`, in four groups.
fn register_api(engine: &mut Engine, session: &Rc<RefCell<Session>>, library: &Rc<Library>) {
    register_moves(engine, session);
    register_settings(engine, session);
    register_state(engine, session);
    register_nested(engine, session, library);
}

/// Moves, feed, spindle and dwell: numeric arguments, checked by `number`.
fn register_moves(engine: &mut Engine, session: &Rc<RefCell<Session>>) {
    macro_rules! api {
        ($name:expr, |$s:ident $(, $arg:ident)*| $body:expr) => {{
            let shared = Rc::clone(session);
            engine.register_fn($name, move |$($arg: Dynamic),*| -> RhaiResult<()> {
                let mut guard = shared.borrow_mut();
                let $s: &mut Session = &mut guard;
                $(let $arg = number(&$arg, &format!("{}(): `{}`", $name, stringify!($arg)))?;)*
                $body
            });
        }};
    }
    let full = |x: f64, y: f64, z: Option<f64>| {
        let mut to = Axes::default();
        to.set(Axis::X, x);
        to.set(Axis::Y, y);
        to.put(Axis::Z, z);
        to
    };
    let z_only = |z: f64| {
        let mut to = Axes::default();
        to.set(Axis::Z, z);
        to
    };
    api!("rapid", |s, x, y| s.motion(
        Motion::Rapid,
        full(x, y, None),
        None
    ));
    api!("rapid", |s, x, y, z| s.motion(
        Motion::Rapid,
        full(x, y, Some(z)),
        None
    ));
    api!("rapid_z", |s, z| s.motion(Motion::Rapid, z_only(z), None));
    api!("line", |s, x, y| s.motion(
        Motion::Linear,
        full(x, y, None),
        None
    ));
    api!("line", |s, x, y, z| s.motion(
        Motion::Linear,
        full(x, y, Some(z)),
        None
    ));
    api!("line_z", |s, z| s.motion(Motion::Linear, z_only(z), None));
    for (name, motion) in [("arc_cw", Motion::ArcCw), ("arc_ccw", Motion::ArcCcw)] {
        api!(name, |s, x, y, i, j| s.motion(
            motion,
            full(x, y, None),
            Some([Some(i), Some(j), None])
        ));
        api!(name, |s, x, y, z, i, j, k| s.motion(
            motion,
            full(x, y, Some(z)),
            Some([Some(i), Some(j), Some(k)])
        ));
    }
    api!("feed", |s, f| if f > 0.0 {
        s.feed = Some(f);
        s.push(Action::Op(Op::Feed(f)))
    } else {
        fail("the feed must be positive")
    });
    api!("spindle", |s, rpm| {
        s.push(Action::Op(Op::Speed(rpm)))?;
        s.push(Action::Op(Op::Spindle(ir::Spindle::Clockwise)))
    });
    api!("spindle_ccw", |s, rpm| {
        s.push(Action::Op(Op::Speed(rpm)))?;
        s.push(Action::Op(Op::Spindle(ir::Spindle::CounterClockwise)))
    });
    api!("spindle_off", |s| s
        .push(Action::Op(Op::Spindle(ir::Spindle::Off))));
    api!("dwell", |s, seconds| if seconds >= 0.0 {
        s.push(Action::Op(Op::Dwell(seconds)))
    } else {
        fail("a dwell time is positive")
    });
}

/// Coolant, plane, comments and raw lines: string arguments.
fn register_settings(engine: &mut Engine, session: &Rc<RefCell<Session>>) {
    let shared = Rc::clone(session);
    engine.register_fn("coolant", move |kind: &str| -> RhaiResult<()> {
        let coolant = match kind.to_ascii_lowercase().as_str() {
            "flood" => ir::Coolant::Flood,
            "mist" => ir::Coolant::Mist,
            "off" => ir::Coolant::Off,
            other => {
                return fail(format!(
                    "coolant \"{other}\": expected \"flood\", \"mist\" or \"off\""
                ))
            }
        };
        shared.borrow_mut().push(Action::Op(Op::Coolant(coolant)))
    });
    let shared = Rc::clone(session);
    engine.register_fn("plane", move |name: &str| -> RhaiResult<()> {
        let plane = match name.to_ascii_lowercase().as_str() {
            "xy" => ir::Plane::XY,
            "zx" | "xz" => ir::Plane::ZX,
            "yz" => ir::Plane::YZ,
            other => {
                return fail(format!(
                    "plane \"{other}\": expected \"xy\", \"zx\" or \"yz\""
                ))
            }
        };
        shared.borrow_mut().push(Action::Op(Op::Plane(plane)))
    });
    let shared = Rc::clone(session);
    engine.register_fn("comment", move |text: &str| -> RhaiResult<()> {
        shared
            .borrow_mut()
            .push(Action::Op(Op::Comment(text.to_string())))
    });
    let shared = Rc::clone(session);
    engine.register_fn("gcode", move |text: &str| -> RhaiResult<()> {
        if text.contains('\n') {
            return fail("gcode() takes one line");
        }
        // A line that does not parse is the script's error, at its line.
        let (line, problems) = crate::syntax::parse_program(text, 0);
        if let Some(first) = problems.first() {
            return fail(format!("gcode(\"{text}\"): {}", first.message));
        }
        shared.borrow_mut().push(Action::Line(line))
    });
}

/// What a wizard can read of the machine (SPEC §5).
fn register_state(engine: &mut Engine, session: &Rc<RefCell<Session>>) {
    for (name, axis) in [("pos_x", 0), ("pos_y", 1), ("pos_z", 2)] {
        let shared = Rc::clone(session);
        engine.register_fn(name, move || -> Dynamic {
            shared.borrow().position[axis].map_or(Dynamic::UNIT, Dynamic::from_float)
        });
    }
    let shared = Rc::clone(session);
    engine.register_fn("units", move || -> String {
        shared
            .borrow()
            .units
            .unwrap_or(ir::Units::Inch)
            .name()
            .to_string()
    });
    let shared = Rc::clone(session);
    engine.register_fn("tool", move || -> rhai::INT {
        shared.borrow().tool as rhai::INT
    });
    let shared = Rc::clone(session);
    engine.register_fn("tool_diameter", move || -> rhai::FLOAT {
        shared.borrow().tool_diameter
    });
    let shared = Rc::clone(session);
    engine.register_fn("tool_angle", move || -> Dynamic {
        shared
            .borrow()
            .tool_angle
            .map_or(Dynamic::UNIT, Dynamic::from_float)
    });
    let shared = Rc::clone(session);
    engine.register_fn("feed_rate", move || -> Dynamic {
        shared
            .borrow()
            .feed
            .map_or(Dynamic::UNIT, Dynamic::from_float)
    });
}

/// `wizard(name, args)`: one wizard calling another, depth-limited.
fn register_nested(engine: &mut Engine, session: &Rc<RefCell<Session>>, library: &Rc<Library>) {
    let shared = Rc::clone(session);
    let lib = Rc::clone(library);
    let nested = move |ctx: NativeCallContext, name: &str, args: Array| -> RhaiResult<()> {
        let Some(wizard) = lib.get(name) else {
            return fail(format!("no wizard named `{name}`"));
        };
        if shared.borrow().stack.len() >= MAX_WIZARD_DEPTH {
            return fail(format!("wizards nested more than {MAX_WIZARD_DEPTH} deep"));
        }
        // The calling wizard gets the problem as its own Rhai error.
        let summary = |kind| WizardError::new(&wizard.name, kind, Span::default()).summary();
        let decl = wizard
            .declaration
            .as_ref()
            .map_err(|e| {
                summary(WizardErrorKind::BadDeclaration {
                    line: line_span(&wizard.text, wizard.file, Some(e.line)),
                    message: e.message.clone(),
                })
            })
            .or_else(fail)?;
        let ast = wizard
            .compiled(ctx.engine())
            .map_err(|e| e.summary())
            .or_else(fail)?;
        let scope = bind(decl, args)
            .map_err(|message| {
                summary(WizardErrorKind::WrongArguments {
                    message,
                    usage: decl.signature(&wizard.name),
                })
            })
            .or_else(fail)?;
        shared.borrow_mut().stack.push(wizard.name.clone());
        let result = ctx.engine().run_ast_with_scope(&mut { scope }, &ast);
        shared.borrow_mut().stack.pop();
        result.map_err(|e| {
            let (line, message) = innermost(&e);
            let at = line.map_or(String::new(), |l| format!(" (line {l})"));
            Box::new(EvalAltResult::ErrorRuntime(
                Dynamic::from(format!("in wizard `{}`{at}: {message}", wizard.name)),
                Position::NONE,
            ))
        })
    };
    engine.register_fn("wizard", nested.clone());
    engine.register_fn("wizard", move |ctx: NativeCallContext, name: &str| {
        nested(ctx, name, Array::new())
    });
}

/// `stdlib/_prelude.rhai`: functions every wizard can call. It is part of
/// the binary and tested with it, so a failure here is a bug in ger.
fn register_prelude(engine: &mut Engine) {
    let Some((_, text)) = stdlib::STDLIB.iter().find(|(name, _)| *name == "_prelude") else {
        return;
    };
    let module = engine
        .compile(text)
        .map_err(|e| e.to_string())
        .and_then(|ast| {
            rhai::Module::eval_ast_as_new(Scope::new(), &ast, engine).map_err(|e| e.to_string())
        });
    match module {
        Ok(module) => {
            engine.register_global_module(module.into());
        }
        Err(e) => debug_assert!(false, "stdlib/_prelude.rhai: {e}"),
    }
}

/// Bind call arguments to the declared parameters.
fn bind(decl: &Declaration, args: Array) -> Result<Scope<'static>, String> {
    if args.len() > decl.params.len() {
        return Err(format!(
            "{} argument(s) given, at most {} expected",
            args.len(),
            decl.params.len()
        ));
    }
    let mut scope = Scope::new();
    let given = args.len();
    for (i, p) in decl.params.iter().enumerate() {
        let value = match args.get(i) {
            Some(v) => match (v.as_int(), p.default.as_ref()) {
                // Numbers are floats inside wizards, whoever passes them.
                (Ok(n), _) => Dynamic::from_float(n as f64),
                _ => v.clone(),
            },
            None => match &p.default {
                Some(declaration::Default::Number(n)) => Dynamic::from_float(*n),
                Some(declaration::Default::Str(s)) => Dynamic::from(s.clone()),
                Some(declaration::Default::Bool(b)) => Dynamic::from_bool(*b),
                None => {
                    let required = decl.params.iter().filter(|p| p.default.is_none()).count();
                    return Err(format!(
                        "{given} argument(s) given, {required} required: `{}` is missing",
                        p.name
                    ));
                }
            },
        };
        scope.push_dynamic(p.name.clone(), value);
    }
    Ok(scope)
}

/// The innermost error of a Rhai error chain: its script line and message.
fn innermost(e: &EvalAltResult) -> (Option<usize>, String) {
    match e {
        EvalAltResult::ErrorInFunctionCall(_, _, inner, _) => innermost(inner),
        EvalAltResult::ErrorRuntime(value, pos) => (
            pos.line(),
            value
                .clone()
                .into_string()
                .unwrap_or_else(|_| value.to_string()),
        ),
        EvalAltResult::ErrorTooManyOperations(pos) => (
            pos.line(),
            format!("the script ran more than {MAX_OPERATIONS} operations (an endless loop?)"),
        ),
        other => {
            let pos = other.position();
            let text = other.to_string();
            // Rhai appends " (line N, position M)"; the label shows it.
            let message = text.split(" (line ").next().unwrap_or(&text).to_string();
            (pos.line(), message)
        }
    }
}

impl Wizard {
    fn compiled(&self, engine: &Engine) -> Result<Rc<AST>, WizardError> {
        if let Some(done) = self.ast.borrow().as_ref() {
            return done.clone();
        }
        let result = engine.compile(&self.text).map(Rc::new).map_err(|e| {
            let span = line_span(&self.text, self.file, e.1.line());
            let message = e.0.to_string();
            WizardError::new(
                &self.name,
                WizardErrorKind::DoesNotCompile { message },
                span,
            )
        });
        *self.ast.borrow_mut() = Some(result.clone());
        result
    }
}

/// The span of a 1-based line of a script (the whole script if unknown).
fn line_span(text: &str, file: FileId, line: Option<usize>) -> Span {
    let Some(line) = line else {
        return Span::new(file, 1, 0, text.len().min(1));
    };
    let start: usize = text
        .split_inclusive('\n')
        .take(line - 1)
        .map(str::len)
        .sum();
    let len = text[start.min(text.len())..]
        .find('\n')
        .unwrap_or(text.len() - start.min(text.len()));
    Span::new(file, line as u32, start, start + len)
}

impl WizardHost for WizardEngine {
    fn call(
        &mut self,
        name: &str,
        args: &[Value],
        call: &WizardCall<'_>,
        ctx: &mut dyn WizardContext,
    ) -> Option<Result<(), Vec<Diagnostic>>> {
        let wizard = self.library.get(name)?;
        Some(self.run(wizard, args, call, ctx))
    }

    fn has(&self, name: &str) -> bool {
        self.library.get(name).is_some()
    }

    fn names(&self) -> Vec<String> {
        self.library
            .wizards
            .iter()
            .map(|w| w.name.clone())
            .collect()
    }
}

impl WizardEngine {
    fn run(
        &self,
        wizard: &Wizard,
        args: &[Value],
        call: &WizardCall<'_>,
        ctx: &mut dyn WizardContext,
    ) -> Result<(), Vec<Diagnostic>> {
        let decl = match &wizard.declaration {
            Ok(d) => d,
            Err(e) => {
                let kind = WizardErrorKind::BadDeclaration {
                    line: line_span(&wizard.text, wizard.file, Some(e.line)),
                    message: e.message.clone(),
                };
                return Err(vec![
                    WizardError::new(&wizard.name, kind, call.span).to_diagnostic()
                ]);
            }
        };
        let ast = wizard
            .compiled(self.engine())
            .map_err(|e| vec![e.to_diagnostic().with_secondary(call.span, "called here")])?;
        let mut scope = arguments(wizard, decl, args, call)?;
        let state: MachineState = ctx.state();
        {
            let mut s = self.session.borrow_mut();
            *s = Session {
                position: state.position,
                incremental: false,
                units: state.units,
                tool: state.tool,
                tool_diameter: state.tool_diameter,
                tool_angle: state.tool_angle,
                feed: state.feed,
                stack: vec![wizard.name.clone()],
                actions: Vec::new(),
            };
        }
        let result = self.engine().run_ast_with_scope(&mut scope, &ast);
        let actions = std::mem::take(&mut self.session.borrow_mut().actions);
        if let Err(e) = result {
            let (line, message) = innermost(&e);
            let raised = line_span(&wizard.text, wizard.file, line);
            let kind = WizardErrorKind::Failed { message, raised };
            return Err(vec![
                WizardError::new(&wizard.name, kind, call.span).to_diagnostic()
            ]);
        }
        replay(actions, &state, ctx)
    }
}

/// The call's arguments bound to the declared parameters, as the script's
/// scope; an error names the usage.
fn arguments(
    wizard: &Wizard,
    decl: &Declaration,
    args: &[Value],
    call: &WizardCall<'_>,
) -> Result<Scope<'static>, Vec<Diagnostic>> {
    let values: Array = args
        .iter()
        .map(|v| match v {
            Value::Number(n) => Dynamic::from_float(*n),
            Value::Bool(b) => Dynamic::from_bool(*b),
            Value::Str(s) => Dynamic::from(call.names.text(*s).to_string()),
        })
        .collect();
    bind(decl, values).map_err(|message| {
        let kind = WizardErrorKind::WrongArguments {
            message,
            usage: decl.signature(&wizard.name),
        };
        let at = call
            .arg_spans
            .first()
            .map_or(call.span, |f| f.to(*call.arg_spans.last().unwrap_or(f)));
        vec![WizardError::new(&wizard.name, kind, at).to_diagnostic()]
    })
}

/// What a script did, sent to the caller in order. Wizard coordinates are
/// absolute and Cartesian, their arc centres relative, their feeds per
/// minute: a G91, G16, G90.1 or G93 caller is switched to
/// G90/G15/G91.1/G94 around them, and back.
fn replay(
    actions: Vec<Action>,
    state: &MachineState,
    ctx: &mut dyn WizardContext,
) -> Result<(), Vec<Diagnostic>> {
    // (Each mode that is on: the op that leaves it, the op back.)
    let modes = [
        (
            state.incremental,
            Op::Distance(ir::Distance::Absolute),
            Op::Distance(ir::Distance::Incremental),
        ),
        (state.polar, Op::Polar(false), Op::Polar(true)),
        (
            state.absolute_centers,
            Op::ArcCenters(ir::Distance::Incremental),
            Op::ArcCenters(ir::Distance::Absolute),
        ),
        (
            state.inverse_time,
            Op::InverseTime(false),
            Op::InverseTime(true),
        ),
    ];
    let on: Vec<(Op, Op)> = modes
        .into_iter()
        .filter_map(|(is_on, leave, back)| is_on.then_some((leave, back)))
        .collect();
    for (leave, _) in &on {
        ctx.emit(leave.clone()).map_err(|d| vec![d])?;
    }
    for action in actions {
        match action {
            Action::Op(op) => ctx.emit(op).map_err(|d| vec![d])?,
            Action::Line(line) => ctx.run_line(&line)?,
        }
    }
    for (_, back) in on.into_iter().rev() {
        ctx.emit(back).map_err(|d| vec![d])?;
    }
    Ok(())
}
