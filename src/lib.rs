//! ger: a compiler from extended G-code (`.egc`) to plain ISO G-code.
//!
//! The library is the whole compiler. Its entry point is
//! [`driver::Session`]: source text (through a file-system view) and
//! options in; G-code text, diagnostics and the tool path out. It reads
//! files only through [`driver::fs::FileSystem`] and writes them only in
//! [`driver::output`]; terminals and exit codes belong to the binary
//! (`src/bin/ger/`). See ARCHITECTURE.md for the map.

// Support: spans, sources, diagnostics.
pub mod diagnostic;
pub mod source;

// The source languages: syntax tree and front ends.
pub mod ast;
pub mod syntax;

// The compiler: evaluation to IR, lowering, G-code output; the driver
// that runs it.
pub mod driver;
pub mod emit;
pub mod eval;
pub mod geometry;
pub mod ir;
pub mod lower;
pub mod tool_table;
pub mod toolpath;
pub mod wizard;

// The run time on a machine, planned as its controller plans it.
pub mod plan;

// The editor server: the driver's session behind the Language Server
// Protocol.
pub mod lsp;

// The picture: the tool path carved into a heightmap, drawn.
pub mod render;

// `ger view`: the compiled part as the browser page draws it.
pub mod view;

#[cfg(test)]
mod test_random;
