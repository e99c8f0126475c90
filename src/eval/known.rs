//! rs274's predefined parameters as data: their names (`#<_x>`,
//! `#<_metric>`, `#5400`, …) and the state ger follows for them (the
//! current point, the motion mode, the tool, the coolant, …). The
//! evaluator's half, which follows statements and fills the values in,
//! is [`super::predefined`]; this module must stay free of the evaluator
//! (it is what the evaluator and the values hold).

use super::options::Flavour;
use crate::ast::{Names, Symbol};
use crate::ir::Axis;

/// One predefined parameter: what it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Param {
    /// `#<_x>`…`#<_w>`, `#5420`–`#5428`: the current point, program frame
    /// and units.
    Position(Axis),
    /// `#<_abs_x>`…: the point in machine coordinates.
    Absolute,
    Metric,
    Imperial,
    AbsoluteMode,
    IncrementalMode,
    InverseTime,
    UnitsPerMinute,
    UnitsPerRev,
    /// `#<_coord_system>` (540 … 593).
    CoordSystem,
    /// `#5220` (1 … 9).
    CoordIndex,
    ToolOffset,
    RetractR,
    RetractOldZ,
    RpmMode,
    CssMode,
    IjkAbsolute,
    DiameterMode,
    RadiusMode,
    SpindleOn,
    SpindleCw,
    Mist,
    Flood,
    /// `#<_speed_override>`, `_feed_override`, `_adaptive_feed`,
    /// `_feed_hold`: the enables M48–M53 set.
    Enable(usize),
    Feed,
    Rpm,
    /// `#<_current_tool>`, `#5400`.
    CurrentTool,
    SelectedTool,
    /// `#<_current_pocket>`, `#<_selected_pocket>`: the machine's table.
    Pocket,
    MotionMode,
    Plane,
    CutterComp,
    Line,
    CallLevel,
    RemapLevel,
    Task,
    VersionMajor,
    VersionMinor,
    MetricMachine,
}

/// Names and what they read; the names as the lexer spells them.
const NAMED: &[(&str, Param)] = &[
    ("#<_metric>", Param::Metric),
    ("#<_imperial>", Param::Imperial),
    ("#<_absolute>", Param::AbsoluteMode),
    ("#<_incremental>", Param::IncrementalMode),
    ("#<_inverse_time>", Param::InverseTime),
    ("#<_units_per_minute>", Param::UnitsPerMinute),
    ("#<_units_per_rev>", Param::UnitsPerRev),
    ("#<_coord_system>", Param::CoordSystem),
    ("#5220", Param::CoordIndex),
    ("#<_tool_offset>", Param::ToolOffset),
    ("#<_retract_r_plane>", Param::RetractR),
    ("#<_retract_old_z>", Param::RetractOldZ),
    ("#<_spindle_rpm_mode>", Param::RpmMode),
    ("#<_spindle_css_mode>", Param::CssMode),
    ("#<_ijk_absolute_mode>", Param::IjkAbsolute),
    ("#<_lathe_diameter_mode>", Param::DiameterMode),
    ("#<_lathe_radius_mode>", Param::RadiusMode),
    ("#<_spindle_on>", Param::SpindleOn),
    ("#<_spindle_cw>", Param::SpindleCw),
    ("#<_mist>", Param::Mist),
    ("#<_flood>", Param::Flood),
    ("#<_speed_override>", Param::Enable(SPEED_OVERRIDE)),
    ("#<_feed_override>", Param::Enable(FEED_OVERRIDE)),
    ("#<_adaptive_feed>", Param::Enable(ADAPTIVE_FEED)),
    ("#<_feed_hold>", Param::Enable(FEED_HOLD)),
    ("#<_feed>", Param::Feed),
    ("#<_rpm>", Param::Rpm),
    ("#<_current_tool>", Param::CurrentTool),
    ("#5400", Param::CurrentTool),
    ("#<_selected_tool>", Param::SelectedTool),
    ("#<_current_pocket>", Param::Pocket),
    ("#<_selected_pocket>", Param::Pocket),
    ("#<_motion_mode>", Param::MotionMode),
    ("#<_plane>", Param::Plane),
    ("#<_ccomp>", Param::CutterComp),
    ("#<_line>", Param::Line),
    ("#<_call_level>", Param::CallLevel),
    ("#<_remap_level>", Param::RemapLevel),
    ("#<_task>", Param::Task),
    ("#<_vmajor>", Param::VersionMajor),
    ("#<_vminor>", Param::VersionMinor),
    ("#<_metric_machine>", Param::MetricMachine),
];

/// The letters of `#<_x>`…`#<_w>` and `#<_abs_x>`…, in [`Axis::ALL`]'s
/// order.
const AXES: &str = "xyzabcuvw";
/// The numbered parameter of the current X; Y … W follow it.
const FIRST_POSITION: u32 = 5420;

pub(super) const SPEED_OVERRIDE: usize = 0;
pub(super) const FEED_OVERRIDE: usize = 1;
pub(super) const ADAPTIVE_FEED: usize = 2;
pub(super) const FEED_HOLD: usize = 3;

/// rs274's version, as the one the oracle runs (2.9.0~pre1) reads it.
pub(super) const VERSION: (f64, f64) = (2.9, 0.0);

impl Param {
    /// The predefined parameter `text` (a name as the lexer spells it).
    pub(super) fn of_name(text: &str) -> Option<Param> {
        if let Some(&(_, p)) = NAMED.iter().find(|(n, _)| *n == text) {
            return Some(p);
        }
        if let Some(n) = super::state::parameter_number(text) {
            let i = n.checked_sub(FIRST_POSITION)? as usize;
            return Axis::ALL.get(i).map(|&a| Param::Position(a));
        }
        let inner = text.strip_prefix("#<_")?.strip_suffix('>')?;
        let (letter, absolute) = match inner.strip_prefix("abs_") {
            Some(l) => (l, true),
            None => (inner, false),
        };
        let mut chars = letter.chars();
        let (Some(c), None) = (chars.next(), chars.next()) else {
            return None;
        };
        let i = AXES.find(c)?;
        Some(if absolute {
            Param::Absolute
        } else {
            Param::Position(Axis::ALL[i])
        })
    }

    /// Why ger cannot know it, for the error at its use.
    pub(super) fn machine_only(self) -> &'static str {
        match self {
            Param::Position(_) => {
                "ger knows where the tool stands only from the program's own moves: not before its first move on the axis, after G28/G30/G53, a work offset or tool length ger was not given, or under cutter compensation"
            }
            Param::Absolute => {
                "machine coordinates add the work offsets and tool length the machine holds"
            }
            Param::Metric | Param::Imperial => {
                "the program has not stated its units: they are the machine's (give G20/G21, or --units)"
            }
            Param::CurrentTool => {
                "the tool in the spindle before the program's first M6 or M61 is the machine's"
            }
            Param::SelectedTool => "the tool selected before the program's first T is the machine's",
            Param::Pocket => "pockets are in the machine's tool table",
            Param::ToolOffset => "the tool's length is the machine's (not in the tool table given)",
            Param::MetricMachine => "the machine's units are in its INI file",
            _ => "ger does not know this value",
        }
    }
}

/// What the predefined parameters read that the rest of the evaluator does
/// not keep, and the ones the program names.
#[derive(Debug)]
pub(super) struct Predefined {
    /// The predefined parameters the program names, with their symbols.
    pub(super) named: Vec<(Symbol, Param)>,
    /// rs274's current point, in the program's frame and units (`None`:
    /// the machine's).
    pub(super) here: [Option<f64>; 9],
    /// `_motion_mode`: the G code times 10 (800 at power-up).
    pub(super) motion: f64,
    pub(super) speed: f64,
    pub(super) surface_speed: bool,
    pub(super) mist: bool,
    pub(super) flood: bool,
    /// The tool in the spindle (`None`: the machine's).
    pub(super) tool: Option<u32>,
    /// A tool length is on: `Some(false)` none or zero, `None` unknown.
    pub(super) tool_offset: Option<bool>,
    pub(super) enables: [bool; 4],
    /// `#<_task>` was read and warned about.
    pub(super) task_warned: bool,
}

impl Default for Predefined {
    fn default() -> Self {
        Predefined {
            named: Vec::new(),
            here: [None; 9],
            motion: 800.0,
            speed: 0.0,
            surface_speed: false,
            mist: false,
            flood: false,
            tool: None,
            tool_offset: Some(false),
            enables: [true, true, false, true],
            task_warned: false,
        }
    }
}

impl Predefined {
    /// The predefined parameters among the names from `from` on.
    pub(super) fn add_names(&mut self, names: &Names, from: usize, flavour: Flavour) {
        if flavour == Flavour::Fanuc {
            return;
        }
        for (symbol, text) in names.iter().skip(from) {
            if let Some(p) = Param::of_name(text) {
                self.named.push((symbol, p));
            }
        }
    }

    /// A tool length is on (`None`: the machine's).
    pub(super) fn tool_offset(&self) -> Option<bool> {
        self.tool_offset
    }

    /// The last S.
    pub(super) fn speed(&self) -> f64 {
        self.speed
    }

    /// Mist and flood are on.
    pub(super) fn coolant(&self) -> (bool, bool) {
        (self.mist, self.flood)
    }

    /// Does the program name any?
    pub(super) fn named_any(&self) -> bool {
        !self.named.is_empty()
    }
}
