//! The machine a program runs on (`[machine]` of `ger.toml`, SPEC §9):
//! its controller, per-axis rates, accelerations and travel, cornering
//! (grbl's junction deviation, LinuxCNC's path tolerance), arc tolerance,
//! planner depth and the time of tool changes and spindle starts. Read in
//! the units the table states and kept in millimetres and seconds; each
//! wrong value an error at its line. Also the table made from a LinuxCNC
//! INI or a grbl `$$` dump (`ger machine import`).

use crate::diagnostic::Diagnostic;
use crate::source::Locator;
use serde::Deserialize;
use std::fmt::Write as _;
use toml::Spanned;

/// Millimetres in an inch.
const MM_PER_INCH: f64 = 25.4;
/// The most blocks a planner may hold: far beyond any controller's
/// (grbl's 16 slots, LinuxCNC's look-ahead of 50 by default), and the
/// planner's window is held in memory.
pub const MAX_PLANNER_BLOCKS: u32 = 10_000;

/// The controller whose planner the machine runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub enum Controller {
    #[serde(rename = "grbl")]
    Grbl,
    #[serde(rename = "linuxcnc")]
    LinuxCnc,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub enum TableUnits {
    #[serde(rename = "mm")]
    Mm,
    #[serde(rename = "inch")]
    Inch,
}

/// `[machine]` as written: lengths in `units`, velocities in units per
/// minute, accelerations in units per second squared, times in seconds.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct MachineTable {
    controller: Controller,
    units: TableUnits,
    x: Option<AxisTable>,
    y: Option<AxisTable>,
    z: Option<AxisTable>,
    rapid_rate: Option<Spanned<f64>>,
    /// LinuxCNC's path limits (`[TRAJ] MAX_LINEAR_VELOCITY`, units/min,
    /// and `MAX_LINEAR_ACCELERATION`, units/s²).
    max_velocity: Option<Spanned<f64>>,
    max_acceleration: Option<Spanned<f64>>,
    junction_deviation: Option<Spanned<f64>>,
    path_tolerance: Option<Spanned<f64>>,
    arc_tolerance: Option<Spanned<f64>>,
    planner_blocks: Option<Spanned<u32>>,
    tool_change_s: Option<Spanned<f64>>,
    spindle_start_s: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct AxisTable {
    max_velocity: Option<Spanned<f64>>,
    max_acceleration: Option<Spanned<f64>>,
    /// Per millimetre whatever the table's units (grbl's `$100`–`$102`).
    steps_per_mm: Option<Spanned<f64>>,
    min: Option<Spanned<f64>>,
    max: Option<Spanned<f64>>,
}

/// The machine, in millimetres, minutes for rates and seconds for the
/// rest; `None` where the table does not say.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    pub controller: Controller,
    /// X, Y, Z.
    pub axes: [Axis; 3],
    /// mm/min for every rapid (else each axis's maximum velocity).
    pub rapid_rate: Option<f64>,
    /// LinuxCNC's limits on the path of every move, rapids included
    /// (`[TRAJ] MAX_LINEAR_VELOCITY`, `MAX_LINEAR_ACCELERATION`), after
    /// each axis's: mm/min and mm/s².
    pub max_velocity: Option<f64>,
    pub max_acceleration: Option<f64>,
    /// mm (grbl `$11`).
    pub junction_deviation: Option<f64>,
    /// mm (LinuxCNC's `G64 P` when the program gives none).
    pub path_tolerance: Option<f64>,
    /// mm (grbl `$12`).
    pub arc_tolerance: Option<f64>,
    /// The planner buffer's blocks (grbl's `BLOCK_BUFFER_SIZE`, 16 on a
    /// stock grbl, which holds one fewer; LinuxCNC's look-ahead depth).
    pub planner_blocks: Option<u32>,
    pub tool_change_s: Option<f64>,
    pub spindle_start_s: Option<f64>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axis {
    /// mm/min.
    pub max_velocity: Option<f64>,
    /// mm/s².
    pub max_acceleration: Option<f64>,
    /// Machine coordinates, mm: `(min, max)`.
    pub travel: Option<(f64, f64)>,
    /// Steps per mm (grbl `$100`–`$102`).
    pub steps_per_mm: Option<f64>,
}

impl MachineTable {
    /// The machine in millimetres, or every wrong value at its line.
    pub fn checked(self, at: &Locator) -> Result<Machine, Vec<Diagnostic>> {
        let scale = match self.units {
            TableUnits::Mm => 1.0,
            TableUnits::Inch => MM_PER_INCH,
        };
        let mut wrong = Vec::new();
        let mut positive = |value: &Option<Spanned<f64>>, name: &str, scale: f64| {
            let v = value.as_ref()?;
            if v.get_ref().is_finite() && *v.get_ref() > 0.0 {
                return Some(v.get_ref() * scale);
            }
            let span = at.span(v.span().start, v.span().end);
            let message = format!("ger.toml: `{name}` must be a positive number");
            wrong.push(crate::diagnostic::error(message, span, "here"));
            None
        };
        let rapid_rate = positive(&self.rapid_rate, "rapid-rate", scale);
        let max_velocity = positive(&self.max_velocity, "max-velocity", scale);
        let max_acceleration = positive(&self.max_acceleration, "max-acceleration", scale);
        let junction_deviation = positive(&self.junction_deviation, "junction-deviation", scale);
        let path_tolerance = positive(&self.path_tolerance, "path-tolerance", scale);
        let arc_tolerance = positive(&self.arc_tolerance, "arc-tolerance", scale);
        let tool_change_s = positive(&self.tool_change_s, "tool-change-s", 1.0);
        let spindle_start_s = positive(&self.spindle_start_s, "spindle-start-s", 1.0);
        let mut axes = [Axis::default(); 3];
        for (axis, table) in axes.iter_mut().zip([&self.x, &self.y, &self.z]) {
            let Some(table) = table else { continue };
            axis.max_velocity = positive(&table.max_velocity, "max-velocity", scale);
            axis.max_acceleration = positive(&table.max_acceleration, "max-acceleration", scale);
            axis.steps_per_mm = positive(&table.steps_per_mm, "steps-per-mm", 1.0);
        }
        for (axis, table) in axes.iter_mut().zip([&self.x, &self.y, &self.z]) {
            let Some(table) = table else { continue };
            axis.travel = travel(table, scale, at, &mut wrong);
        }
        self.other_controllers_keys(at, &mut wrong);
        let planner_blocks = self.planner_blocks.as_ref().map(|b| *b.get_ref());
        let blocks_out = |b: &&Spanned<u32>| !(1..=MAX_PLANNER_BLOCKS).contains(b.get_ref());
        if let Some(b) = self.planner_blocks.as_ref().filter(blocks_out) {
            let span = at.span(b.span().start, b.span().end);
            let message =
                format!("ger.toml: `planner-blocks` must be from 1 to {MAX_PLANNER_BLOCKS}");
            wrong.push(crate::diagnostic::error(message, span, "here"));
        }
        if !wrong.is_empty() {
            return Err(wrong);
        }
        Ok(Machine {
            controller: self.controller,
            axes,
            rapid_rate,
            max_velocity,
            max_acceleration,
            junction_deviation,
            path_tolerance,
            arc_tolerance,
            planner_blocks,
            tool_change_s,
            spindle_start_s,
        })
    }
}

impl MachineTable {
    /// Each key of the controller the table does not name, an error at
    /// its line: its planner would ignore it (or, read as its own
    /// controller's nearest setting, misreport).
    fn other_controllers_keys(&self, at: &Locator, wrong: &mut Vec<Diagnostic>) {
        let mut grbl_only = vec![
            (
                &self.junction_deviation,
                "`junction-deviation` is grbl's ($11); LinuxCNC's corners take \
                 `path-tolerance` (G64 P)",
            ),
            (
                &self.arc_tolerance,
                "`arc-tolerance` is grbl's ($12); LinuxCNC plans an arc whole",
            ),
        ];
        for table in [&self.x, &self.y, &self.z].into_iter().flatten() {
            let steps = "`steps-per-mm` is grbl's ($100-$102); LinuxCNC's planner \
                         is not planned in steps";
            grbl_only.push((&table.steps_per_mm, steps));
        }
        let linuxcnc_only = vec![
            (
                &self.path_tolerance,
                "`path-tolerance` is LinuxCNC's (G64 P); grbl's corners take \
                 `junction-deviation` ($11)",
            ),
            (
                &self.max_velocity,
                "`max-velocity` of the path is LinuxCNC's ([TRAJ]); grbl has \
                 only each axis's ([machine.x] and so on)",
            ),
            (
                &self.max_acceleration,
                "`max-acceleration` of the path is LinuxCNC's ([TRAJ]); grbl \
                 has only each axis's ([machine.x] and so on)",
            ),
        ];
        let foreign = match self.controller {
            Controller::Grbl => linuxcnc_only,
            Controller::LinuxCnc => grbl_only,
        };
        for (value, message) in foreign {
            if let Some(v) = value {
                let span = at.span(v.span().start, v.span().end);
                let message = format!("ger.toml: {message}");
                wrong.push(crate::diagnostic::error(message, span, "here"));
            }
        }
    }
}

/// An axis's travel: both ends or neither, the first below the second.
fn travel(
    table: &AxisTable,
    scale: f64,
    at: &Locator,
    wrong: &mut Vec<Diagnostic>,
) -> Option<(f64, f64)> {
    let (min, max) = match (&table.min, &table.max) {
        (None, None) => return None,
        (Some(min), Some(max)) if min.get_ref() < max.get_ref() => {
            return Some((min.get_ref() * scale, max.get_ref() * scale))
        }
        (Some(min), Some(max)) => (min, max),
        (Some(one), None) | (None, Some(one)) => (one, one),
    };
    let span = at.span(min.span().start, max.span().end.max(min.span().end));
    let message = "ger.toml: an axis's travel needs both `min` and `max`, `min` below `max`";
    wrong.push(crate::diagnostic::error(message, span, "here"));
    None
}

/// What `ger machine import` read a machine from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImportFormat {
    /// A LinuxCNC INI file.
    LinuxCncIni,
    /// grbl's `$$` settings dump.
    GrblSettings,
}

impl ImportFormat {
    /// Told from the text: `$110=` lines are grbl's, `[TRAJ]` LinuxCNC's.
    pub fn of_text(text: &str) -> Option<ImportFormat> {
        let lines = || text.lines().map(str::trim);
        if lines().any(|l| l.starts_with("$110=") || l.starts_with("$11=")) {
            Some(ImportFormat::GrblSettings)
        } else if lines().any(|l| l.eq_ignore_ascii_case("[TRAJ]") || l.starts_with("[AXIS_")) {
            Some(ImportFormat::LinuxCncIni)
        } else {
            None
        }
    }
}

/// The `[machine]` table for the machine `text` describes, as TOML text;
/// `Err`: what is missing.
pub fn import(text: &str, format: ImportFormat) -> Result<String, String> {
    match format {
        ImportFormat::GrblSettings => import_grbl(text),
        ImportFormat::LinuxCncIni => import_linuxcnc(text),
    }
}

/// grbl's `$$`: steps per mm (`$100`–`$102`), rates (`$110`–`$112`,
/// mm/min), accelerations (`$120`–`$122`, mm/s²), travel (`$130`–`$132`,
/// mm: homed to the positive end, so machine coordinates run from minus
/// the travel to 0), junction deviation (`$11`) and arc tolerance
/// (`$12`). grbl's settings are in millimetres whatever `$13` reports in.
fn import_grbl(text: &str) -> Result<String, String> {
    let setting = |n: u32| -> Option<f64> {
        let key = format!("${n}=");
        text.lines()
            .map(str::trim)
            .find_map(|l| l.strip_prefix(&key))
            .and_then(|v| v.split(|c: char| c.is_whitespace() || c == '(').next())
            .and_then(|v| v.parse().ok())
    };
    let mut out = String::from("[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n");
    for (key, n) in [("junction-deviation", 11), ("arc-tolerance", 12)] {
        if let Some(v) = setting(n) {
            let _ = writeln!(out, "{key} = {}", number(v));
        }
    }
    out.push_str("planner-blocks = 16\n");
    let mut found = false;
    for (axis, i) in ["x", "y", "z"].iter().zip(0..) {
        let (rate, accel, reach) = (setting(110 + i), setting(120 + i), setting(130 + i));
        found |= rate.is_some() || accel.is_some();
        let _ = writeln!(out, "\n[machine.{axis}]");
        if let Some(v) = setting(100 + i).filter(|v| *v > 0.0) {
            let _ = writeln!(out, "steps-per-mm = {}", number(v));
        }
        if let Some(v) = rate {
            let _ = writeln!(out, "max-velocity = {}", number(v));
        }
        if let Some(v) = accel {
            let _ = writeln!(out, "max-acceleration = {}", number(v));
        }
        if let Some(v) = reach.filter(|v| *v > 0.0) {
            let _ = writeln!(out, "min = {}\nmax = 0.0", number(-v));
        }
    }
    match found {
        true => Ok(out),
        false => Err("no axis settings ($110-$122) in the grbl dump".into()),
    }
}

/// A LinuxCNC INI: `[TRAJ]`'s `LINEAR_UNITS`, its path limits
/// `MAX_LINEAR_VELOCITY` and `MAX_LINEAR_ACCELERATION` (before 2.8
/// `MAX_VELOCITY`, `MAX_ACCELERATION`: LinuxCNC reads the old names
/// where the new are absent), and per axis `[AXIS_X]` (or
/// the joint of that axis) `MAX_VELOCITY` (units/s, written per minute),
/// `MAX_ACCELERATION`, `MIN_LIMIT`, `MAX_LIMIT`.
fn import_linuxcnc(text: &str) -> Result<String, String> {
    let ini = Ini::parse(text);
    let units = match ini.get("TRAJ", "LINEAR_UNITS").map(str::to_ascii_lowercase) {
        Some(u) if ["inch", "in", "imperial"].contains(&u.as_str()) => "inch",
        Some(u) if ["mm", "metric"].contains(&u.as_str()) => "mm",
        Some(u) => return Err(format!("[TRAJ] LINEAR_UNITS = {u}: neither mm nor inch")),
        None => return Err("no LINEAR_UNITS in [TRAJ]".into()),
    };
    let mut out = format!("[machine]\ncontroller = \"linuxcnc\"\nunits = \"{units}\"\n");
    let traj = |new: &str, old: &str| -> Option<f64> {
        let value = ini.get("TRAJ", new).or_else(|| ini.get("TRAJ", old));
        value.and_then(|v| v.parse().ok())
    };
    if let Some(v) = traj("MAX_LINEAR_VELOCITY", "MAX_VELOCITY") {
        let _ = writeln!(out, "max-velocity = {}", number(v * 60.0));
    }
    if let Some(v) = traj("MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION") {
        let _ = writeln!(out, "max-acceleration = {}", number(v));
    }
    let coordinates: Vec<char> = ini
        .get("TRAJ", "COORDINATES")
        .unwrap_or("XYZ")
        .chars()
        .filter(|c| c.is_ascii_alphabetic())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    let mut found = false;
    for axis in ['X', 'Y', 'Z'] {
        let axis_section = format!("AXIS_{axis}");
        let joint_section = coordinates
            .iter()
            .position(|&c| c == axis)
            .map(|j| format!("JOINT_{j}"));
        let get = |key: &str| -> Option<f64> {
            ini.get(&axis_section, key)
                .or_else(|| joint_section.as_deref().and_then(|j| ini.get(j, key)))
                .and_then(|v| v.parse().ok())
        };
        let _ = writeln!(out, "\n[machine.{}]", axis.to_ascii_lowercase());
        if let Some(v) = get("MAX_VELOCITY") {
            let _ = writeln!(out, "max-velocity = {}", number(v * 60.0));
            found = true;
        }
        if let Some(v) = get("MAX_ACCELERATION") {
            let _ = writeln!(out, "max-acceleration = {}", number(v));
            found = true;
        }
        if let (Some(min), Some(max)) = (get("MIN_LIMIT"), get("MAX_LIMIT")) {
            let _ = writeln!(out, "min = {}\nmax = {}", number(min), number(max));
        }
    }
    match found {
        true => Ok(out),
        false => Err("no [AXIS_X]/[JOINT_0] MAX_VELOCITY or MAX_ACCELERATION in the INI".into()),
    }
}

/// A number as TOML writes a float: always with a point.
fn number(v: f64) -> String {
    let text = format!("{v}");
    match text.contains(['.', 'e', 'i', 'N']) {
        true => text,
        false => format!("{text}.0"),
    }
}

/// An INI file's `KEY = value` lines by section; of a key written twice
/// the first is taken, as LinuxCNC's reader takes it.
struct Ini<'a> {
    entries: Vec<(&'a str, &'a str, &'a str)>,
}

impl<'a> Ini<'a> {
    fn parse(text: &'a str) -> Ini<'a> {
        let mut section = "";
        let mut entries = Vec::new();
        for line in text.lines().map(str::trim) {
            if line.starts_with('#') || line.starts_with(';') || line.is_empty() {
                continue;
            }
            if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                section = name.trim();
            } else if let Some((key, value)) = line.split_once('=') {
                let value = value.split('#').next().unwrap_or("").trim();
                entries.push((section, key.trim(), value));
            }
        }
        Ini { entries }
    }

    fn get(&self, section: &str, key: &str) -> Option<&'a str> {
        self.entries
            .iter()
            .find(|(s, k, _)| s.eq_ignore_ascii_case(section) && k.eq_ignore_ascii_case(key))
            .map(|(_, _, v)| *v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn machine(text: &str) -> Result<Machine, String> {
        #[derive(Deserialize)]
        struct File {
            machine: MachineTable,
        }
        let at = Locator::new(0, text);
        let file: File = toml::from_str(text).map_err(|e| e.message().to_string())?;
        file.machine
            .checked(&at)
            .map_err(|d| format!("{} errors", d.len()))
    }

    #[test]
    fn a_grbl_dump_imports_as_a_table_that_reads_back() {
        let dump = "$0=10\n$11=0.010\n$12=0.002\n$13=0\n$100=250.000\n$101=250.000\n\
                    $102=800.5\n$110=5000.000\n$111=5000.000\n\
                    $112=500.000\n$120=250.000\n$121=250.000\n$122=50.000\n$130=300.000\n\
                    $131=200.000\n$132=80.000\nok\n";
        assert_eq!(
            ImportFormat::of_text(dump),
            Some(ImportFormat::GrblSettings)
        );
        let table = import(dump, ImportFormat::GrblSettings).unwrap();
        let m = machine(&table).unwrap();
        assert_eq!(m.controller, Controller::Grbl);
        assert_eq!(m.junction_deviation, Some(0.01));
        assert_eq!(m.axes[2].max_velocity, Some(500.0));
        assert_eq!(m.axes[0].max_acceleration, Some(250.0));
        assert_eq!(m.axes[1].travel, Some((-200.0, 0.0)));
        assert_eq!(m.axes[0].steps_per_mm, Some(250.0));
        assert_eq!(m.axes[2].steps_per_mm, Some(800.5));
    }

    #[test]
    fn a_linuxcnc_ini_imports_per_minute_in_its_units() {
        let ini = "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = inch\n\n[AXIS_X]\n\
                   MAX_VELOCITY = 2.5\nMAX_ACCELERATION = 20.0\nMIN_LIMIT = -0.001\n\
                   MAX_LIMIT = 12.0\n[JOINT_2]\nMAX_VELOCITY = 1 # slow Z\nMAX_ACCELERATION = 10\n";
        assert_eq!(ImportFormat::of_text(ini), Some(ImportFormat::LinuxCncIni));
        let table = import(ini, ImportFormat::LinuxCncIni).unwrap();
        let m = machine(&table).unwrap();
        assert_eq!(m.controller, Controller::LinuxCnc);
        // 2.5 in/s = 150 in/min = 3810 mm/min.
        assert!((m.axes[0].max_velocity.unwrap() - 3810.0).abs() < 1e-9);
        assert!((m.axes[2].max_velocity.unwrap() - 60.0 * 25.4).abs() < 1e-9);
        assert_eq!(m.axes[0].travel, Some((-0.001 * 25.4, 12.0 * 25.4)));
        assert_eq!(m.axes[1], Axis::default());
        assert_eq!((m.max_velocity, m.max_acceleration), (None, None));
    }

    #[test]
    fn a_linuxcnc_ini_imports_its_path_limits() {
        let axes = "\n[AXIS_X]\nMAX_VELOCITY = 50\nMAX_ACCELERATION = 500\n";
        let ini = format!(
            "[TRAJ]\nLINEAR_UNITS = mm\nMAX_LINEAR_VELOCITY = 20\n\
             MAX_LINEAR_ACCELERATION = 100\nMAX_VELOCITY = 99\n{axes}"
        );
        let m = machine(&import(&ini, ImportFormat::LinuxCncIni).unwrap()).unwrap();
        assert_eq!(
            (m.max_velocity, m.max_acceleration),
            (Some(1200.0), Some(100.0))
        );
        assert_eq!(m.axes[0].max_velocity, Some(3000.0));
        // An older INI's names; inches as the axes' are.
        let old =
            format!("[TRAJ]\nLINEAR_UNITS = inch\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\n{axes}");
        let m = machine(&import(&old, ImportFormat::LinuxCncIni).unwrap()).unwrap();
        assert!((m.max_velocity.unwrap() - 60.0 * 25.4).abs() < 1e-9);
        assert!((m.max_acceleration.unwrap() - 254.0).abs() < 1e-9);
    }

    #[test]
    fn wrong_values_and_keys_are_refused() {
        let base = "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n";
        assert!(machine(&format!("{base}junction-deviation = -1\n")).is_err());
        assert!(machine(&format!("{base}[machine.x]\nmin = 5\nmax = 1\n")).is_err());
        assert!(machine(&format!("{base}[machine.x]\nmin = 5\n")).is_err());
        assert!(machine(&format!("{base}planner-blocks = 0\n")).is_err());
        assert!(machine(&format!("{base}planner-blocks = 10000\n")).is_ok());
        // The planner holds its window in memory: a bound, not an abort.
        assert!(machine(&format!("{base}planner-blocks = 4000000000\n")).is_err());
        assert!(machine(&format!("{base}acceleration = 5\n")).is_err());
        assert!(machine("[machine]\ncontroller = \"mach4\"\nunits = \"mm\"\n").is_err());
        let inch =
            machine(&format!("{base}[machine.z]\nmax-velocity = 100\n").replace("mm", "inch"));
        assert_eq!(inch.unwrap().axes[2].max_velocity, Some(2540.0));
        // Steps are per mm whatever the table's units; grbl's only.
        let steps = format!("{base}[machine.x]\nsteps-per-mm = 80\n").replace("mm\"", "inch\"");
        assert_eq!(machine(&steps).unwrap().axes[0].steps_per_mm, Some(80.0));
        assert!(machine(&format!("{base}[machine.x]\nsteps-per-mm = 0\n")).is_err());
        let linuxcnc =
            format!("{base}[machine.x]\nsteps-per-mm = 80\n").replace("grbl", "linuxcnc");
        assert!(machine(&linuxcnc).is_err());
    }

    #[test]
    fn a_key_of_the_other_controller_is_refused() {
        let grbl = "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\n";
        let linuxcnc = grbl.replace("grbl", "linuxcnc");
        for key in ["junction-deviation = 5", "arc-tolerance = 0.1"] {
            assert!(machine(&format!("{grbl}{key}\n")).is_ok(), "{key}");
            assert!(machine(&format!("{linuxcnc}{key}\n")).is_err(), "{key}");
        }
        assert!(machine(&format!("{linuxcnc}path-tolerance = 5\n")).is_ok());
        assert!(machine(&format!("{grbl}path-tolerance = 5\n")).is_err());
        for key in ["max-velocity = 1200", "max-acceleration = 100"] {
            assert!(machine(&format!("{linuxcnc}{key}\n")).is_ok(), "{key}");
            assert!(machine(&format!("{grbl}{key}\n")).is_err(), "{key}");
        }
        // The look-ahead's depth is both planners'.
        for base in [grbl, &linuxcnc] {
            assert!(machine(&format!("{base}planner-blocks = 16\n")).is_ok());
        }
    }
}
