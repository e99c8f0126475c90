//! ger: a compiler from extended G-code (`.egc`) to plain ISO G-code.
//!
//! The library is the whole compiler and does no I/O: it takes source text
//! and returns G-code text and diagnostics. Files, terminals and exit codes
//! belong to the binary (`src/main.rs`). See ARCHITECTURE.md for the map.

// Support: spans, sources, diagnostics.
pub mod diagnostic;
pub mod source;

// The source languages: syntax tree and front ends.
pub mod ast;
pub mod syntax;

// The compiler: evaluation to IR, lowering, G-code output.
pub mod compile;
pub mod emit;
pub mod eval;
pub mod geometry;
pub mod ir;
pub mod lower;
pub mod tool_table;
pub mod toolpath;
pub mod wizard;

// The picture: the tool path carved into a heightmap, drawn.
pub mod render;

#[cfg(test)]
mod test_random;
