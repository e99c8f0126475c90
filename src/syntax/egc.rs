//! ger's own language, `.egc` (SPEC §2): a logos lexer with G-code's
//! context rules and a LALRPOP grammar (`grammar/egc.lalrpop`), behind
//! [`parse_program`]. What they find wrong is a [`error::SyntaxError`].

pub mod chunk;
pub mod error;
pub mod lexer;
pub mod parser;

pub use lexer::Language;
pub use parser::{
    parse_program, parse_program_as, parse_program_at, parse_program_files,
    parse_program_with_fast_path, with_fast_path,
};
