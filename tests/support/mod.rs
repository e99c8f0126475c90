//! Shared by the test harnesses: finding case files, running ger, and
//! LinuxCNC's rs274 as the reference ([`rs274`]).

#![allow(dead_code)] // each harness uses a part

use std::path::{Path, PathBuf};
use std::process::Command;

pub mod cdp;
pub mod rs274;

pub fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The folder of third-party real programs beside the repository, when
/// it is there (a clone of this repository alone has none).
pub fn shared_real() -> Option<PathBuf> {
    Some(manifest().join("../shared/real")).filter(|d| d.is_dir())
}

/// The `.egc` files directly in `dir`, sorted.
pub fn egc_files(dir: &Path) -> Vec<PathBuf> {
    files_with(dir, "egc")
}

/// Where the programs of a corpus test come from.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Corpus {
    /// `examples` and every case folder of `tests/oracle` and `tests/cases`.
    Own,
    /// `../shared/real` (empty where it is absent: such tests are ignored
    /// then, `cfg(shared_real)`).
    SharedReal,
}

/// The plain programs of `corpus` (read a part at a time as plain,
/// `chunk::chunkable`), with their decoded text.
pub fn plain_programs(corpus: Corpus) -> Vec<(PathBuf, String)> {
    programs(corpus)
        .into_iter()
        .filter(|(_, t)| ger::syntax::chunk::chunkable(t))
        .collect()
}

/// The programs of `corpus`, with their decoded text, sorted.
pub fn programs(corpus: Corpus) -> Vec<(PathBuf, String)> {
    let root = manifest();
    let dirs: Vec<PathBuf> = match corpus {
        Corpus::SharedReal => vec![root.join("../shared/real")],
        Corpus::Own => ["tests/oracle", "tests/cases"]
            .iter()
            .flat_map(|d| {
                std::fs::read_dir(root.join(d))
                    .into_iter()
                    .flatten()
                    .flatten()
            })
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .chain([root.join("examples")])
            .collect(),
    };
    let mut found = Vec::new();
    for dir in dirs {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            let program = path.extension().is_some_and(|x| {
                ["nc", "ngc", "gcode", "tap", "txt", "egc"].contains(&&*x.to_string_lossy())
            });
            if !program || !path.is_file() {
                continue;
            }
            let text = std::fs::read(&path)
                .ok()
                .and_then(|b| ger::source::decode(b).ok());
            if let Some(text) = text {
                found.push((path, text));
            }
        }
    }
    found.sort();
    found
}

/// The files of `dir` whose extension is `extension`, sorted.
#[allow(dead_code)]
pub fn files_with(dir: &Path, extension: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == extension))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// `ger compile input -o out`: its warnings (stderr) when it succeeds, its
/// diagnostics as the error when it does not.
pub fn compile(input: &Path, out: &Path) -> Result<String, String> {
    compile_with(input, out, &[])
}

/// [`compile`] with more command-line options.
pub fn compile_with(input: &Path, out: &Path, options: &[&str]) -> Result<String, String> {
    let ger = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("compile")
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(options)
        .output()
        .map_err(|e| format!("cannot run ger: {e}"))?;
    let stderr = String::from_utf8_lossy(&ger.stderr).into_owned();
    if ger.status.success() {
        Ok(stderr)
    } else {
        Err(format!("ger failed:\n{stderr}"))
    }
}
