//! The project file `ger.toml` (SPEC §9): found from the program's folder
//! upward, as `rustfmt.toml` is; `[compile]` holds compile options by
//! their long names, `[machine]` the machine the program runs on. A wrong
//! key or value is an error at its line of the file. Read through the
//! [`FileSystem`] view, like everything a compile reads; paths in it are
//! relative to its folder.

use super::discovery::Search;
use super::fs::FileSystem;
use super::options::{usable_tolerance, CompileOptions, OptionError};
use crate::diagnostic::Diagnostic;
use crate::emit::{ArcFormat, Numbering, Target, MOST_DECIMALS};
use crate::eval::Flavour;
use crate::ir::Units;
use crate::source::{FileId, Sources};
use crate::syntax::Language;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// The project file's name.
pub const FILE_NAME: &str = "ger.toml";

/// At most this many folders are looked through upward.
const MOST_FOLDERS: usize = 64;

/// A project file read: where it is, and what it says.
#[derive(Clone, Debug, Default)]
pub struct Project {
    pub path: PathBuf,
    /// The file in the sources it was read into (for its diagnostics).
    pub file: FileId,
    pub compile: CompileTable,
    pub machine: Option<super::machine::Machine>,
}

/// `[compile]`: each key a compile option's long name (`tool-table` or
/// `tool_table`); `None` where the file does not say.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct CompileTable {
    pub target: Option<TargetKey>,
    pub from: Option<FromKey>,
    pub input: Option<InputKey>,
    pub units: Option<UnitsKey>,
    #[serde(alias = "tool_table")]
    pub tool_table: Option<PathBuf>,
    /// The tool table's units (a LinuxCNC table is in the machine's).
    #[serde(alias = "tool_units")]
    pub tool_units: Option<UnitsKey>,
    pub arcs: Option<ArcsKey>,
    /// Spanned: a wrong value is an error at its line ([`checked`]).
    ///
    /// [`checked`]: CompileTable::checked
    pub tolerance: Option<Spanned<f64>>,
    pub decimals: Option<Spanned<usize>>,
    /// Spanned: kept with a target that cannot keep them, an error at
    /// their line ([`configure`]).
    pub cycles: Option<Spanned<CyclesKey>>,
    pub comp: Option<Spanned<CompKey>>,
    #[serde(alias = "comp_entry")]
    pub comp_entry: Option<CompEntryKey>,
    pub numbers: Option<NumbersKey>,
    pub comments: Option<CommentsKey>,
    #[serde(alias = "max_iterations")]
    pub max_iterations: Option<u64>,
    /// Folders of wizards, searched first.
    pub wizards: Option<Vec<PathBuf>>,
    /// Folders of LinuxCNC subroutine files.
    pub subroutines: Option<Vec<PathBuf>>,
}

/// The values of `[compile]`'s keys, as the command line spells them.
macro_rules! keys {
    ($name:ident { $($variant:ident = $text:literal),* $(,)? }) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
        pub enum $name {
            $(#[serde(rename = $text)] $variant,)*
        }
    };
}

keys!(TargetKey { Generic = "generic", Fanuc = "fanuc", Grbl = "grbl", LinuxCnc = "linuxcnc" });
keys!(FromKey { Generic = "generic", LinuxCnc = "linuxcnc", Fanuc = "fanuc", Grbl = "grbl", Mach3 = "mach3" });
keys!(InputKey { Egc = "egc", Gcode = "gcode" });
keys!(UnitsKey { Mm = "mm", Inch = "inch" });
keys!(ArcsKey { Ij = "ij", R = "r", Lines = "lines", Fit = "fit", FitR = "fit-r" });
keys!(CyclesKey { Expand = "expand", Keep = "keep" });
keys!(CompKey { Resolve = "resolve", Keep = "keep" });
keys!(CompEntryKey { Rs274 = "rs274", Lookahead = "lookahead" });
keys!(NumbersKey { Source = "source", Seq = "seq", Keep = "keep", None = "none" });
keys!(CommentsKey { Keep = "keep", Drop = "drop" });

/// The whole file, for serde.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProjectFile {
    #[serde(default)]
    compile: CompileTable,
    machine: Option<super::machine::MachineTable>,
}

/// The project file for a program at `part` (or in the folder `start`):
/// the first `ger.toml` in its folder or a folder above it.
pub fn find(fs: &dyn FileSystem, start: &Path) -> Option<PathBuf> {
    let mut folder = Some(start);
    for _ in 0..MOST_FOLDERS {
        let here = folder?;
        let candidate = here.join(FILE_NAME);
        if fs.is_file(&candidate) {
            return Some(candidate);
        }
        folder = here.parent();
    }
    None
}

/// Read the project file at `path`, added to `sources` (its errors point
/// into it). `Err`: the diagnostics, or why it could not be read.
pub fn read(
    fs: &dyn FileSystem,
    sources: &mut Sources,
    path: &Path,
) -> Result<Project, ProjectError> {
    let bytes = fs
        .read(path)
        .map_err(|e| ProjectError::Unread(format!("cannot read `{}`: {e}", path.display())))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| ProjectError::Unread(format!("`{}` is not UTF-8 text", path.display())))?;
    let file = sources.add(path.display().to_string(), text);
    let parsed: ProjectFile = toml::from_str(sources.text(file))
        .map_err(|e| ProjectError::Invalid(vec![toml_diagnostic(sources, file, &e)]))?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let locator = sources.locator(file);
    let mut wrong = parsed.compile.wrong_values(&locator);
    let machine = match parsed.machine.map(|table| table.checked(&locator)) {
        Some(Err(more)) => {
            wrong.extend(more);
            None
        }
        Some(Ok(machine)) => Some(machine),
        None => None,
    };
    if !wrong.is_empty() {
        return Err(ProjectError::Invalid(wrong));
    }
    let mut compile = parsed.compile;
    let within = |p: &PathBuf| folder.join(p);
    compile.tool_table = compile.tool_table.as_ref().map(within);
    compile.wizards = compile
        .wizards
        .map(|dirs| dirs.iter().map(within).collect());
    compile.subroutines = compile
        .subroutines
        .map(|dirs| dirs.iter().map(within).collect());
    Ok(Project {
        path: path.to_path_buf(),
        file,
        compile,
        machine,
    })
}

/// Put the `[compile]` of the project file found from the folder `start`
/// upward (if any) into `options` and `search`, less the keys `given` says
/// the caller set; the project read. `Err`: its problems, shown with the
/// sources given back.
pub fn configure(
    fs: &dyn FileSystem,
    start: &Path,
    options: &mut CompileOptions,
    search: &mut Search,
    given: &dyn Fn(&str) -> bool,
) -> Result<Option<Project>, (Sources, ProjectError)> {
    let Some(path) = find(fs, start) else {
        return Ok(None);
    };
    let mut sources = Sources::new();
    match read(fs, &mut sources, &path) {
        Ok(project) => {
            project.compile.apply(options, search, given);
            let kept = project.compile.kept_without(options, given);
            if let Some((span, message)) = kept {
                let span = sources.locator(project.file).span(span.start, span.end);
                let wrong =
                    crate::diagnostic::error(format!("{FILE_NAME}: {message}"), span, "here");
                return Err((sources, ProjectError::Invalid(vec![wrong])));
            }
            if let Some(machine) = &project.machine {
                let travel = machine.axes.map(|a| a.travel);
                options.travel = travel.iter().any(Option::is_some).then_some(travel);
            }
            Ok(Some(project))
        }
        Err(e) => Err((sources, e)),
    }
}

/// Why a project file could not be had.
#[derive(Debug)]
pub enum ProjectError {
    Unread(String),
    /// Wrong keys or values, at their lines.
    Invalid(Vec<Diagnostic>),
}

/// A TOML error at its place in the file.
fn toml_diagnostic(sources: &Sources, file: FileId, error: &toml::de::Error) -> Diagnostic {
    let range = error.span().unwrap_or(0..0);
    let span = sources.locator(file).span(range.start, range.end);
    let message = error.message().trim_end();
    crate::diagnostic::error(format!("{FILE_NAME}: {message}"), span, "here")
}

impl CompileTable {
    /// Each value no compile can run with, an error at its line (the
    /// limits `CompileOptions::validate` holds the command line's flags
    /// to, there reported by the flags' names).
    fn wrong_values(&self, at: &crate::source::Locator) -> Vec<Diagnostic> {
        let mut wrong = Vec::new();
        let mut refuse = |span: std::ops::Range<usize>, message: &str| {
            let span = at.span(span.start, span.end);
            let message = format!("{FILE_NAME}: {message}");
            wrong.push(crate::diagnostic::error(message, span, "here"));
        };
        if let Some(t) = self.tolerance.as_ref() {
            if !usable_tolerance(*t.get_ref()) {
                refuse(t.span(), "`tolerance` must be a positive number");
            }
        }
        if let Some(d) = self
            .decimals
            .as_ref()
            .filter(|d| *d.get_ref() > MOST_DECIMALS)
        {
            refuse(
                d.span(),
                &format!("`decimals` must be at most {MOST_DECIMALS}"),
            );
        }
        wrong
    }

    /// The file's `cycles = "keep"` or `comp = "keep"` (not overridden on
    /// the command line) where the options it ends in are refused for it
    /// ([`CompileOptions::validate`]): where it is, and why.
    fn kept_without(
        &self,
        options: &CompileOptions,
        given: &dyn Fn(&str) -> bool,
    ) -> Option<(std::ops::Range<usize>, &'static str)> {
        let (span, key, why) = match options.validate() {
            Err(OptionError::CyclesKeptWithout) => (
                self.cycles.as_ref().map(Spanned::span),
                "cycles",
                "`cycles = \"keep\"` needs a controller that runs canned cycles: target fanuc or linuxcnc",
            ),
            Err(OptionError::CompKeptWithout) => (
                self.comp.as_ref().map(Spanned::span),
                "comp",
                "`comp = \"keep\"` needs a controller that compensates: target fanuc or linuxcnc",
            ),
            _ => return None,
        };
        Some((span.filter(|_| !given(key))?, why))
    }

    /// Put the file's options into `options` and `search`, except those
    /// `given` says the command line set (`given("target")`, by the long
    /// name): a flag on the command line wins over the file.
    pub fn apply(
        &self,
        options: &mut CompileOptions,
        search: &mut Search,
        given: &dyn Fn(&str) -> bool,
    ) {
        let take = |key: &str| !given(key);
        if let Some(v) = self.target.filter(|_| take("target")) {
            options.emit.target = match v {
                TargetKey::Generic => Target::Generic,
                TargetKey::Fanuc => Target::Fanuc,
                TargetKey::Grbl => Target::Grbl,
                TargetKey::LinuxCnc => Target::LinuxCnc,
            };
        }
        if let Some(v) = self.from.filter(|_| take("from")) {
            options.from = Some(match v {
                FromKey::Generic => Flavour::Generic,
                FromKey::LinuxCnc => Flavour::LinuxCnc,
                FromKey::Fanuc => Flavour::Fanuc,
                FromKey::Grbl => Flavour::Grbl,
                FromKey::Mach3 => Flavour::Mach3,
            });
        }
        if let Some(v) = self.input.filter(|_| take("input")) {
            options.input = Some(match v {
                InputKey::Egc => Language::Egc,
                InputKey::Gcode => Language::Gcode,
            });
        }
        let units = |v: UnitsKey| match v {
            UnitsKey::Mm => Units::Mm,
            UnitsKey::Inch => Units::Inch,
        };
        if let Some(v) = self.units.filter(|_| take("units")) {
            options.eval.units = Some(units(v));
        }
        if let Some(v) = self.tool_units.filter(|_| take("tool-units")) {
            options.eval.tool_units = Some(units(v));
        }
        self.apply_output(options, &take);
        if let Some(v) = self.max_iterations.filter(|_| take("max-iterations")) {
            options.eval.max_iterations = v;
        }
        if let Some(v) = self.tool_table.as_ref().filter(|_| take("tool-table")) {
            search.tool_table = Some(v.clone());
        }
        if let Some(v) = self.wizards.as_ref().filter(|_| take("wizards")) {
            search.wizard_dirs = v.clone();
        }
        if let Some(v) = self.subroutines.as_ref().filter(|_| take("subroutines")) {
            search.subroutine_dirs = v.clone();
        }
    }

    /// The keys of how the output is written and lowered.
    fn apply_output(&self, options: &mut CompileOptions, take: &dyn Fn(&str) -> bool) {
        if let Some(v) = self.arcs.filter(|_| take("arcs")) {
            options.emit.arcs = match v {
                ArcsKey::Ij => ArcFormat::Ij,
                ArcsKey::R => ArcFormat::R,
                ArcsKey::Lines => ArcFormat::Lines,
                ArcsKey::Fit => ArcFormat::Fit,
                ArcsKey::FitR => ArcFormat::FitR,
            };
        }
        if let Some(v) = self.tolerance.as_ref().filter(|_| take("tolerance")) {
            options.emit.tolerance = Some(*v.get_ref());
        }
        if let Some(v) = self.decimals.as_ref().filter(|_| take("decimals")) {
            options.emit.decimals = Some(*v.get_ref());
        }
        if let Some(v) = self.numbers.filter(|_| take("numbers")) {
            options.emit.numbering = match v {
                NumbersKey::Source => Numbering::Source,
                NumbersKey::Seq => Numbering::Seq,
                NumbersKey::Keep => Numbering::Keep,
                NumbersKey::None => Numbering::None,
            };
        }
        if let Some(v) = self.comments.filter(|_| take("comments")) {
            options.eval.keep_comments = v == CommentsKey::Keep;
        }
        if let Some(v) = self.cycles.as_ref().filter(|_| take("cycles")) {
            options.lower.keep_cycles = *v.get_ref() == CyclesKey::Keep;
        }
        if let Some(v) = self.comp.as_ref().filter(|_| take("comp")) {
            options.lower.keep_comp = *v.get_ref() == CompKey::Keep;
        }
        if let Some(v) = self.comp_entry.filter(|_| take("comp-entry")) {
            options.lower.comp_entry_lookahead = v == CompEntryKey::Lookahead;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::fs::Memory;

    fn read_text(text: &str) -> Result<Project, ProjectError> {
        let mut fs = Memory::new();
        fs.insert("/shop/jobs/ger.toml", text);
        read(&fs, &mut Sources::new(), Path::new("/shop/jobs/ger.toml"))
    }

    #[test]
    fn the_file_is_found_upward_and_its_paths_are_its_folders() {
        let mut fs = Memory::new();
        fs.insert("/shop/ger.toml", "[compile]\ntool-table = \"tools.tbl\"\n");
        fs.insert("/shop/jobs/a/part.nc", "G0 X1");
        let found = find(&fs, Path::new("/shop/jobs/a"));
        assert_eq!(found.as_deref(), Some(Path::new("/shop/ger.toml")));
        assert_eq!(find(&fs, Path::new("/elsewhere")), None);
        let project = read(&fs, &mut Sources::new(), &found.unwrap())
            .ok()
            .unwrap();
        let table = project.compile.tool_table;
        assert_eq!(table.as_deref(), Some(Path::new("/shop/tools.tbl")));
    }

    #[test]
    fn a_flag_on_the_command_line_wins_over_the_file() {
        let project =
            read_text("[compile]\ntarget = \"grbl\"\ndecimals = 4\ncomp_entry = \"lookahead\"\n")
                .ok()
                .unwrap();
        let (mut options, mut search) = (CompileOptions::default(), Search::default());
        project
            .compile
            .apply(&mut options, &mut search, &|key| key == "decimals");
        assert_eq!(options.emit.target, Target::Grbl);
        assert_eq!(options.emit.decimals, None);
        assert!(options.lower.comp_entry_lookahead);
    }

    #[test]
    fn a_wrong_key_or_value_is_an_error_at_its_line() {
        for (text, line) in [
            ("[compile]\ntarget = \"grbl\"\ntargets = \"fanuc\"\n", 3),
            ("[compile]\n\narcs = \"spline\"\n", 3),
            ("[compile]\ndecimals = -2\n", 2),
            ("[compile]\ntarget = \"grbl\"\ndecimals = 12\n", 3),
            ("[compile]\n\ntolerance = -1\n", 3),
            ("[compile]\ntolerance = 0.0\n", 2),
            ("[compile]\ntolerance = nan\n", 2),
            (
                "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\nrapid-rate = 0\n",
                4,
            ),
            ("[compiler]\n", 1),
        ] {
            match read_text(text) {
                Err(ProjectError::Invalid(d)) => {
                    let lines: Vec<_> = d[0].labels.iter().map(|l| l.range.start).collect();
                    let at = text[..lines[0]].matches('\n').count() + 1;
                    assert_eq!(at, line, "{text}: {:?}", d[0].message);
                }
                _ => panic!("{text} was read"),
            }
        }
    }
}
