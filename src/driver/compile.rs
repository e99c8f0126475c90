//! A compile from source text to G-code text or a tool path, through the
//! stages in order (parse, expand, lowering passes, emit): the entry
//! points below the session. Writes only to the `Write` it is handed.

use super::backend::{Backend, Output, SourceFacts};
use super::clock::Clock;
use super::options::{CompileOptions, Stage};
use super::parts::{LineReader, PartSource, Parts, ProgramReader, Whole};
use super::scan::{FileScan, Unforeseen};
use super::threads::on_two_threads;
use crate::diagnostic::{is_error, Diagnostic};
use crate::eval::{self, EvalOptions, WizardHost};
use crate::source::{FileId, Locator, Sources};
use crate::syntax::{chunk, Language};
use crate::toolpath::{PathSink, ToolPath};
use std::io::Write;
use std::time::Duration;

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
    attempt(
        sources,
        file,
        options,
        wizards,
        Output::Text(out),
        Cutting::PlainOnly,
    )
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
        attempt(sources, file, options, wizards, Output::Text(out), cutting)
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

/// One compile of the file `file` into `out` (text, a path, moves), a
/// program that is not plain read in parts as `cutting` says; `Err`: a
/// part needs the whole program.
fn attempt<'a>(
    sources: &'a Sources,
    file: FileId,
    options: &'a CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: Output<'a>,
    cutting: Cutting,
) -> Result<Report, Whole> {
    let (mut diagnostics, mut clock) = (Vec::new(), Clock::new());
    let input = Input::of(sources, file, options);
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

/// What a read that needs the whole program says where it has it.
const WHOLE_TWICE: &str = "internal: a whole read asked for a whole read";

/// The report of a compile that stopped for the whole program where it
/// cannot ([`Cutting::PlainOnly`]): none is ever made.
fn unreachable_whole() -> Report {
    Report {
        diagnostics: Vec::new(),
        timings: Vec::new(),
        write_error: Some(std::io::Error::other(WHOLE_TWICE)),
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
        let mut path = None;
        let wizards = wizards.as_mut().map(|w| &mut **w as &mut dyn WizardHost);
        let out = Output::Path(&mut path);
        // Nothing is written: no write can fail.
        let report = attempt(sources, file, &options, wizards, out, cutting)?;
        Ok((path, report.diagnostics))
    });
    let (mut path, diagnostics) =
        found.unwrap_or_else(|Whole| (None, vec![Diagnostic::error().with_message(WHOLE_TWICE)]));
    if diagnostics.iter().any(is_error) {
        path = None;
    }
    (path, diagnostics)
}

/// The tool path of file `file` of `sources` handed to `sink` move by
/// move as the back end makes it ([`tool_path`] without holding it); the
/// diagnostics. With errors among them, what `sink` was fed is not the
/// program's path.
pub fn feed_tool_path(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    sink: &mut dyn PathSink,
) -> Vec<Diagnostic> {
    let options = CompileOptions {
        stage: None,
        ..options.clone()
    };
    let mut wizards = wizards;
    let mut started = false;
    let found = in_parts_else_whole(|cutting| {
        if std::mem::replace(&mut started, true) {
            sink.restart();
        }
        let wizards = wizards.as_mut().map(|w| &mut **w as &mut dyn WizardHost);
        let out = Output::Moves(&mut *sink);
        // Nothing is written: no write can fail.
        Ok(attempt(sources, file, &options, wizards, out, cutting)?.diagnostics)
    });
    found.unwrap_or_else(|Whole| vec![Diagnostic::error().with_message(WHOLE_TWICE)])
}

/// The values the variables of file `file` of `sources` have where the
/// program reads and sets them ([`eval::watch_program`]): the program
/// parsed whole and run without output; nothing when it does not parse.
pub fn watch(
    sources: &Sources,
    file: FileId,
    options: &CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
) -> eval::Watched {
    let input = Input::of(sources, file, options);
    let (mut program, parsed) = crate::syntax::parse_program_files(
        (input.text, &input.locator),
        &input.library,
        input.language,
    );
    if parsed.iter().any(is_error) {
        return eval::Watched::default();
    }
    if input.from.0 == eval::Flavour::Fanuc && input.language == Language::Gcode {
        map_fanuc_functions(&mut program.main);
        for sub in &mut program.subprograms {
            map_fanuc_functions(&mut sub.body);
        }
    }
    let eval_options = options.eval_options(input.from, input.language);
    eval::watch_program(&program, &eval_options, wizards)
}

/// The file to compile: its text, id, language and flavour.
struct Input<'a> {
    /// The subroutine files read with it (`CompileOptions::library`).
    library: Vec<(&'a str, Locator)>,
    text: &'a str,
    file: FileId,
    locator: Locator,
    language: Language,
    from: (eval::Flavour, eval::Chosen),
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
            from: options.flavour(name, super::scan::clue(sources.text(file))),
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
    let fanuc_functions = from.0 == eval::Flavour::Fanuc && language == Language::Gcode;
    // A program is read in parts, unless it needs to be read whole.
    let at = &locator;
    let (read, tape_note) = read_in_parts(text, at, language);
    let source =
        match library.is_empty() && options.stage != Some(Stage::Parse) && chunk::by_parts() {
            false => None,
            true if language == Language::Gcode && chunk::chunkable(read) => {
                let ranges = Box::new(chunk::chunks(read));
                Some(PartSource::Text {
                    text: read,
                    at,
                    ranges,
                })
            }
            true => match cutting {
                Cutting::PlainOnly => None,
                Cutting::AsItGoes => Some(PartSource::TextCut {
                    text: read,
                    at,
                    from: 0,
                    defined: Vec::new(),
                }),
            },
        };
    if let Some(source) = source {
        let backend = Backend::new(SourceFacts::Text(text), file, options, out);
        let mut parts = Parts::new(source);
        parts.tape_note = tape_note;
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
        crate::syntax::parse_program_files((text, &locator), &library, language);
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
            Output::Path(_) | Output::Moves(_) => Ok(()),
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

/// What the parts of `text` read: a tape's text up to its closing `%`
/// line (a whole read sees to it itself), and the note on what follows it.
fn read_in_parts<'t>(
    text: &'t str,
    at: &Locator,
    language: Language,
) -> (&'t str, Option<Diagnostic>) {
    let tape = match language {
        Language::Gcode => crate::syntax::tape_end(text, at),
        Language::Egc => None,
    };
    match tape {
        Some((cut, note)) => (&text[..cut], note.map(|n| n.to_diagnostic())),
        None => (text, None),
    }
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
    let source = (reader, name, file, scan);
    file_to(source, options, wizards, Output::Text(out))
}

/// [`compile_file`] into `out` (text, or moves: [`feed_tool_path`]'s
/// stream, for which the options have no stage).
pub(super) fn file_to<'a>(
    (reader, name, file, scan): (&mut dyn std::io::BufRead, &str, FileId, FileScan),
    options: &'a CompileOptions,
    wizards: Option<&mut dyn WizardHost>,
    out: Output<'a>,
) -> std::io::Result<Streamed> {
    let mut diagnostics = Vec::new();
    let mut clock = Clock::new();
    let (from, language) = (options.flavour(name, scan.clue), options.language(name));
    let eval_options = options.eval_options(from, language);
    let printed = !matches!(out, Output::Path(_) | Output::Moves(_));
    let backend = Backend::new(SourceFacts::Known(scan), file, options, out);
    let mut lines = LineReader::new(reader, (file, language), scan);
    lines.printed = printed;
    // G-code is read as plain until a part is found not to be.
    let mut parts = Parts::new(match language == Language::Gcode {
        true => PartSource::Reader(lines),
        false => PartSource::Program(ProgramReader::new(lines, language)),
    });
    let written = run_by_parts(
        &mut parts,
        language,
        from.0 == eval::Flavour::Fanuc && language == Language::Gcode,
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
    let tape_note = parts.take_tape_note();
    diagnostics.append(&mut parts.diagnostics);
    diagnostics.extend(tape_note);
    clock.ran_inside(backend.lower_time_ahead);
    clock.split("expand", &[("parse", parts.time)]);
    // A syntax error (among `diagnostics` now) stops the compile: what the
    // evaluator said of the parts before it is not reported.
    if !parts.broken {
        diagnostics.extend(evaluated);
    }
    finish_back_end(backend, diagnostics, clock)
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
