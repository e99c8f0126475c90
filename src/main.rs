//! The `ger` command line: reads files, calls the library, writes output
//! atomically and maps results to exit codes. No compiler logic lives here.

fn main() {
    let text = std::fs::read_to_string(std::env::args().nth(1).unwrap()).unwrap();
    let (p, d) = ger::parser::parse_program(&text, 0);
    let mut s = ger::source::Sources::new();
    s.add("x", text.clone());
    eprint!("{}", ger::diagnostic::render(&s, &d));
    println!("{:#?}", p.main.len());
}
