//! The library's entry point for every caller: the binary, the tests, the
//! editor server and the studio. A [`Session`] holds the options (checked
//! once, here) and the [`FileSystem`] view; it loads a program with what
//! it needs (wizards, subroutine files, the tool table) into a [`Job`],
//! and compiles it to an [`Outcome`]: the output text, the diagnostics
//! and the tool path, each move with its source line.
//!
//! [`Session::compile`] is the binary's policy for a file to an output:
//! a program on disk is compiled from its file a part at a time (memory
//! does not grow with its length) when it can be, and again, whole, when a
//! part turns out to need the whole program.

use super::backend::Output;
use super::compile::{self, Report, Streamed};
use super::discovery::{self, Search, ToolTableError};
use super::fs::{FileSystem, Stamp};
use super::options::{CompileOptions, OptionError, Stage};
use super::output;
use super::scan::{self, FileScan};
use crate::diagnostic::Diagnostic;
use crate::eval::WizardHost;
use crate::source::{self, FileId, Sources, Span};
use crate::syntax::Language;
use crate::toolpath::{PathSink, ToolPath};
use crate::wizard::{Library, WizardEngine};
use std::io::{Seek, Write};
use std::path::Path;
use std::time::Duration;

/// Options and a file-system view, for any number of compiles.
pub struct Session<'fs> {
    fs: &'fs dyn FileSystem,
    options: CompileOptions,
    search: Search,
}

/// The program to load.
pub enum Program<'a> {
    /// A file, read through the view.
    Path(&'a Path),
    /// Text at hand: an editor's unsaved buffer (with the path it stands
    /// for, whose folder holds its wizards and subroutine files), or
    /// standard input (no path). `name` names it in diagnostics and, with
    /// no `--input`, says its language.
    Text {
        name: &'a str,
        path: Option<&'a Path>,
        text: String,
    },
}

/// Why a program could not be loaded; nothing was compiled.
pub enum LoadError {
    /// A file or folder could not be read (exit status 2).
    Unread(String),
    /// The program is not text (exit status 1).
    NotText(String),
    /// The tool table has errors at its lines (exit status 1): shown with
    /// `sources`.
    ToolTable {
        sources: Sources,
        diagnostics: Vec<Diagnostic>,
    },
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Unread(why) | LoadError::NotText(why) => f.write_str(why),
            LoadError::ToolTable {
                sources,
                diagnostics,
            } => f.write_str(&crate::diagnostic::render(sources, diagnostics)),
        }
    }
}

impl LoadError {
    /// The exit status `ger` gives it (SPEC §1).
    pub fn exit_status(&self) -> u8 {
        match self {
            LoadError::Unread(_) => 2,
            LoadError::NotText(_) | LoadError::ToolTable { .. } => 1,
        }
    }
}

/// A program loaded with everything it needs, ready to compile (as often
/// as asked: an editor compiles the same job on each request).
pub struct Job {
    /// The program, the tool table, the subroutine files and the wizards.
    pub sources: Sources,
    pub file: FileId,
    /// The session's options, with the tool table and the subroutine
    /// files filled in.
    pub options: CompileOptions,
    engine: WizardEngine,
}

/// A whole compile's result.
pub struct Outcome {
    /// The output text; `None` when there are errors.
    pub output: Option<String>,
    /// Every diagnostic, warnings included, in order.
    pub diagnostics: Vec<Diagnostic>,
    /// The tool path, each move with its source span ([`Job::line_of`]);
    /// `None` when there are errors.
    pub tool_path: Option<ToolPath>,
    pub timings: Vec<(&'static str, Duration)>,
}

/// Where [`Session::compile`] puts the output.
pub enum Destination<'a> {
    /// A file, written atomically ([`output::write_atomically`]).
    File(&'a Path),
    /// Held until the program is known whole, for the caller to copy on
    /// ([`Held::copy_to`]): what goes to standard output.
    Held,
    /// Thrown away: `ger check`.
    Nowhere,
}

/// An output held until it was known whole.
pub enum Held {
    /// In an unnamed temporary file: memory stays bounded.
    File(std::fs::File),
    Text(Vec<u8>),
}

impl Held {
    pub fn copy_to(self, out: &mut dyn Write) -> std::io::Result<()> {
        match self {
            Held::File(mut file) => {
                file.seek(std::io::SeekFrom::Start(0))?;
                std::io::copy(&mut file, out).map(|_| ())
            }
            Held::Text(text) => out.write_all(&text),
        }
    }
}

/// What [`Session::compile`] did.
pub struct Finished {
    /// The job, for showing the diagnostics with their lines.
    pub job: Job,
    pub report: Report,
    /// The output, for [`Destination::Held`], when the program compiled.
    pub held: Option<Held>,
    /// The program's file could not be read part way (exit status 2).
    pub read_error: Option<std::io::Error>,
    /// The diagnostics' lines could not be read again to show them.
    pub lines_unshown: bool,
}

/// Why one try of [`Session::compile`] must be made again (nothing was
/// written or reported).
enum Again {
    /// The program needs to be read whole.
    Whole,
    /// A part of the file was not as its first lines said
    /// ([`scan::first_look`]): it needs a scan of the whole file.
    Rescan,
}

/// A program file compiled from the file itself, as `scan` found it, with
/// the stamp it had when it was scanned.
type Streamable = (FileScan, Stamp);

impl<'fs> Session<'fs> {
    /// A session with these options (refused if no compile could run with
    /// them).
    pub fn new(
        fs: &'fs dyn FileSystem,
        options: CompileOptions,
        search: Search,
    ) -> Result<Session<'fs>, OptionError> {
        options.validate()?;
        Ok(Session {
            fs,
            options,
            search,
        })
    }

    pub fn options(&self) -> &CompileOptions {
        &self.options
    }

    /// Lower the path of the tool's tip (`LowerOptions::tip_path`), or the
    /// machine's controlled point.
    pub fn set_tip_path(&mut self, tip: bool) {
        self.options.lower.tip_path = tip;
    }

    /// Load `program` and everything it needs.
    pub fn load(&self, program: Program<'_>) -> Result<Job, LoadError> {
        match program {
            Program::Path(path) => {
                let shown = path.display().to_string();
                let bytes = self
                    .fs
                    .read(path)
                    .map_err(|e| LoadError::Unread(format!("cannot read `{shown}`: {e}")))?;
                let text = program_text(bytes, &shown)?;
                self.load_text(&shown, Some(path), text)
            }
            Program::Text { name, path, text } => self.load_text(name, path, text),
        }
    }

    /// [`Session::load`] of `text`, named `name`, standing for the file
    /// `part` (if any).
    fn load_text(&self, name: &str, part: Option<&Path>, text: String) -> Result<Job, LoadError> {
        let fs = self.fs;
        let mut sources = Sources::new();
        let file = sources.add(name, text);
        let mut options = self.options.clone();
        if let Some(path) = &self.search.tool_table {
            match discovery::tool_table(fs, &mut sources, path) {
                Ok(tools) => options.eval.tools = tools,
                Err(ToolTableError::Unread(why)) => return Err(LoadError::Unread(why)),
                Err(ToolTableError::Invalid(diagnostics)) => {
                    return Err(LoadError::ToolTable {
                        sources,
                        diagnostics,
                    })
                }
            }
        }
        if options.language(name) == Language::Gcode {
            options.library =
                discovery::subroutine_files(fs, &mut sources, file, &self.search, part)
                    .map_err(LoadError::Unread)?;
        }
        let found = discovery::wizards(fs, &self.search, part).map_err(LoadError::Unread)?;
        let engine = WizardEngine::new(Library::new(found, &mut sources));
        Ok(Job {
            sources,
            file,
            options,
            engine,
        })
    }

    /// Compile `program` into `destination`: from its file a part at a
    /// time where it can be (a plain file, no `--subroutines`, not
    /// `--stage parse`), else whole.
    pub fn compile(
        &self,
        program: Program<'_>,
        destination: Destination<'_>,
    ) -> Result<Finished, LoadError> {
        let Program::Path(path) = program else {
            return self.compile_whole(program, &destination);
        };
        // The file is read once: its first lines say how its numbers are
        // printed, and each part is checked as it is read; a file found to
        // be otherwise further on is scanned whole, and compiled again.
        if let Some(first) = self.streamable(path, scan::first_look) {
            match self.compile_streamed(path, first, &destination) {
                Ok(finished) => return finished,
                Err(Again::Rescan) => {
                    let scanned = self.streamable(path, scan::scan_path);
                    if let Some(Ok(finished)) =
                        scanned.map(|s| self.compile_streamed(path, s, &destination))
                    {
                        return finished;
                    }
                }
                Err(Again::Whole) => {}
            }
        }
        self.compile_whole(program, &destination)
    }

    /// A program file that can be compiled from the file itself, a part at
    /// a time, as `scan` found it: a plain file (a pipe cannot be read
    /// twice) whose subroutine folders need no reading. `None`: compile it
    /// whole.
    fn streamable(
        &self,
        path: &Path,
        scan: fn(&dyn FileSystem, &Path) -> std::io::Result<Option<FileScan>>,
    ) -> Option<Streamable> {
        let before = self.fs.stamp(path).ok()??;
        if self.options.stage == Some(Stage::Parse)
            || !before.plain
            || !self.search.subroutine_dirs.is_empty()
        {
            return None;
        }
        let scan = scan(self.fs, path).ok()??;
        Some((scan, before))
    }

    /// Compile the program whole, its text held.
    fn compile_whole(
        &self,
        program: Program<'_>,
        destination: &Destination<'_>,
    ) -> Result<Finished, LoadError> {
        let mut job = self.load(program)?;
        let (mut text, mut held) = (Vec::new(), None);
        let report = match destination {
            Destination::File(path) => output::write_atomically(path, |out| {
                let (sources, file, options) = (&job.sources, job.file, &job.options);
                let engine = Some(&mut job.engine as &mut dyn WizardHost);
                compile::compile_to(sources, file, options, engine, out)
            }),
            Destination::Held => {
                // Held in memory: a program found to need a whole read
                // part way is compiled again into an emptied buffer.
                let (sources, file, options) = (&job.sources, job.file, &job.options);
                let engine = Some(&mut job.engine as &mut dyn WizardHost);
                let report = compile::compile_to_vec(sources, file, options, engine, &mut text);
                held = report.succeeded().then(|| Held::Text(text));
                report
            }
            Destination::Nowhere => job.check(),
        };
        Ok(Finished {
            job,
            report,
            held,
            read_error: None,
            lines_unshown: false,
        })
    }

    /// Compile the file `path` from the file, a part at a time, as
    /// `streamed` found it.
    fn compile_streamed(
        &self,
        path: &Path,
        streamed: Streamable,
        destination: &Destination<'_>,
    ) -> Result<Result<Finished, LoadError>, Again> {
        let shown = path.display().to_string();
        let mut job = match self.load_text(&shown, Some(path), String::new()) {
            Ok(job) => job,
            Err(e) => return Ok(Err(e)),
        };
        let (mut read_error, mut again) = (None, None);
        let mut compile = |out: &mut (dyn Write + Send)| {
            let compiled = self.compile_from_file(path, &streamed, &mut job, Output::Text(out));
            let why = match compiled {
                Ok(Streamed::Compiled(report)) => return report,
                Ok(Streamed::Whole) => {
                    again = Some(Again::Whole);
                    "the program needs to be read whole"
                }
                Ok(Streamed::Rescan) => {
                    again = Some(Again::Rescan);
                    "the file needs to be scanned whole"
                }
                Err(e) => {
                    read_error = Some(e);
                    "the input could not be read"
                }
            };
            // Not a compiled program: the output is thrown away.
            Report {
                diagnostics: Vec::new(),
                timings: Vec::new(),
                write_error: Some(std::io::Error::other(why)),
            }
        };
        let mut held = None;
        let report = match destination {
            Destination::File(out) => output::write_atomically(out, compile),
            Destination::Held => {
                // Held in an unnamed file (memory bounded as with a file);
                // with no temporary file to be had, compiled whole.
                let Ok(file) = output::held_file() else {
                    return Err(Again::Whole);
                };
                compile(held.insert(file))
            }
            Destination::Nowhere => compile(&mut std::io::sink()),
        };
        // A temporary file that could not be written (a full `/tmp`): the
        // program is compiled again, into memory.
        let held_failed = held.is_some() && report.write_error.is_some();
        if let Some(again) = again {
            return Err(again);
        }
        if held_failed && read_error.is_none() {
            return Err(Again::Whole);
        }
        let held = held.filter(|_| report.succeeded()).map(Held::File);
        Ok(Ok(self.shown(path, job, report, held, read_error)))
    }

    /// What a compile from the file `path` did, the lines its diagnostics
    /// are about read again to show them.
    fn shown(
        &self,
        path: &Path,
        mut job: Job,
        report: Report,
        held: Option<Held>,
        read_error: Option<std::io::Error>,
    ) -> Finished {
        let mut lines_unshown = false;
        if read_error.is_none() && !report.diagnostics.is_empty() {
            let shown = self
                .fs
                .open(path)
                .and_then(|mut file| scan::lines_shown(&mut file, job.file, &report.diagnostics));
            match shown {
                Ok(lines) => job.sources.set_lines(job.file, lines),
                Err(_) => lines_unshown = true,
            }
        }
        Finished {
            job,
            report,
            held,
            read_error,
            lines_unshown,
        }
    }

    /// The tool path of `program` handed to `sink` move by move, never
    /// held (`ger stats`): read as [`Session::compile`] reads it, from its
    /// file a part at a time where it can be, else whole (`sink` is
    /// restarted before a second reading).
    pub fn feed_tool_path(
        &self,
        program: Program<'_>,
        sink: &mut dyn PathSink,
    ) -> Result<Finished, LoadError> {
        if let Program::Path(path) = program {
            if let Some(first) = self.streamable(path, scan::first_look) {
                match self.feed_streamed(path, first, sink) {
                    Ok(finished) => return finished,
                    Err(Again::Rescan) => {
                        sink.restart();
                        let scanned = self.streamable(path, scan::scan_path);
                        if let Some(Ok(finished)) =
                            scanned.map(|s| self.feed_streamed(path, s, sink))
                        {
                            return finished;
                        }
                    }
                    Err(Again::Whole) => {}
                }
                sink.restart();
            }
        }
        let mut job = self.load(program)?;
        let diagnostics = job.feed_tool_path(sink);
        Ok(Finished {
            job,
            report: Report {
                diagnostics,
                timings: Vec::new(),
                write_error: None,
            },
            held: None,
            read_error: None,
            lines_unshown: false,
        })
    }

    /// [`Session::feed_tool_path`] from the file `path`, a part at a time.
    fn feed_streamed(
        &self,
        path: &Path,
        streamed: Streamable,
        sink: &mut dyn PathSink,
    ) -> Result<Result<Finished, LoadError>, Again> {
        let shown = path.display().to_string();
        let mut job = match self.load_text(&shown, Some(path), String::new()) {
            Ok(job) => job,
            Err(e) => return Ok(Err(e)),
        };
        // A path is the program's whole meaning, whatever stage is asked.
        job.options.stage = None;
        let fed = self.compile_from_file(path, &streamed, &mut job, Output::Moves(sink));
        let (report, read_error) = match fed {
            Ok(Streamed::Compiled(report)) => (report, None),
            Ok(Streamed::Whole) => return Err(Again::Whole),
            Ok(Streamed::Rescan) => return Err(Again::Rescan),
            Err(e) => {
                let report = Report {
                    diagnostics: Vec::new(),
                    timings: Vec::new(),
                    write_error: None,
                };
                (report, Some(e))
            }
        };
        Ok(Ok(self.shown(path, job, report, None, read_error)))
    }

    /// Compile the file `path` from the file a part at a time
    /// ([`Session::streamable`]); an error if it cannot be read or changed
    /// since it was scanned.
    fn compile_from_file<'o>(
        &self,
        path: &Path,
        (scan, before): &Streamable,
        job: &'o mut Job,
        out: Output<'o>,
    ) -> std::io::Result<Streamed> {
        let mut reader = self.fs.open(path)?;
        let name = job.sources.name(job.file).to_string();
        let (file, options) = (job.file, &job.options);
        let engine = Some(&mut job.engine as &mut dyn WizardHost);
        let source = (
            &mut reader as &mut dyn std::io::BufRead,
            name.as_str(),
            file,
            *scan,
        );
        let compiled = compile::file_to(source, options, engine, out)?;
        let Streamed::Compiled(report) = compiled else {
            return Ok(compiled);
        };
        let stamp = |s: &Stamp| (s.len, s.modified);
        match self.fs.stamp(path)? {
            Some(now) if stamp(&now) == stamp(before) => Ok(Streamed::Compiled(report)),
            _ => Err(std::io::Error::other("it changed while it was compiled")),
        }
    }
}

/// A program's bytes (named `shown`) as text, or why they are not: for
/// a file read through the view, and for standard input the caller read.
pub fn program_text(bytes: Vec<u8>, shown: &str) -> Result<String, LoadError> {
    source::decode(bytes).map_err(|why| {
        let (what, at) = match why {
            source::NotText::Nul(at) => ("a NUL byte", at),
            source::NotText::Control(at) => ("a control character", at),
        };
        LoadError::NotText(format!(
            "`{shown}` is not a text file: {what} at byte {at}\n  = note: ger reads G-code programs as text (UTF-8 or Latin-1)"
        ))
    })
}

impl Job {
    /// The wizards, as the compile calls them.
    pub fn host(&mut self) -> Option<&mut dyn WizardHost> {
        Some(&mut self.engine as &mut dyn WizardHost)
    }

    /// The output text, the diagnostics and the tool path.
    pub fn outcome(&mut self) -> Outcome {
        let compiled = self.compile();
        let tool_path = match compiled.output {
            // The tool path of a program that compiled: its moves, cycles
            // expanded and compensation resolved whatever the options keep.
            Some(_) => self.tool_path().0,
            None => None,
        };
        Outcome {
            output: compiled.output,
            diagnostics: compiled.diagnostics,
            tool_path,
            timings: compiled.timings,
        }
    }

    /// The output text and the diagnostics.
    pub fn compile(&mut self) -> compile::Compiled {
        let (sources, file, options) = (&self.sources, self.file, &self.options);
        compile::compile(sources, file, options, Some(&mut self.engine))
    }

    /// The diagnostics only (the output thrown away as it is made).
    pub fn check(&mut self) -> Report {
        let (sources, file, options) = (&self.sources, self.file, &self.options);
        compile::check(sources, file, options, Some(&mut self.engine))
    }

    /// The tool path (`None` when there are errors) and the diagnostics.
    pub fn tool_path(&mut self) -> (Option<ToolPath>, Vec<Diagnostic>) {
        let (sources, file, options) = (&self.sources, self.file, &self.options);
        compile::tool_path(sources, file, options, Some(&mut self.engine))
    }

    /// The tool path handed to `sink` move by move, never held whole
    /// (`ger stats`); the diagnostics.
    pub fn feed_tool_path(&mut self, sink: &mut dyn crate::toolpath::PathSink) -> Vec<Diagnostic> {
        let (sources, file, options) = (&self.sources, self.file, &self.options);
        compile::feed_tool_path(sources, file, options, Some(&mut self.engine), sink)
    }

    /// The values variables have where the program reads and sets them
    /// (the editor's hover; no compile records them).
    pub fn watch(&mut self) -> crate::eval::Watched {
        let (sources, file, options) = (&self.sources, self.file, &self.options);
        compile::watch(sources, file, options, Some(&mut self.engine))
    }

    /// The file name and 1-based line of a span (a move's, a
    /// diagnostic's).
    pub fn line_of(&self, span: Span) -> (&str, usize) {
        (self.sources.name(span.file_id()), span.line as usize)
    }

    /// The wizard library the program sees (`ger wizards`, completion).
    pub fn wizards(&self) -> &Library {
        self.engine.library()
    }
}
