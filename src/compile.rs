//! The driver: source text → G-code text, through the stages in order
//! (parse, expand, lowering passes, emit). It is the library's one entry
//! point for a whole compile; it does no I/O of its own, and writes only to
//! the `Write` it is handed.

use crate::ast::Names;
use crate::diagnostic::{is_error, Diagnostic};
use crate::emit::{self, EmitOptions};
use crate::eval::{self, EvalOptions, WizardHost};
use crate::ir;
use crate::lower::{self, Pipeline};
use crate::source::{self, FileId, Locator, Sources, BLOCK};
use crate::syntax::egc::{chunk, Language};
use crate::toolpath::{Builder as ToolPathBuilder, ToolPath};
use std::io::Write;
use std::sync::{mpsc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// The stages of SPEC §4, in order; `--stage NAME` stops after one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    /// The parsed program, normalised (no evaluation).
    Parse,
    Expand,
    /// After the pass of this index in [`lower::PASSES`].
    Lower(usize),
}

impl Stage {
    /// Every stage name, in order.
    pub fn names() -> impl Iterator<Item = &'static str> {
        ["parse", "expand"]
            .into_iter()
            .chain(lower::PASSES.iter().map(|p| p.name))
    }

    pub fn from_name(name: &str) -> Option<Stage> {
        match name.to_ascii_lowercase().as_str() {
            "parse" => Some(Stage::Parse),
            "expand" => Some(Stage::Expand),
            _ => lower::pass_index(name).map(Stage::Lower),
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    pub eval: EvalOptions,
    /// The source language (`--input`); `None`: from the file name.
    pub input: Option<crate::syntax::egc::Language>,
    /// `--from`; `None`: from the file name (`.ngc` is LinuxCNC's).
    pub from: Option<eval::Flavour>,
    pub emit: EmitOptions,
    pub lower: lower::LowerOptions,
    /// Print the program after this stage instead of the final output.
    pub stage: Option<Stage>,
    /// Files of LinuxCNC subroutines (`o<name> sub` … `endsub`) the
    /// program calls but does not hold; the caller found and read them.
    pub library: Vec<FileId>,
}

impl CompileOptions {
    /// The language of the file `name`: `--input`, else its name's.
    pub fn language(&self, name: &str) -> Language {
        self.input.unwrap_or_else(|| Language::of_file(name))
    }

    /// Whose meaning holds for the file `name`: `--from`, else its name's.
    fn flavour(&self, name: &str) -> eval::Flavour {
        self.from.unwrap_or_else(|| eval::Flavour::of_file(name))
    }

    /// The evaluator's options for a file in `language` read as `from`.
    fn eval_options(&self, from: eval::Flavour, language: Language) -> EvalOptions {
        EvalOptions {
            from,
            plain: language == Language::Gcode,
            ..self.eval.clone()
        }
    }
}

/// The result of a compile: the text (absent when there are errors) and
/// every diagnostic, warnings included.
pub struct Compiled {
    pub output: Option<String>,
    pub diagnostics: Vec<Diagnostic>,
    /// Time spent in each stage, in order (`ger compile --timings`).
    pub timings: Vec<(&'static str, Duration)>,
}

/// What [`compile_to`] reports: every diagnostic, warnings included, the
/// time spent in each stage, and the first write that failed.
pub struct Report {
    pub diagnostics: Vec<Diagnostic>,
    pub timings: Vec<(&'static str, Duration)>,
    /// Nothing more was written after it.
    pub write_error: Option<std::io::Error>,
}

impl Report {
    /// No errors in the program.
    pub fn compiled(&self) -> bool {
        !self.diagnostics.iter().any(is_error)
    }

    /// No errors, and what was written is the whole program.
    pub fn succeeded(&self) -> bool {
        self.compiled() && self.write_error.is_none()
    }
}

/// Times the stages of one compile.
struct Clock {
    last: Instant,
    timings: Vec<(&'static str, Duration)>,
    /// Time the next lap spent on a stage reported apart.
    inside: Duration,
}

impl Clock {
    fn new() -> Clock {
        Clock {
            last: Instant::now(),
            timings: Vec::new(),
            inside: Duration::ZERO,
        }
    }

    fn lap(&mut self, stage: &'static str) {
        self.split(stage, &[]);
    }

    /// A lap that ran `parts` inside it: they are reported after it, and
    /// its own time without them.
    fn split(&mut self, stage: &'static str, parts: &[(&'static str, Duration)]) {
        let now = Instant::now();
        let inner =
            parts.iter().map(|(_, d)| *d).sum::<Duration>() + std::mem::take(&mut self.inside);
        self.timings
            .push((stage, (now - self.last).saturating_sub(inner)));
        self.timings.extend_from_slice(parts);
        self.last = now;
    }

    /// Time the next lap spends on a stage reported apart (the passes the
    /// evaluator's thread runs, reported with the lowering).
    fn ran_inside(&mut self, took: Duration) {
        self.inside += took;
    }

    /// Stages timed on another thread, at the same time as the last lap:
    /// reported, not taken from it.
    fn add(&mut self, stages: &[(&'static str, Duration)]) {
        self.timings.extend_from_slice(stages);
    }
}

/// Compile the file `file` of `sources` to a string.
pub fn compile(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> Compiled {
    let mut text = Vec::new();
    // Writing to a Vec cannot fail.
    let report = compile_to_vec(sources, file, options, wizards, &mut text);
    let output = report.succeeded().then(|| {
        String::from_utf8(text)
            .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
    });
    Compiled {
        output,
        diagnostics: report.diagnostics,
        timings: report.timings,
    }
}

/// Compile the file `file` of `sources`, writing the output to `out` as it
/// is made (once the output units are known, memory does not grow with the
/// program's length). When the report has errors what was written is
/// incomplete: the caller must throw it away (`ger` writes to a temporary
/// file and renames it on success). What was written cannot be taken
/// back, so only a plain program is read in parts; any other is read
/// whole ([`compile_to_vec`] and [`check`] read it in parts).
pub fn compile_to(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: &mut (dyn Write + Send),
) -> Report {
    attempt(sources, file, options, wizards, out, Cutting::PlainOnly)
        .unwrap_or_else(|Whole| unreachable_whole())
}

/// [`compile_to`] into `out`, which is cleared first. A program that is
/// not plain is cut as it is read (each part parsed once); if a part needs
/// the whole program, `out` is cleared and it is compiled again, whole.
pub fn compile_to_vec(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: &mut Vec<u8>,
) -> Report {
    restarting(sources, file, options, wizards, out, Vec::clear)
}

/// [`compile_to_vec`] with the output thrown away as it is made: the
/// diagnostics of `ger check`.
pub fn check(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> Report {
    restarting(
        sources,
        file,
        options,
        wizards,
        &mut std::io::sink(),
        |_| {},
    )
}

/// A compile into `out` that reads a program in parts as it goes and, if a
/// part needs the whole program, empties `out` with `reset` and compiles
/// it again, whole.
fn restarting<W: Write + Send>(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    mut wizards: Option<&mut dyn WizardHost>,
    out: &mut W,
    reset: impl Fn(&mut W),
) -> Report {
    in_parts_else_whole(|cutting| {
        reset(out);
        let wizards = wizards.as_mut().map(|w| &mut **w as &mut dyn WizardHost);
        attempt(sources, file, options, wizards, out, cutting)
    })
    .unwrap_or_else(|Whole| unreachable_whole())
}

/// `compile` reading a program in parts as it goes and, if a part needs the
/// whole program, again reading in parts only a plain program (which never
/// needs it): `Err` is never the second's.
fn in_parts_else_whole<T>(
    mut compile: impl FnMut(Cutting) -> Result<T, Whole>,
) -> Result<T, Whole> {
    compile(Cutting::AsItGoes).or_else(|Whole| compile(Cutting::PlainOnly))
}

/// One compile of the file `file` into `out`, a program that is not plain
/// read in parts as `cutting` says; `Err`: a part needs the whole program.
fn attempt(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: &mut (dyn Write + Send),
    cutting: Cutting,
) -> Result<Report, Whole> {
    let (mut diagnostics, mut clock) = (Vec::new(), Clock::new());
    let input = Input::of(sources, file, options);
    let out = Output::Text(out);
    let written = run(
        input,
        options,
        wizards,
        out,
        &mut diagnostics,
        &mut clock,
        cutting,
    )?;
    Ok(Report {
        diagnostics,
        timings: clock.timings,
        write_error: written.err(),
    })
}

/// The report of a compile that stopped for the whole program where it
/// cannot ([`Cutting::PlainOnly`]): none is ever made.
fn unreachable_whole() -> Report {
    Report {
        diagnostics: Vec::new(),
        timings: Vec::new(),
        write_error: Some(std::io::Error::other(
            "internal: a whole read asked for a whole read",
        )),
    }
}

/// The tool path of the file `file` of `sources` (SPEC §4 to the end, then
/// [`crate::toolpath`] instead of text); `None` when there are errors.
pub fn tool_path(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> (Option<ToolPath>, Vec<Diagnostic>) {
    let options = CompileOptions {
        stage: None,
        ..options.clone()
    };
    let mut wizards = wizards;
    let found = in_parts_else_whole(|cutting| {
        let (mut path, mut diagnostics) = (None, Vec::new());
        let input = Input::of(sources, file, &options);
        let wizards = wizards.as_mut().map(|w| &mut **w as &mut dyn WizardHost);
        let out = Output::Path(&mut path);
        let clock = &mut Clock::new();
        // Nothing is written: no write can fail.
        let _ = run(
            input,
            &options,
            wizards,
            out,
            &mut diagnostics,
            clock,
            cutting,
        )?;
        Ok((path, diagnostics))
    });
    let (mut path, diagnostics) = found.unwrap_or_else(|Whole| {
        let internal = "internal: a whole read asked for a whole read";
        (None, vec![Diagnostic::error().with_message(internal)])
    });
    if diagnostics.iter().any(is_error) {
        path = None;
    }
    (path, diagnostics)
}

/// A subroutine file a caller found: its name (for diagnostics) and text.
pub type SubroutineFile = (String, String);

/// At most this many subroutine files are read for one program.
pub const MAX_SUBROUTINE_FILES: usize = 1000;

/// The files of the LinuxCNC subroutines (`o<name> call`) that `main`
/// calls but does not hold, and those they call in turn, added to
/// `sources`, for [`CompileOptions::library`]. `find(name)` reads
/// `name.ngc` wherever the caller looks (the library does no I/O): its
/// name and text, or `None`. A name found nowhere is left to the compile,
/// which reports it at the call.
pub fn subroutine_library(
    sources: &mut Sources,
    main: FileId,
    find: &mut dyn FnMut(&str) -> Result<Option<SubroutineFile>, String>,
) -> Result<Vec<FileId>, String> {
    let mut library = Vec::new();
    let mut defined = std::collections::BTreeSet::new();
    let mut looked = std::collections::BTreeSet::new();
    let mut queue = vec![main];
    let mut wanted = Vec::new();
    while let Some(file) = queue.pop() {
        let (calls, subs) = named_subroutines(sources.text(file));
        defined.extend(subs);
        wanted.extend(calls);
        for name in &wanted {
            if defined.contains(name) || !looked.insert(name.clone()) {
                continue;
            }
            let Some((origin, text)) = find(name)? else {
                continue;
            };
            if library.len() >= MAX_SUBROUTINE_FILES {
                return Err(format!(
                    "the program calls more than {MAX_SUBROUTINE_FILES} subroutine files"
                ));
            }
            let id = sources.add(origin, text);
            library.push(id);
            queue.push(id);
        }
    }
    Ok(library)
}

/// The `o<name>` subroutines a text calls and those it defines (`sub`),
/// named as the lexer names them (trimmed, in lower case).
fn named_subroutines(text: &str) -> (Vec<String>, Vec<String>) {
    let (mut calls, mut subs) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let line = line.trim_start();
        let Some(rest) = line
            .strip_prefix(['o', 'O'])
            .and_then(|r| r.strip_prefix('<'))
        else {
            continue;
        };
        let Some(close) = rest.find('>') else {
            continue;
        };
        let name = crate::syntax::egc::lexer::subroutine_name(&rest[..close]);
        let keyword = rest[close + 1..]
            .trim_start()
            .split(|c: char| !c.is_ascii_alphabetic())
            .next()
            .unwrap_or("")
            .to_ascii_lowercase();
        match keyword.as_str() {
            "call" => calls.push(name),
            "sub" => subs.push(name),
            _ => {}
        }
    }
    (calls, subs)
}

/// Where the back end's result goes.
enum Output<'a> {
    Text(&'a mut (dyn Write + Send)),
    Path(&'a mut Option<ToolPath>),
}

/// The file to compile: its text, id, language and flavour.
struct Input<'a> {
    /// The subroutine files read with it (`CompileOptions::library`).
    library: Vec<(&'a str, Locator)>,
    text: &'a str,
    file: FileId,
    locator: Locator,
    language: Language,
    from: eval::Flavour,
}

impl<'a> Input<'a> {
    /// The file's language and flavour are the options', else its name's.
    fn of(sources: &'a Sources, file: FileId, options: &'a CompileOptions) -> Input<'a> {
        let name = sources.name(file);
        Input {
            library: options
                .library
                .iter()
                .map(|&f| (sources.text(f), sources.locator(f)))
                .collect(),
            text: sources.text(file),
            file,
            locator: sources.locator(file),
            language: options.language(name),
            from: options.flavour(name),
        }
    }
}

/// How [`run`] reads a program in parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cutting {
    /// Any program, cut as it is read; a part that needs the whole program
    /// stops the compile (`Err(Whole)`: the caller throws the output away
    /// and starts again with `PlainOnly`).
    AsItGoes,
    /// Only a plain program (which never needs the whole); any other is
    /// read whole.
    PlainOnly,
}

/// The stages in order, writing to `out`; they stop at the first stage
/// that reports an error. `Err`: a part needs the whole program
/// ([`Cutting::AsItGoes`]).
fn run<'a>(
    input: Input<'a>,
    options: &'a CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: Output<'a>,
    diagnostics: &mut Vec<Diagnostic>,
    clock: &mut Clock,
    cutting: Cutting,
) -> Result<std::io::Result<()>, Whole> {
    let Input {
        library,
        text,
        file,
        locator,
        language,
        from,
    } = input;
    let eval_options = options.eval_options(from, language);
    let fanuc_functions = from == eval::Flavour::Fanuc && language == Language::Gcode;
    // A program is read in parts, unless it needs to be read whole.
    let at = &locator;
    let source =
        match library.is_empty() && options.stage != Some(Stage::Parse) && chunk::by_parts() {
            false => None,
            true if language == Language::Gcode && chunk::chunkable(text) => {
                let ranges = Box::new(chunk::chunks(text));
                Some(PartSource::Text { text, at, ranges })
            }
            true => match cutting {
                Cutting::PlainOnly => None,
                Cutting::AsItGoes => Some(PartSource::TextCut {
                    text,
                    at,
                    from: 0,
                    defined: Vec::new(),
                }),
            },
        };
    if let Some(source) = source {
        let backend = Backend::new(SourceFacts::Text(text), file, options, out);
        let mut parts = Parts::new(source);
        let written = run_by_parts(
            &mut parts,
            language,
            fanuc_functions,
            &eval_options,
            wizards,
            backend,
            diagnostics,
            clock,
        );
        return match parts.whole {
            true => Err(Whole),
            false => Ok(written),
        };
    }
    let (mut program, parse_diagnostics) =
        crate::syntax::egc::parse_program_files((text, &locator), &library, language);
    if fanuc_functions {
        map_fanuc_functions(&mut program.main);
        for sub in &mut program.subprograms {
            map_fanuc_functions(&mut sub.body);
        }
    }
    diagnostics.extend(parse_diagnostics);
    clock.lap("parse");
    if diagnostics.iter().any(is_error) {
        return Ok(Ok(()));
    }
    if options.stage == Some(Stage::Parse) {
        return Ok(match out {
            Output::Text(out) => out.write_all(program.to_text().as_bytes()),
            Output::Path(_) => Ok(()),
        });
    }
    let backend = Backend::new(SourceFacts::Text(text), file, options, out);
    let (eval_diagnostics, backend) = on_two_threads(backend, |sink| match wizards {
        Some(host) => eval::eval_program(
            &program,
            &eval_options,
            Some(&mut *host as &mut dyn WizardHost),
            sink,
        ),
        None => eval::eval_program(&program, &eval_options, None, sink),
    });
    diagnostics.extend(eval_diagnostics);
    drop(program);
    clock.ran_inside(backend.lower_time_ahead);
    clock.lap("expand");
    Ok(finish_back_end(backend, diagnostics, clock))
}

/// Fanuc's meaning for the functions whose names Fanuc and LinuxCNC
/// share.
fn map_fanuc_functions(stmts: &mut [crate::ast::Stmt]) {
    let on_fanuc = |f: crate::ast::Function| f.on_fanuc();
    for stmt in stmts {
        stmt.map_functions(&on_fanuc);
    }
}

/// After evaluation: the back end's times (it ran on its own thread, at the
/// same time), and unless a stage before it failed, the end of its output
/// and its diagnostics.
fn finish_back_end(
    backend: Backend<'_>,
    diagnostics: &mut Vec<Diagnostic>,
    clock: &mut Clock,
) -> std::io::Result<()> {
    clock.add(&[("lower", backend.lower_time), ("emit", backend.emit_time)]);
    if diagnostics.iter().any(is_error) {
        return Ok(());
    }
    let (lowered, written) = backend.finish();
    diagnostics.extend(lowered);
    written
}

/// What the back end needs to know of the source: its length (to size the
/// output's buffer) and the most decimals its numbers are written with.
enum SourceFacts<'a> {
    Text(&'a str),
    /// Of a file read a part at a time, found by [`scan_file`].
    Known(FileScan),
}

impl SourceFacts<'_> {
    fn len(&self) -> usize {
        match self {
            SourceFacts::Text(text) => text.len(),
            SourceFacts::Known(file) => file.len,
        }
    }

    fn decimals(&self) -> usize {
        match self {
            SourceFacts::Text(text) => input_decimals(text),
            SourceFacts::Known(file) => file.decimals,
        }
    }
}

/// Where the parts of a program come from.
enum PartSource<'a> {
    /// Ranges of a text held whole.
    Text {
        text: &'a str,
        at: &'a Locator,
        ranges: Box<dyn Iterator<Item = std::ops::Range<usize>> + 'a>,
    },
    /// A program that is not plain, held whole, cut as it is read
    /// ([`chunk::next_cut`]: each part parsed once, where it is cut).
    TextCut {
        text: &'a str,
        at: &'a Locator,
        from: usize,
        /// The subprograms of the parts read ([`chunk::cut_part`]).
        defined: Vec<u32>,
    },
    /// Lines read from a file as they are needed (its text is never
    /// held), as plain G-code, until a part is not
    /// ([`chunk::parse_plain_chunk`]): then a [`PartSource::Program`].
    Reader(LineReader<'a>),
    /// A program that is not plain, read from a file a part at a time.
    Program(ProgramReader<'a>),
    /// Only while one source gives way to another.
    Done,
}

/// A program read a part at a time ([`chunk`]): each part is parsed
/// when the evaluator asks for it. After a syntax error nothing more is
/// run, but every part is still read, so that all syntax errors are found.
struct Parts<'a> {
    source: PartSource<'a>,
    diagnostics: Vec<Diagnostic>,
    broken: bool,
    time: Duration,
    /// The first read error; the program stops there.
    read_error: Option<std::io::Error>,
    /// A part needs the whole program; nothing more is read.
    whole: bool,
    /// Emptied runs of lines of plain words, for the lines to come
    /// ([`chunk::recycle`]).
    spare: chunk::Spare,
}

impl<'a> Parts<'a> {
    fn new(source: PartSource<'a>) -> Parts<'a> {
        Parts {
            source,
            diagnostics: Vec::new(),
            broken: false,
            time: Duration::ZERO,
            read_error: None,
            whole: false,
            spare: chunk::Spare::default(),
        }
    }

    /// The statements of a part that has run: their runs of lines are
    /// kept for the parts to come while those are read as plain (no other
    /// source takes them).
    fn recycle(&mut self, ran: Vec<crate::ast::Stmt>) {
        match self.source {
            PartSource::Reader(_) => chunk::recycle(ran, &mut self.spare),
            _ => self.spare.clear(),
        }
    }

    /// The next part to run; `None` at the end, or after a syntax error
    /// (the rest is read for its errors).
    fn next(&mut self, language: Language, names: &mut Names) -> Option<eval::Part> {
        loop {
            let started = Instant::now();
            let (stmts, subprograms, found) = self.parse_next(language, names)?;
            self.time += started.elapsed();
            self.broken |= found.iter().any(is_error);
            self.diagnostics.extend(found);
            if !self.broken {
                return Some((stmts, subprograms));
            }
        }
    }

    /// The next part, parsed; none after a read error.
    fn parse_next(&mut self, language: Language, names: &mut Names) -> Option<Parsed> {
        if self.read_error.is_some() {
            return None;
        }
        // A plain program has no subprogram.
        let no_subprograms = |(stmts, diagnostics)| (stmts, Vec::new(), diagnostics);
        match &mut self.source {
            PartSource::Text { text, at, ranges } => {
                let range = ranges.next()?;
                Some(no_subprograms(chunk::parse_chunk(
                    text, range, at, language, names,
                )))
            }
            PartSource::Reader(reader) => match reader.next_part() {
                Ok(Some((text, at))) => {
                    let range = 0..text.len();
                    let spare = &mut self.spare;
                    match chunk::parse_plain_chunk(&text, range, &at, language, names, spare) {
                        Some(parsed) => Some(no_subprograms(parsed)),
                        None => {
                            // Not plain: this part and the rest are cut
                            // where the program allows (what was parsed of
                            // it is thrown away; nothing of it has run).
                            let PartSource::Reader(reader) =
                                std::mem::replace(&mut self.source, PartSource::Done)
                            else {
                                return None;
                            };
                            let program = ProgramReader::resume(reader, language, text, &at);
                            self.source = PartSource::Program(program);
                            self.parse_next(language, names)
                        }
                    }
                }
                Ok(None) => None,
                Err(e) => {
                    self.read_error = Some(e);
                    None
                }
            },
            PartSource::Done => None,
            PartSource::TextCut { .. } | PartSource::Program(_) if self.whole => None,
            PartSource::TextCut { text, from, .. } if *from >= text.len() => None,
            PartSource::TextCut {
                text,
                at,
                from,
                defined,
            } => {
                match chunk::next_cut(text, *from, at, language, names, defined) {
                    chunk::Cut::Part(end, stmts, subprograms, diagnostics) => {
                        *from = end;
                        Some((stmts, subprograms, diagnostics))
                    }
                    // (`next_cut` never asks to grow: the text is all there.)
                    chunk::Cut::Grow | chunk::Cut::Whole => {
                        self.whole = true;
                        None
                    }
                }
            }
            PartSource::Program(reader) => match reader.next_part(names) {
                Ok(Some(Ok(parsed))) => Some(parsed),
                Ok(Some(Err(Whole))) => {
                    self.whole = true;
                    None
                }
                Ok(None) => None,
                Err(e) => {
                    self.read_error = Some(e);
                    None
                }
            },
        }
    }
}

/// A file's whole lines as bytes, about [`chunk::CHUNK_BYTES`] of them at a
/// time (the first without a byte-order mark), for [`scan_file`].
struct RawBlocks<'a> {
    reader: &'a mut dyn std::io::BufRead,
    first: bool,
    block: Vec<u8>,
}

impl<'a> RawBlocks<'a> {
    fn new(reader: &'a mut dyn std::io::BufRead) -> RawBlocks<'a> {
        RawBlocks {
            reader,
            first: true,
            block: Vec::new(),
        }
    }

    /// The lines of a file from a line after its first (no byte-order mark).
    fn after_start(reader: &'a mut dyn std::io::BufRead) -> RawBlocks<'a> {
        RawBlocks {
            first: false,
            ..RawBlocks::new(reader)
        }
    }

    /// The next lines with their line ends; `None` at the end of the file.
    fn next(&mut self) -> std::io::Result<Option<&[u8]>> {
        self.block.clear();
        let read = read_lines(
            self.reader,
            chunk::CHUNK_BYTES,
            &mut self.first,
            &mut self.block,
        )?;
        Ok(read.then_some(&self.block[..]))
    }
}

/// Append to `bytes` the next lines of `reader`, up to the one with the
/// `want`th byte; the first lines of a file (`first`) without a byte-order
/// mark. `false` at the end of the file.
fn read_lines(
    reader: &mut dyn std::io::BufRead,
    want: usize,
    first: &mut bool,
    bytes: &mut Vec<u8>,
) -> std::io::Result<bool> {
    let start = bytes.len();
    while bytes.len() - start < want {
        let block = reader.fill_buf()?;
        if block.is_empty() {
            break;
        }
        let take = block.len().min(want - (bytes.len() - start));
        bytes.extend_from_slice(&block[..take]);
        reader.consume(take);
    }
    if bytes.len() == start {
        return Ok(false);
    }
    if !bytes.ends_with(b"\n") {
        reader.read_until(b'\n', bytes)?;
    }
    if std::mem::take(first) {
        source::drop_bom(bytes);
    }
    Ok(true)
}

/// Whole lines of a program, read from a file about
/// [`chunk::CHUNK_BYTES`] at a time and decoded as [`source::decode`]
/// decodes the whole file (a file [`scan_file`] accepted: no NUL, control
/// character or lone CR, so the two agree).
struct LineReader<'a> {
    reader: &'a mut dyn std::io::BufRead,
    file: FileId,
    /// No part read yet (the first may start with a byte-order mark).
    first: bool,
    /// Where the next part starts in the decoded file, and its lines before.
    base: usize,
    lines_before: usize,
    /// A [`FileScan::partial`] scan each part is checked against.
    check: Option<FileScan>,
}

impl<'a> LineReader<'a> {
    fn new(reader: &'a mut dyn std::io::BufRead, file: FileId, scan: FileScan) -> LineReader<'a> {
        LineReader {
            reader,
            file,
            first: true,
            base: 0,
            lines_before: 0,
            check: scan.partial.then_some(scan),
        }
    }

    /// The next part's text and span maker; `None` at the end of the file.
    /// A part is the lines up to the one with its [`chunk::part_size`]th
    /// byte.
    fn next_part(&mut self) -> std::io::Result<Option<(String, Locator)>> {
        let Some(text) = self.next_lines(chunk::part_size())? else {
            return Ok(None);
        };
        let at = Locator::part(self.file, &text, self.base, self.lines_before);
        self.base += text.len();
        self.lines_before += at.line_ends();
        Ok(Some((text, at)))
    }

    /// The next lines, up to the one with the `part`th byte, decoded;
    /// `None` at the end of the file. Read in blocks.
    /// With a [`FileScan::partial`] scan (`check`), each is checked first
    /// as the whole scan would have read it: `Err(`[`Unforeseen`]`)`.
    fn next_lines(&mut self, part: usize) -> std::io::Result<Option<String>> {
        let mut bytes = Vec::with_capacity(part + 256);
        if !read_lines(self.reader, part, &mut self.first, &mut bytes)? {
            return Ok(None);
        }
        let unforeseen = || Err(std::io::Error::other(Unforeseen));
        if self.check.is_some() && !streamable_block(&bytes) {
            return unforeseen();
        }
        let text = source::decode_lines(bytes);
        match self.check {
            Some(scan) if !scan.prints_as(input_decimals(&text)) => unforeseen(),
            _ => Ok(Some(text)),
        }
    }
}

/// A part's statements and diagnostics.
type Parsed = (
    Vec<crate::ast::Stmt>,
    Vec<crate::ast::Subprogram>,
    Vec<Diagnostic>,
);

/// The program must be read whole ([`chunk::cut_part`]).
struct Whole;

/// The parts of a program that is not plain, read from a file as they are
/// needed ([`chunk::cut_part`]): the text from the last cut on is held
/// until the next.
struct ProgramReader<'a> {
    lines: LineReader<'a>,
    language: Language,
    /// The text read from the last cut on, and where it is in the file.
    text: String,
    base: usize,
    lines_before: usize,
    /// The file has been read to its end.
    read_all: bool,
    /// The subprograms of the parts read ([`chunk::cut_part`]).
    defined: Vec<u32>,
}

impl<'a> ProgramReader<'a> {
    fn new(lines: LineReader<'a>, language: Language) -> ProgramReader<'a> {
        ProgramReader {
            lines,
            language,
            text: String::new(),
            base: 0,
            lines_before: 0,
            read_all: false,
            defined: Vec::new(),
        }
    }

    /// Go on from a part `lines` gave as plain (`text`, placed by `at`),
    /// which is not: it is the text read from the last cut on.
    fn resume(
        lines: LineReader<'a>,
        language: Language,
        text: String,
        at: &Locator,
    ) -> ProgramReader<'a> {
        ProgramReader {
            base: lines.base - text.len(),
            lines_before: lines.lines_before - at.line_ends(),
            text,
            ..ProgramReader::new(lines, language)
        }
    }

    /// The next part, parsed into `names`: its statements and diagnostics,
    /// or `Err` if the program must be read whole; `None` at the end of the
    /// file.
    fn next_part(&mut self, names: &mut Names) -> std::io::Result<Option<Result<Parsed, Whole>>> {
        let mut want = chunk::part_size();
        loop {
            while !self.read_all && self.text.len() < want.saturating_mul(2) {
                match self.lines.next_lines(want)? {
                    Some(more) => self.text.push_str(&more),
                    None => self.read_all = true,
                }
            }
            if self.text.is_empty() {
                return Ok(None);
            }
            let (file, complete) = (self.lines.file, self.read_all);
            let at = Locator::part(file, &self.text, self.base, self.lines_before);
            let cut = chunk::cut_part(
                &self.text,
                0,
                want,
                complete,
                &at,
                self.language,
                names,
                &mut self.defined,
            );
            match cut {
                chunk::Cut::Grow => want = want.saturating_mul(2),
                chunk::Cut::Part(end, stmts, subprograms, diagnostics) => {
                    self.base += end;
                    self.lines_before += self.text[..end].bytes().filter(|&b| b == b'\n').count();
                    self.text.drain(..end);
                    return Ok(Some(Ok((stmts, subprograms, diagnostics))));
                }
                chunk::Cut::Whole => return Ok(Some(Err(Whole))),
            }
        }
    }
}

/// A program that can be compiled from a reader, a part at a time, without
/// holding its text: its decoded length and the most decimals its numbers
/// are written with ([`input_decimals`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileScan {
    pub len: usize,
    pub decimals: usize,
    /// Found from the file's first lines only ([`first_look`]; `len` is
    /// then the file's size): each part read after them is checked as it
    /// is read, and one the scan of the whole file would have answered
    /// otherwise stops the compile ([`Streamed::Rescan`]).
    pub partial: bool,
}

impl FileScan {
    /// Whether a file that also has numbers with `decimals` is printed as
    /// this one ([`grid_decimals`], in either units).
    fn prints_as(&self, decimals: usize) -> bool {
        let most = self.decimals.max(decimals);
        [Some(ir::Units::Mm), Some(ir::Units::Inch)]
            .into_iter()
            .all(|units| grid_decimals(most, units) == grid_decimals(self.decimals, units))
    }
}

/// The output's decimals for an input whose numbers have `most` at most
/// (SPEC §6): as many, at least 3 for mm and 4 for inch (or units not
/// stated), at most 6.
fn grid_decimals(most: usize, units: Option<ir::Units>) -> usize {
    let least = match units {
        Some(ir::Units::Mm) => 3,
        Some(ir::Units::Inch) | None => 4,
    };
    most.clamp(least, 6)
}

/// The bytes [`first_look`] reads of a file larger than this: its whole
/// lines up to about 256 KB (a 200,000-move program is 5 MB).
const FIRST_LOOK: u64 = 1 << 18;

/// [`scan_path`] of the file's first lines only (all of a file up to
/// [`FIRST_LOOK`] bytes): the compile then reads the file once, not twice,
/// and checks each part against the answer as it reads it. A program from
/// CAM writes its numbers with as many decimals throughout; one with more
/// further on is compiled again, after the whole scan.
pub fn first_look(path: &std::path::Path) -> std::io::Result<Option<FileScan>> {
    first_look_within(path, FIRST_LOOK)
}

/// [`first_look`] with `most` bytes for [`FIRST_LOOK`] (for the tests: the
/// first block, about 16 KB of lines, is always read).
pub fn first_look_within(path: &std::path::Path, most: u64) -> std::io::Result<Option<FileScan>> {
    let size = std::fs::metadata(path)?.len();
    if size <= most {
        return scan_path(path);
    }
    let file = std::fs::File::open(path)?;
    let mut reader = std::io::BufReader::with_capacity(1 << 16, file);
    let scan = scan_blocks(RawBlocks::new(&mut reader), most as usize)?;
    Ok(scan.map(|scan| FileScan {
        len: size as usize,
        partial: true,
        ..scan
    }))
}

/// How a program read from a file a part at a time ([`compile_file`])
/// ended.
pub enum Streamed {
    Compiled(Report),
    /// A part needs the whole program ([`chunk::cut_part`]), which must be
    /// compiled whole instead, by [`compile_to`].
    Whole,
    /// A part read did not hold to a [`FileScan::partial`] scan: the file
    /// must be scanned whole and compiled again.
    Rescan,
}

impl Streamed {
    /// The report of a program compiled.
    pub fn compiled(self) -> Option<Report> {
        match self {
            Streamed::Compiled(report) => Some(report),
            Streamed::Whole | Streamed::Rescan => None,
        }
    }
}

/// The error a [`LineReader`] stops with at a part that does not hold to
/// a [`FileScan::partial`] scan.
#[derive(Debug)]
struct Unforeseen;

impl std::fmt::Display for Unforeseen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the file is not as its first lines said")
    }
}

impl std::error::Error for Unforeseen {}

/// Every line of the file `reader` reads, decoded as [`compile_file`]
/// decodes it (its spans are offsets into these lines): `each` is given
/// its 1-based number, its bytes (its line end included) and its text
/// without its line end. Read a part at a time: nothing but the part is
/// held.
pub fn each_line(
    reader: &mut dyn std::io::BufRead,
    each: &mut dyn FnMut(usize, std::ops::Range<usize>, &str),
) -> std::io::Result<()> {
    let mut blocks = RawBlocks::new(reader);
    let (mut number, mut start) = (1, 0);
    // After a line end (or in an empty file) an empty line follows, as in
    // a text's line index.
    let mut ended = true;
    while let Some(bytes) = blocks.next()? {
        let text = source::decode_lines(bytes.to_vec());
        for line in text.split_inclusive('\n') {
            let shown = line.strip_suffix('\n').unwrap_or(line);
            ended = shown.len() < line.len();
            let bytes = start..start + line.len();
            each(number, bytes, shown.strip_suffix('\r').unwrap_or(shown));
            number += 1;
            start += line.len();
        }
    }
    if ended {
        each(number, start..start, "");
    }
    Ok(())
}

/// The lines of file `file` that `diagnostics` show, read a part at a time
/// from `reader` (memory grows with the lines, not with the
/// file), as [`Sources::set_lines`] takes them: the lines each
/// label covers, at most 21 from its first, as the diagnostics' excerpts
/// take them ([`crate::diagnostic::render`]), and the line after each
/// (shown between two labelled lines one apart).
pub fn lines_shown(
    reader: &mut dyn std::io::BufRead,
    file: FileId,
    diagnostics: &[Diagnostic],
) -> std::io::Result<Vec<(usize, usize, String)>> {
    // Each label's first and last byte.
    let labels: Vec<(usize, usize)> = diagnostics
        .iter()
        .flat_map(|d| &d.labels)
        .filter(|label| label.file_id == file)
        .map(|label| {
            (
                label.range.start,
                label.range.end.max(label.range.start + 1) - 1,
            )
        })
        .collect();
    let mut first_lines: Vec<Option<usize>> = vec![None; labels.len()];
    let mut lines = Vec::new();
    // The line after one shown is shown too; the last line read is kept
    // (its text's room used again) for a label past the end.
    let (mut after, mut last) = (false, (0, 0, String::new()));
    each_line(reader, &mut |number, bytes, text| {
        let mut holds = false;
        for ((from, to), first) in labels.iter().zip(&mut first_lines) {
            if *from < bytes.end && bytes.start <= *to {
                holds |= *first.get_or_insert(number) + 20 >= number;
            }
        }
        if holds || std::mem::take(&mut after) {
            lines.push((number, bytes.start, text.to_string()));
        }
        after = holds;
        (last.0, last.1) = (number, bytes.start);
        last.2.clear();
        last.2.push_str(text);
    })?;
    // The last line holds every offset from its start on (the end of the
    // file, after a last line with no line end).
    let past_the_end =
        |((from, _), first): (&(usize, usize), &Option<usize>)| first.is_none() && *from >= last.1;
    let shown = lines
        .last()
        .is_some_and(|l: &(usize, usize, String)| l.0 == last.0);
    if labels.iter().zip(&first_lines).any(past_the_end) && !shown {
        lines.push(last);
    }
    Ok(lines)
}

/// Read a program through once: whether it can be compiled a part at a
/// time from a reader ([`compile_file`]): it has no NUL, control character
/// or lone CR (which [`crate::source::decode`] reports or rewrites).
/// `None`: read it whole.
pub fn scan_file(reader: &mut dyn std::io::BufRead) -> std::io::Result<Option<FileScan>> {
    scan_lines(RawBlocks::new(reader))
}

/// [`scan_file`] of the file at `path`, its two halves (cut at a line end)
/// read at the same time on two threads.
pub fn scan_path(path: &std::path::Path) -> std::io::Result<Option<FileScan>> {
    use std::io::{BufRead, Read, Seek};
    let open = || std::fs::File::open(path).map(|f| std::io::BufReader::with_capacity(1 << 16, f));
    let mut second = open()?;
    let middle = second.seek(std::io::SeekFrom::End(0))? / 2;
    second.seek(std::io::SeekFrom::Start(middle))?;
    // The first half ends with the line the middle is on.
    let cut = middle + second.read_until(b'\n', &mut Vec::new())? as u64;
    let scan_first = move || scan_lines(RawBlocks::new(&mut open()?.take(cut)));
    let (first, second) = std::thread::scope(|scope| {
        let first = std::thread::Builder::new().spawn_scoped(scope, scan_first);
        let second = scan_lines(RawBlocks::after_start(&mut second));
        let first = match first {
            Ok(thread) => thread
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            // No second thread: one after the other.
            Err(_) => scan_first(),
        };
        (first, second)
    });
    Ok(match (first?, second?) {
        (Some(a), Some(b)) => Some(FileScan {
            len: a.len + b.len,
            decimals: a.decimals.max(b.decimals),
            partial: false,
        }),
        _ => None,
    })
}

/// [`scan_file`] of the lines `lines` reads.
fn scan_lines(blocks: RawBlocks<'_>) -> std::io::Result<Option<FileScan>> {
    scan_blocks(blocks, usize::MAX)
}

/// Whether whole lines of a file have no control character and no CR
/// that is not before a LF (even at the end), which is a line end to
/// `decode`: what [`scan_file`] asks of each.
fn streamable_block(bytes: &[u8]) -> bool {
    // First one look for both (a CR before a LF is looked at again).
    // (Folded without a stop at the first: it vectorises.)
    let odd = |b: u8| b < 0x20 && b != b'\n' && b != b'\t';
    if bytes.iter().fold(false, |found, &b| found | odd(b)) {
        let control = bytes.iter().any(|&b| odd(b) && b != b'\r');
        let mut at = bytes.iter().enumerate();
        let lone_cr = at.any(|(i, &b)| b == b'\r' && bytes.get(i + 1) != Some(&b'\n'));
        if control || lone_cr {
            return false;
        }
    }
    true
}

/// [`scan_lines`] of the blocks of `blocks` until `most` bytes are read
/// (the block that passes it included).
fn scan_blocks(mut blocks: RawBlocks<'_>, most: usize) -> std::io::Result<Option<FileScan>> {
    let (mut len, mut decimals) = (0, 0);
    while let Some(bytes) = blocks.next()? {
        if !streamable_block(bytes) {
            return Ok(None);
        }
        // Whole lines: UTF-8 as a whole, else line by line.
        let latin1;
        let text = match std::str::from_utf8(bytes) {
            Ok(text) => text,
            Err(_) => {
                latin1 = source::decode_lines(bytes.to_vec());
                &latin1
            }
        };
        decimals = decimals.max(input_decimals(text));
        len += text.len();
        if len >= most {
            break;
        }
    }
    Ok(Some(FileScan {
        len,
        decimals,
        partial: false,
    }))
}

/// Compile a program from `reader`, a part at a time, as file `file`
/// (named `name`, for its language and flavour) of a [`Sources`] whose text
/// stays empty: memory grows with the longest part, not with the program.
/// `scan` is [`scan_file`]'s answer for the same bytes. The report is
/// [`compile_to`]'s; its spans are in the decoded file ([`lines_shown`]
/// reads the lines they show). [`Streamed::Whole`] and
/// [`Streamed::Rescan`]: what was written is incomplete (throw it away).
/// `Err`: the file could not be read.
pub fn compile_file(
    reader: &mut dyn std::io::BufRead,
    name: &str,
    file: FileId,
    scan: FileScan,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: &mut (dyn Write + Send),
) -> std::io::Result<Streamed> {
    let mut diagnostics = Vec::new();
    let mut clock = Clock::new();
    let (from, language) = (options.flavour(name), options.language(name));
    let eval_options = options.eval_options(from, language);
    let backend = Backend::new(SourceFacts::Known(scan), file, options, Output::Text(out));
    let lines = LineReader::new(reader, file, scan);
    // G-code is read as plain until a part is found not to be.
    let mut parts = Parts::new(match language == Language::Gcode {
        true => PartSource::Reader(lines),
        false => PartSource::Program(ProgramReader::new(lines, language)),
    });
    let written = run_by_parts(
        &mut parts,
        language,
        from == eval::Flavour::Fanuc && language == Language::Gcode,
        &eval_options,
        wizards,
        backend,
        &mut diagnostics,
        &mut clock,
    );
    if let Some(e) = parts.read_error {
        return match e.get_ref().is_some_and(|e| e.is::<Unforeseen>()) {
            true => Ok(Streamed::Rescan),
            false => Err(e),
        };
    }
    if parts.whole {
        return Ok(Streamed::Whole);
    }
    Ok(Streamed::Compiled(Report {
        diagnostics,
        timings: clock.timings,
        write_error: written.err(),
    }))
}

/// [`run`] for a program read a part at a time: the same diagnostics, in
/// the same order, as reading it whole.
#[allow(clippy::too_many_arguments)]
fn run_by_parts(
    parts: &mut Parts<'_>,
    language: Language,
    fanuc_functions: bool,
    eval_options: &EvalOptions,
    wizards: Option<&mut dyn WizardHost>,
    backend: Backend<'_>,
    diagnostics: &mut Vec<Diagnostic>,
    clock: &mut Clock,
) -> std::io::Result<()> {
    let (chunked, backend) = on_two_threads(backend, |sink| {
        eval::eval_chunks(eval_options, wizards, sink, &mut |names, ran| {
            parts.recycle(ran);
            let (mut stmts, mut subprograms) = parts.next(language, names)?;
            if fanuc_functions {
                map_fanuc_functions(&mut stmts);
                for sub in &mut subprograms {
                    map_fanuc_functions(&mut sub.body);
                }
            }
            Some((stmts, subprograms))
        })
    });
    let eval::Chunked {
        diagnostics: evaluated,
        mut names,
        needs_whole,
    } = chunked;
    parts.whole |= needs_whole;
    // The parts after the program's end, for their syntax errors (and
    // their subprograms, numbered by the program's names).
    while parts.next(language, &mut names).is_some() {
        names.forget_notes();
    }
    diagnostics.append(&mut parts.diagnostics);
    clock.ran_inside(backend.lower_time_ahead);
    clock.split("expand", &[("parse", parts.time)]);
    // A syntax error (among `diagnostics` now) stops the compile: what the
    // evaluator said of the parts before it is not reported.
    if !parts.broken {
        diagnostics.extend(evaluated);
    }
    finish_back_end(backend, diagnostics, clock)
}

/// The back end as the evaluator's sink: each batch of statements is
/// lowered up to the requested stage and printed, then dropped, so the
/// whole program is never held in memory (ARCHITECTURE.md, "streaming").
struct Backend<'s> {
    source: SourceFacts<'s>,
    file: FileId,
    options: &'s CompileOptions,
    out: Output<'s>,
    /// The first write that failed; nothing more is written after it.
    write_error: Option<std::io::Error>,
    /// Made by the first batch, when the setup and units are known.
    started: Option<Started>,
    /// How many of the passes the evaluator's thread runs before it hands
    /// a batch on ([`PASSES_AHEAD`]); the back end runs the others.
    ahead: usize,
    /// Those passes, given back when the program has been lowered (for
    /// their diagnostics).
    lowered_ahead: Option<Pipeline>,
    /// The time those passes took (in `lower_time` too), inside the
    /// evaluator's.
    lower_time_ahead: Duration,
    lower_time: Duration,
    emit_time: Duration,
}

/// The passes the evaluator's thread runs when the back end has a thread
/// of its own: units, polar, offsets and cycles. Chosen when the back end
/// was the slower thread on a plain program (57 % of the samples, `perf`,
/// the 2M program; 2026-11-28); since its printer got lighter the
/// evaluator is the busier, but one, two or three ahead give the same wall
/// time (a batch's lines come over from the other core in whichever pass
/// first touches them there). ARCHITECTURE.md, "Streaming" and "The ninth
/// stop".
const PASSES_AHEAD: usize = 4;

struct Started {
    /// `None` for `--stage expand`.
    lowering: Option<Pipeline>,
    printer: Printer,
}

enum Printer {
    Stage(emit::StagePrinter),
    Program(Box<emit::ProgramPrinter>),
    /// [`tool_path`]: the path is built instead of text.
    Path(Box<crate::toolpath::Builder>),
}

impl<'s> Backend<'s> {
    fn new(
        source: SourceFacts<'s>,
        file: FileId,
        options: &'s CompileOptions,
        out: Output<'s>,
    ) -> Backend<'s> {
        Backend {
            source,
            file,
            options,
            out,
            write_error: None,
            started: None,
            ahead: 0,
            lowered_ahead: None,
            lower_time_ahead: Duration::ZERO,
            lower_time: Duration::ZERO,
            emit_time: Duration::ZERO,
        }
    }

    /// The last pass to run, if any.
    fn last_pass(&self) -> Option<usize> {
        match self.options.stage {
            Some(Stage::Lower(pass)) => Some(pass),
            Some(Stage::Parse | Stage::Expand) => None,
            None => Some(lower::PASSES.len() - 1),
        }
    }

    /// How the passes lower.
    fn lower_options(&self) -> lower::LowerOptions {
        match self.out {
            // A tool path is built from moves: cycles are always expanded
            // and compensation resolved.
            Output::Path(_) => lower::LowerOptions {
                keep_cycles: false,
                keep_comp: false,
                ..self.options.lower.clone()
            },
            _ => self.options.lower.clone(),
        }
    }

    /// The passes the evaluator's thread is to run ([`PASSES_AHEAD`], and
    /// none past the last), and their options.
    fn ahead(&self) -> (usize, lower::LowerOptions) {
        let passes = self
            .last_pass()
            .map_or(0, |last| PASSES_AHEAD.min(last + 1));
        (passes, self.lower_options())
    }

    fn started(&self, start: &ir::Start) -> Started {
        let (len, file) = (self.source.len(), self.file);
        let last = self.last_pass();
        let options = self.lower_options();
        let context = lower::Context {
            start,
            options: &options,
        };
        // What the first pass starts from is what is printed, unless the
        // units pass has run.
        let units = match last {
            Some(last) if last >= lower::pass_index("units").unwrap_or(0) => start.output_units,
            _ => start.program_units,
        };
        Started {
            lowering: last.map(|last| Pipeline::new(&context, self.ahead..last + 1)),
            printer: match self.options.stage {
                _ if matches!(self.out, Output::Path(_)) => {
                    Printer::Path(Box::new(ToolPathBuilder::new(units, &start.setup)))
                }
                Some(_) => Printer::Stage(emit::StagePrinter::new(units, len, file)),
                None => {
                    let mut emit = self.options.emit.clone();
                    if emit.decimals.is_none() {
                        emit.decimals = Some(grid_decimals(self.source.decimals(), units));
                    }
                    Printer::Program(Box::new(emit::ProgramPrinter::new(&emit, units, len, file)))
                }
            },
        }
    }

    /// The passes' diagnostics, and the rest of the output unless a pass
    /// failed; and whether the output was written.
    fn finish(self) -> (Vec<Diagnostic>, std::io::Result<()>) {
        let written = self.write_error.map_or(Ok(()), Err);
        let Some(Started {
            lowering,
            mut printer,
        }) = self.started
        else {
            return (Vec::new(), written);
        };
        let mut diagnostics = Vec::new();
        // The evaluator's passes come first: after one failed, nothing of
        // the later ones is reported (as with [`Pipeline::diagnostics`]).
        if let Some(ahead) = self.lowered_ahead {
            let failed = ahead.failed();
            diagnostics = ahead.diagnostics();
            if failed {
                return (diagnostics, written);
            }
        }
        if let Some(mut lowering) = lowering {
            lowering.finish(&mut |rest| {
                printer.print(rest);
                rest.clear();
            });
            let failed = lowering.failed();
            diagnostics.extend(lowering.diagnostics());
            if failed {
                return (diagnostics, written);
            }
        }
        if let Printer::Program(p) = &printer {
            diagnostics.extend(p.arcs_not_r());
        }
        match (printer.finish(), self.out) {
            (Ok(rest), Output::Text(out)) => {
                (diagnostics, written.and_then(|()| out.write_all(&rest)))
            }
            (Err(path), Output::Path(slot)) => {
                *slot = Some(*path);
                (diagnostics, written)
            }
            (Ok(_), Output::Path(_)) | (Err(_), Output::Text(_)) => (diagnostics, written),
        }
    }
}

/// The letters of coordinate words, either case: X Y Z I J K R and the
/// other axes A B C U V W.
const COORDINATE: [bool; 256] = {
    let mut table = [false; 256];
    let letters = b"XYZIJKRABCUVWxyzijkrabcuvw";
    let mut i = 0;
    while i < letters.len() {
        table[letters[i] as usize] = true;
        i += 1;
    }
    table
};

/// The most decimals any coordinate word (X Y Z I J K R, and the other
/// axes) of the source has: the digits after a point that follows a
/// coordinate letter, blanks and signs, and digits (`X-1.25`, `y .5`,
/// `X - + 1.1234`). A word inside a comment counts too, which can only add
/// precision. A block of 64 bytes at a time: its points are looked at only
/// when one has digits both `most` and `most + 1` bytes after it (one
/// after it while `most` is 0), else none has more than `most` decimals.
/// (LLVM makes the test of a block a few vector instructions; looking at
/// the digit `most` after a point as well leaves out `I2.5 J0`.)
fn input_decimals(text: &str) -> usize {
    let bytes = text.as_bytes();
    let mut most = 0;
    let mut at = 0;
    // Each block from `at` beside the blocks `most` (at least one) and
    // `most + 1` bytes after it; again from where `most` grew.
    'blocks: while let (Some(from), Some(near), Some(far)) = (
        bytes.get(at..),
        bytes.get(at + most.max(1)..),
        bytes.get(at + most + 1..),
    ) {
        let (blocks, _) = from.as_chunks::<BLOCK>();
        let (nears, _) = near.as_chunks::<BLOCK>();
        let (fars, _) = far.as_chunks::<BLOCK>();
        for ((block, near), far) in blocks.iter().zip(nears).zip(fars) {
            if may_have_more_decimals(block, near, far) {
                let before = most;
                source::each_byte(block, b'.', |i| more_decimals(bytes, at + i, &mut most));
                if most != before {
                    at += BLOCK;
                    continue 'blocks;
                }
            }
            at += BLOCK;
        }
        break;
    }
    for p in at..bytes.len() {
        if bytes[p] == b'.' {
            more_decimals(bytes, p, &mut most);
        }
    }
    most
}

/// Whether a byte of `block` is a point with a digit at its place in
/// `near` and in `far`: folded without a stop, so that it vectorises.
fn may_have_more_decimals(block: &[u8; BLOCK], near: &[u8; BLOCK], far: &[u8; BLOCK]) -> bool {
    let digit = |b: u8| u8::from(b.wrapping_sub(b'0') < 10);
    let mut found = 0;
    for i in 0..BLOCK {
        found |= u8::from(block[i] == b'.') & digit(near[i]) & digit(far[i]);
    }
    found != 0
}

/// Make `most` the decimals of the point at `bytes[p]` if it has more and
/// is a coordinate word's. (Apart: it is seldom called, and inlined it
/// takes the registers of the loop that calls it.)
#[inline(never)]
fn more_decimals(bytes: &[u8], p: usize, most: &mut usize) {
    if !bytes.get(p + *most + 1).is_some_and(u8::is_ascii_digit) {
        return;
    }
    let decimals = bytes[p + 1..]
        .iter()
        .position(|b| !b.is_ascii_digit())
        .unwrap_or(bytes.len() - p - 1);
    if decimals > *most && in_coordinate_word(bytes, p) {
        *most = decimals;
    }
}

/// Whether the point at `bytes[p]` is a coordinate word's: before it,
/// digits, then blanks and signs, then a coordinate letter (what reading
/// forward from the letter over them would reach).
fn in_coordinate_word(bytes: &[u8], p: usize) -> bool {
    let before = &bytes[..p];
    let digits = before
        .iter()
        .rev()
        .take_while(|b| b.is_ascii_digit())
        .count();
    let before = &before[..p - digits];
    let blanks = before
        .iter()
        .rev()
        .take_while(|b| matches!(b, b' ' | b'\t' | b'+' | b'-'))
        .count();
    let before = &before[..before.len() - blanks];
    before.last().is_some_and(|&b| COORDINATE[usize::from(b)])
}

/// The printed text is written out once there is this much of it.
const WRITE_AT: usize = 64 * 1024;

impl Printer {
    /// Print the statements; the text not yet written (none for a path).
    fn print(&mut self, stmts: &[ir::Stmt]) -> Option<&mut Vec<u8>> {
        match self {
            Printer::Stage(p) => Some(p.print(stmts)),
            Printer::Program(p) => Some(p.print(stmts)),
            Printer::Path(b) => {
                for stmt in stmts {
                    b.feed(stmt);
                }
                None
            }
        }
    }

    /// The rest of the text, or the path.
    fn finish(self) -> Result<Vec<u8>, Box<ToolPath>> {
        match self {
            Printer::Stage(p) => Ok(p.finish()),
            Printer::Program(p) => Ok(p.finish()),
            Printer::Path(b) => Err(Box::new(b.finish())),
        }
    }
}

/// Run `front` (the evaluator) with a sink that hands each batch to
/// `backend` on a thread of its own, so lowering and printing one batch
/// overlap making the next; `backend` is given back when both are done.
/// Memory stays bounded: at most [`BATCHES_IN_FLIGHT`] batches wait between
/// the two. The order of everything is the one thread's order. Where no
/// thread can be started, both run on this one.
fn on_two_threads<'s, R>(
    mut backend: Backend<'s>,
    front: impl FnOnce(&mut dyn ir::Sink) -> R,
) -> (R, Backend<'s>) {
    // The first passes run on the evaluator's thread, if there are two.
    let (ahead, lower_options) = backend.ahead();
    backend.ahead = ahead;
    let backend = Mutex::new(backend);
    let slot = &backend;
    let result = std::thread::scope(|scope| {
        let (to_back, from_front) = mpsc::sync_channel(BATCHES_IN_FLIGHT);
        let (to_front, spare) = mpsc::sync_channel(BATCHES_IN_FLIGHT + 1);
        let back = std::thread::Builder::new()
            .name("ger back end".into())
            .spawn_scoped(scope, move || {
                let mut apart = Apart::new();
                let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
                for handed in from_front {
                    match handed {
                        Handed::Start(start) => ir::Sink::start(&mut *backend, &start),
                        Handed::Batch(mut batch, front_cpu) => {
                            apart.keep_off(front_cpu);
                            ir::Sink::batch(&mut *backend, &mut batch);
                            // Full: the front allocates another.
                            let _ = to_front.try_send(batch);
                        }
                    }
                }
            });
        let Ok(back) = back else {
            // One thread: it runs the back end, every pass, too.
            let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
            backend.ahead = 0;
            return front(&mut *backend);
        };
        let mut handoff = Handoff {
            to_back,
            spare,
            ahead,
            lower_options,
            lowering: None,
            lower_time: Duration::ZERO,
        };
        let result = front(&mut handoff);
        let (lowering, lower_time) = handoff.finish();
        // The hand-off is gone: the back end has seen the last batch.
        if let Err(panic) = back.join() {
            std::panic::resume_unwind(panic);
        }
        let mut backend = slot.lock().unwrap_or_else(PoisonError::into_inner);
        backend.lowered_ahead = lowering;
        backend.lower_time += lower_time;
        backend.lower_time_ahead = lower_time;
        result
    });
    (
        result,
        backend.into_inner().unwrap_or_else(PoisonError::into_inner),
    )
}

/// Batches made but not yet lowered, at most. Eight (about 1.4 MB of
/// statements at most): the evaluator runs on while the back end is held
/// up a moment (the kernel's work on its core: the output's writeback is
/// started there), and a batch comes back to be filled after the back
/// end's core has moved on from its lines. With two, a 200k compile took
/// 1–2 ms longer (ARCHITECTURE, "The ninth stop"; two and four measured
/// again in the tenth: no faster).
const BATCHES_IN_FLIGHT: usize = 8;

/// The back end's thread kept off the processor the evaluator's thread
/// was last seen on (Linux, where more than one is allowed). Left to
/// itself, the kernel now and then wakes the back end, woken for each
/// batch, on the evaluator's processor and leaves it there while the
/// other idles, and the compile takes up to twice as long (on this
/// project's virtual machine, traced, the threads shared a processor for
/// more than 3 ms in 74–85 of 200 runs of the 200k program, 6–10 with
/// this; ARCHITECTURE.md, "The eleventh stop"). The evaluator's thread is
/// left free, to go wherever the kernel sends it (a faster core, say):
/// each batch says where it was, and the back end moves off that
/// processor when it changes (one system call then, none otherwise). The
/// thread ends with the compile, and its affinity with it.
struct Apart {
    #[cfg(target_os = "linux")]
    allowed: Option<rustix::thread::CpuSet>,
    /// The processor kept off, if any yet.
    off: Option<usize>,
}

impl Apart {
    fn new() -> Apart {
        Apart {
            #[cfg(target_os = "linux")]
            allowed: rustix::thread::sched_getaffinity(None)
                .ok()
                .filter(|cpus| cpus.count() >= 2),
            off: None,
        }
    }

    /// Keep off `cpu`, where the evaluator was when it sent the batch. A
    /// failure leaves the thread where the kernel puts it.
    fn keep_off(&mut self, cpu: usize) {
        if self.off == Some(cpu) {
            return;
        }
        self.off = Some(cpu);
        #[cfg(target_os = "linux")]
        if let Some(allowed) = &self.allowed {
            if cpu >= rustix::thread::CpuSet::MAX_CPU {
                return;
            }
            let mut others = *allowed;
            others.unset(cpu);
            if others.count() > 0 {
                let _ = rustix::thread::sched_setaffinity(None, &others);
            }
        }
    }
}

/// The processor this thread is on (0 where it cannot be known).
fn this_cpu() -> usize {
    #[cfg(target_os = "linux")]
    {
        rustix::thread::sched_getcpu()
    }
    #[cfg(not(target_os = "linux"))]
    {
        0
    }
}

/// What the evaluator sends the back-end thread.
enum Handed {
    Start(Box<ir::Start>),
    /// A batch, and the processor the evaluator sent it from.
    Batch(Vec<ir::Stmt>, usize),
}

/// The evaluator's end of [`on_two_threads`]: it runs the first `ahead`
/// passes on each batch and hands what comes out on.
struct Handoff {
    to_back: mpsc::SyncSender<Handed>,
    /// Emptied batches coming back, to be filled again.
    spare: mpsc::Receiver<Vec<ir::Stmt>>,
    ahead: usize,
    lower_options: lower::LowerOptions,
    /// Those passes, made when the program starts.
    lowering: Option<Pipeline>,
    lower_time: Duration,
}

impl Handoff {
    /// The end of the program: the passes flush what they hold back.
    /// Returns them (for their diagnostics) and the time they took.
    fn finish(mut self) -> (Option<Pipeline>, Duration) {
        if let Some(lowering) = &mut self.lowering {
            let (t0, mut handing) = (Instant::now(), Duration::ZERO);
            let (to_back, spare) = (&self.to_back, &self.spare);
            lowering.finish(&mut |lowered| handing += hand_on(to_back, spare, lowered));
            self.lower_time += t0.elapsed().saturating_sub(handing);
        }
        (self.lowering, self.lower_time)
    }
}

/// Send `stmts` to the back end, and leave an empty batch in their place;
/// the time it took (waiting while the back end is behind).
fn hand_on(
    to_back: &mpsc::SyncSender<Handed>,
    spare: &mpsc::Receiver<Vec<ir::Stmt>>,
    stmts: &mut Vec<ir::Stmt>,
) -> Duration {
    let t0 = Instant::now();
    let empty = spare
        .try_recv()
        .unwrap_or_else(|_| Vec::with_capacity(stmts.capacity()));
    let full = std::mem::replace(stmts, empty);
    let _ = to_back.send(Handed::Batch(full, this_cpu()));
    t0.elapsed()
}

impl ir::Sink for Handoff {
    fn start(&mut self, start: &ir::Start) {
        if self.ahead > 0 {
            let context = lower::Context {
                start,
                options: &self.lower_options,
            };
            self.lowering = Some(Pipeline::new(&context, 0..self.ahead));
        }
        let _ = self.to_back.send(Handed::Start(Box::new(start.clone())));
    }

    /// Lower the batch through the passes ahead (if any) and send what
    /// comes out to the back end, leaving an empty batch in its place.
    fn batch(&mut self, batch: &mut Vec<ir::Stmt>) {
        let (to_back, spare) = (&self.to_back, &self.spare);
        match &mut self.lowering {
            Some(lowering) => {
                let (t0, mut handing) = (Instant::now(), Duration::ZERO);
                lowering.run(batch, &mut |lowered| {
                    handing += hand_on(to_back, spare, lowered)
                });
                self.lower_time += t0.elapsed().saturating_sub(handing);
            }
            None => {
                hand_on(to_back, spare, batch);
            }
        }
    }
}

impl ir::Sink for Backend<'_> {
    fn start(&mut self, start: &ir::Start) {
        self.started = Some(self.started(start));
    }

    fn batch(&mut self, batch: &mut Vec<ir::Stmt>) {
        let Some(started) = &mut self.started else {
            batch.clear();
            return;
        };
        let t0 = Instant::now();
        let mut emit_time = Duration::ZERO;
        let (printer, out, write_error) =
            (&mut started.printer, &mut self.out, &mut self.write_error);
        let mut print = |stmts: &mut Vec<ir::Stmt>| {
            let t = Instant::now();
            print_and_write(printer, out, write_error, stmts);
            emit_time += t.elapsed();
        };
        match &mut started.lowering {
            Some(lowering) => lowering.run(batch, &mut print),
            None => print(batch),
        }
        batch.clear();
        self.lower_time += t0.elapsed() - emit_time;
        self.emit_time += emit_time;
    }
}

/// Print statements (and empty them); hand the text on in large writes.
fn print_and_write(
    printer: &mut Printer,
    out: &mut Output<'_>,
    write_error: &mut Option<std::io::Error>,
    stmts: &mut Vec<ir::Stmt>,
) {
    let text = printer.print(stmts);
    stmts.clear();
    let Some(text) = text else {
        return;
    };
    if text.len() >= WRITE_AT {
        if let (None, Output::Text(out)) = (&write_error, out) {
            if let Err(e) = out.write_all(text) {
                *write_error = Some(e);
            }
        }
        text.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`input_decimals`] as one pass forward from each coordinate letter
    /// reads it: blanks and signs, digits, a point, the decimals.
    fn decimals_read_forward(text: &str) -> usize {
        let bytes = text.as_bytes();
        let (mut most, mut i) = (0, 0);
        while i < bytes.len() {
            i += 1;
            if !COORDINATE[usize::from(bytes[i - 1])] {
                continue;
            }
            while i < bytes.len() && matches!(bytes[i], b' ' | b'\t' | b'+' | b'-') {
                i += 1;
            }
            while i < bytes.len() && bytes[i].is_ascii_digit() {
                i += 1;
            }
            if i < bytes.len() && bytes[i] == b'.' {
                i += 1;
                let start = i;
                while i < bytes.len() && bytes[i].is_ascii_digit() {
                    i += 1;
                }
                most = most.max(i - start);
            }
        }
        most
    }

    proptest::proptest! {
        #[test]
        fn decimals_found_from_the_points_are_those_read_forward(
            text in r"[XxYyGgRrNn0-9 \t.+\-(\n]{0,400}"
        ) {
            proptest::prop_assert_eq!(input_decimals(&text), decimals_read_forward(&text));
        }
    }

    /// A file with a control character or a CR not before a LF is read
    /// whole (`decode` reports or rewrites them); tabs and CRLF are not.
    #[test]
    fn the_scan_refuses_control_characters_and_lone_crs() {
        for (bytes, streamed) in [
            (&b"G1 X1\tY2\r\nM30\r\n"[..], true),
            (b"G1 X1\nM30", true),
            (b"G1 X1\x01\nM30\n", false),
            (b"G1 X1\x00\nM30\n", false),
            (b"G1 X1\x0c\nM30\n", false),
            (b"G1 X1\x1f\r\nM30\r\n", false),
            (b"G1 X1\rM30\n", false),
            (b"G1 X1\r\nM30\r", false),
            (b"G1 X1\r\r\nM30\n", false),
        ] {
            let scan = scan_file(&mut &bytes[..]).ok().flatten();
            assert_eq!(scan.is_some(), streamed, "{bytes:?}");
        }
    }

    #[test]
    fn decimals_are_those_of_coordinate_words() {
        for (text, most) in [
            ("G1 X1.234 Y-0.5 Z+.25", 3),
            ("G1 F100.12345 X1.5", 1),
            ("N10.5 G1.25 P0.75", 0),
            ("X - + 1.1234", 4),
            ("X-5-3.21", 0),
            ("XX.5", 1),
            ("X1.2.345", 1),
            ("x.25 i-1.125", 3),
            ("(Y1.123456) G1 X1", 6),
            (".5 1.25", 0),
            ("X.", 0),
            ("", 0),
            ("X12345678.123456789", 9),
            ("G1 X1.5 Y2.25 (a longer line, past eight bytes) Z3.125", 3),
            ("Y1.5\nG4 P0.123456\nX.12", 2),
            ("1.23456 X-- 7.1234", 4),
        ] {
            assert_eq!(input_decimals(text), most, "{text:?}");
            assert_eq!(decimals_read_forward(text), most, "{text:?}");
        }
    }

    /// The back end moves off the evaluator's processor, and only off it:
    /// every other allowed processor stays allowed. (On one processor
    /// nothing changes.)
    #[cfg(target_os = "linux")]
    #[test]
    fn the_back_end_keeps_off_the_evaluators_processor() {
        use rustix::thread::sched_getaffinity;
        std::thread::spawn(|| {
            let allowed = sched_getaffinity(None).unwrap();
            let here = this_cpu();
            assert!(allowed.is_set(here));
            let mut apart = Apart::new();
            apart.keep_off(here);
            let now = sched_getaffinity(None).unwrap();
            if allowed.count() < 2 {
                assert_eq!(now, allowed);
                return;
            }
            assert!(!now.is_set(here), "still allowed on {here}");
            assert_eq!(now.count(), allowed.count() - 1);
            assert_ne!(this_cpu(), here, "not moved off {here}");
            // The evaluator moved: the first one is allowed again.
            let other = (0..rustix::thread::CpuSet::MAX_CPU)
                .find(|&c| c != here && allowed.is_set(c))
                .unwrap();
            apart.keep_off(other);
            let now = sched_getaffinity(None).unwrap();
            assert!(now.is_set(here) && !now.is_set(other));
        })
        .join()
        .unwrap();
    }
}
