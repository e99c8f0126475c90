//! The front ends: source text → AST, for `.egc`, plain G-code, LinuxCNC's
//! language and Fanuc Macro B, all producing the one tree of `ast.rs`.
//! Word and number lexing is shared (`words`); one lexer (`lexer`) keeps
//! the statement being read and calls the rules of each language (`egc`,
//! `gcode`, `linuxcnc`, `fanuc`); one grammar (`parser`) builds the tree;
//! `chunk` reads a long program a part at a time. Nothing here evaluates
//! or knows what a code means.

mod after_end;
pub mod chunk;
pub mod egc;
pub mod error;
mod fanuc;
mod gcode;
pub mod language;
mod lexer;
pub mod linuxcnc;
pub mod parser;
pub mod token;
pub mod words;

pub use after_end::{tape_end, Tape, Unread};
pub use language::Language;
pub use parser::{
    parse_program, parse_program_as, parse_program_at, parse_program_files,
    parse_program_with_fast_path, with_fast_path,
};
