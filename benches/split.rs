//! Temporary: time lexing alone.
fn main() {
    let text = {
        let mut text = String::new();
        let mut x = 0.0f64;
        for i in 0..200_000 {
            let y = (i % 100) as f64 * 0.5;
            if i % 5 == 4 {
                text.push_str(&format!("G2 X{:.3} Y{:.3} I2.5 J0\n", x + 5.0, y));
                x += 5.0;
            } else {
                x = (x + 0.731) % 400.0;
                text.push_str(&format!("G1 X{x:.3} Y{y:.3}\n"));
            }
        }
        text
    };
    for _ in 0..std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3)
    {
        let t = std::time::Instant::now();
        let mut names = ger::ast::Names::default();
        let l = ger::lexer::lex(&text, 0, &mut names);
        let lex = t.elapsed();
        let t = std::time::Instant::now();
        let (p, _) = ger::parser::parse_program(&text, 0);
        let all = t.elapsed();
        eprintln!(
            "lex {:?} ({} tokens) lex+parse {:?} {}",
            lex,
            l.tokens.len(),
            all,
            p.main.len()
        );
    }
}
