//! Build script: generates the LALRPOP parser from `grammar/*.lalrpop`, and
//! the list of standard-library wizards (`stdlib/*.rhai`, embedded with
//! `include_str!`) into `$OUT_DIR`; and sets `cfg(shared_real)` when the
//! third-party programs of `../shared/real` are beside the repository, so
//! the tests over them are reported ignored, by name, in a clone alone
//! (and `cfg(chromium)` when a Chromium is installed, for the page's tests).

use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::var("OUT_DIR")?;
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(&out)
        .emit_rerun_directives(true)
        .process()?;

    let shared_real = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/real");
    println!("cargo::rustc-check-cfg=cfg(shared_real)");
    if shared_real.is_dir() {
        println!("cargo:rustc-cfg=shared_real");
    }
    watch(&shared_real);

    // The page tests drive a headless Chromium; without one they are
    // reported ignored by name (CI installs it).
    println!("cargo::rustc-check-cfg=cfg(chromium)");
    println!("cargo:rerun-if-env-changed=GER_CHROMIUM");
    let chromium = std::env::var_os("GER_CHROMIUM")
        .map_or(Path::new("/usr/bin/chromium").to_path_buf(), Into::into);
    if chromium.is_file() {
        println!("cargo:rustc-cfg=chromium");
    }
    watch(&chromium);

    println!("cargo:rerun-if-changed=stdlib");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("stdlib");
    let mut entries: Vec<_> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rhai"))
        .collect();
    entries.sort();
    let mut list = String::from(
        "/// The standard library: (name, script).\npub const STDLIB: &[(&str, &str)] = &[\n",
    );
    for path in entries {
        println!("cargo:rerun-if-changed={}", path.display());
        let name = path.file_stem().unwrap_or_default().to_string_lossy();
        list.push_str(&format!(
            "    ({name:?}, include_str!({:?})),\n",
            path.display().to_string()
        ));
    }
    list.push_str("];\n");
    std::fs::write(Path::new(&out).join("stdlib.rs"), list)?;
    Ok(())
}

/// Run again when `path` comes or goes. Cargo takes a watched path that
/// does not exist as changed at every build, which rebuilt the crate each
/// time in a clone without `../shared`; so an absent path is watched
/// through its folder where that exists (its time changes as the path
/// appears), and not at all where neither does (after adding it, `touch
/// build.rs`).
fn watch(path: &Path) {
    let watched = match path.exists() {
        true => Some(path),
        false => path.parent().filter(|folder| folder.is_dir()),
    };
    if let Some(watched) = watched {
        println!("cargo:rerun-if-changed={}", watched.display());
    }
}
