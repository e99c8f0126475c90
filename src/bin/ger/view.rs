//! `ger view`: the page of `ger::view` served on 127.0.0.1 (never another
//! address), its files watched and the scene made again when one changes,
//! or written once as a self-contained file (`-o`). The scene is the
//! library's; here are only the socket, the polling of the files' stamps,
//! the browser's launch and the printing.

use crate::args::{Options, StockArgs};
use crate::picture::parse_stock;
use crate::session_and_machine;
use ger::driver::machine::Machine;
use ger::driver::output::write_file;
use ger::driver::Program;
use ger::plan::Limits;
use ger::render::RenderOptions;
use ger::view::{page, studio, Studio};
use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, SystemTime};

/// How often the watched files' stamps are read.
const POLL: Duration = Duration::from_millis(200);

/// How often the listener looks for a connection and at the stop flag.
const ACCEPT_POLL: Duration = Duration::from_millis(20);

/// How long a `version?after=N` request waits for a change.
const LONG_POLL: Duration = Duration::from_secs(20);

/// `ger view INPUT [-o page.html] [--port N] [--no-open]`.
pub fn view(
    input: &str,
    output: Option<&Path>,
    port: u16,
    no_open: bool,
    options: &Options,
    stock: &StockArgs,
) -> ExitCode {
    if input == "-" {
        eprintln!("error: ger view needs a file to watch; give the program's path");
        return ExitCode::from(2);
    }
    let render = match render_options(stock) {
        Ok(render) => render,
        Err(why) => {
            eprintln!("error: {why}");
            return ExitCode::from(2);
        }
    };
    let built = match build(input, options, &render) {
        Ok(built) => built,
        Err(code) => return code,
    };
    eprint!("{}", built.studio.rendered);
    if let Some(output) = output {
        return write_page(&built.studio, output);
    }
    serve(input, options, &render, built, port, no_open)
}

fn render_options(stock: &StockArgs) -> Result<RenderOptions, &'static str> {
    let size = match stock.stock.as_deref().map(parse_stock) {
        None => None,
        Some(Some(size)) => Some(size),
        Some(None) => return Err("--stock takes three positive sizes, X,Y,Z"),
    };
    if stock
        .resolution
        .is_some_and(|r| !(r.is_finite() && r > 0.0))
    {
        return Err("--resolution must be a positive number");
    }
    Ok(RenderOptions {
        resolution: stock.resolution,
        max_cells: stock.max_cells,
        stock: size,
        described: Vec::new(),
    })
}

/// One compile's scene and the files it read.
struct Built {
    studio: Studio,
    watched: Vec<PathBuf>,
}

/// The program loaded, compiled and carved; the problem printed.
fn build(input: &str, options: &Options, render: &RenderOptions) -> Result<Built, ExitCode> {
    let (session, machine) = session_and_machine(input, options, None)?;
    let limits = limits_of(machine.as_ref())?;
    let path = Path::new(input);
    let mut job = session
        .load(Program::Path(path))
        .map_err(crate::load_failed)?;
    let studio = studio(&mut job, limits.as_ref(), render);
    let mut watched = vec![path.to_path_buf()];
    let folder = ger::driver::discovery::folder_of(path);
    // New wizards or subroutine files appear in these folders.
    watched.push(folder.to_path_buf());
    watched.push(folder.join("wizards"));
    watched.push(folder.join("ger.toml"));
    let mut id = 0;
    while job.sources.get(id).is_some() {
        let name = Path::new(job.sources.name(id));
        if name.is_file() {
            watched.push(name.to_path_buf());
        }
        id += 1;
    }
    watched.extend(options.search().tool_table);
    Ok(Built { studio, watched })
}

fn limits_of(machine: Option<&Machine>) -> Result<Option<Limits>, ExitCode> {
    match machine.map(Limits::of) {
        None => Ok(None),
        Some(Ok(limits)) => Ok(Some(limits)),
        Some(Err(why)) => {
            eprintln!("error: ger.toml's [machine] cannot be planned with: {why}");
            Err(ExitCode::from(2))
        }
    }
}

/// `-o`: the page with its scene inside, written atomically; a program
/// with errors writes nothing.
fn write_page(studio: &Studio, output: &Path) -> ExitCode {
    if studio.failed {
        return ExitCode::from(1);
    }
    let html = page(Some(&studio.payload));
    match write_file(output, |out| out.write_all(html.as_bytes())) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: cannot write `{}`: {e}", output.display());
            ExitCode::from(2)
        }
    }
}

/// What the server hands out: the latest scene and its version.
struct Current {
    version: u64,
    payload: String,
}

type Shared = Arc<(Mutex<Current>, Condvar)>;

/// Serve the page until Ctrl-C (SIGINT): then the listener is
/// closed and the run ends with status 0. The accept loop and the watcher
/// look at the stop flag between their waits.
fn serve(
    input: &str,
    options: &Options,
    render: &RenderOptions,
    built: Built,
    port: u16,
    no_open: bool,
) -> ExitCode {
    let listener = match TcpListener::bind(("127.0.0.1", port)) {
        Ok(listener) => listener,
        Err(e) => {
            eprintln!("error: cannot listen on 127.0.0.1:{port}: {e}");
            return ExitCode::from(2);
        }
    };
    // The handler is in place before the address is printed: whoever
    // reads it may send SIGINT at once.
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    if let Err(e) = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst)) {
        eprintln!("note: Ctrl-C cannot be caught here ({e}); it ends the server as it is");
    }
    let port = listener.local_addr().map_or(port, |a| a.port());
    let url = format!("http://127.0.0.1:{port}/");
    println!("{url}");
    let _ = std::io::stdout().flush();
    if !no_open {
        open_browser(&url);
    }
    let shared: Shared = Arc::new((
        Mutex::new(Current {
            version: 1,
            payload: built.studio.payload,
        }),
        Condvar::new(),
    ));
    let page = Arc::new(page(None));
    if let Err(e) = listener.set_nonblocking(true) {
        eprintln!("error: cannot poll 127.0.0.1:{port}: {e}");
        return ExitCode::from(2);
    }
    std::thread::scope(|scope| {
        scope.spawn(|| watch(input, options, render, built.watched, &shared, &stop));
        while !stop.load(Ordering::SeqCst) {
            match listener.accept() {
                Ok((stream, _)) => {
                    let (shared, page) = (Arc::clone(&shared), Arc::clone(&page));
                    std::thread::spawn(move || {
                        stream.set_nonblocking(false)?;
                        answer(stream, &shared, &page, port)
                    });
                }
                // Nothing to accept (or a connection that failed on the
                // way): look at the flag again shortly.
                Err(_) => std::thread::sleep(ACCEPT_POLL),
            }
        }
        drop(listener);
    });
    eprintln!("note: stopped; 127.0.0.1:{port} closed");
    ExitCode::SUCCESS
}

/// `xdg-open`; a browser that does not open is a note, not an error.
fn open_browser(url: &str) {
    let opened = std::process::Command::new("xdg-open")
        .arg(url)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if let Err(e) = opened {
        eprintln!("note: could not open a browser ({e}); open {url}");
    }
}

/// Each watched path's length and time of change (`None`: absent).
fn stamps(paths: &[PathBuf]) -> Vec<Option<(u64, Option<SystemTime>)>> {
    paths
        .iter()
        .map(|p| {
            std::fs::metadata(p)
                .ok()
                .map(|m| (m.len(), m.modified().ok()))
        })
        .collect()
}

/// Poll the files' stamps; on a change, build again and bump the version
/// (a program with errors too: the page shows them over its last picture).
fn watch(
    input: &str,
    options: &Options,
    render: &RenderOptions,
    mut watched: Vec<PathBuf>,
    shared: &Shared,
    stop: &AtomicBool,
) {
    let mut seen = stamps(&watched);
    while !stop.load(Ordering::SeqCst) {
        std::thread::sleep(POLL);
        let now = stamps(&watched);
        if now == seen {
            continue;
        }
        let Ok(built) = build(input, options, render) else {
            // Unreadable for now (an editor saving): tried again on the
            // next change.
            seen = now;
            continue;
        };
        eprint!("{}", built.studio.rendered);
        watched = built.watched;
        seen = stamps(&watched);
        let (lock, changed) = &**shared;
        if let Ok(mut current) = lock.lock() {
            current.version += 1;
            current.payload = built.studio.payload;
            eprintln!("note: redrawn (version {})", current.version);
        }
        changed.notify_all();
    }
}

/// One HTTP request: the page, the scene, or the version (held until it
/// passes `after`). Requests naming another host are refused, so that no
/// other site's page can read the server through a rebound name.
fn answer(stream: TcpStream, shared: &Shared, page: &str, port: u16) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request = String::new();
    reader.read_line(&mut request)?;
    let mut host = String::new();
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 || line.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':') {
            if name.eq_ignore_ascii_case("host") {
                host = value.trim().to_string();
            }
        }
    }
    let target = request.split_whitespace().nth(1).unwrap_or("/");
    let ours = [format!("127.0.0.1:{port}"), format!("localhost:{port}")];
    if !ours.contains(&host) {
        return respond(
            stream,
            "403 Forbidden",
            "text/plain",
            "not this server's host",
        );
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    match path {
        "/" | "/index.html" => respond(stream, "200 OK", "text/html; charset=utf-8", page),
        "/scene" => {
            let payload = shared
                .0
                .lock()
                .map(|c| c.payload.clone())
                .unwrap_or_default();
            respond(stream, "200 OK", "text/plain", &payload)
        }
        "/version" => {
            let after = query
                .strip_prefix("after=")
                .and_then(|v| v.parse::<u64>().ok());
            let version = wait_for_version(shared, after);
            respond(stream, "200 OK", "text/plain", &version.to_string())
        }
        _ => respond(stream, "404 Not Found", "text/plain", "not found"),
    }
}

/// The version, once it differs from `after` (or the wait ends).
fn wait_for_version(shared: &Shared, after: Option<u64>) -> u64 {
    let (lock, changed) = &**shared;
    let Ok(current) = lock.lock() else {
        return 0;
    };
    match after {
        Some(after) => changed
            .wait_timeout_while(current, LONG_POLL, |c| c.version == after)
            .map_or(0, |(c, _)| c.version),
        None => current.version,
    }
}

fn respond(mut stream: TcpStream, status: &str, kind: &str, body: &str) -> std::io::Result<()> {
    write!(
        stream,
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    stream.write_all(body.as_bytes())?;
    stream.flush()
}
