//! The `ger` command line: parses the arguments, calls the library's
//! session, prints diagnostics and maps results to exit codes (0 success,
//! 1 the program has errors, 2 usage or I/O). The compile policy (reading
//! a file in parts, compiling again whole), the option checks and the
//! discovery of wizards and subroutine files are the library's
//! (`ger::driver`); the atomic writer of the output too.

mod args;
mod picture;
mod stats;
mod view;

use args::{Command, MachineCommand, Options};
use ger::diagnostic::render;
use ger::driver::fs::Disk;
use ger::driver::machine::Machine;
use ger::driver::output::same_file;
use ger::driver::{Destination, Finished, Job, LoadError, Program, Report, Session, Stage};
use ger::source::Sources;
use ger::wizard::Library;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

// Big programs build a large tree, then a large IR, then a large text:
// mimalloc reuses the freed pages where the system allocator returns them
// and faults in new ones (about a third of the wall time on 200k lines).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
    let cli = args::parse();
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
        } => picture::render_part(&input, &output, &options, &picture),
        Command::Wizards { name, dirs, part } => {
            list_wizards(name.as_deref(), &dirs, part.as_deref())
        }
        Command::Stats {
            input,
            options,
            json,
        } => stats::print_stats(&input, &options, json),
        Command::View {
            input,
            output,
            port,
            no_open,
            options,
            stock,
        } => view::view(&input, output.as_deref(), port, no_open, &options, &stock),
        Command::Machine {
            action: MachineCommand::Import { file },
        } => import_machine(&file),
        Command::Lsp => {
            let (connection, threads) = lsp_server::Connection::stdio();
            let served = ger::lsp::serve(&connection);
            drop(connection);
            match served.and_then(|()| threads.join().map_err(Into::into)) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: ger lsp: {e}");
                    ExitCode::from(2)
                }
            }
        }
    }
}

/// `ger machine import FILE`: the `[machine]` table on standard output.
fn import_machine(file: &str) -> ExitCode {
    use ger::driver::machine::{import, ImportFormat};
    let text = match file {
        "-" => read_stdin(),
        path => std::fs::read(path)
            .map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
            .map_err(|e| {
                eprintln!("error: cannot read `{path}`: {e}");
                ExitCode::from(2)
            }),
    };
    let Ok(text) = text else {
        return ExitCode::from(2);
    };
    let Some(format) = ImportFormat::of_text(&text) else {
        eprintln!("error: `{file}` is neither a LinuxCNC INI ([TRAJ], [AXIS_X]) nor a grbl `$$` dump ($110=…)");
        return ExitCode::from(2);
    };
    match import(&text, format) {
        Ok(table) => {
            print!("{table}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("error: `{file}`: {why}");
            ExitCode::from(2)
        }
    }
}

/// The session for these options and the `ger.toml` found from the
/// program's folder upward (its `[compile]` keys, less those the command
/// line set); the problem printed.
fn session(
    input: &str,
    options: &Options,
    stage: Option<Stage>,
) -> Result<Session<'static>, ExitCode> {
    session_and_machine(input, options, stage).map(|(session, _)| session)
}

/// [`session`], and the `[machine]` of the `ger.toml` found.
fn session_and_machine(
    input: &str,
    options: &Options,
    stage: Option<Stage>,
) -> Result<(Session<'static>, Option<Machine>), ExitCode> {
    use ger::driver::project::{self, ProjectError};
    let (mut compile, mut search) = (options.compile_options(stage), options.search());
    let start = match input {
        "-" => Path::new("."),
        path => ger::driver::discovery::folder_of(Path::new(path)),
    };
    // Absolute, so that the search climbs above the working folder.
    let start = std::path::absolute(start).unwrap_or_else(|_| start.to_path_buf());
    let given = |key: &str| options.given.contains(&key);
    let machine = match project::configure(&Disk, &start, &mut compile, &mut search, &given) {
        Ok(project) => project.and_then(|p| p.machine),
        Err((_, ProjectError::Unread(why))) => {
            eprintln!("error: {why}");
            return Err(ExitCode::from(2));
        }
        Err((sources, ProjectError::Invalid(diagnostics))) => {
            eprint!("{}", render(&sources, &diagnostics));
            return Err(ExitCode::from(2));
        }
    };
    match Session::new(&Disk, compile, search) {
        Ok(session) => Ok((session, machine)),
        Err(e) => {
            eprintln!("error: {e}");
            Err(ExitCode::from(2))
        }
    }
}

/// Print why a program could not be loaded; its exit code.
fn load_failed(error: LoadError) -> ExitCode {
    let status = error.exit_status();
    match error {
        LoadError::ToolTable { .. } => eprint!("{error}"),
        LoadError::Unread(_) | LoadError::NotText(_) => eprintln!("error: {error}"),
    }
    ExitCode::from(status)
}

/// Read standard input for `-`.
fn read_stdin() -> Result<String, ExitCode> {
    let mut bytes = Vec::new();
    if let Err(e) = std::io::stdin().read_to_end(&mut bytes) {
        eprintln!("error: cannot read `-`: {e}");
        return Err(ExitCode::from(2));
    }
    ger::driver::session::program_text(bytes, "-").map_err(load_failed)
}

/// The program `input` names: standard input for `-`, else a file.
fn program(input: &str) -> Result<Program<'_>, ExitCode> {
    Ok(match input {
        "-" => Program::Text {
            name: "<stdin>",
            path: None,
            text: read_stdin()?,
        },
        path => Program::Path(Path::new(path)),
    })
}

/// `input` loaded as a whole job (for the picture); the problem printed.
fn load(input: &str, options: &Options, stage: Option<Stage>) -> Result<Job, ExitCode> {
    load_with_machine(input, options, stage).map(|(job, _)| job)
}

/// [`load`], and the `[machine]` of the `ger.toml` found.
fn load_with_machine(
    input: &str,
    options: &Options,
    stage: Option<Stage>,
) -> Result<(Job, Option<Machine>), ExitCode> {
    let (session, machine) = session_and_machine(input, options, stage)?;
    session
        .load(program(input)?)
        .map(|job| (job, machine))
        .map_err(load_failed)
}

/// `ger compile` (`write`) and `ger check`.
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
    let session = match session(input, options, stage) {
        Ok(session) => session,
        Err(code) => return code,
    };
    let destination = match (write, output) {
        (true, Some(path)) => Destination::File(path),
        (true, None) => Destination::Held,
        (false, _) => Destination::Nowhere,
    };
    let program = match program(input) {
        Ok(program) => program,
        Err(code) => return code,
    };
    let finished = match session.compile(program, destination) {
        Ok(finished) => finished,
        Err(e) => return load_failed(e),
    };
    finish(input, finished, options, started)
}

/// Print a compile's diagnostics and write the held output; the exit code.
fn finish(
    input: &str,
    finished: Finished,
    options: &Options,
    started: std::time::Instant,
) -> ExitCode {
    if let Some(e) = finished.read_error {
        eprintln!("error: cannot read `{input}`: {e}");
        return ExitCode::from(2);
    }
    if finished.lines_unshown {
        eprintln!("note: `{input}` could not be read again to show its lines");
    }
    if let Some(code) = reported(&finished.job.sources, &finished.report, options, started) {
        return code;
    }
    if let Some(held) = finished.held {
        if let Err(e) = held.copy_to(&mut std::io::stdout().lock()) {
            eprintln!("error: cannot write output: {e}");
            return ExitCode::from(2);
        }
    }
    ExitCode::SUCCESS
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

/// `ger wizards [NAME]`.
fn list_wizards(name: Option<&str>, dirs: &[PathBuf], part: Option<&Path>) -> ExitCode {
    let search = ger::driver::discovery::Search {
        wizard_dirs: dirs.to_vec(),
        wizard_path: args::wizard_path(),
        ..Default::default()
    };
    let found = match ger::driver::discovery::wizards(&Disk, &search, part) {
        Ok(found) => found,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut sources = Sources::new();
    let library = Library::new(found, &mut sources);
    match name {
        None => {
            for w in library.iter() {
                let (signature, summary) = w.described();
                println!("{signature}\n    {summary}  [{}]", w.origin);
            }
            ExitCode::SUCCESS
        }
        Some(name) => {
            let Some(w) = library.get(name) else {
                eprintln!("error: no wizard named `{name}`; `ger wizards` lists them");
                return ExitCode::from(2);
            };
            // A closed pipe is no error of `ger wizards`.
            let _ = std::io::stdout().lock().write_all(w.manual().as_bytes());
            ExitCode::SUCCESS
        }
    }
}
