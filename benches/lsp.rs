//! Benchmark (issue 44's latency goal: diagnostics for a 10,000-line
//! program within 150 ms of a change): the editor server's analysis of a
//! document, a 10,000-line CAM-like program with one error, and the same
//! at 200,000 lines (which must never block the editor: changes that
//! arrive meanwhile cancel it, so it is analysed for the newest): how
//! long an analysis of it runs on after it is cancelled.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use criterion::{criterion_group, criterion_main, Criterion};
use ger::driver::fs::Memory;
use ger::lsp::analysis::{analyse, analyse_unless};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A program of `lines` lines: a zig-zag of feed moves, one line of them
/// with an error in the middle.
fn program(lines: usize) -> String {
    let mut text = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\n");
    for i in 0..lines {
        if i == lines / 2 {
            text.push_str("G1 X<Width>\n");
        } else {
            text.push_str(&format!("G1 X{}.{:03} Y{}\n", i % 100, i % 997, i / 100));
        }
    }
    text.push_str("M30\n");
    text
}

fn bench(c: &mut Criterion) {
    let fs = Memory::new();
    let mut group = c.benchmark_group("lsp");
    group.sample_size(10);
    for lines in [10_000, 200_000] {
        let text = program(lines);
        let a = analyse(&fs, Path::new("/p/part.egc"), &text);
        assert_eq!(a.diagnostics.len(), 1);
        group.bench_function(format!("analyse {lines} lines"), |b| {
            b.iter(|| analyse(&fs, Path::new("/p/part.egc"), &text))
        });
        let fixed = text.replace("X<Width>", "X1");
        group.bench_function(format!("analyse {lines} lines, no error"), |b| {
            b.iter(|| analyse(&fs, Path::new("/p/part.egc"), &fixed))
        });
    }
    // Cancelled 50 ms in: the time it runs on after the flag is set.
    let text = program(200_000).replace("X<Width>", "X1");
    let wait = Duration::from_millis(50);
    group.bench_function("200000 lines, cancelled 50 ms in: runs on", |b| {
        b.iter_custom(|iterations| {
            let mut after = Duration::ZERO;
            for _ in 0..iterations {
                let cancel = Arc::new(AtomicBool::new(false));
                let setter = Arc::clone(&cancel);
                let started = Instant::now();
                let timer = std::thread::spawn(move || {
                    std::thread::sleep(wait);
                    setter.store(true, Ordering::Relaxed);
                });
                let a = analyse_unless(&fs, Path::new("/p/part.egc"), &text, &cancel);
                assert!(a.is_none(), "cancelled");
                after += started.elapsed().saturating_sub(wait);
                timer.join().unwrap();
            }
            after
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
