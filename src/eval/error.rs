//! The evaluator's own problems (limits, loops, the order of a program's
//! parts, names it does not know), as data with one wording function. The
//! problems of one kind of block have their own enums beside the code
//! that finds them (`setup`, `comp`, `cycle`, the expressions of `value`).

use crate::diagnostic::{error, note, warning, Diagnostic, DiagnosticExt, Located, Wording};
use crate::ir;
use crate::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub enum EvalErrorKind {
    /// More statements than `--max-statements` allows.
    TooManyStatements(usize),
    /// The caller stopped the run (`EvalOptions::cancel`).
    Cancelled,
    FeedBeforeRate,
    /// A feed move after F0, outside G93: rs274 and grbl refuse it.
    ZeroFeed,
    /// A feed move after G94 ended G93, before any F.
    FeedAfterInverseTime,
    /// A feed move under G93 without an F on its line.
    InverseTimeWithoutF,
    /// An arc under G93 and compensation (rs274 times the offset arc).
    InverseTimeArcUnderComp,
    /// A warning: the program never says its units.
    UnitsUnstated,
    /// A warning: a controller command (`$H`) written through.
    CommandPassedThrough(String),
    /// A loop ran more than `--max-iterations` times.
    LoopLimit(u64),
    /// A loop pass changed no variable.
    LoopNeverEnds,
    AssignToPi,
    /// A setup directive after the first move (where it was).
    SetupAfterFirstMove {
        directive: &'static str,
        first: Span,
    },
    /// A note: the file defines subprograms and runs nothing (a file of
    /// subroutines, rs274's empty program).
    OnlySubprograms,
    /// A note: a `(DEBUG,…)` or `(PRINT,…)` message, its parameters
    /// written in.
    Message {
        kind: String,
        text: String,
    },
    /// A note: messages past the limit are not shown.
    MessagesCut(usize),
    /// A `GOTO` to a label its program does not have.
    NoLabel(u32),
    /// A `break` (true) or `continue` (false) with no `while` or `do` loop
    /// of its label around it.
    NoLoop {
        /// The o-word as written: `o100`, `o<name>`.
        label: String,
        is_break: bool,
    },
    /// A `GOTO` target that is no label number.
    BadLabel(f64),
    /// Fanuc's `#0` and system variables cannot be set.
    ReadOnlyVariable(String),
    /// rs274's predefined parameters (`#<_x>`, `#<_feed>`) cannot be set.
    ReadOnlyParameter(String),
    /// A warning: `#<_task>` reads 0, as rs274 run alone (a preview).
    TaskAsPreview,
    /// Fanuc's `#3000 = n (MESSAGE)`.
    Alarm {
        number: f64,
        message: String,
    },
    /// A name that is no wizard or directive, and the nearest one there is.
    UnknownWizard {
        name: String,
        nearest: Option<String>,
    },
}

/// What goes wrong, and where: see [`EvalErrorKind`].
pub type EvalError = Located<EvalErrorKind>;

impl Wording for EvalErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        match self {
            EvalErrorKind::TooManyStatements(limit) => error(
                format!("loops and subprogram calls make more than {limit} statements"),
                at,
                "the limit was reached here",
            )
            .with_help("check the loops and subprogram repeats"),
            EvalErrorKind::Cancelled => error(
                "the compile was stopped by its caller",
                at,
                "stopped after this statement",
            ),
            EvalErrorKind::FeedBeforeRate => error(
                "a feed move before any feed rate",
                at,
                "no F word has been given yet",
            )
            .with_help("set the feed on this line or before it: `G1 X10 F300`"),
            EvalErrorKind::ZeroFeed => error(
                "a feed move at a zero feed rate",
                at,
                "the feed rate is 0 here",
            )
            .with_note(
                "it would never end: rs274 and grbl (error 22, undefined feed rate) refuse it",
            )
            .with_help("set a feed above 0 on this line or before it: `G1 X10 F300`"),
            EvalErrorKind::FeedAfterInverseTime => error(
                "a feed move after G94 before a feed rate",
                at,
                "no F word since G93 ended",
            )
            .with_note("G94 after G93 leaves no feed per minute (rs274 sets it to 0)")
            .with_help("set the feed on this line or before it: `G1 X10 F300`"),
            EvalErrorKind::InverseTimeWithoutF => error(
                "a feed move under G93 without an F word",
                at,
                "G93 (inverse time) is on: each feed move gives its own F",
            )
            .with_note(
                "F is the inverse of the move's time in minutes: `G1 X10 F2` takes half a minute",
            )
            .with_help("give F on this line, or G94 for a feed per minute"),
            EvalErrorKind::InverseTimeArcUnderComp => error(
                "an arc under G93 and cutter compensation",
                at,
                "not supported: the feed would depend on the compensated arc's length",
            )
            .with_help("switch to G94 for the compensated profile"),
            EvalErrorKind::UnitsUnstated => warning(
                "the program does not state its units",
                at,
                "this move runs in the machine's units",
            )
            .with_note("nothing is converted and no G20/G21 is written")
            .with_help("add G21 (mm) or G20 (inch) at the top, or pass --units mm|inch"),
            EvalErrorKind::CommandPassedThrough(text) => warning(
                format!("`{text}` is passed through"),
                at,
                "a command to the controller, not G-code",
            )
            .with_note("ger writes controller commands as they are, in their place"),
            EvalErrorKind::LoopLimit(limit) => error(
                format!("this loop ran more than {limit} times"),
                at,
                "loop stopped here",
            )
            .with_help("check that the condition becomes false, or raise --max-iterations"),
            EvalErrorKind::LoopNeverEnds => error(
                "this loop never ends",
                at,
                "a pass through it changed no variable, so the condition stays true",
            )
            .with_help("change a variable the condition reads inside the loop"),
            EvalErrorKind::OnlySubprograms => note(
                "the file defines subprograms and runs nothing: an empty program",
                at,
                "the first subprogram",
            )
            .with_note("rs274 runs such a file (a file of subroutines) as an empty program"),
            EvalErrorKind::Message { kind, text } => {
                note(format!("{kind}: {text}"), at, "the program's message")
            }
            EvalErrorKind::MessagesCut(limit) => note(
                format!("more DEBUG and PRINT messages: only the first {limit} are shown"),
                at,
                "this one and those after it",
            ),
            EvalErrorKind::NoLabel(label) => error(
                format!("no N{label} to go to"),
                at,
                "GOTO looks for the label in its own program or subprogram",
            )
            .with_note("a GOTO may leave a WHILE loop but not jump into one"),
            EvalErrorKind::NoLoop { label, is_break } => {
                let keyword = if *is_break { "break" } else { "continue" };
                error(
                    format!("`{keyword}` outside the loop it names"),
                    at,
                    "no `while` or `do` loop with this o-word is around it",
                )
                .with_note(format!(
                    "LinuxCNC's `{label} {keyword}` needs `{label} while` or `{label} do` \
                     around it in the same subroutine (a `repeat` loop cannot be left this way)"
                ))
            }
            EvalErrorKind::BadLabel(n) => error(
                format!("`GOTO {n}` names no line"),
                at,
                "a label is a whole number from 0",
            ),
            EvalErrorKind::ReadOnlyVariable(name) => error(
                format!("`{name}` cannot be set"),
                at,
                "#0 is always vacant and #1000 and up are the machine's",
            ),
            EvalErrorKind::ReadOnlyParameter(name) => error(
                format!("`{name}` cannot be set"),
                at,
                "a parameter rs274 keeps for its own state: read-only",
            ),
            EvalErrorKind::TaskAsPreview => warning(
                "`#<_task>` reads 0 here, as in LinuxCNC's preview",
                at,
                "the machine's task reads 1",
            )
            .with_note("ger follows rs274 run alone: the output takes the branches a preview takes")
            .with_help("if the program must run its `#<_task>` branch, write it without the test"),
            EvalErrorKind::Alarm { number, message } => error(
                match message.is_empty() {
                    true => format!("alarm {number}"),
                    false => message.clone(),
                },
                at,
                format!("the program raises alarm {number} (#3000)"),
            )
            .with_note("on the machine the program stops here; ger writes no output"),
            EvalErrorKind::AssignToPi => error("`PI` is a constant", at, "cannot assign to it"),
            EvalErrorKind::SetupAfterFirstMove { directive, first } => error(
                format!("`{directive}` after the first move"),
                at,
                "the machine setup must be complete before the tool moves",
            )
            .with_secondary(*first, "the first move")
            .with_help("put the setup directives at the top of the program"),
            EvalErrorKind::UnknownWizard { name, nearest } => {
                let d = error(
                    format!("unknown wizard `{name}`"),
                    at,
                    "no wizard or directive has this name",
                );
                match nearest {
                    Some(close) => d.with_help(format!("did you mean `{close}`?")),
                    None => d.with_note(
                        "a statement that starts with a name is an assignment (`Name = …`) or a wizard call; `;` ends a statement, so comments are written `( … )` or `//`",
                    ),
                }
            }
        }
    }
}

/// A number no machine has where a length, feed or speed belongs.
pub fn out_of_range(message: String, what: &str, value: f64, span: Span) -> Diagnostic {
    error(message, span, format!("this is {value:e}")).with_note(format!(
        "{what} must be between -{0} and {0}",
        ir::MAX_LENGTH
    ))
}
