//! The problems a lowering pass can find, as data: a kind and the span of
//! the statement. [`LowerError::to_diagnostic`] is the one place their
//! wording lives.

use crate::diagnostic::{error, warning, Diagnostic, DiagnosticExt};
use crate::ir::{Axis, Corner, Plane, MAX_POSITION};
use crate::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub struct LowerError {
    pub kind: LowerErrorKind,
    pub span: Span,
}

/// What a G10 L10/L11 needs that only the machine knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unmeasurable {
    /// Where the tool is in Z.
    Position,
    /// The tool length offset in force (a G43 of a length ger was not given).
    LengthInForce,
    /// Compensation on in a plane with Z: the tool's Z is the comp pass's.
    CompOnZ,
    /// G59.3's origin (L11 measures from it).
    Fixture,
    /// G54's origin, set by a `G10 L20 P1` passed to the machine.
    MachineG54,
    /// A G92 of the machine's own.
    MachineG92,
    /// The work offset in force is the machine's (none selected, or one
    /// whose values ger does not know).
    MachineFrame,
}

#[derive(Clone, Debug, PartialEq)]
pub enum LowerErrorKind {
    /// `what` needs the position of `axis`, which no move has set (or a
    /// machine move at `since` made unknown).
    UnknownPosition {
        axis: Axis,
        what: &'static str,
        since: Option<Span>,
    },
    /// A move would take `axis` to `value`, beyond [`MAX_POSITION`].
    PositionOutOfRange {
        axis: Axis,
        value: f64,
    },
    /// A canned cycle ger cannot expand (the cycles pass).
    Cycle(CycleError),
    /// Compensation ger cannot compute (the comp pass).
    Comp(CompError),
    /// A corner (`,R`, `,C`) ger cannot cut (the corners pass).
    Corner(CornerError),
    /// R smaller than half the chord.
    ArcRadiusTooSmall {
        radius: f64,
        half_chord: f64,
    },
    /// A warning: R a hair under half the chord (rs274's tolerance),
    /// drawn as the half circle about the chord's middle.
    ArcRadiusShort {
        radius: f64,
        half_chord: f64,
    },
    /// An R arc whose end is its start.
    FullCircleWithR,
    /// I/J/K whose radii at start and end differ by more than 1 % and
    /// LinuxCNC's 0.0283 mm.
    ArcRadiiDiffer {
        start: f64,
        end: f64,
        /// G90.1 was on: I/J/K were the centre's coordinates.
        absolute: bool,
    },
    /// I/J/K that put the centre on the start point.
    ArcZeroRadius,
    /// An arc under G90.1 without one of the centre's two coordinates.
    AbsoluteCentreIncomplete {
        letter: char,
    },
    /// An offset changed under G91.
    OffsetsUnderIncremental {
        since: Option<Span>,
    },
    /// An offset changed under G16.
    OffsetsUnderPolar {
        since: Option<Span>,
    },
    PlaneChangeUnderPolar,
    /// The first move under G16 gives only the radius or only the angle.
    PolarIncomplete {
        plane: Plane,
    },
    /// A machine move (G28, G30, G53) under G16.
    MachineMoveUnderPolar,
    /// G53 under G91.
    MachineMoveIncremental,
    /// Warning: G43 H`tool` with no known length is passed through.
    ToolLengthUnknown {
        tool: u32,
    },
    /// G10 L10/L11 (`l`) whose length needs what only the machine knows.
    ToolLengthNotMeasurable {
        l: u32,
        unknown: Unmeasurable,
    },
    /// Warning: a work offset with unknown values is passed through.
    WorkOffsetUnknown {
        index: u8,
    },
    /// G10 L2/L20 or G92 for an axis whose offset ger cannot know.
    OffsetAxisUnknown {
        axis: Axis,
        index: u8,
    },
    /// Warning: G10 L20 where the position is not known: the machine sets
    /// the offset.
    WorkOffsetSetByMachine {
        index: u8,
    },
    /// A system ger knows selected after G54 was left to the machine (a
    /// `G10 L20 P1` passed through, at `since`): it cannot be written in
    /// G54's terms, and the machine does not have its values.
    WorkOffsetOverMachineG54 {
        index: u8,
        since: Option<Span>,
    },
    /// Warning: a system whose values a `G10 L2` gave (machine
    /// coordinates) written in G54's terms, G54 taken to be at machine
    /// zero.
    WorkOffsetFromMachineZero {
        index: u8,
    },
    /// G10 L20 at an unknown point on the active system, which is written
    /// in G54's terms, and whose other values the machine does not have.
    WorkOffsetHereFolded {
        index: u8,
    },
    /// Warning: a feed given before the program states its units (LinuxCNC
    /// runs F before G20/G21 of the same line): it is in the machine's
    /// units, whatever the output's are.
    FeedInMachineUnits,
    /// Warning: the program has no M2/M30; one is added after its last
    /// statement.
    NoProgramEnd,
    /// The program has no statement at all (blank lines and comments).
    EmptyProgram,
}

/// The cycles pass's errors.
#[derive(Clone, Debug, PartialEq)]
pub enum CycleError {
    /// G87 or G88 expanded: they need the operator or an oriented spindle.
    NeedsOperator { code: u32 },
    /// G84/G74 outside G17 (rs274 feeds to the wrong axes there).
    TappingOutsideXy { code: u32 },
    /// G73/G83 where the units are not known: the clearance is 0.254 mm.
    PeckUnits { code: u32 },
    /// More pecks in one hole than [`crate::eval::MAX_PECKS`].
    TooManyPecks,
    /// Haas's G73 with a dwell kept: no other controller reads its P.
    PeckDwellKept,
    /// Fanuc's G87 under G99: it returns to the initial level only.
    BackBoreToR,
    /// The cycles of the program expand to more than `limit` statements
    /// (the cycles pass's `MAX_EXPANDED`).
    TooLarge { limit: u64 },
}

/// The comp pass's errors.
#[derive(Clone, Debug, PartialEq)]
pub enum CompError {
    /// G41/G42 without D and no tool loaded.
    NoTool,
    /// G41/G42 D`tool` not in the tool table.
    UnknownTool { tool: u32 },
    /// The entry move is not longer than the radius.
    EntryTooShort { radius: f64 },
    /// An arc the tool is inside of, not larger than the radius.
    ArcTooSmall,
    /// A corner the tool cannot reach without cutting into the part; the
    /// held move's line.
    Gouge {
        what: &'static str,
        held: Option<Span>,
    },
    /// An inside corner right after M0/M1 under compensation: the move
    /// before it has gone out and cannot be trimmed.
    CornerAfterStop,
    /// An arc right after G40.
    ArcAfterOff { off: Span },
    /// A G53 move right after G40: rs274 leaves compensation on it, back
    /// to the programmed point in the plane, which no one line can write.
    MachineMoveAfterOff { off: Span },
    /// The program ends with compensation on (a warning: LinuxCNC turns
    /// it off there).
    StillOn { since: Span },
    /// A near-tangent corner into an arc makes rs274 start the arc off its
    /// circle: radii differ.
    Spiral { start: f64, end: f64 },
}

/// The corners pass's errors, each at the line of the move with the
/// corner word; `next`, the line of the statement after it that decides.
#[derive(Clone, Debug, PartialEq)]
pub enum CornerError {
    /// What comes after the cornered move is not a G1, G2 or G3 (what it
    /// is); `None`: the program ends.
    NextNotG1 {
        what: &'static str,
        next: Option<Span>,
    },
    /// The cornered move (`next` is `None`) or the move after it leaves
    /// the plane.
    OutOfPlane { next: Option<Span> },
    /// The round or chamfer takes `need` of a move only `room` long.
    TooShort { need: f64, room: f64, next: Span },
    /// The two moves are in line: no corner to cut.
    InLine { next: Span },
    /// A line and an arc, or two arcs, meet tangent: no corner to cut.
    Tangent { next: Span },
    /// No round of that radius touches both moves; no point of an arc is
    /// the chamfer's length from the corner.
    NoCut { corner: Corner, next: Span },
    /// The cornered move (`next` is `None`) or the move after it is an arc
    /// of more than one turn.
    MultiTurn { next: Option<Span> },
}

impl From<CornerError> for LowerErrorKind {
    fn from(e: CornerError) -> LowerErrorKind {
        LowerErrorKind::Corner(e)
    }
}

impl From<CycleError> for LowerErrorKind {
    fn from(e: CycleError) -> LowerErrorKind {
        LowerErrorKind::Cycle(e)
    }
}

impl From<CompError> for LowerErrorKind {
    fn from(e: CompError) -> LowerErrorKind {
        LowerErrorKind::Comp(e)
    }
}

impl LowerError {
    pub fn new(kind: impl Into<LowerErrorKind>, span: Span) -> LowerError {
        LowerError {
            kind: kind.into(),
            span,
        }
    }

    pub fn is_error(&self) -> bool {
        !matches!(
            self.kind,
            LowerErrorKind::ToolLengthUnknown { .. }
                | LowerErrorKind::WorkOffsetUnknown { .. }
                | LowerErrorKind::NoProgramEnd
                | LowerErrorKind::FeedInMachineUnits
                | LowerErrorKind::ArcRadiusShort { .. }
                | LowerErrorKind::WorkOffsetSetByMachine { .. }
                | LowerErrorKind::WorkOffsetFromMachineZero { .. }
                | LowerErrorKind::Comp(CompError::StillOn { .. })
        )
    }

    pub fn to_diagnostic(&self) -> Diagnostic {
        use LowerErrorKind::*;
        let span = self.span;
        match &self.kind {
            Cycle(e) => cycle_diagnostic(e, span),
            Comp(e) => comp_diagnostic(e, span),
            Corner(e) => corner_diagnostic(e, span),
            UnknownPosition { axis, what, since } => {
                let letter = axis.letter() as char;
                let d = error(
                    format!("{what} needs the current {letter} position, which is not known"),
                    span,
                    match since {
                        None => format!("no move has set {letter} yet"),
                        Some(_) => format!("no move has set {letter} since ger lost it"),
                    },
                )
                .with_help(format!("move to an absolute {letter} position first"));
                match since {
                    Some(at) => d.with_secondary(*at, "the position is not known after this"),
                    None => d,
                }
            }
            PositionOutOfRange { axis, value } => {
                let letter = axis.letter() as char;
                error(
                    format!("the move takes {letter} out of range"),
                    span,
                    format!("{letter} would be {value:e}"),
                )
                .with_note(format!(
                    "machine positions must be between -{MAX_POSITION} and {MAX_POSITION}"
                ))
            }
            ArcRadiusTooSmall { radius, half_chord } => error(
                "arc radius too small",
                span,
                format!(
                    "R{radius} cannot reach an end point {} away",
                    fmt(2.0 * half_chord)
                ),
            )
            .with_note(format!(
                "the radius must be at least half the distance: {}",
                fmt(*half_chord)
            )),
            ArcRadiusShort { radius, half_chord } => warning(
                "arc radius a hair short of half the chord",
                span,
                format!(
                    "R{radius} is {} under half of the chord, {}",
                    fmt(half_chord - radius),
                    fmt(*half_chord)
                ),
            )
            .with_note(
                "drawn as the half circle about the chord's middle, as Mach3 and Fanuc draw it (rs274 refuses it); \
                 the output gives its centre (I/J), so any controller draws the same (the first such arc)",
            ),
            FullCircleWithR => error(
                "an R arc cannot be a full circle",
                span,
                "the end point is the start point",
            )
            .with_help("give a full circle's centre with I/J/K"),
            ArcRadiiDiffer {
                start,
                end,
                absolute,
            } => error(
                "arc end is not on the circle",
                span,
                format!("radius {} at the start, {} at the end", fmt(*start), fmt(*end)),
            )
            .with_note(if *absolute {
                "the two radii may differ by at most 1% or 0.0283 mm; check the centre (G90.1 is on: I/J/K are its coordinates)"
            } else {
                "the two radii may differ by at most 1% or 0.0283 mm; check the centre (I/J/K are relative to the start)"
            }),
            ArcZeroRadius => error("arc with zero radius", span, "the centre is the start point"),
            AbsoluteCentreIncomplete { letter } => error(
                format!("{letter} word missing in absolute centre arc"),
                span,
                "G90.1 is on: I/J/K are the centre's coordinates, both needed",
            )
            .with_help("give both of the plane's centre words, or G91.1 for centres relative to the start"),
            OffsetsUnderIncremental { since } => {
                let d = error(
                    "offsets changed under G91",
                    span,
                    "incremental mode is on here",
                )
                .with_help("switch to G90 before changing offsets");
                match since {
                    Some(at) => d.with_secondary(*at, "G91 from here"),
                    None => d,
                }
            }
            OffsetsUnderPolar { since } => {
                let d = error(
                    "offsets changed under G16",
                    span,
                    "polar coordinates are on here",
                )
                .with_help("cancel polar coordinates with G15 before changing offsets");
                match since {
                    Some(at) => d.with_secondary(*at, "G16 is on from here"),
                    None => d,
                }
            }
            PlaneChangeUnderPolar => error(
                "plane changed under G16",
                span,
                "polar coordinates are on",
            )
            .with_help("cancel polar coordinates with G15 first"),
            PolarIncomplete { plane } => error(
                "polar move without radius and angle",
                span,
                "the first move under G16 needs both",
            )
            .with_note(match plane {
                Plane::XY => "in G17 the X word is the radius and Y the angle (degrees from +X)",
                Plane::ZX => "in G18 the Z word is the radius and X the angle (degrees from +Z)",
                Plane::YZ => "in G19 the Y word is the radius and Z the angle (degrees from +Y)",
            }),
            MachineMoveUnderPolar => error(
                "a machine move under G16",
                span,
                "polar coordinates are on here",
            )
            .with_help("cancel polar coordinates with G15 first"),
            MachineMoveIncremental => error(
                "G53 under G91",
                span,
                "machine coordinates are always absolute",
            )
            .with_help("switch to G90 first"),
            ToolLengthUnknown { tool } => warning(
                format!("tool {tool}'s length is not known: the length offset is passed through"),
                span,
                "the machine applies its own tool table here",
            )
            .with_help(format!(
                "to fold it into the coordinates, give `SetTool {tool} diameter length` or --tool-table"
            )),
            ToolLengthNotMeasurable { l, unknown } => tool_length_not_measurable(*l, *unknown, span),
            WorkOffsetSetByMachine { index } => warning(
                format!(
                    "G10 L20 sets {} where the tool is, which ger does not know: passed through",
                    work_offset_name(*index)
                ),
                span,
                "the machine sets this offset",
            )
            .with_note("coordinates after it are in that offset, as the machine sets it"),
            WorkOffsetFromMachineZero { index } => warning(
                format!(
                    "{}'s G10 L2 values are folded into the coordinates as if the machine's G54 were at machine zero",
                    work_offset_name(*index)
                ),
                span,
                "G10 L2 gives machine coordinates; ger does not know where the machine's G54 is",
            )
            .with_note("the output moves as the program does only where the machine's G54 is at machine zero (as in a fresh LinuxCNC parameter file)")
            .with_help("set G54 with G10 L2 P1 before the program selects a system (as CAM posts do): it then goes to the machine, and every system is measured from it"),
            FeedInMachineUnits => warning(
                "this feed comes before the program states its units",
                span,
                "in the machine's units, which ger does not know",
            )
            .with_note("LinuxCNC sets F before G20/G21 of the same line: ger writes this F on a line of its own before the G20/G21, so it stays in the machine's units on every target")
            .with_help("put G20/G21 on a line before the first F, or pass --units"),
            NoProgramEnd => warning(
                "the program has no end (M2 or M30)",
                span,
                "its last statement",
            )
            .with_note("the output ends with a program end: a controller needs one to stop the spindle and reset"),
            EmptyProgram => error(
                "nothing to compile: the program has no statement",
                span,
                "the file holds only blank lines",
            )
            .with_help("write the program's lines, e.g. `G21 G90`, the moves, then `M30`"),
            WorkOffsetUnknown { index } => warning(
                format!(
                    "{} has no known values: passed through to the machine",
                    work_offset_name(*index)
                ),
                span,
                "coordinates after this are in the machine's own offsets",
            )
            .with_help({
                // `SetOffset` sets G55 … G59 only.
                let set_offset = match index {
                    2..=6 => format!("`SetOffset {}` or ", 53 + index),
                    _ => String::new(),
                };
                format!("to fold it into the coordinates, give its X, Y and Z with {set_offset}G10 L2 P{index}")
            }),
            WorkOffsetHereFolded { index } => {
                let name = work_offset_name(*index);
                error(
                    format!("G10 L20 sets {name} where the tool is, which ger does not know"),
                    span,
                    format!("{name} is written in G54's terms here, and the machine does not have its other values"),
                )
                .with_help(format!("move to a known point first (an absolute move on each axis it sets), or give {name}'s values with G10 L2 before the program selects a system, so that they go to the machine"))
            }
            WorkOffsetOverMachineG54 { index, since } => {
                let d = error(
                    format!(
                        "{} is known, but G54 is now the machine's",
                        work_offset_name(*index)
                    ),
                    span,
                    "ger cannot write this system in G54's terms",
                )
                .with_help("set G54 with G10 L2 P1 (its values, not where the tool is), or give this system's G10 L2 before the program selects a system, so that it goes to the machine");
                match since {
                    Some(at) => d.with_secondary(*at, "G54 was set here, by the machine"),
                    None => d,
                }
            }
            OffsetAxisUnknown { axis, index } => error(
                format!(
                    "the {} offset of {} is not known",
                    axis.letter() as char,
                    work_offset_name(*index)
                ),
                span,
                "this needs it",
            )
            .with_help("set the offset with G10 L2 or `SetOffset` first"),
        }
    }
}

/// `G54` … `G59`, `G59.1` … `G59.3` for the indices 1..=9.
pub fn work_offset_name(index: u8) -> String {
    crate::ir::work_offset_code(index).map_or_else(|| format!("work offset {index}"), String::from)
}

fn fmt(v: f64) -> String {
    let mut s = String::new();
    crate::emit::number::push_fixed(&mut s, v, 4);
    s
}

/// The wording of the cycles pass's errors.
fn cycle_diagnostic(e: &CycleError, span: Span) -> Diagnostic {
    use CycleError::*;
    match *e {
        NeedsOperator { code: 87 } => error(
            "G87 cannot be expanded",
            span,
            "back boring needs oriented spindle stops (M19), which the output cannot express",
        )
        .with_help("keep the cycle for a controller that has it (`--cycles keep`)"),
        BackBoreToR => error(
            "Fanuc's G87 under G99",
            span,
            "back boring returns to the initial level only: R is below the part",
        )
        .with_help("write G98 before the cycle"),
        PeckDwellKept => error(
            "G73 with a dwell cannot be kept",
            span,
            "only Haas reads a dwell P on G73",
        )
        .with_help("leave out `--cycles keep` to have it expanded to moves and a dwell"),
        NeedsOperator { code } => error(
            format!("G{code} cannot be expanded"),
            span,
            "the operator takes the tool out by hand: where it is after the stop is not known",
        )
        .with_help(
            "use G86 or G89, or keep the cycle for a controller that has it (`--cycles keep`)",
        ),
        TappingOutsideXy { code } => error(
            format!("G{code} tapping outside the XY plane (G17)"),
            span,
            "LinuxCNC feeds these taps to the wrong axes; ger does not pick a meaning",
        )
        .with_help("tap in G17, or write the moves out"),
        PeckUnits { code } => error(
            format!("G{code} in unknown units"),
            span,
            "the peck clearance is 0.254 mm (0.010 in): it needs the units",
        )
        .with_help("state G20 or G21 in the program, or pass --units"),
        TooManyPecks => error(
            format!("more than {} pecks in one hole", crate::eval::MAX_PECKS),
            span,
            "Q is very small for this depth",
        ),
        TooLarge { limit } => error(
            format!("the canned cycles make more than {limit} moves"),
            span,
            "the limit was reached here",
        )
        .with_help("check the repeat counts (L, K) and the peck depths (Q)"),
    }
}

/// The wording of the comp pass's errors.
fn corner_diagnostic(e: &CornerError, span: Span) -> Diagnostic {
    const HELP: &str =
        "`,R` and `,C` join a G1, G2 or G3 to the G1, G2 or G3 right after it, in the plane (G17, G18, G19)";
    let (d, next) = match e {
        CornerError::NextNotG1 { what, next } => (
            error(
                "a corner word needs a G1, G2 or G3 move after it",
                span,
                format!("{what} comes next"),
            ),
            *next,
        ),
        CornerError::OutOfPlane { next } => (
            error(
                "a corner word on a move that leaves the plane",
                span,
                match next {
                    None => "this move",
                    Some(_) => "the move after this one",
                }
                .to_string()
                    + " moves along an axis outside the plane",
            ),
            *next,
        ),
        CornerError::TooShort { need, room, next } => (
            error(
                "a move too short for its corner",
                span,
                format!(
                    "the corner takes {} of a move {} long",
                    fmt_len(*need),
                    fmt_len(*room)
                ),
            ),
            Some(*next),
        ),
        CornerError::InLine { next } => (
            error(
                "a corner word between two moves in line",
                span,
                "the next move goes on straight (or straight back): there is no corner",
            ),
            Some(*next),
        ),
        CornerError::Tangent { next } => (
            error(
                "a corner word between two moves that meet tangent",
                span,
                "the next move goes on in the same direction (or straight back): there is no corner",
            ),
            Some(*next),
        ),
        CornerError::NoCut { corner, next } => (
            error(
                "a corner that cannot be cut",
                span,
                match corner {
                    Corner::Round(r) => {
                        format!("no arc of radius {} touches both moves", fmt_len(*r))
                    }
                    Corner::Chamfer(c) => {
                        format!("no point of the arc is {} from the corner", fmt_len(*c))
                    }
                },
            ),
            Some(*next),
        ),
        CornerError::MultiTurn { next } => (
            error(
                "a corner word next to an arc of more than one turn",
                span,
                match next {
                    None => "this arc",
                    Some(_) => "the arc after this move",
                }
                .to_string()
                    + " turns more than once (P): ger cuts corners on arcs of one turn",
            ),
            *next,
        ),
    };
    let d = d.with_help(HELP);
    match next {
        Some(at) if at != span => d.with_secondary(at, "what comes next"),
        _ => d,
    }
}

/// A length in a message: at most 6 decimals, no trailing zeros.
fn fmt_len(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn comp_diagnostic(e: &CompError, span: Span) -> Diagnostic {
    use CompError::*;
    match e {
            NoTool => error(
                "cutter compensation without a tool",
                span,
                "no tool number here (no D, or D0: the loaded tool) and no tool loaded (M6)",
            )
            .with_help("name the tool (`G41 D1`) or load it first (`T1 M6`)"),
            UnknownTool { tool } => error(
                format!("tool {tool} is not in the tool table"),
                span,
                "compensation needs its diameter",
            )
            .with_help(format!(
                "give it with `SetTool {tool} diameter` or --tool-table (D names a tool, as in LinuxCNC, not a radius register), or leave compensation to the controller's own table: --comp keep --target fanuc or linuxcnc"
            )),
            EntryTooShort { radius } => error(
                "the move that starts compensation is too short",
                span,
                format!("it must be longer than the tool radius ({radius})"),
            )
            .with_help("start compensation farther from the part, on a move in the plane"),
            ArcTooSmall => error(
                "an inside arc not larger than the tool radius",
                span,
                "the tool cannot follow this arc",
            )
            .with_help("use a smaller tool or a larger radius"),
            Gouge { what, held } => {
                let d = error(
                    format!("the tool cannot reach this corner without gouging ({what})"),
                    span,
                    "the tool radius does not fit in this inside corner",
                )
                .with_help("use a smaller tool, or lengthen the short move");
                match held {
                    Some(at) if *at != span => d.with_secondary(*at, "the move before it"),
                    _ => d,
                }
            }
            CornerAfterStop => error(
                "an inside corner right after a stop under compensation",
                span,
                "the move before the M0/M1 has been sent and cannot be trimmed",
            )
            .with_help("stop before the profile or after it, or on an outside corner (LinuxCNC gouges here)"),
            ArcAfterOff { off } => error(
                "an arc right after G40",
                span,
                "the move after compensation ends must be straight",
            )
            .with_secondary(*off, "compensation ended here"),
            MachineMoveAfterOff { off } => error(
                "a G53 move right after G40",
                span,
                "LinuxCNC leaves compensation on this move, back to the programmed point",
            )
            .with_secondary(*off, "compensation ended here")
            .with_note("one line cannot move in machine coordinates and to a program point")
            .with_help("give a straight move after G40 first"),
            StillOn { since } => warning(
                "the program ends with cutter compensation on",
                span,
                "no G40 before the end",
            )
            .with_secondary(*since, "compensation turned on here")
            .with_note("the last move ends at its offset point and the tool stays there, as LinuxCNC turns compensation off at the end")
            .with_help("end the profile with a G40 move"),
            Spiral { start, end } => error(
                "a near-tangent corner into this arc",
                span,
                format!(
                    "compensated, the arc would start {start:.4} and end {end:.4} from its centre"
                ),
            )
            .with_help("LinuxCNC makes a spiral here; make the corner sharper or tangent"),
        }
}

/// G10 L10/L11 (`l`) that needs `unknown`.
fn tool_length_not_measurable(l: u32, unknown: Unmeasurable, span: Span) -> Diagnostic {
    let needs = match unknown {
        Unmeasurable::Position => "where the tool is in Z, which no absolute Z move has set here (or a machine move, a cycle or an offset left to the machine made unknown)",
        Unmeasurable::LengthInForce => "the tool length offset in force, a G43 of a length ger was not given",
        Unmeasurable::CompOnZ => "the tool's Z under compensation in a plane with Z, which the compensated path decides",
        Unmeasurable::Fixture => "G59.3's origin (`G10 L2 P9` sets it), which the program has not given",
        Unmeasurable::MachineG54 => "G54's origin, set by a `G10 L20 P1` left to the machine",
        Unmeasurable::MachineG92 => "the machine position, under a G92 left to the machine",
        Unmeasurable::MachineFrame => "the machine position, in a work offset whose values are the machine's",
    };
    error(
        format!("G10 L{l} sets a tool's length from what only the machine knows here"),
        span,
        format!("it needs {needs}"),
    )
    .with_help("give the length itself with `G10 L1 P… Z…`, `SetTool` or --tool-table")
}
