//! The front ends: source text → AST. One lexer/parser pair per input
//! language, all producing the one tree of `ast.rs`: `egc` for ger's own
//! language. Nothing here evaluates or knows what a code means.

pub mod egc;
