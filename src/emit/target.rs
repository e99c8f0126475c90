//! The output flavours (`--target`, SPEC §6): what each controller family
//! wants around and inside the program. Everything a target changes is a
//! method here, so a new target is one variant and its answers. It
//! decides what a controller runs, never how a pass lowers: a code a
//! target cannot run is refused here, at its line, and not written.

use crate::diagnostic::{error, Diagnostic, DiagnosticExt, Wording};
use crate::ir::{self, Axis, CompRadius, Op, Passthrough};
use crate::source::Span;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Target {
    #[default]
    Generic,
    Fanuc,
    Grbl,
    LinuxCnc,
}

impl Target {
    /// Every target, as `--target` names them.
    pub const ALL: [(Target, &'static str); 4] = [
        (Target::Generic, "generic"),
        (Target::Fanuc, "fanuc"),
        (Target::Grbl, "grbl"),
        (Target::LinuxCnc, "linuxcnc"),
    ];

    /// Lines before the program: Fanuc's tape start and program number.
    pub fn prologue(self, program_number: u32) -> Option<String> {
        match self {
            Target::Fanuc => Some(format!("%\nO{:04}\n", program_number % 10_000)),
            Target::Generic | Target::Grbl | Target::LinuxCnc => None,
        }
    }

    /// Lines after the program end: Fanuc's tape end.
    pub fn epilogue(self) -> Option<&'static str> {
        match self {
            Target::Fanuc => Some("%\n"),
            Target::Generic | Target::Grbl | Target::LinuxCnc => None,
        }
    }

    /// Does the controller take N words? GRBL ignores them at best.
    pub fn takes_line_numbers(self) -> bool {
        !matches!(self, Target::Grbl)
    }

    /// The program end code.
    pub fn program_end(self) -> &'static str {
        match self {
            Target::Grbl => "M2",
            Target::Generic | Target::Fanuc | Target::LinuxCnc => "M30",
        }
    }

    /// The letter of G4's dwell time in seconds (Fanuc's P is in ms).
    pub fn dwell_letter(self) -> u8 {
        match self {
            Target::Fanuc => b'X',
            Target::Generic | Target::Grbl | Target::LinuxCnc => b'P',
        }
    }

    /// The longest dwell the controller counts, in seconds: grbl's
    /// `delay_sec` counts 50 ms steps (`DWELL_TIME_STEP`) in 16 bits.
    pub fn longest_dwell(self) -> f64 {
        match self {
            Target::Grbl => f64::from(u16::MAX) * 0.050,
            Target::Generic | Target::Fanuc | Target::LinuxCnc => f64::INFINITY,
        }
    }

    /// What M6 becomes: GRBL has no tool changer, so it stops and the
    /// comment names the tool for the operator.
    pub fn tool_change(self, selected: Option<u32>) -> String {
        match (self, selected) {
            (Target::Grbl, Some(t)) => format!("M0 (change to tool {t})"),
            (Target::Grbl, None) => "M0 (tool change)".to_string(),
            (Target::Generic | Target::Fanuc | Target::LinuxCnc, _) => "M6".to_string(),
        }
    }

    /// Whether path control `pc` is written otherwise than the program
    /// gave it, or not at all: grbl has none (it blends every corner
    /// within its junction deviation); Fanuc's G61 is an exact stop and
    /// its G64 takes no tolerance.
    pub fn loses(self, pc: &ir::PathControl) -> bool {
        match (self, pc) {
            (Target::Grbl, _) => true,
            (Target::Fanuc, ir::PathControl::ExactStop) => true,
            (Target::Fanuc, ir::PathControl::Blend { tolerance, naive }) => {
                tolerance.is_some() || naive.is_some()
            }
            (Target::Fanuc, ir::PathControl::ExactPath) => false,
            (Target::Generic | Target::LinuxCnc, _) => false,
        }
    }

    /// Where `op` runs in a block, when it shares the line of its source
    /// line's move: its place in rs274's order of execution (SPEC §2.2),
    /// every one before the motion; `None` where it keeps a line of its
    /// own. Fanuc gives an M, S or T code written with a move to the
    /// machine with the move or after it (the machine builder's choice),
    /// not before: they keep their lines there. Grbl's M6 is a stop.
    pub fn before_motion(self, op: &Op) -> Option<u8> {
        let (fanuc, grbl) = (self == Target::Fanuc, self == Target::Grbl);
        match op {
            Op::Speed(_) if !fanuc => Some(4),
            Op::SelectTool(_) if !fanuc && !grbl => Some(5),
            Op::ChangeTool if !fanuc && !grbl => Some(6),
            Op::Spindle(_) if !fanuc => Some(7),
            Op::Coolant(_) if !fanuc => Some(8),
            Op::Plane(_) => Some(11),
            Op::Comp { .. } | Op::CompOff => Some(13),
            Op::ToolLength { .. } | Op::CancelToolLength => Some(14),
            Op::SelectWorkOffset(_) => Some(15),
            Op::PathControl(_) => Some(16),
            _ => None,
        }
    }

    /// The controller's name in messages.
    pub fn controller(self) -> &'static str {
        match self {
            Target::Generic => "a generic controller",
            Target::Fanuc => "Fanuc",
            Target::Grbl => "grbl 1.1",
            Target::LinuxCnc => "LinuxCNC",
        }
    }

    /// Whether the controller runs `op` as ger would write it; `None` when
    /// it does, else the code and why not (SPEC §6: each target's list).
    /// Generic runs everything SPEC §6 allows; what the passes already
    /// folded never gets here.
    pub fn cannot_run(self, op: &Op) -> Option<Unrunnable> {
        let (code, why) = match self {
            Target::Generic => return None,
            Target::Grbl => grbl_cannot_run(op)?,
            Target::LinuxCnc => linuxcnc_cannot_run(op)?,
            Target::Fanuc => fanuc_cannot_run(op)?,
        };
        Some(Unrunnable {
            target: self,
            code,
            why,
        })
    }
}

/// A statement a target's controller cannot run: the code as ger would
/// write it, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Unrunnable {
    pub target: Target,
    pub code: String,
    pub why: Why,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Why {
    /// G43/G44 H on grbl, which keeps no tool table.
    NoToolTable,
    /// A code the controller does not have at all.
    NoSuchCode,
    /// An axis grbl does not have (it drives X, Y and Z).
    NoSuchAxis,
    /// G2/G3 with P turns.
    Turns,
    /// G59.1–G59.3, or a G10 P beyond G59 (Fanuc: P0 is its external offset).
    WorkOffset,
    /// G10 L20 on Fanuc, where it sets the extra systems (G54.1 P).
    FanucL20,
    /// G41/G42 without D on Fanuc, which ties no radius to the tool.
    CompWithoutD,
    /// An M code the controller does not know.
    MCode,
    /// A controller command (grbl's `$H`) for another controller.
    Command,
    /// G96 D on Fanuc, whose limit is a G50 (lathe) or G92 (mill) S.
    FanucMaxRpm,
    /// G10 L1 on Fanuc, whose tool data are offset registers (G10 L10–L13).
    FanucToolData,
    /// G33, a feed locked to the spindle, which grbl does not have.
    NoThread,
    /// G33 on Fanuc, whose thread cutting (G32/G33 F) takes the lead
    /// along the long axis, not along the path as LinuxCNC's K.
    FanucThread,
    /// G33.1, which Fanuc writes as a tapping cycle.
    FanucRigidTap,
}

impl Wording for Unrunnable {
    fn wording(&self, at: Span) -> Diagnostic {
        let (label, help) = match self.why {
            Why::NoToolTable => (
                "grbl keeps no tool table (it has only `G43.1 Z`)",
                "give the tool's length (`SetTool n diameter length` or --tool-table) and ger folds it into Z",
            ),
            Why::NoSuchCode => (
                "the controller has no such code",
                "leave it out, or compile for a target that has it",
            ),
            Why::NoSuchAxis => (
                "grbl drives X, Y and Z only",
                "compile for a target with that axis",
            ),
            Why::Turns => (
                "the controller has no P (turns) on G2/G3",
                "write the arc as lines (`--arcs lines`), or one turn per block",
            ),
            Why::WorkOffset => (
                "the controller has no such work coordinate system",
                "use G54–G59 (P1–P6)",
            ),
            Why::FanucToolData => (
                "Fanuc's tool data are offset registers (G10 L10–L13 P register R value), not LinuxCNC's G10 L1 tool entry",
                "give the tool with `SetTool` or --tool-table so that ger folds its length and radius, or compile for linuxcnc or generic",
            ),
            Why::FanucL20 => (
                "Fanuc's G10 L20 sets its extra systems (G54.1 P), not G54–G59",
                "give the offset's values with G10 L2",
            ),
            Why::CompWithoutD => (
                "Fanuc's compensation takes its radius from a D register",
                "write D with the tool's offset register",
            ),
            Why::MCode => (
                "the controller does not know this M code",
                "leave it out, or compile for a target whose controller has it (--target generic writes it as it is)",
            ),
            Why::Command => (
                "a grbl command, not G-code",
                "leave it out, or compile for grbl (--target grbl)",
            ),
            Why::NoThread => (
                "grbl has no spindle-synchronised motion",
                "cut the thread with a thread mill (helical G2/G3), or compile for linuxcnc",
            ),
            Why::FanucThread => (
                "Fanuc's thread cutting takes F, the lead along the long axis; LinuxCNC's K is along the path",
                "compile for linuxcnc (or generic), or write the thread in Fanuc's own terms",
            ),
            Why::FanucRigidTap => (
                "Fanuc taps rigidly with a cycle (M29 S…, G84 … F), not G33.1",
                "compile for linuxcnc (or generic), or write the tap as M29 S… G84 … R… F…",
            ),
            Why::FanucMaxRpm => (
                "Fanuc's G96 takes no D: its spindle limit is a G50 (lathe) or G92 (mill) S",
                "leave D out and set the machine's limit, or compile for a target that has G96 D",
            ),
        };
        error(
            format!("`{}` cannot run on {}", self.code, self.target.controller()),
            at,
            label,
        )
        .with_help(help)
    }
}

/// The code that names `op` in a message: its first words as printed
/// (`G43 H1`, `G10 L2`), an M code's number alone.
fn code_of(op: &Op) -> String {
    if let Op::Move(ir::Move { lead: Some(_), .. }) = op {
        return "G33".into();
    }
    if let Op::RigidTap(_) = op {
        return "G33.1".into();
    }
    if let Op::Move(ir::Move {
        motion,
        arc: Some(arc),
        ..
    }) = op
    {
        return format!("{} P{}", super::printer::motion_code(*motion), arc.turns);
    }
    let mut p = super::printer::Printer::new(
        super::Numbering::None,
        Target::Generic,
        Some(3),
        None,
        0,
        64,
    );
    p.op(op);
    let text = String::from_utf8_lossy(&p.out).into_owned();
    let words = match op {
        Op::Passthrough(Passthrough::MCode { .. }) => 1,
        _ => 2,
    };
    text.split(' ').take(words).collect::<Vec<_>>().join(" ")
}

/// The axes of a move grbl does not drive.
fn not_xyz(axes: &ir::Axes) -> Option<Axis> {
    axes.iter()
        .map(|(axis, _)| axis)
        .find(|a| !matches!(a, Axis::X | Axis::Y | Axis::Z))
}

/// G2/G3 with more than one turn.
fn turns(op: &Op) -> bool {
    matches!(op, Op::Move(ir::Move { arc: Some(a), motion, .. }) if motion.is_arc() && a.turns > 1)
}

/// grbl 1.1's list: G0–G4, G10 L2/L20 P0–P6, G17–G21, G28, G30, G40,
/// G43.1, G49, G53–G59, G80, G90, G91, G91.1, G92, G92.1, G93, G94; M0–M9
/// but M6, M30, M56; axes X, Y, Z.
fn grbl_cannot_run(op: &Op) -> Option<(String, Why)> {
    let why = match op {
        Op::Move(m) | Op::IncrementalMove(m) if m.lead.is_some() => Why::NoThread,
        Op::RigidTap(_) => Why::NoThread,
        Op::Move(m) | Op::MachineMove(m) | Op::IncrementalMove(m) => match not_xyz(&m.to) {
            Some(axis) => return Some(((axis.letter() as char).to_string(), Why::NoSuchAxis)),
            None if turns(op) => Why::Turns,
            None => return None,
        },
        Op::Home { via, .. } => {
            let axis = not_xyz(via)?;
            return Some(((axis.letter() as char).to_string(), Why::NoSuchAxis));
        }
        Op::SelectWorkOffset(i) if *i > 6 => Why::WorkOffset,
        Op::SetWorkOffset { index, .. } | Op::SetWorkOffsetHere { index, .. } if *index > 6 => {
            Why::WorkOffset
        }
        Op::ToolLength { .. } => Why::NoToolTable,
        Op::ArcCenters(ir::Distance::Absolute)
        | Op::SpindleMode(_)
        | Op::LocalOffset(_)
        | Op::Polar(_)
        | Op::DiameterMode(_)
        | Op::ReturnLevel(_)
        | Op::Cycle(_)
        | Op::Spline(_)
        | Op::Comp { .. } => Why::NoSuchCode,
        Op::Passthrough(Passthrough::MCode { number: 56, words }) if words.is_empty() => {
            return None
        }
        Op::Passthrough(Passthrough::MCode { .. }) => Why::MCode,
        _ => return None,
    };
    Some((code_of(op), why))
}

/// LinuxCNC runs all of ger's codes but G44 and G15/G16 (its polar
/// words are `@` and `^`); its M codes are M0–M9, M19, M30, M48–M53,
/// M60–M68, M70–M73 and the user's M100–M199.
fn linuxcnc_cannot_run(op: &Op) -> Option<(String, Why)> {
    let why = match op {
        Op::ToolLength { negative: true, .. } | Op::Polar(_) => Why::NoSuchCode,
        Op::Passthrough(Passthrough::MCode { number, .. }) if !matches!(number, 0..=9 | 19 | 30 | 48..=53 | 60..=68 | 70..=73 | 100..=199) => {
            Why::MCode
        }
        Op::Passthrough(Passthrough::Line(_)) => Why::Command,
        _ => return None,
    };
    Some((code_of(op), why))
}

/// Fanuc (0i/30i milling) has no G90.1/G91.1 (centres are incremental),
/// no G7/G8, G41.1/G42.1 or G92.1 as LinuxCNC means it, no G59.1–G59.3
/// (its extra systems are G54.1 P), its G10 L20 sets those, and G10 L2 P0
/// is its external offset; G2/G3 take no P.
fn fanuc_cannot_run(op: &Op) -> Option<(String, Why)> {
    let why = match op {
        _ if turns(op) => Why::Turns,
        Op::Move(m) | Op::IncrementalMove(m) if m.lead.is_some() => Why::FanucThread,
        Op::RigidTap(_) => Why::FanucRigidTap,
        Op::SelectWorkOffset(i) if *i > 6 => Why::WorkOffset,
        Op::SetWorkOffset { index, .. } if *index == 0 || *index > 6 => Why::WorkOffset,
        Op::SetWorkOffsetHere { .. } => Why::FanucL20,
        Op::SetToolData(_) => Why::FanucToolData,
        Op::ArcCenters(_) | Op::DiameterMode(_) | Op::CancelPosition | Op::Spline(_) => {
            Why::NoSuchCode
        }
        Op::Comp {
            radius: CompRadius::Diameter(_),
            ..
        } => Why::NoSuchCode,
        Op::Comp {
            radius: CompRadius::LoadedTool,
            ..
        } => Why::CompWithoutD,
        Op::Passthrough(Passthrough::Line(_)) => Why::Command,
        Op::SpindleMode(ir::SpindleMode::SurfaceSpeed {
            max_rpm: Some(_), ..
        }) => Why::FanucMaxRpm,
        _ => return None,
    };
    Some((code_of(op), why))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Axes, Motion};

    fn axes(pairs: &[(Axis, f64)]) -> Axes {
        let mut a = Axes::NONE;
        for &(axis, v) in pairs {
            a.set(axis, v);
        }
        a
    }

    fn line(motion: Motion, to: Axes, turns: u32) -> ir::Move {
        let arc = motion.is_arc().then_some(ir::Arc {
            geometry: ir::ArcGeometry::Center([Some(1.0), Some(0.0), None]),
            turns,
        });
        ir::Move {
            motion,
            to,
            arc,
            corner: None,
            lead: None,
        }
    }

    /// One statement of every kind ger can write, and which of generic,
    /// grbl, LinuxCNC and Fanuc run it (`g`, `b`, `l`, `f` in the string).
    fn every_code() -> Vec<(Op, &'static str)> {
        let xy = axes(&[(Axis::X, 1.0), (Axis::Y, 2.0)]);
        let xa = axes(&[(Axis::X, 1.0), (Axis::A, 2.0)]);
        let cycle = |kind| {
            Op::Cycle(Box::new(ir::Cycle {
                kind,
                at: axes(&[(Axis::X, 1.0), (Axis::Z, -1.0)]),
                r: 1.0,
                q: None,
                dwell: None,
                repeats: 1,
                ijk: [None; 3],
                starts_run: true,
                pecks: None,
                kept: None,
            }))
        };
        let comp = |radius| Op::Comp {
            side: ir::Side::Left,
            radius,
        };
        let m = |number| {
            Op::Passthrough(Passthrough::MCode {
                number,
                words: Vec::new(),
            })
        };
        let home = Op::Home {
            home: ir::Home::G28,
            via: xy,
            incremental: true,
        };
        let g10 = |index| Op::SetWorkOffset { index, origin: xy };
        let tool_data = Op::SetToolData(ir::ToolData {
            tool: 1,
            radius: Some(3.0),
            length: Some(25.0),
            measured: ir::Measured::Given,
            lathe: [None; 3],
        });
        let surface = |max_rpm| {
            Op::SpindleMode(ir::SpindleMode::SurfaceSpeed {
                speed: 100.0,
                max_rpm,
            })
        };
        let length = |negative| Op::ToolLength {
            tool: Some(1),
            negative,
        };
        let thread = ir::Move {
            lead: Some(1.5),
            ..line(Motion::Linear, axes(&[(Axis::Z, -10.0)]), 1)
        };
        vec![
            (Op::Move(thread), "gl"),
            (Op::IncrementalMove(thread), "gl"),
            (
                Op::RigidTap(ir::RigidTap {
                    to: axes(&[(Axis::Z, -10.0)]),
                    lead: 1.25,
                    speedup: None,
                }),
                "gl",
            ),
            (Op::Move(line(Motion::Rapid, xy, 1)), "gblf"),
            (Op::Move(line(Motion::Linear, xa, 1)), "glf"),
            (Op::Move(line(Motion::ArcCw, xy, 1)), "gblf"),
            (Op::Move(line(Motion::ArcCcw, xy, 3)), "gl"),
            (Op::MachineMove(line(Motion::Rapid, xy, 1)), "gblf"),
            (Op::MachineMove(line(Motion::Rapid, xa, 1)), "glf"),
            (Op::IncrementalMove(line(Motion::Linear, xy, 1)), "gblf"),
            (Op::IncrementalMove(line(Motion::Rapid, xa, 1)), "glf"),
            (home, "gblf"),
            (Op::Feed(100.0), "gblf"),
            (Op::Speed(1000.0), "gblf"),
            (Op::SpindleMode(ir::SpindleMode::Rpm), "glf"),
            (surface(None), "glf"),
            (surface(Some(2500.0)), "gl"),
            (Op::SelectTool(2), "gblf"),
            (Op::ChangeTool, "gblf"),
            (Op::Spindle(ir::Spindle::CounterClockwise), "gblf"),
            (Op::Coolant(ir::Coolant::Mist), "gblf"),
            (Op::Dwell(1.0), "gblf"),
            (Op::Stop(ir::Stop::Optional), "gblf"),
            (Op::End, "gblf"),
            (Op::Units(ir::Units::Inch), "gblf"),
            (Op::Distance(ir::Distance::Incremental), "gblf"),
            (Op::ArcCenters(ir::Distance::Absolute), "gl"),
            (Op::ArcCenters(ir::Distance::Incremental), "gbl"),
            (Op::InverseTime(true), "gblf"),
            (Op::Plane(ir::Plane::YZ), "gblf"),
            (Op::SelectWorkOffset(6), "gblf"),
            (Op::SelectWorkOffset(7), "gl"),
            (g10(2), "gblf"),
            // grbl's printer leaves it out: ger folds the values.
            (tool_data, "gbl"),
            (g10(0), "gbl"),
            (Op::SetWorkOffsetHere { index: 1, at: xy }, "gbl"),
            (Op::LocalOffset(xy), "glf"),
            (Op::SetPosition(xy), "gblf"),
            (Op::CancelPosition, "gbl"),
            (length(false), "glf"),
            (length(true), "gf"),
            (Op::CancelToolLength, "gblf"),
            (Op::Polar(true), "gf"),
            (Op::DiameterMode(true), "gl"),
            (Op::ReturnLevel(ir::ReturnLevel::R), "glf"),
            (cycle(ir::CycleKind::G81), "glf"),
            (cycle(ir::CycleKind::G87), "glf"),
            (Op::CycleOff, "gblf"),
            (
                Op::Spline(Box::new(ir::Spline {
                    to: xy,
                    kind: ir::SplineKind::Quadratic {
                        control: [1.0, 0.0],
                    },
                })),
                "gl",
            ),
            (comp(CompRadius::Tool(1)), "glf"),
            (comp(CompRadius::LoadedTool), "gl"),
            (comp(CompRadius::Diameter(6.0)), "gl"),
            (Op::CompOff, "gblf"),
            (Op::ReadPosition(ir::Plane::XY), "gblf"),
            (Op::InverseTimeFloor(0.1), "gblf"),
            (Op::Comment("x".into()), "gblf"),
            (m(62), "glf"),
            (m(56), "gbf"),
            (m(10), "gf"),
            (m(150), "glf"),
            (Op::Passthrough(Passthrough::Line("$H".into())), "gb"),
            // Never refused: grbl's printer drops it with a warning.
            (Op::PathControl(ir::PathControl::ExactStop), "gblf"),
        ]
    }

    /// Every op variant is in [`every_code`]: a new one fails to compile
    /// here until its targets are decided.
    fn listed(op: &Op) {
        match op {
            Op::Move(_)
            | Op::MachineMove(_)
            | Op::IncrementalMove(_)
            | Op::RigidTap(_)
            | Op::Home { .. }
            | Op::Feed(_)
            | Op::Speed(_)
            | Op::SpindleMode(_)
            | Op::SelectTool(_)
            | Op::ChangeTool
            | Op::Spindle(_)
            | Op::Coolant(_)
            | Op::Dwell(_)
            | Op::Stop(_)
            | Op::End
            | Op::Units(_)
            | Op::Distance(_)
            | Op::ArcCenters(_)
            | Op::InverseTime(_)
            | Op::InverseTimeFloor(_)
            | Op::Plane(_)
            | Op::SelectWorkOffset(_)
            | Op::SetWorkOffset { .. }
            | Op::SetWorkOffsetHere { .. }
            | Op::SetToolData(_)
            | Op::LocalOffset(_)
            | Op::SetPosition(_)
            | Op::CancelPosition
            | Op::ToolLength { .. }
            | Op::CancelToolLength
            | Op::Polar(_)
            | Op::DiameterMode(_)
            | Op::ReturnLevel(_)
            | Op::Cycle(_)
            | Op::Spline(_)
            | Op::CycleOff
            | Op::Comp { .. }
            | Op::CompOff
            | Op::ReadPosition(_)
            | Op::Comment(_)
            | Op::PathControl(_)
            | Op::Passthrough(_) => {}
        }
    }

    #[test]
    fn each_target_runs_its_list_of_codes() {
        let targets = [
            (b'g', Target::Generic),
            (b'b', Target::Grbl),
            (b'l', Target::LinuxCnc),
            (b'f', Target::Fanuc),
        ];
        for (op, runs) in every_code() {
            listed(&op);
            for (letter, target) in targets {
                let refusal = target.cannot_run(&op);
                assert_eq!(
                    refusal.is_none(),
                    runs.as_bytes().contains(&letter),
                    "{target:?} on {op:?}: {refusal:?}"
                );
                if let Some(r) = refusal {
                    let text = format!("{:?}", r.wording(Span::default()).message);
                    assert!(text.contains(&r.code), "{text}");
                }
            }
        }
    }

    #[test]
    fn refusals_name_the_code_as_written() {
        let g43 = Op::ToolLength {
            tool: Some(1),
            negative: false,
        };
        assert_eq!(Target::Grbl.cannot_run(&g43).unwrap().code, "G43 H1");
        let m62 = Op::Passthrough(Passthrough::MCode {
            number: 62,
            words: vec![(b'P', 1.0)],
        });
        assert_eq!(Target::Grbl.cannot_run(&m62).unwrap().code, "M62");
        assert_eq!(
            Target::Fanuc
                .cannot_run(&Op::SelectWorkOffset(8))
                .unwrap()
                .code,
            "G59.2"
        );
    }
}
