//! Shared by the test harnesses: finding case files, and whether the rs274
//! oracle can run here.

#![allow(dead_code)] // each harness uses a part

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

/// rs274 crashes (SIGBUS) when two instances run at once: one at a time.
pub static RS274: Mutex<()> = Mutex::new(());

pub fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The `.egc` files directly in `dir`, sorted.
pub fn egc_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "egc"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// Whether rs274, python3 and `../shared/oracle` are here, and whether a
/// missing oracle must fail (`GER_REQUIRE_ORACLE`, set by `.ci/run`) rather
/// than mark the oracle tests ignored.
pub fn oracle() -> (bool, bool) {
    let have = manifest().join("../shared/oracle/compare.py").exists()
        && Command::new("rs274").arg("--help").output().is_ok()
        && Command::new("python3").arg("--version").output().is_ok();
    (have, std::env::var_os("GER_REQUIRE_ORACLE").is_some())
}

/// Run a python script of the oracle, one rs274 at a time.
pub fn run_oracle(
    script: &str,
    args: &[&std::ffi::OsStr],
) -> std::io::Result<std::process::Output> {
    let _one_at_a_time = RS274.lock().unwrap_or_else(|e| e.into_inner());
    Command::new("python3")
        .arg(manifest().join("../shared/oracle").join(script))
        .args(args)
        .output()
}

/// `ger compile input -o out`: its warnings (stderr) when it succeeds, its
/// diagnostics as the error when it does not.
pub fn compile(input: &Path, out: &Path) -> Result<String, String> {
    let ger = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("compile")
        .arg(input)
        .arg("-o")
        .arg(out)
        .output()
        .map_err(|e| format!("cannot run ger: {e}"))?;
    let stderr = String::from_utf8_lossy(&ger.stderr).into_owned();
    if ger.status.success() {
        Ok(stderr)
    } else {
        Err(format!("ger failed:\n{stderr}"))
    }
}
