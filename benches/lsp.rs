//! Benchmark (issue 44's latency goal: diagnostics for a 10,000-line
//! program within 150 ms of a change): the editor server's analysis of a
//! document, a 10,000-line CAM-like program with one error, and the same
//! at 200,000 lines (which must never block the editor: changes that
//! arrive meanwhile cancel it, so it is analysed for the newest): how
//! long an analysis of it runs on after it is cancelled. Through the
//! protocol (a scripted client on an in-memory connection): the time
//! from a change of the 10,000-line program to its diagnostics, and,
//! while a 200,000-line program's analysis runs, the time to the answer
//! of a request the loop answers from the last analysis (an outline).

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use criterion::{criterion_group, criterion_main, Criterion};
use ger::driver::fs::Memory;
use ger::lsp::analysis::{analyse, analyse_unless};
use lsp_server::{Connection, Message, Notification, Request, RequestId};
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

/// A server on one end of an in-memory connection, initialised; the
/// client's end.
fn server() -> (Connection, std::thread::JoinHandle<()>) {
    let (server, client) = Connection::memory();
    let handle = std::thread::spawn(move || ger::lsp::serve(&server).unwrap());
    let init = serde_json::json!({ "capabilities": {}, "processId": null, "rootUri": null });
    let request = Request::new(RequestId::from(0), "initialize".into(), init);
    client.sender.send(Message::Request(request)).unwrap();
    while !matches!(client.receiver.recv().unwrap(), Message::Response(_)) {}
    let initialized = Notification::new("initialized".into(), serde_json::json!({}));
    client
        .sender
        .send(Message::Notification(initialized))
        .unwrap();
    (client, handle)
}

/// Tell the server `text` is now the document's, as `version` (opened
/// when 1).
fn send_text(client: &Connection, version: i32, text: &str) {
    let uri = "file:///nowhere/bench/part.egc";
    let (method, params) = match version {
        1 => (
            "textDocument/didOpen",
            serde_json::json!({ "textDocument": { "uri": uri, "languageId": "gcode",
                                "version": 1, "text": text } }),
        ),
        _ => (
            "textDocument/didChange",
            serde_json::json!({ "textDocument": { "uri": uri, "version": version },
                                "contentChanges": [{ "text": text }] }),
        ),
    };
    let n = Notification::new(method.into(), params);
    client.sender.send(Message::Notification(n)).unwrap();
}

/// Wait for the diagnostics of `version`.
fn published(client: &Connection, version: i32) {
    loop {
        if let Message::Notification(n) = client.receiver.recv().unwrap() {
            if n.params["version"] == version {
                return;
            }
        }
    }
}

fn bench_protocol(c: &mut Criterion) {
    let mut group = c.benchmark_group("lsp protocol");
    group.sample_size(10);
    let (client, handle) = server();
    let text = program(10_000);
    send_text(&client, 1, &text);
    published(&client, 1);
    let mut version = 1;
    group.bench_function("10000 lines: a change to its diagnostics", |b| {
        b.iter(|| {
            version += 1;
            // Every other change fixes the error: each is a new text.
            let changed = match version % 2 {
                0 => text.replace("X<Width>", "X1"),
                _ => text.clone(),
            };
            send_text(&client, version, &changed);
            published(&client, version);
        })
    });
    let long = program(200_000).replace("X<Width>", "X1");
    version += 1;
    send_text(&client, version, &long);
    published(&client, version);
    let mut id = 0;
    group.bench_function(
        "200000 lines: an outline asked while the analysis runs",
        |b| {
            b.iter_custom(|iterations| {
                let mut waited = Duration::ZERO;
                for _ in 0..iterations {
                    version += 1;
                    id += 1;
                    let changed = format!("{long}(version {version})\n");
                    send_text(&client, version, &changed);
                    let started = Instant::now();
                    let params = serde_json::json!({ "textDocument":
                        { "uri": "file:///nowhere/bench/part.egc" } });
                    let r = Request::new(
                        RequestId::from(id),
                        "textDocument/documentSymbol".into(),
                        params,
                    );
                    client.sender.send(Message::Request(r)).unwrap();
                    let mut answered = None;
                    let mut analysed = false;
                    while answered.is_none() || !analysed {
                        match client.receiver.recv().unwrap() {
                            Message::Response(_) => answered = Some(started.elapsed()),
                            Message::Notification(n) => analysed |= n.params["version"] == version,
                            Message::Request(_) => {}
                        }
                        assert!(
                            answered.is_some() || !analysed,
                            "answered before the analysis"
                        );
                    }
                    waited += answered.unwrap();
                }
                waited
            })
        },
    );
    group.finish();
    let shutdown = Request::new(
        RequestId::from(-1),
        "shutdown".into(),
        serde_json::Value::Null,
    );
    client.sender.send(Message::Request(shutdown)).unwrap();
    while !matches!(client.receiver.recv().unwrap(), Message::Response(_)) {}
    let exit = Notification::new("exit".into(), serde_json::Value::Null);
    client.sender.send(Message::Notification(exit)).unwrap();
    handle.join().unwrap();
}

criterion_group!(benches, bench, bench_protocol);
criterion_main!(benches);
