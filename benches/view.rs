//! `ger view`'s figures in a headless Chromium with software WebGL: for a
//! 3D finishing raster of 200k and 2M moves (a ball end mill over a wavy
//! surface, every tenth row an arc), the time `ger view -o` takes, the
//! page's bytes per move, the time from navigation to
//! `data-ger-state=ready`, and the time to show the stock after a jump
//! of the scrubber. `cargo bench --bench view` (needs /usr/bin/chromium or
//! GER_CHROMIUM); `GER_VIEW_BENCH_MOVES=200000` runs one size.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[path = "../tests/support/cdp.rs"]
#[allow(dead_code)] // the tests' client: clicks and captures unused here
mod cdp;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

fn main() {
    if !Path::new(&cdp::chromium()).is_file() {
        println!("view: no chromium at {}; nothing measured", cdp::chromium());
        return;
    }
    let sizes: Vec<usize> = match std::env::var("GER_VIEW_BENCH_MOVES") {
        Ok(n) => n.split(',').filter_map(|v| v.trim().parse().ok()).collect(),
        Err(_) => vec![200_000, 2_000_000],
    };
    for moves in sizes {
        measure(moves);
    }
}

/// A raster of about `moves` moves over 100 x 100 mm.
fn program(moves: usize) -> String {
    let rows = ((moves as f64 / 5.0).sqrt() as usize).max(10);
    let per_row = moves / rows;
    let mut text = String::from("G21 G90 G17\nT1 M6\nS12000 M3\nG0 Z5\nG0 X0 Y0\nG1 Z0 F600\n");
    text.reserve(moves * 24);
    for row in 0..rows {
        let y = 100.0 * row as f64 / rows as f64;
        for k in 0..per_row {
            let along = k as f64 / per_row as f64;
            let x = 100.0 * if row % 2 == 0 { along } else { 1.0 - along };
            let z = -2.0 - 1.5 * (x / 9.0).sin() * (y / 13.0).cos();
            let _ = writeln!(text, "G1 X{x:.3} Y{y:.3} Z{z:.3} F1800");
        }
        if row % 10 == 9 {
            // A half circle up to Y + 0.2, where it ends.
            let x = 100.0
                * if row % 2 == 0 {
                    (per_row - 1) as f64 / per_row as f64
                } else {
                    1.0 / per_row as f64
                };
            let _ = writeln!(text, "G2 X{x:.3} Y{:.3} I0 J0.1 F1800", y + 0.2);
        }
    }
    text.push_str("G0 Z5\nM5\nM30\n");
    text
}

fn measure(moves: usize) {
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("raster.ngc");
    std::fs::write(&part, program(moves)).unwrap();
    let page = dir.path().join("raster.html");
    let started = Instant::now();
    let status = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("view")
        .arg(&part)
        .arg("-o")
        .arg(&page)
        .status()
        .unwrap();
    assert!(status.success());
    let made = started.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(&page).unwrap().len();
    let mut browser = cdp::Browser::launch();
    let session = browser.page(1200, 800);
    let url = format!("file://{}", page.display());
    browser.navigate(&session, &url);
    browser.wait_for(
        &session,
        "document.body.dataset.gerState === 'ready' || document.body.dataset.gerState === 'error'",
        120.0,
    );
    let drawn: f64 = browser.hook(&session, "data-ger-moves").parse().unwrap();
    let ready = browser
        .eval(&session, "window.gerReadyMs")
        .as_f64()
        .unwrap();
    // Scrubbing: the stock made for the new time (checkpoint and sweep,
    // the removed volume, the texture), then the frame drawn (software
    // WebGL: SwiftShader on the processor).
    let mut stock = Vec::new();
    let mut frame = Vec::new();
    for k in 0..10 {
        // Jumps all over the run, not in order.
        let f = (k * 7 % 10) as f64 / 10.0 + 0.05;
        let ms = browser.eval(
            &session,
            &format!("(() => {{ const t0 = performance.now(); setTime(view.total * {f}); const t1 = performance.now(); draw(); gl.finish(); return [t1 - t0, performance.now() - t1]; }})()"),
        );
        stock.push(ms[0].as_f64().unwrap());
        frame.push(ms[1].as_f64().unwrap());
    }
    stock.sort_by(f64::total_cmp);
    frame.sort_by(f64::total_cmp);
    println!(
        "view {drawn} moves: ger view -o {made:.2} s, {bytes} bytes ({:.1} bytes/move), ready {:.2} s; scrub: stock median {:.0} ms, worst {:.0} ms; frame median {:.0} ms",
        bytes as f64 / drawn,
        ready / 1000.0,
        stock[stock.len() / 2],
        stock[stock.len() - 1],
        frame[frame.len() / 2],
    );
}
