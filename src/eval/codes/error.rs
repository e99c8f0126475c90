//! What a G or M code statement gets wrong, and what ger tells the user
//! about the codes it passes through or drops, as data with one wording
//! function.

use crate::diagnostic::{error, note, warning, Diagnostic, DiagnosticExt, Located, Wording};
use crate::eval::options::{Chosen, Flavour};
use crate::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub enum CodeErrorKind {
    /// A letter given twice; where the first one was.
    WordTwice {
        letter: String,
        first: Span,
    },
    /// `G1.25`: not a whole code or one with a decimal.
    NotACode {
        letter: char,
        value: f64,
    },
    NegativeFeed,
    NegativeSpeed,
    MoveWithoutMotion,
    ArcInMachineCoordinates,
    /// A word no code took; the code of the statement, when there is one.
    UnusedWord {
        letter: String,
        code: Option<String>,
    },
    ZeroTurns,
    /// G96 without its surface speed (rs274: "S word missing with G96").
    SurfaceSpeedWithoutS,
    RadiusAndCentre,
    ZeroRadius,
    ArcWithoutCentre,
    /// A code ger does not lower, and why.
    Unsupported {
        code: String,
        why: &'static str,
    },
    G76,
    /// A warning: G7 makes the X words diameters.
    DiameterMode,
    /// A warning: G28 or G30 moves to a home only the machine knows.
    HomePassedThrough(String),
    /// A warning: an M code ger does not know is written as it is.
    MCodePassedThrough(u32),
    /// M72 with no state saved at its call level (rs274: "Cannot restore
    /// context from invalid stack frame - missing M70/M73?").
    NoSavedModes,
    /// A warning: M73 outside a subroutine has nothing to return to.
    M73AtTopLevel,
    /// A note: the first dwell P, read as `from` reads it, which no flag
    /// chose.
    DwellMeaning {
        p: f64,
        from: Flavour,
        chosen: Chosen,
    },
    DwellTwice,
    DwellWithoutTime,
    NegativeDwell,
    G10WithoutL,
    G10WithoutP,
    WorkOffsetNumber,
    RotatedWorkOffset,
    G10Form,
    /// G10 L10, L11 read as Fanuc's: its offset memory.
    FanucOffsetMemory,
    /// G10 L1/L10/L11 (the number) without P (the tool).
    ToolDataWithoutP(u32),
    /// G10 L1/L10/L11 R below zero.
    NegativeToolRadius,
    /// G10 L1/L10/L11 with an offset on an axis other than Z.
    ToolDataAxis(char),
    /// G52/G92/G10 with no axis word.
    WithoutAxes(&'static str),
    M98WithoutP,
    G65WithoutP,
    M98CountTwice,
    /// A call of a subprogram the program does not have: its name, the
    /// file ger looked for (a LinuxCNC `o<name>`), the ones it has.
    NoSubprogram {
        name: String,
        file: Option<String>,
        known: Vec<String>,
    },
    /// Calls nested past the limit; the subprogram that calls itself and
    /// where it was first called, when that is the cause.
    CallDepth {
        limit: usize,
        recursion: Option<(String, Span)>,
    },
    /// A word that must be a whole number from 0, and what it counts.
    NotWhole(&'static str),
    WizardLineNotPlain,
    WizardLineVariables,
    /// A polar word (`@`, `^`) outside the G17 plane.
    PolarPlane,
    /// A polar word with an X or Y word.
    PolarAndAxis(char),
    /// A polar word with G53.
    PolarMachine,
    /// A radius alone (G90) or any polar word (G91) with the tool at the
    /// program zero, where its angle is undefined.
    PolarAtOrigin {
        incremental: bool,
    },
    /// A polar word that needs the current X and Y, which ger does not know.
    PolarPosition,
    /// A G5/G5.1 line rs274 refuses, or ger does not cut.
    Spline(SplineProblem),
    /// A warning: a G5 without I J after a move that was not a G5 takes
    /// these, left by an earlier G5 (or G87), as rs274 does.
    SplineLeftover([f64; 2]),
    /// `,R` and `,C` on one line.
    RoundAndChamfer,
    /// `,R`/`,C` on a move that is not a G1, G2 or G3 (the motion or mode
    /// named).
    CornerNotOnG1(&'static str),
    /// `,R`/`,C` of 0 or less (its spelling).
    CornerSize(String),
    /// A G33 or G33.1 (the code) line rs274 refuses, or ger does not cut.
    Thread(ThreadProblem, &'static str),
    /// A LinuxCNC G76 line rs274 refuses, or ger cannot expand.
    ThreadCycle(ThreadCycleProblem),
}

/// What a G33 line gets wrong (rs274's checks, and what ger does not cut).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThreadProblem {
    NoK,
    /// An F word: the feed is the spindle's.
    Feed,
    SpindleOff,
    /// Under G41/G42.
    Comp,
    /// No axis word (rs274: "All axes missing with motion code").
    NoAxes,
}

/// What a LinuxCNC G76 line gets wrong (rs274's checks, in its words
/// where it has them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThreadCycleProblem {
    /// P, I, J or K (the letter) missing.
    Missing(char),
    /// H or L (the letter) not a whole number.
    NotWhole(char),
    IZero,
    JNotPositive,
    KNotAboveJ,
    NoAxes,
    /// A rotary or U/V/W axis word (the letter).
    OtherAxis(char),
    SpindleOff,
    Comp,
    /// Where the tool starts (the axis letter), which the cycle needs.
    UnknownStart(char),
    /// More passes than [`crate::eval`] allows (the count, rounded).
    TooManyPasses(f64),
}

/// What a G5/G5.1 line gets wrong (rs274's checks, in its words where it
/// has them, and what ger does not cut).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplineProblem {
    /// G5 with one of I and J.
    IOrJ,
    /// G5.1 without both I and J.
    NoIJ,
    /// G5 without both P and Q.
    NoPQ,
    /// Not in G17.
    Plane,
    /// A word of another axis.
    Axis(char),
    /// No X or Y.
    NoEnd,
    /// Axis words alone in the spline's motion mode: rs274 moves nowhere
    /// and takes the point as reached.
    Again,
    /// G5.1 I0 J0: a straight line LinuxCNC's planner cannot cut.
    Straight,
    Polar,
    InverseTime,
    Diameter,
}

/// What goes wrong, and where: see [`CodeErrorKind`].
pub type CodeError = Located<CodeErrorKind>;

impl Wording for CodeErrorKind {
    fn wording(&self, at: Span) -> Diagnostic {
        use CodeErrorKind as K;
        match self {
            K::WordTwice { letter, first } => error(
                format!("`{letter}` appears twice in one statement"),
                at,
                "second one",
            )
            .with_secondary(*first, "first one"),
            K::NotACode { letter, value } => error(
                format!("`{letter}{value}` is not a code"),
                at,
                "codes are whole numbers, or with one decimal (G54.1)",
            ),
            K::NegativeFeed => error("negative feed rate", at, "F must be positive"),
            K::NegativeSpeed => error("negative spindle speed", at, "S must be positive"),
            K::MoveWithoutMotion => error(
                "a move without a motion mode",
                at,
                "no G0, G1, G2 or G3 is active yet",
            )
            .with_help("start the move with `G0` or `G1`"),
            K::ArcInMachineCoordinates => error(
                "an arc in machine coordinates (G53)",
                at,
                "G53 takes only G0 or G1",
            ),
            K::UnusedWord { letter, code } => {
                let label = match code {
                    None => "no code on this line uses it".to_string(),
                    Some(code) => format!("{code} does not use `{letter}`"),
                };
                error(format!("unexpected `{letter}` word"), at, label)
            }
            K::ZeroTurns => error("zero turns", at, "P counts turns, from 1"),
            K::SurfaceSpeedWithoutS => error(
                "G96 without S",
                at,
                "G96 needs the surface speed on its line",
            ),
            K::RadiusAndCentre => error(
                "an arc with both R and I/J/K",
                at,
                "give the radius or the centre, not both",
            ),
            K::ZeroRadius => error("zero arc radius", at, "R must not be 0"),
            K::ArcWithoutCentre => error(
                "an arc needs its centre or radius",
                at,
                "no I, J, K or R here",
            )
            .with_help("give the centre with I/J/K (relative to the start) or the radius with R"),
            K::Unsupported { code, why } => error(format!("unsupported code {code}"), at, *why),
            K::G76 => error(
                "G76 is not supported",
                at,
                "G76 is fine boring on Fanuc and threading on LinuxCNC",
            )
            .with_help("--from linuxcnc reads it as threading, --from fanuc as fine boring"),
            K::DiameterMode => warning(
                "G7: X words are diameters",
                at,
                "from here the output's X is half of what is written (a radius)",
            ),
            K::HomePassedThrough(code) => warning(
                format!("{code} is passed through"),
                at,
                "the machine moves to the home position it stores",
            )
            .with_note(
                "the position after it is not known to ger: an arc or a cycle needs an absolute \
                 move first; straight steps (G91) are written as steps",
            ),
            K::NoSavedModes => error(
                "M72 with no modal state saved",
                at,
                "no M70 or M73 saved one at this call level, or M71 forgot it",
            )
            .with_help("save the state with M70 before restoring it"),
            K::M73AtTopLevel => warning(
                "M73 outside a subroutine",
                at,
                "nothing returns here: the state is saved as M70 saves it",
            )
            .with_note("rs274 says the same and restores it only at an M72"),
            K::MCodePassedThrough(number) => warning(
                format!("M{number} is passed through"),
                at,
                "ger does not know what this code does on your machine",
            )
            .with_note("it is written to the output as it is, in its place"),
            K::DwellMeaning { p, from, chosen } => {
                let seconds = "--from fanuc reads it in milliseconds";
                let (unit, who, other) = match from {
                    Flavour::Fanuc => (
                        "ms",
                        "Fanuc's",
                        "--from linuxcnc (or grbl, mach3) reads it in seconds",
                    ),
                    Flavour::Generic => ("s", "most controllers'", seconds),
                    Flavour::LinuxCnc => ("s", "LinuxCNC's", seconds),
                    Flavour::Grbl => ("s", "grbl's", seconds),
                    Flavour::Mach3 => ("s", "Mach3's", seconds),
                };
                note(
                    format!("dwells are read as {who}: P{p} is {p} {unit}"),
                    at,
                    format!("{who} meaning, as no --from was given: {}", chosen.reason()),
                )
                .with_help(other)
            }
            K::DwellTwice => error("G4 with both P and X", at, "give the dwell once"),
            K::DwellWithoutTime => error("G4 without a time", at, "no P or X here")
                .with_help("`G4 P500` dwells 500 ms, `G4 P0.5` or `G4 X0.5` half a second"),
            K::NegativeDwell => error("negative dwell", at, "a dwell time is positive"),
            K::G10WithoutL => error("G10 without L", at, "ger knows G10 L1, L10, L11, L2 and L20")
                .with_help("`G10 L2 P2 X… Y… Z…` sets the origin of G55"),
            K::G10WithoutP => error(
                "G10 without P",
                at,
                "P names the work offset: P1 = G54 … P6 = G59, P7 … P9 = G59.1 … G59.3",
            ),
            K::WorkOffsetNumber => error(
                "unsupported work offset number",
                at,
                "P1 (G54) to P9 (G59.3) are supported",
            ),
            K::RotatedWorkOffset => error(
                "rotated work offsets are not supported",
                at,
                "G10 R rotates the coordinate system",
            ),
            K::G10Form => error("unsupported G10 form", at, "ger knows G10 L1, L10, L11, L2 and L20"),
            K::FanucOffsetMemory => error(
                "Fanuc's G10 L10–L13 are not supported",
                at,
                "on Fanuc they write the offset memory (tool lengths and radii by H and D number)",
            )
            .with_note("ger reads G10 L10 and L11 as LinuxCNC's (a tool's length from where the tool stands), not under --from fanuc")
            .with_help("give the tool with `SetTool` or --tool-table"),
            K::ToolDataWithoutP(l) => error(
                format!("G10 L{l} without P"),
                at,
                "P names the tool: `G10 L1 P1 R3 Z50`",
            ),
            K::ToolDataAxis(axis) => error(
                format!("a tool offset along {axis} is not supported"),
                at,
                "ger keeps a tool's radius (R) and length (Z) only",
            )
            .with_help("leave the offset out, or give it to the machine's tool table"),
            K::NegativeToolRadius => error("negative tool radius", at, "G10's R is the tool's radius"),
            K::WithoutAxes(code) => error(format!("{code} without axes"), at, "give X, Y or Z"),
            K::M98WithoutP => error("M98 without P", at, "P names the subprogram: `M98 P1000`"),
            K::G65WithoutP => error("G65 without P", at, "P names the macro: `G65 P9010 A… B…`"),
            K::M98CountTwice => error(
                "M98 with both L and a repeat count in P",
                at,
                "the P word already holds the count",
            ),
            K::NoSubprogram { name, file, known } => {
                let mut d = error(format!("no subprogram {name}"), at, "called here");
                if let Some(file) = file {
                    d = d.with_note(format!(
                        "ger reads `{file}.ngc` from the --subroutines folders and the program's own folder"
                    ));
                }
                if !known.is_empty() {
                    d = d.with_note(format!("this file has {}", known.join(", ")));
                }
                d
            }
            K::CallDepth { limit, recursion } => {
                let d = error(
                    format!("subprograms nested more than {limit} deep"),
                    at,
                    "this call is too deep",
                );
                match recursion {
                    Some((name, first)) => d
                        .with_secondary(*first, format!("{name} was first called here"))
                        .with_help(format!(
                            "{name} calls itself; make sure a condition stops the recursion"
                        )),
                    None => d,
                }
            }
            K::NotWhole(what) => error(
                format!("expected {what}"),
                at,
                "a whole number from 0 is needed here",
            ),
            K::WizardLineNotPlain => error(
                "a wizard's raw line must be plain G-code",
                at,
                "from this call",
            ),
            K::WizardLineVariables => error(
                "a wizard's raw line cannot use variables",
                at,
                "from this call",
            ),
            K::PolarPlane => error(
                "polar coordinates outside the XY plane",
                at,
                "`@` and `^` are read in G17 only",
            ),
            K::PolarAndAxis(letter) => error(
                format!("`{letter}` and a polar coordinate in one block"),
                at,
                "`@` and `^` give X and Y: write one or the other",
            ),
            K::PolarMachine => error(
                "polar coordinates with G53",
                at,
                "`@` and `^` are program coordinates",
            ),
            K::PolarAtOrigin { incremental } => {
                let why = match incremental {
                    true => "under G91 a polar word steps from the current point's angle",
                    false => "a radius alone keeps the current point's angle",
                };
                error(
                    "the tool is at the program zero, where the angle is undefined",
                    at,
                    why,
                )
                .with_help("give the angle `^` (with G90)")
            }
            K::PolarPosition => error(
                "a polar word needs the current X and Y position, which is not known",
                at,
                "the radius or angle left out (or stepped from under G91) is the current point's",
            )
            .with_help("give both `@` and `^` under G90, or move to a known X and Y first"),
            K::Spline(problem) => spline_wording(*problem, at),
            K::SplineLeftover([i, j]) => warning(
                "G5 without I and J after a move that was not a G5",
                at,
                format!("its first control point is I{i} J{j} from here, left by an earlier G5 (its P Q turned round) or G87, as rs274 takes it"),
            )
            .with_help("give I and J on a G5 that does not follow another"),
            K::RoundAndChamfer => error(
                "`,R` and `,C` on one move",
                at,
                "a corner is rounded or chamfered, not both",
            ),
            K::CornerNotOnG1(what) => error(
                format!("a corner word on {what}"),
                at,
                "`,R` and `,C` round and chamfer the corner after a G1, G2 or G3 move",
            ),
            K::CornerSize(word) => error(
                format!("`{word}` must be more than 0"),
                at,
                "the radius of the round, or the length of the chamfer's legs",
            ),
            K::Thread(problem, code) => thread_wording(*problem, code, at),
            K::ThreadCycle(problem) => thread_cycle_wording(*problem, at),
        }
    }
}

fn spline_wording(problem: SplineProblem, at: Span) -> Diagnostic {
    use SplineProblem as P;
    let (message, label, help): (String, &str, &str) = match problem {
        P::IOrJ => (
            "G5 needs both I and J, or neither".into(),
            "only one of them",
            "I J is the first control point from the start; without both, a G5 after a G5 joins it smoothly",
        ),
        P::NoIJ => (
            "G5.1 needs both I and J".into(),
            "the control point from the start is missing",
            "give I and J",
        ),
        P::NoPQ => (
            "G5 needs both P and Q".into(),
            "the second control point, from the end, is missing",
            "give P and Q",
        ),
        P::Plane => (
            "splines must be in the XY plane".into(),
            "G18 or G19 is active",
            "select G17 before G5/G5.1",
        ),
        P::Axis(letter) => (
            format!("a spline may not move `{letter}`"),
            "only X and Y move on G5/G5.1",
            "move it on a line of its own",
        ),
        P::NoEnd => (
            "a spline without X or Y".into(),
            "no end point",
            "give the end point's X and Y",
        ),
        P::Again => (
            "axis words in the G5/G5.1 mode without G5 or G5.1 on the line".into(),
            "rs274 moves nowhere on these and takes the point as reached",
            "write G5 (with P and Q) or G5.1 (with I and J) on the line, or G1 for a line",
        ),
        P::Straight => (
            "G5.1 with I0 J0 is a straight line".into(),
            "LinuxCNC's planner cannot cut it (its biarcs divide by zero)",
            "write G1",
        ),
        P::Polar => (
            "a spline under G16 polar coordinates".into(),
            "not supported",
            "G15 before G5/G5.1",
        ),
        P::InverseTime => (
            "a spline under G93 (inverse time) is not supported".into(),
            "LinuxCNC would give each of its many arcs the time of the whole",
            "use G94 (feed per minute) for G5/G5.1",
        ),
        P::Diameter => (
            "a spline under G7 (diameter mode) is not supported".into(),
            "not supported",
            "G8 before G5/G5.1",
        ),
    };
    error(message, at, label).with_help(help)
}

fn thread_wording(problem: ThreadProblem, code: &str, at: Span) -> Diagnostic {
    use ThreadProblem as P;
    let (message, label, help) = match problem {
        P::NoK => (
            format!("{code} without K"),
            "K, the distance per spindle revolution, is missing".to_string(),
            format!("give K on every {code} move (the thread's pitch along the move)"),
        ),
        P::Feed => (
            format!("an F word with {code}"),
            format!("a {code} move's feed is the spindle's: K per revolution"),
            "set F on a line of its own, before or after the thread".to_string(),
        ),
        P::SpindleOff => (
            format!("spindle not turning in {code}"),
            "the move is locked to the spindle, which is off here".to_string(),
            "start the spindle (M3 or M4) before the thread".to_string(),
        ),
        P::Comp => (
            format!("{code} under cutter compensation"),
            "ger does not offset a spindle-synchronised move".to_string(),
            "turn compensation off (G40) before the thread".to_string(),
        ),
        P::NoAxes => (
            format!("{code} without an axis word"),
            "where the tap goes is missing".to_string(),
            format!("give the end point: {code} Z… K…"),
        ),
    };
    error(message, at, label).with_help(help)
}

fn thread_cycle_wording(problem: ThreadCycleProblem, at: Span) -> Diagnostic {
    use ThreadCycleProblem as P;
    let (message, label, help): (String, &str, &str) = match problem {
        P::Missing(letter) => (
            format!("{letter} word missing with G76"),
            "G76 needs P (the pitch), I, J and K",
            "P: pitch; I: the thread's peak from the drive line; J: the first cut; K: the full depth",
        ),
        P::NotWhole(letter) => (
            format!("{letter} is not a whole number"),
            "G76 counts with it",
            "H: spring passes; L: 0-3, which ends taper",
        ),
        P::IZero => ("in G76, I must not be 0".into(), "the thread's peak", "I < 0: an external thread; I > 0: internal"),
        P::JNotPositive => ("in G76, J must be greater than 0".into(), "the first cut's depth", "J > 0"),
        P::KNotAboveJ => ("in G76, K must be greater than J".into(), "the full depth", "K > J"),
        P::NoAxes => ("G76 without an axis word".into(), "where the thread ends is missing", "give the thread's end: G76 … Z…"),
        P::OtherAxis(letter) => (
            format!("G76 with {letter}"),
            "G76 moves X and Z only (rs274 refuses other axes that move)",
            "move that axis on a line of its own",
        ),
        P::SpindleOff => ("spindle not turning in G76".into(), "its passes are locked to the spindle", "start the spindle (M3 or M4) before the cycle"),
        P::Comp => (
            "G76 under cutter compensation".into(),
            "rs274 refuses the threading cycle with compensation on",
            "turn compensation off (G40) before the cycle",
        ),
        P::UnknownStart(axis) => (
            format!("G76 where {axis} is not known"),
            "the cycle starts where the tool is",
            "move the tool to the thread's start (G0 X… Z…) before G76",
        ),
        P::TooManyPasses(n) => (
            format!("G76 makes {n:.0} passes"),
            "more passes than ger expands (100,000)",
            "a larger J, or R (degression) nearer 1",
        ),
    };
    error(message, at, label).with_help(help)
}
