//! Golden tests.
fn main() {}
