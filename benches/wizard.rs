//! Benchmark (issue target: under 0.5 s): a wizard that emits 100,000
//! moves, compiled end to end.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use criterion::{criterion_group, criterion_main, Criterion};
use ger::driver::{compile, CompileOptions};
use ger::source::Sources;
use ger::wizard::{Library, WizardEngine, WizardSource};

const ZIGZAG: &str = r#"//! 100,000 short moves in a zig-zag.
//! @param count   number of moves
let n = count.to_int();
for i in 0..n {
    let x = (i % 1000).to_float() * 0.1;
    let y = (i / 1000).to_float() * 0.1;
    line(x, y);
}
"#;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("wizard");
    group.sample_size(10);
    group.bench_function("100k moves", |b| {
        b.iter(|| {
            let mut sources = Sources::new();
            let file = sources.add(
                "part.egc",
                "G21 G90 G0 X0 Y0 Z1\nG1 F500\nZigzag 100000\nM30\n",
            );
            let library = Library::new(
                vec![WizardSource {
                    name: "Zigzag".into(),
                    text: ZIGZAG.into(),
                    origin: "bench".into(),
                }],
                &mut sources,
            );
            let mut engine = WizardEngine::new(library);
            let compiled = compile(
                &sources,
                file,
                &CompileOptions::default(),
                Some(&mut engine),
            );
            assert!(compiled.output.is_some(), "{:?}", compiled.diagnostics);
            compiled
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
