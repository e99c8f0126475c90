//! Criterion benchmarks: lexing + parsing a 200,000-line plain G-code
//! program (issue target: well under 50 ms), and the whole compile of the
//! same program.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use criterion::{criterion_group, criterion_main, Criterion};
use ger::driver::{compile, CompileOptions};
use ger::source::Sources;
use std::hint::black_box;

/// A plain CAM-style program: lines and arcs, `lines` blocks long.
pub fn plain_program(lines: usize) -> String {
    let mut text = String::with_capacity(lines * 32);
    text.push_str("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F800\n");
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for i in 0..lines {
        if i % 5 == 4 {
            // A half circle to the right, at the same Y.
            text.push_str(&format!("G2 X{:.3} Y{:.3} I2.5 J0\n", x + 5.0, y));
            x += 5.0;
        } else {
            x = (x + 0.731) % 400.0;
            y = (i % 100) as f64 * 0.5;
            text.push_str(&format!("G1 X{x:.3} Y{y:.3}\n"));
        }
    }
    text.push_str("M30\n");
    text
}

fn bench(c: &mut Criterion) {
    let text = plain_program(200_000);
    let mut group = c.benchmark_group("200k lines");
    group.sample_size(10);
    group.bench_function("lex+parse", |b| {
        // Freeing the tree is not parsing: keep the drop out of the timing.
        b.iter_with_large_drop(|| ger::syntax::parse_program(black_box(&text), 0))
    });
    group.bench_function("compile", |b| {
        b.iter(|| {
            let mut sources = Sources::new();
            let file = sources.add("bench.egc", text.clone());
            black_box(compile(&sources, file, &CompileOptions::default(), None))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
