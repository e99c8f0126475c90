//! What each G and M code means, for the editor's hover: one line of
//! meaning, the words it takes and its modal group, as rs274 (LinuxCNC)
//! and Fanuc read them; where they differ, both. A table, no logic.

/// One code's entry.
pub struct Code {
    /// `G` or `M`.
    pub letter: u8,
    /// The number, ten times over (G38.2 is 382; G1 is 10).
    pub tenths: u32,
    pub meaning: &'static str,
    /// The words it takes.
    pub words: &'static str,
    pub group: &'static str,
}

macro_rules! codes {
    ($($letter:literal $tenths:literal $meaning:literal, $words:literal, $group:literal;)*) => {
        &[$(Code { letter: $letter, tenths: $tenths, meaning: $meaning, words: $words, group: $group },)*]
    };
}

/// Every code ger knows, in order.
pub const CODES: &[Code] = codes! {
    b'G' 0 "rapid move", "X Y Z (A B C U V W)", "motion";
    b'G' 10 "straight feed move", "X Y Z (A B C U V W) F", "motion";
    b'G' 20 "clockwise arc", "X Y Z, I J K or R, P (turns), F", "motion";
    b'G' 30 "counter-clockwise arc", "X Y Z, I J K or R, P (turns), F", "motion";
    b'G' 40 "dwell", "P: seconds on LinuxCNC, grbl and Mach3; on Fanuc milliseconds when P has no point (X: seconds)", "non-modal";
    b'G' 100 "set data: L1/L10/L11 tool table, L2/L20 work offsets", "L P X Y Z R", "non-modal";
    b'G' 150 "polar coordinates off", "", "polar (Fanuc)";
    b'G' 160 "polar coordinates on: X radius, Y angle in degrees", "", "polar (Fanuc)";
    b'G' 170 "plane XY", "", "plane";
    b'G' 180 "plane ZX", "", "plane";
    b'G' 190 "plane YZ", "", "plane";
    b'G' 200 "units: inch", "", "units";
    b'G' 210 "units: millimetre", "", "units";
    b'G' 280 "go home (position 1), through the point given", "X Y Z", "non-modal";
    b'G' 281 "store home position 1", "", "non-modal";
    b'G' 300 "go to position 2, through the point given", "X Y Z", "non-modal";
    b'G' 301 "store position 2", "", "non-modal";
    b'G' 382 "probe toward the workpiece, error if no contact", "X Y Z F", "motion";
    b'G' 400 "cutter compensation off", "", "cutter compensation";
    b'G' 410 "cutter compensation left of the path", "D (tool)", "cutter compensation";
    b'G' 411 "cutter compensation left, by diameter", "D (diameter)", "cutter compensation";
    b'G' 420 "cutter compensation right of the path", "D (tool)", "cutter compensation";
    b'G' 421 "cutter compensation right, by diameter", "D (diameter)", "cutter compensation";
    b'G' 430 "tool length offset from the tool table", "H (tool)", "tool length";
    b'G' 431 "tool length offset given", "Z (length)", "tool length";
    b'G' 490 "tool length offset off", "", "tool length";
    b'G' 520 "local coordinate shift (cancelled by G54)", "X Y Z", "non-modal";
    b'G' 530 "move in machine coordinates (this line only)", "with G0/G1: X Y Z", "non-modal";
    b'G' 540 "work offset 1", "", "work offset";
    b'G' 550 "work offset 2", "", "work offset";
    b'G' 560 "work offset 3", "", "work offset";
    b'G' 570 "work offset 4", "", "work offset";
    b'G' 580 "work offset 5", "", "work offset";
    b'G' 590 "work offset 6", "", "work offset";
    b'G' 591 "work offset 7", "", "work offset";
    b'G' 592 "work offset 8", "", "work offset";
    b'G' 593 "work offset 9", "", "work offset";
    b'G' 610 "exact path", "", "path control";
    b'G' 611 "exact stop", "", "path control";
    b'G' 640 "blending, within P of the path", "P Q", "path control";
    b'G' 650 "macro call (Fanuc)", "P (program) L (repeats), argument letters", "non-modal";
    b'G' 730 "peck drilling, chips broken", "X Y Z R Q F, L/K repeats", "motion (canned cycle)";
    b'G' 740 "left-hand tapping", "X Y Z R F, L/K repeats", "motion (canned cycle)";
    b'G' 760 "fine boring (Fanuc: Q shift); LinuxCNC: lathe threading", "X Y Z R Q P F", "motion (canned cycle)";
    b'G' 800 "canned cycle off", "", "motion";
    b'G' 810 "drilling", "X Y Z R F, L/K repeats", "motion (canned cycle)";
    b'G' 820 "drilling, dwell at the bottom", "X Y Z R P F, L/K repeats", "motion (canned cycle)";
    b'G' 830 "peck drilling, full retract", "X Y Z R Q F, L/K repeats", "motion (canned cycle)";
    b'G' 840 "right-hand tapping", "X Y Z R F, L/K repeats", "motion (canned cycle)";
    b'G' 850 "boring, feed out", "X Y Z R F, L/K repeats", "motion (canned cycle)";
    b'G' 860 "boring, spindle stop, rapid out (Fanuc: no dwell word)", "X Y Z R P F, L/K repeats", "motion (canned cycle)";
    b'G' 870 "back boring (Fanuc)", "X Y Z R Q F", "motion (canned cycle)";
    b'G' 880 "boring, spindle stop, manual out", "X Y Z R P F", "motion (canned cycle)";
    b'G' 890 "boring, dwell, feed out", "X Y Z R P F, L/K repeats", "motion (canned cycle)";
    b'G' 900 "absolute distances", "", "distance mode";
    b'G' 901 "arc centres absolute", "", "arc distance mode";
    b'G' 910 "incremental distances", "", "distance mode";
    b'G' 911 "arc centres relative to the start", "", "arc distance mode";
    b'G' 920 "this point takes the coordinates given (offset)", "X Y Z", "non-modal";
    b'G' 921 "G92 offset off, values cleared", "", "non-modal";
    b'G' 922 "G92 offset off, values kept", "", "non-modal";
    b'G' 930 "inverse time feed: F is 1 / minutes per move", "", "feed mode";
    b'G' 940 "feed per minute", "", "feed mode";
    b'G' 950 "feed per revolution", "", "feed mode";
    b'G' 960 "constant surface speed", "S D", "spindle mode";
    b'G' 970 "spindle RPM", "S", "spindle mode";
    b'G' 980 "canned cycles return to the initial level", "", "return level";
    b'G' 990 "canned cycles return to R", "", "return level";
    b'M' 0 "program stop", "", "stopping";
    b'M' 10 "optional stop", "", "stopping";
    b'M' 20 "program end", "", "stopping";
    b'M' 30 "spindle on, clockwise", "S", "spindle";
    b'M' 40 "spindle on, counter-clockwise", "S", "spindle";
    b'M' 50 "spindle stop", "", "spindle";
    b'M' 60 "tool change", "T", "tool change";
    b'M' 70 "mist coolant on", "", "coolant";
    b'M' 80 "flood coolant on", "", "coolant";
    b'M' 90 "coolant off", "", "coolant";
    b'M' 300 "program end and rewind", "", "stopping";
    b'M' 700 "save the modal state (LinuxCNC)", "", "modal state";
    b'M' 710 "invalidate the saved modal state (LinuxCNC)", "", "modal state";
    b'M' 720 "restore the saved modal state (LinuxCNC)", "", "modal state";
    b'M' 730 "save, and restore on return (LinuxCNC)", "", "modal state";
    b'M' 980 "call a subprogram (Fanuc)", "P (program) L (repeats)", "subprogram";
    b'M' 990 "return from a subprogram", "", "subprogram";
};

/// The entry of `letter` and `number` (`G`, 38.2), if ger knows it.
pub fn lookup(letter: u8, number: f64) -> Option<&'static Code> {
    let tenths = (number * 10.0).round();
    if !(0.0..=100_000.0).contains(&tenths) || (number * 10.0 - tenths).abs() > 1e-6 {
        return None;
    }
    let letter = letter.to_ascii_uppercase();
    CODES
        .iter()
        .find(|c| c.letter == letter && c.tenths == tenths as u32)
}

impl Code {
    /// As a program writes it: `G38.2`, `M3`.
    pub fn name(&self) -> String {
        match self.tenths % 10 {
            0 => format!("{}{}", self.letter as char, self.tenths / 10),
            d => format!("{}{}.{d}", self.letter as char, self.tenths / 10),
        }
    }

    /// As the hover shows it, in Markdown.
    pub fn markdown(&self) -> String {
        let words = match self.words {
            "" => String::new(),
            w => format!("\n\nwords: {w}"),
        };
        format!(
            "**{}**: {}{words}\n\nmodal group: {}",
            self.name(),
            self.meaning,
            self.group
        )
    }
}
