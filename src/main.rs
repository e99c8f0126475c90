//! The `ger` command line: reads files, calls the library, prints
//! diagnostics, writes output atomically and maps results to exit codes
//! (0 success, 1 the program has errors, 2 usage or I/O). No compiler logic
//! lives here.

use clap::{Parser, Subcommand, ValueEnum};
use ger::compile::{compile_to, CompileOptions, Report, Stage, Streamed};
use ger::diagnostic::render;
use ger::emit::{ArcFormat, Numbering, Target};
use ger::ir::Units;
use ger::source::Sources;
use ger::wizard::{standard_library, Library, WizardEngine, WizardSource};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

// Big programs build a large tree, then a large IR, then a large text:
// mimalloc reuses the freed pages where the system allocator returns them
// and faults in new ones (about a third of the wall time on 200k lines).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "ger",
    version,
    about = "Compile extended G-code (.egc) to plain ISO G-code"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compile a program to plain G-code.
    Compile {
        /// The .egc file, or `-` for standard input.
        input: String,
        /// Output file (standard output when absent, or `-`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[command(flatten)]
        options: Options,
        /// Print the program after this stage (parse, expand, units, polar, offsets, absolute).
        #[arg(long)]
        stage: Option<String>,
    },
    /// Check a program and print its diagnostics; write nothing.
    Check {
        input: String,
        #[command(flatten)]
        options: Options,
    },
    /// Draw the part the program cuts: a depth (or --shade) PNG, the tool
    /// path as SVG, or the part as STL, by the output's extension.
    Render {
        /// The program, or `-` for standard input.
        input: String,
        /// The picture: part.png, part.svg or part.stl.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        options: Options,
        #[command(flatten)]
        picture: PictureArgs,
    },
    /// List the wizards found, or show one wizard's signature and doc.
    Wizards {
        name: Option<String>,
        /// A folder of wizards (`<Name>.rhai`), searched first; repeatable.
        #[arg(long = "wizards", value_name = "DIR")]
        dirs: Vec<PathBuf>,
        /// Also search the `wizards/` folder beside this part program.
        #[arg(long)]
        part: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
struct Options {
    /// Line numbers: the source line (default), a sequence, or none.
    #[arg(long, value_enum, default_value_t = NumbersArg::Source)]
    numbers: NumbersArg,
    /// The output flavour.
    #[arg(long, alias = "dialect", value_enum, default_value_t = TargetArg::Generic)]
    target: TargetArg,
    /// Comments of a plain G-code program in the output.
    #[arg(long, value_enum, default_value_t = CommentsArg::Keep)]
    comments: CommentsArg,
    /// The source language; default: `.egc` is ger's, any other file plain G-code.
    #[arg(long = "input", id = "language", value_name = "LANGUAGE", value_enum)]
    language: Option<InputArg>,
    /// Whose meaning holds where controllers disagree (G4 P in s or ms);
    /// default: linuxcnc for .ngc files, else generic.
    #[arg(long, value_enum)]
    from: Option<FromArg>,
    /// A LinuxCNC tool table (`T1 P1 D6.35 Z75`), in the output's units;
    /// the program's `SetTool` lines win over it.
    #[arg(long = "tool-table", value_name = "FILE")]
    tool_table: Option<PathBuf>,
    /// The units of a program that states none (no G20/G21, no SetUnits).
    #[arg(long, value_enum)]
    units: Option<UnitsArg>,
    /// Canned cycles: expanded to moves, or kept for a controller that has
    /// them (--target fanuc or linuxcnc).
    #[arg(long, value_enum, default_value_t = CyclesArg::Expand)]
    cycles: CyclesArg,
    /// Cutter compensation: resolved into the tool-centre path, or kept for
    /// a controller that compensates itself (--target fanuc or linuxcnc).
    #[arg(long, value_enum, default_value_t = CompArg::Resolve)]
    comp: CompArg,
    /// The move that starts compensation: rs274's (offset square to itself
    /// at its end, then a corner) or lookahead (straight to the offset start
    /// of the next move, as Ger does).
    #[arg(long = "comp-entry", value_enum, default_value_t = CompEntryArg::Rs274)]
    comp_entry: CompEntryArg,
    /// How arcs are written.
    #[arg(long, value_enum, default_value_t = ArcsArg::Ij)]
    arcs: ArcsArg,
    /// Chord tolerance for `--arcs lines`, in output units.
    #[arg(long, default_value_t = 0.001)]
    tolerance: f64,
    /// Decimals in the output (default 3 for mm, 4 for inch).
    #[arg(long)]
    decimals: Option<usize>,
    /// A `while` loop that runs more often is an error.
    #[arg(long, default_value_t = 10_000_000)]
    max_iterations: u64,
    /// Print the time each stage took to stderr.
    #[arg(long)]
    timings: bool,
    /// A folder of wizards (`<Name>.rhai`), searched first; repeatable.
    #[arg(long = "wizards", value_name = "DIR")]
    wizard_dirs: Vec<PathBuf>,
    /// A folder of LinuxCNC subroutine files (`name.ngc` for `o<name>
    /// call`), searched before the program's own folder; repeatable.
    #[arg(long = "subroutines", value_name = "DIR")]
    subroutine_dirs: Vec<PathBuf>,
}

#[derive(clap::Args)]
struct PictureArgs {
    /// The cell size, in the program's units (default 0.001 in / 0.025 mm).
    #[arg(long)]
    resolution: Option<f64>,
    /// Coarser cells when the stock would need more than this many.
    #[arg(long, default_value_t = 40_000_000)]
    max_cells: u64,
    /// The stock's size X,Y,Z (placed as SetPart places it).
    #[arg(long, value_name = "X,Y,Z")]
    stock: Option<String>,
    /// A hill-shaded colour PNG with a depth legend instead of the depth image.
    #[arg(long)]
    shade: bool,
    /// What colours the feeds of an SVG.
    #[arg(long, value_enum, default_value_t = ColorArg::Depth)]
    color: ColorArg,
    /// Rapids in an SVG.
    #[arg(long, value_enum, default_value_t = RapidsArg::Show)]
    rapids: RapidsArg,
    /// Another program: the PNG shows where the two cut differently.
    #[arg(long, value_name = "OTHER")]
    diff: Option<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ColorArg {
    Depth,
    Feed,
    Tool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum RapidsArg {
    Show,
    Hide,
}

#[derive(Clone, Copy, ValueEnum)]
enum NumbersArg {
    Source,
    Seq,
    None,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CommentsArg {
    Keep,
    Drop,
}

#[derive(Clone, Copy, ValueEnum)]
enum FromArg {
    Generic,
    Linuxcnc,
    Fanuc,
    Grbl,
    Mach3,
}

#[derive(Clone, Copy, ValueEnum)]
enum InputArg {
    Egc,
    Gcode,
}

#[derive(Clone, Copy, ValueEnum)]
enum UnitsArg {
    Mm,
    Inch,
}

#[derive(Clone, Copy, ValueEnum)]
enum TargetArg {
    Generic,
    Fanuc,
    Grbl,
    Linuxcnc,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CyclesArg {
    Expand,
    Keep,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CompArg {
    Resolve,
    Keep,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CompEntryArg {
    Rs274,
    Lookahead,
}

#[derive(Clone, Copy, ValueEnum)]
enum ArcsArg {
    Ij,
    R,
    Lines,
}

impl Options {
    /// The library's options for these command-line choices.
    fn compile_options(&self, stage: Option<Stage>) -> CompileOptions {
        CompileOptions {
            eval: ger::eval::EvalOptions {
                max_iterations: self.max_iterations,
                keep_comments: self.comments == CommentsArg::Keep,
                units: self.units.map(|u| match u {
                    UnitsArg::Mm => Units::Mm,
                    UnitsArg::Inch => Units::Inch,
                }),
                ..Default::default()
            },
            from: self.from.map(|f| match f {
                FromArg::Generic => ger::eval::Flavour::Generic,
                FromArg::Linuxcnc => ger::eval::Flavour::LinuxCnc,
                FromArg::Fanuc => ger::eval::Flavour::Fanuc,
                FromArg::Grbl => ger::eval::Flavour::Grbl,
                FromArg::Mach3 => ger::eval::Flavour::Mach3,
            }),
            input: self.language.map(|i| match i {
                InputArg::Egc => ger::syntax::egc::Language::Egc,
                InputArg::Gcode => ger::syntax::egc::Language::Gcode,
            }),
            lower: ger::lower::LowerOptions {
                keep_cycles: self.cycles == CyclesArg::Keep,
                keep_comp: self.comp == CompArg::Keep,
                comp_entry_lookahead: self.comp_entry == CompEntryArg::Lookahead,
                tip_path: false,
            },
            emit: ger::emit::EmitOptions {
                numbering: match self.numbers {
                    NumbersArg::Source => Numbering::Source,
                    NumbersArg::Seq => Numbering::Seq,
                    NumbersArg::None => Numbering::None,
                },
                target: match self.target {
                    TargetArg::Generic => Target::Generic,
                    TargetArg::Fanuc => Target::Fanuc,
                    TargetArg::Grbl => Target::Grbl,
                    TargetArg::Linuxcnc => Target::LinuxCnc,
                },
                arcs: match self.arcs {
                    ArcsArg::Ij => ArcFormat::Ij,
                    ArcsArg::R => ArcFormat::R,
                    ArcsArg::Lines => ArcFormat::Lines,
                },
                decimals: self.decimals,
                tolerance: self.tolerance,
                ..Default::default()
            },
            stage,
            library: Vec::new(),
        }
    }
}

fn main() -> ExitCode {
    // The evaluator and the grammar's trees recurse; the lexer bounds the
    // nesting, and a big stack gives the bounded recursion ample room.
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(real_main)
        .ok()
        .and_then(|t| t.join().ok())
        .unwrap_or(ExitCode::from(2))
}

fn real_main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Compile {
            input,
            output,
            options,
            stage,
        } => {
            let stage = match stage.as_deref().map(|s| (s, Stage::from_name(s))) {
                None => None,
                Some((_, Some(stage))) => Some(stage),
                Some((name, None)) => {
                    let names: Vec<&str> = Stage::names().collect();
                    eprintln!(
                        "error: unknown stage `{name}`; the stages are {}",
                        names.join(", ")
                    );
                    return ExitCode::from(2);
                }
            };
            // `-o -`: standard output, as `-` is standard input.
            let output = output.filter(|o| o.as_os_str() != "-");
            run(&input, output.as_deref(), &options, stage, true)
        }
        Command::Check { input, options } => run(&input, None, &options, None, false),
        Command::Render {
            input,
            output,
            options,
            picture,
        } => render_part(&input, &output, &options, &picture),
        Command::Wizards { name, dirs, part } => {
            list_wizards(name.as_deref(), &dirs, part.as_deref())
        }
    }
}

/// The files of the LinuxCNC subroutines the program calls but does not
/// hold: `name.ngc` from the `--subroutines` folders, then the program's
/// own folder (as LinuxCNC's SUBROUTINE_PATH and the program's folder).
fn subroutine_files(
    sources: &mut Sources,
    main: ger::source::FileId,
    dirs: &[PathBuf],
    part: Option<&Path>,
) -> Result<Vec<ger::source::FileId>, String> {
    for dir in dirs {
        if !dir.is_dir() {
            return Err(format!("cannot read subroutine folder `{}`", dir.display()));
        }
    }
    let mut folders: Vec<PathBuf> = dirs.to_vec();
    if let Some(part) = part {
        folders.push(part.parent().unwrap_or(Path::new(".")).to_path_buf());
    }
    ger::compile::subroutine_library(sources, main, &mut |name| {
        let Some(path) = folders
            .iter()
            .map(|d| d.join(format!("{name}.ngc")))
            .find(|p| p.is_file())
        else {
            return Ok(None);
        };
        let text = std::fs::read(&path)
            .map_err(|e| format!("cannot read `{}`: {e}", path.display()))
            .and_then(|bytes| {
                ger::source::decode(bytes)
                    .map_err(|_| format!("`{}` is not a text file", path.display()))
            })?;
        Ok(Some((path.display().to_string(), text)))
    })
}

/// Wizard scripts in search order (SPEC §5): `--wizards` folders, `wizards/`
/// beside the part, `GER_WIZARDS`, then the standard library.
fn discover_wizards(dirs: &[PathBuf], part: Option<&Path>) -> Result<Vec<WizardSource>, String> {
    let mut folders: Vec<(PathBuf, bool)> = dirs.iter().map(|d| (d.clone(), true)).collect();
    if let Some(part) = part {
        let beside = part.parent().unwrap_or(Path::new(".")).join("wizards");
        folders.push((beside, false));
    }
    if let Some(env) = std::env::var_os("GER_WIZARDS") {
        folders.extend(std::env::split_paths(&env).map(|d| (d, false)));
    }
    let mut found = Vec::new();
    for (dir, required) in folders {
        let entries = match std::fs::read_dir(&dir) {
            Ok(entries) => entries,
            Err(e) if required => {
                return Err(format!(
                    "cannot read wizard folder `{}`: {e}",
                    dir.display()
                ))
            }
            Err(_) => continue,
        };
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "rhai"))
            // `_name.rhai` files are helpers, not wizards.
            .filter(|p| {
                !p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with('_'))
            })
            .collect();
        paths.sort();
        for path in paths {
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
            found.push(WizardSource {
                name: path
                    .file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned(),
                text,
                origin: path.display().to_string(),
            });
        }
    }
    found.extend(standard_library());
    Ok(found)
}

fn list_wizards(name: Option<&str>, dirs: &[PathBuf], part: Option<&Path>) -> ExitCode {
    let found = match discover_wizards(dirs, part) {
        Ok(found) => found,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut sources = Sources::new();
    let library = Library::new(found, &mut sources);
    let describe = |w: &ger::wizard::Wizard| match &w.declaration {
        Ok(d) => (d.signature(&w.name), d.summary().to_string()),
        Err(e) => (
            w.name.clone(),
            format!("(bad declaration, line {}: {})", e.line, e.message),
        ),
    };
    match name {
        None => {
            for w in library.iter() {
                let (signature, summary) = describe(w);
                println!("{signature}\n    {summary}  [{}]", w.origin);
            }
            ExitCode::SUCCESS
        }
        Some(name) => {
            let Some(w) = library.get(name) else {
                eprintln!("error: no wizard named `{name}`; `ger wizards` lists them");
                return ExitCode::from(2);
            };
            let (signature, _) = describe(w);
            println!("{signature}    [{}]\n", w.origin);
            if let Ok(d) = &w.declaration {
                for line in &d.doc {
                    println!("{line}");
                }
                if !d.params.is_empty() {
                    println!();
                }
                for p in &d.params {
                    let default = p
                        .default
                        .as_ref()
                        .map_or(String::new(), |d| format!(" (default {d})"));
                    println!("  {:<12} {}{default}", p.name, p.doc);
                }
            }
            ExitCode::SUCCESS
        }
    }
}

/// A program read and ready to compile: its sources (with the tool table),
/// the library's options, and the wizards found for it.
struct Job {
    sources: Sources,
    file: ger::source::FileId,
    options: CompileOptions,
    engine: WizardEngine,
}

impl Job {
    /// Read `input` and everything it needs; on failure the exit code,
    /// with the problem printed.
    fn load(input: &str, options: &Options, stage: Option<Stage>) -> Result<Job, ExitCode> {
        let bytes = match read_input(input) {
            Ok(bytes) => bytes,
            Err(e) => {
                eprintln!("error: cannot read `{input}`: {e}");
                return Err(ExitCode::from(2));
            }
        };
        let text = match ger::source::decode(bytes) {
            Ok(text) => text,
            Err(why) => {
                let (what, at) = match why {
                    ger::source::NotText::Nul(at) => ("a NUL byte", at),
                    ger::source::NotText::Control(at) => ("a control character", at),
                };
                eprintln!(
                    "error: `{input}` is not a text file: {what} at byte {at}\n  = note: ger reads G-code programs as text (UTF-8 or Latin-1)"
                );
                return Err(ExitCode::from(1));
            }
        };
        Job::with_text(input, text, options, stage)
    }

    /// [`Job::load`] with the input's text given (empty for a file compiled
    /// from a reader, read again only to show diagnostics).
    fn with_text(
        input: &str,
        text: String,
        options: &Options,
        stage: Option<Stage>,
    ) -> Result<Job, ExitCode> {
        let mut sources = Sources::new();
        let name = if input == "-" { "<stdin>" } else { input };
        let file = sources.add(name, text);
        let mut compile_options = options.compile_options(stage);
        if let Some(path) = &options.tool_table {
            let text = match std::fs::read(path).map(ger::source::decode) {
                Ok(Ok(text)) => text,
                Ok(Err(_)) => {
                    eprintln!("error: `{}` is not a text file", path.display());
                    return Err(ExitCode::from(2));
                }
                Err(e) => {
                    eprintln!("error: cannot read `{}`: {e}", path.display());
                    return Err(ExitCode::from(2));
                }
            };
            let table = sources.add(path.display().to_string(), text);
            match ger::tool_table::parse(sources.text(table), table) {
                Ok(tools) => compile_options.eval.tools = tools,
                Err(errors) => {
                    let diagnostics: Vec<_> = errors.iter().map(|e| e.to_diagnostic()).collect();
                    eprint!("{}", ger::diagnostic::render(&sources, &diagnostics));
                    return Err(ExitCode::from(1));
                }
            }
        }
        if !options.tolerance.is_finite()
            || options.tolerance <= 0.0
            || options.decimals.is_some_and(|d| d > 9)
        {
            eprintln!("error: --tolerance must be positive and --decimals at most 9");
            return Err(ExitCode::from(2));
        }
        if options.cycles == CyclesArg::Keep
            && !matches!(options.target, TargetArg::Fanuc | TargetArg::Linuxcnc)
        {
            eprintln!("error: --cycles keep needs a controller with canned cycles: --target fanuc or linuxcnc");
            return Err(ExitCode::from(2));
        }
        if options.comp == CompArg::Keep
            && !matches!(options.target, TargetArg::Fanuc | TargetArg::Linuxcnc)
        {
            eprintln!(
                "error: --comp keep needs a controller that compensates: --target fanuc or linuxcnc"
            );
            return Err(ExitCode::from(2));
        }
        let part = (input != "-").then(|| Path::new(input));
        if compile_options.language(name) == ger::syntax::egc::Language::Gcode {
            match subroutine_files(&mut sources, file, &options.subroutine_dirs, part) {
                Ok(library) => compile_options.library = library,
                Err(e) => {
                    eprintln!("error: {e}");
                    return Err(ExitCode::from(2));
                }
            }
        }
        let found = match discover_wizards(&options.wizard_dirs, part) {
            Ok(found) => found,
            Err(e) => {
                eprintln!("error: {e}");
                return Err(ExitCode::from(2));
            }
        };
        let engine = WizardEngine::new(Library::new(found, &mut sources));
        Ok(Job {
            sources,
            file,
            options: compile_options,
            engine,
        })
    }
}

fn run(
    input: &str,
    output: Option<&Path>,
    options: &Options,
    stage: Option<Stage>,
    write: bool,
) -> ExitCode {
    if let Some(out) = output {
        if input != "-" && same_file(Path::new(input), out) {
            eprintln!("error: the output file is the input file; refusing to overwrite it");
            return ExitCode::from(2);
        }
    }
    let started = std::time::Instant::now();
    // A program written to a file is compiled from its file, a part at a
    // time, without holding its text; one found to need the whole program
    // (a call of a subprogram written further on, a `GOTO`) is then
    // compiled again, whole.
    // Standard output, and `ger check`, too: their output is held in an
    // unnamed temporary file, or thrown away, not in memory.
    // The file is read once: its first lines say how its numbers are
    // printed, and each part is checked as it is read; a file found to be
    // otherwise further on is scanned whole, and compiled again.
    let job = |streamed| compile_job(input, output, options, stage, write, streamed, started);
    let first = streamable(input, options, stage, ger::compile::first_look);
    if let Some(first) = first {
        match job(Some(first)) {
            Ok(code) => return code,
            Err(Again::Rescan) => {
                let scanned = streamable(input, options, stage, ger::compile::scan_path);
                if let Some(Ok(code)) = scanned.map(|scanned| job(Some(scanned))) {
                    return code;
                }
            }
            Err(Again::Whole) => {}
        }
    }
    job(None).unwrap_or(ExitCode::FAILURE)
}

/// Why [`compile_job`] must be run again (nothing was written or reported).
enum Again {
    /// The program needs to be read whole.
    Whole,
    /// A part of the file was not as its first lines said
    /// ([`ger::compile::first_look`]): it needs a scan of the whole file.
    Rescan,
}

/// Compile `input` as `run` says, from its file a part at a time when
/// `streamed` (what [`streamable`] found).
fn compile_job(
    input: &str,
    output: Option<&Path>,
    options: &Options,
    stage: Option<Stage>,
    write: bool,
    streamed: Option<(ger::compile::FileScan, std::fs::Metadata)>,
    started: std::time::Instant,
) -> Result<ExitCode, Again> {
    let loaded = match streamed {
        Some(_) => Job::with_text(input, String::new(), options, stage),
        None => Job::load(input, options, stage),
    };
    let mut job = match loaded {
        Ok(job) => job,
        Err(code) => return Ok(code),
    };
    let (file, compile_options) = (job.file, &job.options);
    let (sources, engine) = (&job.sources, &mut job.engine);
    let (mut read_error, mut again) = (None, None);
    // Not a compiled program: the output is thrown away.
    let not_compiled = |why: &str| Report {
        diagnostics: Vec::new(),
        timings: Vec::new(),
        write_error: Some(std::io::Error::other(why.to_string())),
    };
    let mut compile = |out: &mut (dyn Write + Send)| match &streamed {
        Some(scan) => {
            let engine = Some(&mut *engine as &mut dyn ger::eval::WizardHost);
            match compile_from_file(input, scan, file, compile_options, engine, out) {
                Ok(Streamed::Compiled(report)) => report,
                Ok(Streamed::Whole) => {
                    again = Some(Again::Whole);
                    not_compiled("the program needs to be read whole")
                }
                Ok(Streamed::Rescan) => {
                    again = Some(Again::Rescan);
                    not_compiled("the file needs to be scanned whole")
                }
                Err(e) => {
                    read_error = Some(e);
                    not_compiled("the input could not be read")
                }
            }
        }
        None => compile_to(sources, file, compile_options, Some(&mut *engine), out),
    };
    // A file is written as the program is compiled; standard output gets
    // the program only once it is known to be whole (a pipe to a machine
    // must never see half of one).
    let mut text = Vec::new();
    let mut held = None;
    let report = match (write, output) {
        (true, Some(path)) => write_atomically(path, compile),
        (true, None) if streamed.is_some() => {
            // Held in an unnamed file (memory bounded as with `-o`); with
            // no temporary file to be had, compiled whole into memory.
            let Ok(file) = tempfile::tempfile() else {
                return Err(Again::Whole);
            };
            let file = held.insert(file);
            compile(file)
        }
        (false, _) if streamed.is_some() => compile(&mut std::io::sink()),
        (true, None) => {
            // Held in memory: a program found to need a whole read part
            // way is compiled again into an emptied buffer.
            let engine = Some(&mut *engine as &mut dyn ger::eval::WizardHost);
            ger::compile::compile_to_vec(sources, file, compile_options, engine, &mut text)
        }
        (false, _) => {
            // Nothing is kept: a program found to need a whole read part
            // way is compiled again.
            let engine = Some(&mut *engine as &mut dyn ger::eval::WizardHost);
            ger::compile::check(sources, file, compile_options, engine)
        }
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
    if let Some(e) = read_error {
        eprintln!("error: cannot read `{input}`: {e}");
        return Ok(ExitCode::from(2));
    }
    if streamed.is_some() && !report.diagnostics.is_empty() {
        // The diagnostics show the lines they are about, read again.
        let shown = open_input(input).and_then(|mut file| {
            ger::compile::lines_shown(&mut file, job.file, &report.diagnostics)
        });
        match shown {
            Ok(lines) => job.sources.set_lines(job.file, lines),
            Err(_) => eprintln!("note: `{input}` could not be read again to show its lines"),
        }
    }
    let sources = &job.sources;
    if let Some(code) = reported(sources, &report, options, started) {
        return Ok(code);
    }
    if write && output.is_none() {
        let written = match held {
            Some(mut file) => file
                .seek(std::io::SeekFrom::Start(0))
                .and_then(|_| std::io::copy(&mut file, &mut std::io::stdout().lock()))
                .map(|_| ()),
            None => std::io::stdout().lock().write_all(&text),
        };
        if let Err(e) = written {
            eprintln!("error: cannot write output: {e}");
            return Ok(ExitCode::from(2));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Print a compile's diagnostics (and `--timings`); the exit code when it
/// failed.
fn reported(
    sources: &Sources,
    report: &Report,
    options: &Options,
    started: std::time::Instant,
) -> Option<ExitCode> {
    eprint!("{}", render(sources, &report.diagnostics));
    if options.timings {
        for (stage, took) in &report.timings {
            eprintln!("{stage:>8}: {:8.2} ms", took.as_secs_f64() * 1e3);
        }
        eprintln!("   total: {:8.2} ms", started.elapsed().as_secs_f64() * 1e3);
    }
    if !report.compiled() {
        return Some(ExitCode::from(1));
    }
    if let Some(e) = &report.write_error {
        eprintln!("error: cannot write output: {e}");
        return Some(ExitCode::from(2));
    }
    None
}

/// A program file that can be compiled from the file itself, a part at a
/// time, as `scan` found it ([`ger::compile::scan_path`], or
/// [`ger::compile::first_look`]), with the metadata it had when it was
/// scanned: a regular file (a pipe cannot be read twice) whose
/// subroutine folders need no reading. `None`: compile it whole.
fn streamable(
    input: &str,
    options: &Options,
    stage: Option<Stage>,
    scan: fn(&Path) -> std::io::Result<Option<ger::compile::FileScan>>,
) -> Option<(ger::compile::FileScan, std::fs::Metadata)> {
    let before = std::fs::metadata(input).ok()?;
    if input == "-"
        || stage == Some(Stage::Parse)
        || !before.is_file()
        || !options.subroutine_dirs.is_empty()
    {
        return None;
    }
    let scan = scan(Path::new(input)).ok()??;
    Some((scan, before))
}

fn open_input(input: &str) -> std::io::Result<std::io::BufReader<std::fs::File>> {
    std::fs::File::open(input).map(|f| std::io::BufReader::with_capacity(1 << 16, f))
}

/// Compile `input` from its file a part at a time ([`streamable`]); an
/// error if it cannot be read or changed since it was read through.
fn compile_from_file(
    input: &str,
    (scan, before): &(ger::compile::FileScan, std::fs::Metadata),
    file: usize,
    options: &CompileOptions,
    wizards: Option<&mut dyn ger::eval::WizardHost>,
    out: &mut (dyn Write + Send),
) -> std::io::Result<Streamed> {
    let mut reader = open_input(input)?;
    let compiled =
        ger::compile::compile_file(&mut reader, input, file, *scan, options, wizards, out)?;
    let Streamed::Compiled(report) = compiled else {
        return Ok(compiled);
    };
    let stamp = |m: &std::fs::Metadata| (m.len(), m.modified().ok());
    match std::fs::metadata(input)? {
        now if stamp(&now) == stamp(before) => Ok(Streamed::Compiled(report)),
        _ => Err(std::io::Error::other("it changed while it was compiled")),
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Picture {
    Png,
    Svg,
    Stl,
}

/// `ger render`: compile, simulate, write the picture.
fn render_part(input: &str, output: &Path, options: &Options, picture: &PictureArgs) -> ExitCode {
    use ger::render::Scene;
    if input != "-" && same_file(Path::new(input), output) {
        eprintln!("error: the output file is the input file; refusing to overwrite it");
        return ExitCode::from(2);
    }
    let (format, render_options) = match picture_request(output, picture) {
        Ok(request) => request,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    let mut clock = Laps::new(options.timings);
    let Some((job, path)) = compiled_path(input, options) else {
        return ExitCode::from(1);
    };
    clock.lap("compile");
    let scene = match Scene::new(&path, &render_options) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    };
    eprint!("{}", render(&job.sources, &diagnostics_of(&scene.warnings)));
    clock.lap("scene");
    let drawn = Drawn {
        job: &job,
        path: &path,
        scene: &scene,
        options: &render_options,
    };
    let written = match format {
        Picture::Svg => write_svg(&drawn, output, picture),
        Picture::Png | Picture::Stl => {
            let Some(written) =
                write_carved(&drawn, format, input, output, options, picture, &mut clock)
            else {
                return ExitCode::from(1);
            };
            written
        }
    };
    clock.lap("write");
    clock.report();
    match written {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: cannot write `{}`: {e}", output.display());
            ExitCode::from(2)
        }
    }
}

/// A compiled program and the scene it is drawn in.
struct Drawn<'a> {
    job: &'a Job,
    path: &'a ger::toolpath::ToolPath,
    scene: &'a ger::render::Scene,
    options: &'a ger::render::RenderOptions,
}

/// The picture's format (from the output's name) and its options, or what
/// is wrong with the request.
fn picture_request(
    output: &Path,
    picture: &PictureArgs,
) -> Result<(Picture, ger::render::RenderOptions), &'static str> {
    let extension = output
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let format = match extension.as_deref() {
        Some("png") => Picture::Png,
        Some("svg") => Picture::Svg,
        Some("stl") => Picture::Stl,
        _ => return Err("the picture's format comes from the output's name: .png, .svg or .stl"),
    };
    if (picture.shade || picture.diff.is_some()) && format != Picture::Png {
        return Err("--shade and --diff make a PNG: give -o NAME.png");
    }
    let stock = match picture.stock.as_deref().map(parse_stock) {
        None => None,
        Some(Some(size)) => Some(size),
        Some(None) => return Err("--stock takes three positive sizes, X,Y,Z"),
    };
    if picture
        .resolution
        .is_some_and(|r| !(r.is_finite() && r > 0.0))
    {
        return Err("--resolution must be a positive number");
    }
    let render_options = ger::render::RenderOptions {
        resolution: picture.resolution,
        max_cells: picture.max_cells,
        stock,
    };
    Ok((format, render_options))
}

/// The tool path as an SVG drawing, each segment titled with its line.
fn write_svg(drawn: &Drawn, output: &Path, picture: &PictureArgs) -> std::io::Result<()> {
    use ger::render::svg;
    let sources = &drawn.job.sources;
    let title = |span: ger::source::Span| {
        let text = sources.text(span.file_id()).get(span.range()).unwrap_or("");
        let text: String = text.trim().chars().take(80).collect();
        format!("line {}: {text}", span.line)
    };
    let svg_options = svg::SvgOptions {
        color: match picture.color {
            ColorArg::Depth => svg::ColorBy::Depth,
            ColorArg::Feed => svg::ColorBy::Feed,
            ColorArg::Tool => svg::ColorBy::Tool,
        },
        rapids: picture.rapids == RapidsArg::Show,
    };
    write_file(output, |out| {
        svg::write(drawn.path, drawn.scene, svg_options, &title, out)
    })
}

/// The stock carved by the tool path, written as a PNG (depth, shaded or
/// the difference from `--diff`'s program) or an STL mesh. `None` when it
/// cannot be carved (the error is printed).
fn write_carved(
    drawn: &Drawn,
    format: Picture,
    input: &str,
    output: &Path,
    options: &Options,
    picture: &PictureArgs,
    clock: &mut Laps,
) -> Option<std::io::Result<()>> {
    use ger::render::{image, stl};
    let mut grid = match drawn.scene.grid() {
        Ok(grid) => grid,
        Err(e) => {
            eprintln!("error: {e}");
            return None;
        }
    };
    if let Some(note) = &drawn.scene.coarser {
        eprintln!("note: {note}");
    }
    let other = match &picture.diff {
        Some(other) => Some(carve_other(other, &grid, options, drawn.options)?),
        None => None,
    };
    clock.lap("grid");
    let cuts = drawn.scene.carve(&mut grid, drawn.path, &progress_bar());
    eprint!("{}", render(&drawn.job.sources, &diagnostics_of(&cuts)));
    clock.lap("carve");
    let units = drawn.scene.units;
    Some(match (format, other) {
        (Picture::Stl, _) => {
            if stl::block(&grid) > 1 {
                eprintln!(
                    "note: the mesh takes the lowest of each {0}x{0} cells (at most {1} points)",
                    stl::block(&grid),
                    stl::MAX_CELLS
                );
            }
            write_file(output, |out| stl::write(&grid, out))
        }
        (_, Some(other)) => {
            let tolerance = grid.frame.cell * 0.01;
            write_file(output, |out| {
                image::write_difference(&grid, &other, tolerance, units, out)
            })
            .map(|(differ, largest)| {
                if differ == 0 {
                    eprintln!("note: the two programs cut the same part");
                } else {
                    eprintln!(
                        "note: {differ} cells differ, by up to {largest:.4} (red: `{input}` cuts deeper; blue: the other)"
                    );
                }
            })
        }
        (_, None) if picture.shade => {
            write_file(output, |out| image::write_shaded(&grid, units, out))
        }
        (_, None) => write_file(output, |out| image::write_depth(&grid, units, out)),
    })
}

/// `--diff`'s program carved in a copy of `grid`; `None` when it cannot be
/// (the error is printed).
fn carve_other(
    other: &str,
    grid: &ger::render::carve::Grid,
    options: &Options,
    render_options: &ger::render::RenderOptions,
) -> Option<ger::render::carve::Grid> {
    let (other_job, other_path) = compiled_path(other, options)?;
    let other_scene = match ger::render::Scene::new(&other_path, render_options) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("error: {other}: {e}");
            return None;
        }
    };
    let mut other_grid = grid.clone();
    let cuts = other_scene.carve(&mut other_grid, &other_path, &progress_bar());
    eprint!("{}", render(&other_job.sources, &diagnostics_of(&cuts)));
    Some(other_grid)
}

/// `--timings` for a render: the time of each step, on stderr.
struct Laps {
    on: bool,
    started: std::time::Instant,
    last: std::time::Instant,
    laps: Vec<(&'static str, std::time::Duration)>,
}

impl Laps {
    fn new(on: bool) -> Laps {
        let now = std::time::Instant::now();
        Laps {
            on,
            started: now,
            last: now,
            laps: Vec::new(),
        }
    }

    fn lap(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        self.laps.push((name, now - self.last));
        self.last = now;
    }

    fn report(&self) {
        if self.on {
            for (name, took) in &self.laps {
                eprintln!("{name:>8}: {:8.2} ms", took.as_secs_f64() * 1e3);
            }
            eprintln!(
                "   total: {:8.2} ms",
                self.started.elapsed().as_secs_f64() * 1e3
            );
        }
    }
}

fn diagnostics_of(warnings: &[ger::render::RenderWarning]) -> Vec<ger::diagnostic::Diagnostic> {
    warnings.iter().map(|w| w.to_diagnostic()).collect()
}

/// `X,Y,Z`, each positive.
fn parse_stock(text: &str) -> Option<[f64; 3]> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
        })
        .collect::<Option<_>>()?;
    values.try_into().ok()
}

/// Compile `input` to its tool path, printing the diagnostics; `None` when
/// it has errors.
fn compiled_path(input: &str, options: &Options) -> Option<(Job, ger::toolpath::ToolPath)> {
    let mut job = Job::load(input, options, None).ok()?;
    // The picture draws the tip: tool length offsets do not move it.
    job.options.lower.tip_path = true;
    let (path, diagnostics) =
        ger::compile::tool_path(&job.sources, job.file, &job.options, Some(&mut job.engine));
    eprint!("{}", render(&job.sources, &diagnostics));
    Some((job, path?))
}

/// The progress of a render, on stderr once it has run a second, and only
/// on a terminal.
fn progress_bar() -> impl Fn(usize, usize) + Sync {
    use std::io::IsTerminal;
    let terminal = std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let bar = indicatif::ProgressBar::hidden();
    move |done, total| {
        if !terminal || started.elapsed() < std::time::Duration::from_secs(1) {
            return;
        }
        if bar.is_hidden() {
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("carving {bar:40} {percent:>3}% {eta}")
            {
                bar.set_style(style);
            }
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        if done == total {
            bar.finish_and_clear();
        }
    }
}

/// Write a file through `write`, atomically: into a temporary file beside
/// it, renamed on success; on failure the old file stays.
fn write_file<T>(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<T>,
) -> std::io::Result<T> {
    let (path, tmp, file) = match destination(path)? {
        Destination::Device(path) => {
            // Never replaced: written as it is opened.
            let device = std::fs::OpenOptions::new().write(true).open(path)?;
            let mut out = std::io::BufWriter::new(device);
            let value = write(&mut out)?;
            out.flush()?;
            return Ok(value);
        }
        Destination::Replacing {
            path, tmp, file, ..
        } => (path, tmp, file),
    };
    let mut out = std::io::BufWriter::new(file);
    let result = write(&mut out).and_then(|value| {
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, &path)?;
        Ok(value)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Where a new file for a path given goes.
enum Destination {
    /// A device or a FIFO ([`is_device`]): opened and written, never
    /// replaced.
    Device(PathBuf),
    /// A file, or nothing yet: written to `tmp` beside it
    /// ([`create_replacing`]), then renamed over it. `replaces`: there is
    /// a file there now.
    Replacing {
        path: PathBuf,
        tmp: PathBuf,
        file: std::fs::File,
        replaces: bool,
    },
}

/// The [`Destination`] for `path`, through its links ([`through_links`]).
fn destination(path: &Path) -> std::io::Result<Destination> {
    let path = through_links(path)?;
    if is_device(&path) {
        return Ok(Destination::Device(path));
    }
    let tmp = temporary_beside(&path);
    let (file, replaces) = create_replacing(&tmp, &path)?;
    Ok(Destination::Replacing {
        path,
        tmp,
        file,
        replaces,
    })
}

/// The file `path` names, through symbolic links: the new file replaces
/// the link's target, and the link stays (a link to the folder a machine
/// reads its programs from keeps pointing there, and the machine gets the
/// new program, not the old one). A chain of more than 40 links is an
/// error.
fn through_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..40 {
        let Ok(target) = std::fs::read_link(&path) else {
            // Not a link (or nothing there yet).
            return Ok(path);
        };
        path = match path.parent() {
            Some(folder) if target.is_relative() => folder.join(target),
            _ => target,
        };
    }
    Err(std::io::Error::other(format!(
        "`{}`: too many symbolic links",
        path.display()
    )))
}

/// Whether `path` names something other than a file or a folder: a
/// device (`/dev/null`), a FIFO, a socket. Writing it means opening it,
/// never replacing it.
fn is_device(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Compile into a held copy (an unnamed temporary file, else memory) and
/// write it to the device `path` only when it is whole, as standard output
/// is written: a machine on a FIFO never gets half a program, and on an
/// error it gets nothing.
fn write_when_whole(
    path: &Path,
    compile: impl FnOnce(&mut (dyn Write + Send)) -> Report,
) -> Report {
    let open = || std::fs::OpenOptions::new().write(true).open(path);
    let (report, written) = match tempfile::tempfile() {
        Ok(mut held) => {
            let report = compile(&mut held);
            let copy = |held: &mut std::fs::File| {
                held.seek(std::io::SeekFrom::Start(0))?;
                std::io::copy(held, &mut open()?).map(|_| ())
            };
            let written = report.succeeded().then(|| copy(&mut held));
            (report, written)
        }
        Err(_) => {
            let mut text = Vec::new();
            let report = compile(&mut text);
            let written = report.succeeded().then(|| open()?.write_all(&text));
            (report, written)
        }
    };
    let mut report = report;
    if let Some(Err(e)) = written {
        report.write_error = Some(e);
    }
    report
}

/// Create the file `tmp` that is to replace `path`, with `path`'s
/// permissions if it exists (a program a machine's account may read stays
/// readable to it), and say whether a file is there to be replaced.
fn create_replacing(tmp: &Path, path: &Path) -> std::io::Result<(std::fs::File, bool)> {
    let file = std::fs::File::create(tmp)?;
    let old = std::fs::metadata(path).ok().filter(|old| old.is_file());
    if let Some(old) = &old {
        let done = file.set_permissions(old.permissions());
        if let Err(e) = done {
            let _ = std::fs::remove_file(tmp);
            return Err(e);
        }
    }
    Ok((file, old.is_some()))
}

/// A temporary file's name beside `path` (same folder, so that the rename
/// that replaces `path` is atomic).
fn temporary_beside(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{file_name}.{}.tmp", std::process::id()))
}

fn read_input(input: &str) -> std::io::Result<Vec<u8>> {
    if input == "-" {
        let mut bytes = Vec::new();
        std::io::stdin().read_to_end(&mut bytes)?;
        Ok(bytes)
    } else {
        std::fs::read(input)
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// A file being written whose pages go to the disk as it grows: after each
/// [`EarlyWriteback::EVERY`] bytes the kernel is asked to start writing them,
/// without waiting, so that the `sync_all` before the rename finds little
/// left to write (ARCHITECTURE.md, "Bird's-eye view"). `sync_all` still says
/// whether every write reached the disk.
struct EarlyWriteback<'f> {
    file: &'f mut std::fs::File,
    /// Bytes written and handed to the kernel's writeback, and since.
    started: u64,
    since: u64,
    /// The file the new one will replace, if there is one: its cached
    /// pages are let go of at the first writeback ([`let_go_of`]).
    #[cfg_attr(not(target_os = "linux"), allow(dead_code))]
    old: Option<&'f Path>,
}

impl<'f> EarlyWriteback<'f> {
    const EVERY: u64 = 1 << 18;

    fn new(file: &'f mut std::fs::File, old: Option<&'f Path>) -> EarlyWriteback<'f> {
        EarlyWriteback {
            file,
            started: 0,
            since: 0,
            old,
        }
    }

    /// Start the writeback of the bytes written since the last time. On
    /// Linux, `POSIX_FADV_DONTNEED` on dirty pages starts their writeback
    /// and returns (what PostgreSQL uses where `sync_file_range` is
    /// missing); it drops only pages already clean, so these stay cached.
    /// Elsewhere the sync before the rename writes it all.
    fn start_writeback(&mut self) {
        #[cfg(target_os = "linux")]
        {
            let advice = rustix::fs::Advice::DontNeed;
            // Only a hint: an error here is the final sync's to report.
            let _ = rustix::fs::fadvise(
                &*self.file,
                self.started,
                std::num::NonZeroU64::new(self.since),
                advice,
            );
            if let Some(old) = self.old.take() {
                let_go_of(old);
            }
        }
        self.started += self.since;
        self.since = 0;
    }
}

/// Ask the kernel to drop the cached pages of the file `old`, which the
/// output is about to replace. The rename that replaces it frees them
/// otherwise, on the compile's last step; let go of while the compile
/// still runs, on the back end's thread (which has room), they cost the
/// end nothing: 200k moves with `-o`, 1.2 ms faster at the median
/// (ARCHITECTURE.md, "The eleventh stop"). Only clean pages are dropped,
/// and the file is not changed: if the compile then fails, it stays as
/// it was. Opened without blocking (a FIFO put there since the start
/// would wait for a writer) and let go of only if it is a plain file.
#[cfg(target_os = "linux")]
fn let_go_of(old: &Path) {
    use rustix::fs::{FileType, Mode, OFlags};
    let flags = OFlags::RDONLY | OFlags::NONBLOCK | OFlags::CLOEXEC;
    let Ok(fd) = rustix::fs::open(old, flags, Mode::empty()) else {
        return;
    };
    let plain = rustix::fs::fstat(&fd)
        .is_ok_and(|s| FileType::from_raw_mode(s.st_mode) == FileType::RegularFile);
    if plain {
        // Only a hint, as the writeback's.
        let _ = rustix::fs::fadvise(&fd, 0, None, rustix::fs::Advice::DontNeed);
    }
}

impl Write for EarlyWriteback<'_> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(bytes)?;
        self.since += n as u64;
        if self.since >= Self::EVERY {
            self.start_writeback();
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// Compile into a temporary file beside the target, then rename it on
/// success: a reader never sees half a program, and on failure (errors in
/// the program, or in writing) the old file stays. A target that is not a
/// file (`/dev/null`, a FIFO to a machine) is never replaced: it is sent
/// the program once it is whole ([`write_when_whole`]).
fn write_atomically(
    path: &Path,
    compile: impl FnOnce(&mut (dyn Write + Send)) -> Report,
) -> Report {
    let (path, tmp, mut file, replaces) = match destination(path) {
        Ok(Destination::Device(path)) => return write_when_whole(&path, compile),
        Ok(Destination::Replacing {
            path,
            tmp,
            file,
            replaces,
        }) => (path, tmp, file, replaces),
        Err(e) => {
            // Still compile, for the diagnostics.
            let mut report = compile(&mut std::io::sink());
            report.write_error = Some(e);
            return report;
        }
    };
    // The file it replaces, if any (on Linux its pages are let go of as
    // the compile runs).
    let old = replaces.then_some(path.as_path());
    let mut report = compile(&mut EarlyWriteback::new(&mut file, old));
    if report.succeeded() {
        if let Err(e) = file.sync_all().and_then(|()| std::fs::rename(&tmp, &path)) {
            report.write_error = Some(e);
        }
    }
    if !report.succeeded() {
        let _ = std::fs::remove_file(&tmp);
    }
    report
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    /// Letting go of the old output's pages never waits: a FIFO put where
    /// the old file was (after the first look) is not opened for a writer
    /// to come, and a file is left as it was.
    #[test]
    fn letting_go_of_the_old_output_neither_waits_nor_changes_it() {
        let dir = std::env::temp_dir().join(format!("ger-let-go-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("machine");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        let (done, finished) = std::sync::mpsc::channel();
        let path = fifo.clone();
        std::thread::spawn(move || {
            let_go_of(&path);
            let _ = done.send(());
        });
        let waited = finished.recv_timeout(std::time::Duration::from_secs(10));
        assert!(waited.is_ok(), "waiting on the FIFO for a writer");

        let file = dir.join("old.nc");
        std::fs::write(&file, "G0 X1\n").unwrap();
        let_go_of(&file);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "G0 X1\n");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
