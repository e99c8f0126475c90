//! The driver: the library's one entry point for a compile. Source text
//! (a file on disk, an editor's unsaved buffer, a test's string) and
//! options in; output text, diagnostics and the tool path out.
//!
//! Architecture Invariant: the library touches the file system only
//! through [`fs::FileSystem`] (reading) and [`output`] (the atomic writer
//! of an output file). Everything else in the library takes text and
//! returns data.
//!
//! The rooms, each importing only those below it:
//! - [`options`]: what one compile does, validated here;
//! - [`fs`]: the file-system view (disk, open buffers, a test's map);
//! - [`project`], [`machine`]: `ger.toml`, its `[compile]` options and
//!   the `[machine]` the program runs on;
//! - [`discovery`]: wizards, subroutine files and the tool table, found
//!   through that view;
//! - [`scan`], `parts`: a file read a part at a time, for memory that
//!   does not grow with the program;
//! - `backend`, `threads`, `clock`: the lowering passes and the
//!   printer as the evaluator's sink, on a thread of their own;
//! - [`compile`]: one compile of source text to text or a tool path;
//! - [`session`]: what callers use: a program loaded with everything it
//!   needs, compiled to an [`session::Outcome`], with the policy that
//!   reads big files a part at a time;
//! - [`output`]: the output file, written atomically.

mod backend;
mod clock;
pub mod compile;
pub mod discovery;
pub mod fs;
pub mod machine;
pub mod options;
pub mod output;
mod parts;
pub mod project;
pub mod scan;
pub mod session;
pub mod subroutines;
mod threads;
pub mod travel;

pub use compile::{
    check, compile, compile_file, compile_to, compile_to_vec, feed_tool_path, tool_path, Compiled,
    Report, Streamed,
};
pub use options::{Clue, CompileOptions, OptionError, Stage};
pub use scan::{
    each_line, first_look, first_look_within, lines_shown, scan_file, scan_path, FileScan,
};
pub use session::{Destination, Finished, Held, Job, LoadError, Outcome, Program, Session};
pub use subroutines::{subroutine_library, SubroutineFile, MAX_SUBROUTINE_FILES};
