//! What a program needs besides its own text, found through the
//! [`FileSystem`] view: wizard scripts (SPEC §5's search order), the
//! LinuxCNC subroutine files it calls (`name.ngc`), and the tool table.
//! Every caller (the binary, the tests, the editor server) finds them
//! here, the same way.

use super::fs::FileSystem;
use super::subroutines::subroutine_library;
use crate::diagnostic::Diagnostic;
use crate::ir::Tool;
use crate::source::{self, FileId, Sources};
use crate::wizard::{standard_library, WizardSource};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where a program's wizards and subroutine files are looked for, beyond
/// the folder of the program itself.
#[derive(Clone, Debug, Default)]
pub struct Search {
    /// `--wizards` folders, in order (each must be readable).
    pub wizard_dirs: Vec<PathBuf>,
    /// The `GER_WIZARDS` folders (the caller reads the variable): looked
    /// in after the program's own `wizards/`, skipped when missing.
    pub wizard_path: Vec<PathBuf>,
    /// `--subroutines` folders, before the program's own folder.
    pub subroutine_dirs: Vec<PathBuf>,
    /// `--tool-table`.
    pub tool_table: Option<PathBuf>,
}

/// The folder a program's own files sit in (`.` for a bare name).
pub fn folder_of(part: &Path) -> &Path {
    part.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Wizard scripts in search order (SPEC §5): the `--wizards` folders,
/// `wizards/` beside the part, the `GER_WIZARDS` folders, then the
/// standard library. Within a folder, by name; `_name.rhai` files are
/// helpers, not wizards.
pub fn wizards(
    fs: &dyn FileSystem,
    search: &Search,
    part: Option<&Path>,
) -> Result<Vec<WizardSource>, String> {
    let mut folders: Vec<(PathBuf, bool)> = search
        .wizard_dirs
        .iter()
        .map(|d| (d.clone(), true))
        .collect();
    if let Some(part) = part {
        let beside = part.parent().unwrap_or(Path::new(".")).join("wizards");
        folders.push((beside, false));
    }
    folders.extend(search.wizard_path.iter().map(|d| (d.clone(), false)));
    let mut found = Vec::new();
    for (dir, required) in folders {
        let entries = match fs.list(&dir) {
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
            .into_iter()
            .filter(|p| p.extension().is_some_and(|x| x == "rhai"))
            .filter(|p| {
                !p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with('_'))
            })
            .collect();
        paths.sort();
        for path in paths {
            let text = fs
                .read(&path)
                .map_err(|e| format!("cannot read `{}`: {e}", path.display()))
                .and_then(|bytes| {
                    String::from_utf8(bytes).map_err(|_| {
                        format!(
                            "cannot read `{}`: stream did not contain valid UTF-8",
                            path.display()
                        )
                    })
                })?;
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

/// The files of the LinuxCNC subroutines the program `main` calls but
/// does not hold, added to `sources`: `name.ngc` from the `--subroutines`
/// folders, then the program's own folder (as LinuxCNC's SUBROUTINE_PATH
/// and the program's folder).
pub fn subroutine_files(
    fs: &dyn FileSystem,
    sources: &mut Sources,
    main: FileId,
    search: &Search,
    part: Option<&Path>,
) -> Result<Vec<FileId>, String> {
    for dir in &search.subroutine_dirs {
        if !fs.is_dir(dir) {
            return Err(format!("cannot read subroutine folder `{}`", dir.display()));
        }
    }
    let mut folders: Vec<PathBuf> = search.subroutine_dirs.clone();
    if let Some(part) = part {
        folders.push(part.parent().unwrap_or(Path::new(".")).to_path_buf());
    }
    subroutine_library(sources, main, &mut |name| {
        let Some(path) = folders
            .iter()
            .map(|d| d.join(format!("{name}.ngc")))
            .find(|p| fs.is_file(p))
        else {
            return Ok(None);
        };
        let text = fs
            .read(&path)
            .map_err(|e| format!("cannot read `{}`: {e}", path.display()))
            .and_then(|bytes| {
                source::decode(bytes)
                    .map_err(|_| format!("`{}` is not a text file", path.display()))
            })?;
        Ok(Some((path.display().to_string(), text)))
    })
}

/// Why a tool table could not be had.
pub enum ToolTableError {
    /// Not read (exit status 2): the message.
    Unread(String),
    /// Read, with errors at its lines (exit status 1).
    Invalid(Vec<Diagnostic>),
}

/// The tool table at `path` (LinuxCNC's format), added to `sources`.
pub fn tool_table(
    fs: &dyn FileSystem,
    sources: &mut Sources,
    path: &Path,
) -> Result<BTreeMap<u32, Tool>, ToolTableError> {
    let text = match fs.read(path).map(source::decode) {
        Ok(Ok(text)) => text,
        Ok(Err(_)) => {
            let why = format!("`{}` is not a text file", path.display());
            return Err(ToolTableError::Unread(why));
        }
        Err(e) => {
            let why = format!("cannot read `{}`: {e}", path.display());
            return Err(ToolTableError::Unread(why));
        }
    };
    let table = sources.add(path.display().to_string(), text);
    crate::tool_table::parse(sources.text(table), table).map_err(|errors| {
        ToolTableError::Invalid(errors.iter().map(|e| e.to_diagnostic()).collect())
    })
}
