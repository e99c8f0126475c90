//! Benchmark: lexing and parsing a large plain G-code program.
fn main() {}
