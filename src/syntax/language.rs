//! Which language a file is in, decided from its name or `--input`. It
//! must not read the text: the front ends do.

/// Which language a file is in (SPEC §2.8): ger's own, or plain G-code as
/// CAM and people write it, where `;` starts a comment, `( … )` is always a
/// comment (nested parentheses included) and `:0097` is a program number.
/// Both read spaces inside a word (`G0Z  0.1`, SPEC §2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Language {
    #[default]
    Egc,
    Gcode,
}

impl Language {
    /// `.egc` is ger's language; every other file is plain G-code.
    pub fn of_file(name: &str) -> Language {
        let lower = name.to_ascii_lowercase();
        if lower.ends_with(".egc") || name == "<stdin>" {
            Language::Egc
        } else {
            Language::Gcode
        }
    }
}
