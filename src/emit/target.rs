//! The output flavours (`--target`, SPEC §6): what each controller family
//! wants around and inside the program. Everything a target changes is a
//! method here, so a new target is one variant and its answers.

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

    /// What M6 becomes: GRBL has no tool changer, so it stops and the
    /// comment names the tool for the operator.
    pub fn tool_change(self, selected: Option<u32>) -> String {
        match (self, selected) {
            (Target::Grbl, Some(t)) => format!("M0 (change to tool {t})"),
            (Target::Grbl, None) => "M0 (tool change)".to_string(),
            (Target::Generic | Target::Fanuc | Target::LinuxCnc, _) => "M6".to_string(),
        }
    }
}
