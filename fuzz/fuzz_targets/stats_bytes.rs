//! Arbitrary bytes as a project file and a program, planned: the bytes
//! up to the first NUL are a `ger.toml` (read as `ger stats` reads one),
//! the rest a plain G-code program whose moves go to the planner of that
//! machine (or, where the file gives none, of a grbl with steps and of a
//! LinuxCNC); both bytes also go to `ger machine import`. ger must not
//! panic, hang or run out of memory; it plans or reports.
#![no_main]

use ger::driver::fs::Memory;
use ger::driver::machine::{import, ImportFormat};
use ger::driver::{feed_tool_path, project, CompileOptions};
use ger::eval::EvalOptions;
use ger::plan::{Limits, Tally};
use ger::source::{decode, Sources};
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;

/// A grbl with its steps per mm, and a LinuxCNC: what a file without a
/// usable `[machine]` is planned on.
const MACHINES: [&str; 2] = [
    "[machine]\ncontroller = \"grbl\"\nunits = \"mm\"\nplanner-blocks = 4\n\
     [machine.x]\nsteps-per-mm = 250\nmax-velocity = 3000\nmax-acceleration = 250\n\
     [machine.y]\nsteps-per-mm = 250\nmax-velocity = 3000\nmax-acceleration = 250\n\
     [machine.z]\nsteps-per-mm = 400\nmax-velocity = 1200\nmax-acceleration = 100\n",
    "[machine]\ncontroller = \"linuxcnc\"\nunits = \"inch\"\npath-tolerance = 0.001\n\
     [machine.x]\nmax-velocity = 100\nmax-acceleration = 10\n\
     [machine.y]\nmax-velocity = 100\nmax-acceleration = 10\n\
     [machine.z]\nmax-velocity = 50\nmax-acceleration = 5\n",
];

/// The planner's limits of the `[machine]` of a `ger.toml` holding `text`.
fn limits_of(text: &[u8]) -> Option<Limits> {
    let mut fs = Memory::new();
    fs.insert("/p/ger.toml", text.to_vec());
    let mut sources = Sources::new();
    let project = project::read(&fs, &mut sources, Path::new("/p/ger.toml")).ok()?;
    Limits::of(&project.machine?).ok()
}

/// [`MACHINES`]' limits, read once for every run.
fn built_in() -> &'static [Limits] {
    static LIMITS: OnceLock<Vec<Limits>> = OnceLock::new();
    LIMITS.get_or_init(|| {
        MACHINES
            .iter()
            .filter_map(|text| limits_of(text.as_bytes()))
            .collect()
    })
}

fuzz_target!(|bytes: &[u8]| {
    let (toml, program) = match bytes.iter().position(|&b| b == 0) {
        Some(at) => (&bytes[..at], &bytes[at + 1..]),
        None => (&[][..], bytes),
    };
    let all: Vec<Limits> = limits_of(toml)
        .into_iter()
        .chain(built_in().iter().cloned())
        .collect();
    assert!(all.len() >= 2, "the built-in machines plan");
    for text in [toml, program] {
        if let Ok(text) = std::str::from_utf8(text) {
            for format in [ImportFormat::LinuxCncIni, ImportFormat::GrblSettings] {
                let _ = import(text, format);
            }
        }
    }
    let Ok(text) = decode(program.to_vec()) else {
        return;
    };
    let mut sources = Sources::new();
    let file = sources.add("fuzz.nc", text);
    // Small limits keep each run short; the limits themselves are tested.
    let options = CompileOptions {
        eval: EvalOptions {
            max_iterations: 10_000,
            max_statements: 20_000,
            ..EvalOptions::default()
        },
        ..CompileOptions::default()
    };
    for limits in &all {
        let mut tally = Tally::new(Some(limits), true);
        let _ = feed_tool_path(&sources, file, &options, None, &mut tally);
        let figures = tally.finish();
        if let Some(t) = figures.time_s {
            assert!(!(t < 0.0), "a negative time: {t}");
        }
    }
});
