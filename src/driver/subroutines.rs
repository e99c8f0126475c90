//! The LinuxCNC subroutine files a program calls and does not hold
//! (`o<name> call`), found through the caller's `find`: this module reads
//! no file itself.

use crate::source::{FileId, Sources};

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

/// The `o<name>` subroutines a text calls and those it defines, as the
/// front end reads them (a text with no `o<` has none, and is not parsed).
fn named_subroutines(text: &str) -> (Vec<String>, Vec<String>) {
    if !text.contains("o<") && !text.contains("O<") {
        return (Vec::new(), Vec::new());
    }
    let (program, _) = crate::syntax::parse_program_as(text, 0, crate::syntax::Language::Gcode);
    program.named_subroutines()
}
