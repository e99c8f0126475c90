//! The evaluator's options: the runaway limits, the flavour whose meaning
//! holds where controllers disagree ([`Flavour`]), and what the driver
//! knows before the program runs. Plain data the driver fills in; it must
//! not know the evaluator that reads it.

use crate::ir;

/// Limits that keep evaluation bounded whatever the input.
#[derive(Clone, Debug)]
pub struct EvalOptions {
    /// A `while` that runs more often is an error naming the loop.
    pub max_iterations: u64,
    /// More IR statements than this made by loops, subprogram calls and
    /// jumps back is an error (the program would run on and on). The
    /// program's own lines, run once each, are not counted: their number
    /// is the file's.
    pub max_statements: usize,
    /// Subprogram nesting depth.
    pub max_call_depth: usize,
    /// Statements per batch sent to the back end. The output does not
    /// depend on it (`tests/streaming.rs` checks); it trades cache for
    /// call overhead.
    pub batch: usize,
    /// Statements in the first batch, each next twice as many up to
    /// `batch`: the back end's thread starts on a few while the
    /// evaluator, its caches cold, makes the next.
    pub first_batch: usize,
    /// `--units`: the units of a program that states none.
    pub units: Option<ir::Units>,
    /// `--from`: whose meaning holds where controllers disagree. The
    /// driver fills it from `CompileOptions::from` (or the file's name):
    /// set that one.
    pub from: Flavour,
    /// Why `from` holds (a note says so where it matters).
    pub chosen: Chosen,
    /// `--tool-table`: tools known before the program's `SetTool`s.
    pub tools: std::collections::BTreeMap<u32, ir::Tool>,
    /// `--tool-units`: the units of `tools` (a LinuxCNC table is in the
    /// machine's); `None`: the output's, as `SetTool`'s.
    pub tool_units: Option<ir::Units>,
    /// `--comments keep` (the default): a plain program's comments go to
    /// the output in their place.
    pub keep_comments: bool,
    /// The program is plain G-code (not `.egc`, whose rules are ger's own
    /// and need no warning where controllers disagree).
    pub plain: bool,
    /// A caller's flag (an editor that has newer text): once it is set,
    /// the run stops at its next batch with an error.
    pub cancel: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

impl EvalOptions {
    /// LinuxCNC's macro language read as rs274 reads it: plain G-code not
    /// read as Fanuc's (its trigonometry, its named parameters).
    pub(super) fn rs274(&self) -> bool {
        self.plain && self.from != Flavour::Fanuc
    }
}

/// The controller family a program was written for (`--from`, SPEC §1):
/// it settles the codes controllers read differently.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Flavour {
    /// `G4 P` in seconds, as most programs people have mean it (grbl,
    /// LinuxCNC, Mach3); cycles return to G98 at power-up.
    #[default]
    Generic,
    /// `G4 P` in seconds.
    LinuxCnc,
    /// `G4 P` in milliseconds, `G4 X` in seconds.
    Fanuc,
    /// `G4 P` in seconds.
    Grbl,
    /// `G4 P` in seconds (Mach3's default setting).
    Mach3,
}

impl Flavour {
    /// Where canned cycles return when the program has not said G98 or
    /// G99: LinuxCNC (rs274) starts in G99; Fanuc, Haas, Mach3 and the
    /// generic flavour take G98, the higher and safer of the two.
    pub fn power_up_return_level(self) -> ir::ReturnLevel {
        match self {
            Flavour::LinuxCnc => ir::ReturnLevel::R,
            Flavour::Generic | Flavour::Fanuc | Flavour::Grbl | Flavour::Mach3 => {
                ir::ReturnLevel::Initial
            }
        }
    }

    /// A numbered parameter whose value only the machine knows: on Fanuc
    /// `#500`–`#999` (kept between programs) and the system variables
    /// from `#1000`; on LinuxCNC `#5001` and up (positions, offsets).
    pub fn machine_parameter(self, n: u32) -> bool {
        match self {
            Flavour::Fanuc => n >= 500,
            Flavour::Generic | Flavour::LinuxCnc | Flavour::Grbl | Flavour::Mach3 => {
                n > LAST_USER_PARAMETER
            }
        }
    }

    /// The default for a file: `.ngc` is LinuxCNC's.
    pub fn of_file(name: &str) -> Flavour {
        if name.to_ascii_lowercase().ends_with(".ngc") {
            Flavour::LinuxCnc
        } else {
            Flavour::Generic
        }
    }
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            max_iterations: 10_000_000,
            max_statements: 5_000_000,
            max_call_depth: 64,
            batch: 1024,
            first_batch: 64,
            units: None,
            from: Flavour::Generic,
            chosen: Chosen::Flag,
            plain: false,
            keep_comments: true,
            tools: Default::default(),
            tool_units: None,
            cancel: None,
        }
    }
}

/// Why a flavour holds when `--from` was not given (SPEC §1): the file's
/// name, the `--target`'s controller, a clue only one controller writes,
/// or nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Chosen {
    /// `--from` (or `from` in `ger.toml`).
    Flag,
    /// A `.ngc` file is LinuxCNC's.
    FileName,
    /// The `--target`'s controller.
    Target,
    /// A grbl command (`$H`, `$J=`) in the file's first lines.
    GrblCommand,
    /// A `%` tape with an `O` number.
    FanucTape,
    /// Fanuc's Macro B (`IF`, `WHILE … DO`, `GOTO`, `G65`) in the file's
    /// first lines.
    MacroB,
    /// Nothing decided.
    Nothing,
}

impl Chosen {
    /// Why, for a note.
    pub fn reason(self) -> &'static str {
        match self {
            Chosen::Flag => "as --from says",
            Chosen::FileName => "a .ngc file is LinuxCNC's",
            Chosen::Target => "the --target's controller",
            Chosen::GrblCommand => "the file has grbl's `$` commands",
            Chosen::FanucTape => "the file is a `%` tape with an O number, as Fanuc's are",
            Chosen::MacroB => "the file has Fanuc's Macro B (`IF`, `WHILE … DO`, `GOTO`, `G65`)",
            Chosen::Nothing => "nothing in the file or the options names a controller",
        }
    }
}

/// The last of LinuxCNC's user parameters; those above hold machine state.
pub(crate) const LAST_USER_PARAMETER: u32 = 5000;
