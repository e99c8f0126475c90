//! `ger view` as its users meet it: the page in a headless Chromium
//! (software WebGL), its hooks read and compared with the library's own
//! answers (moves, `ger stats`' time, `ger render`'s removed volume),
//! lines and moves clicked, the presets' pictures compared with reviewed
//! golden images (`GER_BLESS=1` rewrites them), the server's redraw on a
//! change, and the saved page's silence on the network. Without a
//! Chromium (`cfg(chromium)`, build.rs) each is reported ignored by name.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod support;

use ger::driver::fs::Disk;
use ger::driver::{CompileOptions, Program, Session};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use support::cdp::Browser;

/// One browser at a time: several software-rendering Chromiums at once
/// on a small machine lose their WebGL contexts.
static ONE_BROWSER: std::sync::Mutex<()> = std::sync::Mutex::new(());

const WIDTH: u32 = 1200;
const HEIGHT: u32 = 800;

fn example(name: &str) -> PathBuf {
    support::manifest().join("examples").join(name)
}

/// The browser, launched once the tests before are done with theirs, and
/// a page of the tests' size in it. (Bind the guard first: it is dropped
/// last, after the browser.)
fn one_browser() -> (std::sync::MutexGuard<'static, ()>, Browser, String) {
    let one = ONE_BROWSER.lock().unwrap_or_else(|e| e.into_inner());
    let mut browser = Browser::launch();
    let page = browser.page(WIDTH, HEIGHT);
    (one, browser, page)
}

/// `ger view PART -o page.html` into `dir`; the page's file URL.
fn saved_page(part: &Path, dir: &Path) -> String {
    let page = dir.join("page.html");
    let status = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("view")
        .arg(part)
        .arg("-o")
        .arg(&page)
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    format!("file://{}", page.display())
}

/// The library's moves of `part`, each with its source line (main file).
fn library_moves(part: &Path) -> Vec<(usize, u32)> {
    let session = Session::new(&Disk, CompileOptions::default(), Default::default()).unwrap();
    let mut job = session.load(Program::Path(part)).ok().unwrap();
    let path = job.tool_path().0.unwrap();
    path.moves
        .iter()
        .map(|m| (m.span.file_id(), m.span.line))
        .collect()
}

/// The volume `ger render` removes from the stock, mm³ (its steps: the
/// tip's path, the program's described cutters, the default grid).
fn render_volume(part: &Path) -> f64 {
    use ger::render::{described::described_tools, RenderOptions, Scene};
    let session = Session::new(&Disk, CompileOptions::default(), Default::default()).unwrap();
    let mut job = session.load(Program::Path(part)).ok().unwrap();
    job.options.lower.tip_path = true;
    let path = job.tool_path().0.unwrap();
    let options = RenderOptions {
        described: described_tools(job.sources.text(job.file), path.units),
        ..RenderOptions::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    scene.carve(&mut grid, &path, &|_, _| {});
    grid.removed_volume() * ger::ir::Units::mm_per(path.units).powi(3)
}

/// The volume the library's heightmap loses to the first `upto` moves of
/// `part`, mm³, on a grid of `cell` (the page's): `ger render
/// --resolution cell` of the program cut there.
fn render_volume_upto(part: &Path, upto: usize, cell: f64) -> f64 {
    use ger::render::{carve, described::described_tools, RenderOptions, Scene};
    let session = Session::new(&Disk, CompileOptions::default(), Default::default()).unwrap();
    let mut job = session.load(Program::Path(part)).ok().unwrap();
    job.options.lower.tip_path = true;
    let path = job.tool_path().0.unwrap();
    let options = RenderOptions {
        resolution: Some(cell),
        described: described_tools(job.sources.text(job.file), path.units),
        ..RenderOptions::default()
    };
    let scene = Scene::new(&path, &options).unwrap();
    let mut grid = scene.grid().unwrap();
    let end = scene.segments.partition_point(|s| s.move_index < upto);
    carve::carve(
        &mut grid,
        &scene.segments[..end],
        &scene.cutters,
        &|_, _| {},
    );
    grid.removed_volume()
}

/// A ball end mill's raster over a wavy floor, `rows` rows of 60 moves,
/// every third row ending in a level arc, a helix down at the start:
/// lines, arcs, chords and several checkpoints for the page's sweep.
fn ball_raster(rows: usize) -> String {
    use std::fmt::Write as _;
    let mut text = String::from(
        "G21 G90 G17\n(T1 D=6. CR=3. - ZMIN=-4. - ball end mill)\nT1 M6\nS9000 M3\nG0 Z5\nG0 X3 Y0\nG1 Z0 F300\nG2 X3 Y0 Z-2 I-3 J0 F300\n",
    );
    for row in 0..rows {
        let y = 60.0 * row as f64 / rows as f64;
        for k in 0..=60 {
            let x = if row % 2 == 0 { k } else { 60 - k } as f64;
            let z = -2.0 - (x / 7.0).sin() * (y / 11.0).cos();
            let _ = writeln!(text, "G1 X{x:.3} Y{y:.3} Z{z:.3} F1200");
        }
        if row % 3 == 2 {
            let _ = writeln!(
                text,
                "G0 Z-1\nG3 X{:.3} Y{y:.3} I-2 J0",
                if row % 2 == 0 { 56 } else { 0 }
            );
        }
    }
    text.push_str("G0 Z5\nM30\n");
    text
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn the_stock_at_any_time_is_the_librarys_heightmap_of_the_moves_before() {
    let dir = tempfile::tempdir().unwrap();
    let raster = dir.path().join("raster.ngc");
    std::fs::write(&raster, ball_raster(60)).unwrap();
    let (_one, mut browser, page) = one_browser();
    for (part, share) in [
        (example("star_pocket.egc"), 0.5),
        (raster.clone(), 0.5),
        (raster.clone(), 0.23),
    ] {
        let pages = tempfile::tempdir().unwrap();
        let url = saved_page(&part, pages.path());
        browser.navigate(&page, &url);
        ready(&mut browser, &page);
        // The end of the move under way at that share of the run.
        let at = browser.eval(
            &page,
            &format!("(() => {{ const a = moveAt(view.total * {share}); return [a.index, String(view.moves.tEnd[a.index]), view.stock.spec.cell_mm, view.stock.spec.checkpoints.length]; }})()"),
        );
        let (k, t, cell) = (
            at[0].as_u64().unwrap() as usize,
            at[1].as_str().unwrap().to_string(),
            at[2].as_f64().unwrap(),
        );
        browser.navigate(&page, &format!("{url}#t={t}"));
        browser.wait_for(&page, "location.hash.startsWith('#t=')", 5.0);
        ready(&mut browser, &page);
        let shown = number(&mut browser, &page, "data-ger-removed-mm3");
        let library = render_volume_upto(&part, k + 1, cell);
        assert!(
            library > 0.0 && (shown - library).abs() <= 0.005 * library,
            "{}: {share} of the run (move {k}, t={t}, {} checkpoints): page {shown} mm³, library {library} mm³",
            part.display(),
            at[3]
        );
        // The last move half done: less than the whole, more than before.
        browser.eval(
            &page,
            &format!("setTime(({t} + (view.moves.tEnd[{k} - 1])) / 2); 1"),
        );
        let half = number(&mut browser, &page, "data-ger-removed-mm3");
        let before = render_volume_upto(&part, k, cell);
        assert!(
            half >= before * 0.995 && half <= shown * 1.005,
            "half way through move {k}: {half} mm³, {before} before it, {shown} after"
        );
    }
}

/// `ger stats --json`'s run time.
fn stats_time(part: &Path) -> f64 {
    let out = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("stats")
        .arg(part)
        .arg("--json")
        .output()
        .unwrap();
    let figures: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    figures["time_s"]
        .as_f64()
        .unwrap_or_else(|| figures["feed_time_s"].as_f64().unwrap())
}

fn ready(browser: &mut Browser, page: &str) {
    // `loading` again after a lost WebGL context, until it is restored
    // (software WebGL on a loaded machine loses it now and then, even
    // between the wait and the read: wait again, a few times).
    for _ in 0..3 {
        browser.wait_for(
            page,
            "document.body.dataset.gerState === 'ready' || (document.body.dataset.gerState === 'error' && document.getElementById('banner').textContent !== '')",
            60.0,
        );
        if browser.hook(page, "data-ger-state") != "loading" {
            break;
        }
    }
    let banner = browser.eval(page, "document.getElementById('banner').textContent");
    assert_eq!(browser.hook(page, "data-ger-state"), "ready", "{banner}");
}

fn number(browser: &mut Browser, page: &str, hook: &str) -> f64 {
    browser.hook(page, hook).parse().unwrap()
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn the_hooks_give_the_librarys_moves_time_and_removed_volume() {
    let part = example("star_pocket.egc");
    let dir = tempfile::tempdir().unwrap();
    let url = saved_page(&part, dir.path());
    let (_one, mut browser, page) = one_browser();
    browser.navigate(&page, &url);
    ready(&mut browser, &page);
    let moves = library_moves(&part).len();
    assert_eq!(number(&mut browser, &page, "data-ger-moves"), moves as f64);
    assert_eq!(browser.hook(&page, "data-ger-version"), "1");
    let time = number(&mut browser, &page, "data-ger-time-s");
    let stats = stats_time(&part);
    assert!(
        (time - stats).abs() <= 1e-6 * stats.max(1.0),
        "page {time} s, stats {stats} s"
    );
    // #end is the default: all of the cut.
    let removed = number(&mut browser, &page, "data-ger-removed-mm3");
    let rendered = render_volume(&part);
    assert!(
        (removed - rendered).abs() <= 0.005 * rendered,
        "page {removed} mm³, ger render {rendered} mm³"
    );
    // Half way through the time, part of it.
    browser.navigate(&page, &format!("{url}#t={}", time / 2.0));
    browser.wait_for(&page, "location.hash.startsWith('#t=')", 5.0);
    browser.wait_for(
        &page,
        &format!(
            "Number(document.body.dataset.gerRemovedMm3) < {}",
            removed * 0.99
        ),
        5.0,
    );
    let half = number(&mut browser, &page, "data-ger-removed-mm3");
    assert!(half > 0.0, "half way: {half} mm³");
    browser.navigate(&page, &format!("{url}#end"));
    browser.wait_for(
        &page,
        &format!("Number(document.body.dataset.gerRemovedMm3) === {removed}"),
        5.0,
    );
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn a_line_selects_its_moves_and_a_move_its_lines() {
    let part = example("star_pocket.egc");
    let moves = library_moves(&part);
    // The busiest line: a loop's body.
    let line = (1..200u32)
        .max_by_key(|&l| moves.iter().filter(|&&(f, m)| f == 0 && m == l).count())
        .unwrap();
    let on_line = moves.iter().filter(|&&(f, m)| f == 0 && m == line).count();
    assert!(on_line > 1);
    let dir = tempfile::tempdir().unwrap();
    let url = saved_page(&part, dir.path());
    let (_one, mut browser, page) = one_browser();
    browser.navigate(&page, &format!("{url}#L{line}"));
    ready(&mut browser, &page);
    assert_eq!(
        browser.hook(&page, "data-ger-selected-moves"),
        on_line.to_string()
    );
    // A click on another source line: its moves, and the fragment.
    let other = moves.iter().find(|&&(f, m)| f == 0 && m != line).unwrap().1;
    let expected = moves.iter().filter(|&&(f, m)| f == 0 && m == other).count();
    browser.eval(&page, &format!("sourcePane.reveal({other})"));
    let rect = browser.eval(
        &page,
        &format!("(() => {{ const r = document.querySelector('#source .line[data-line=\"{other}\"]').getBoundingClientRect(); return [r.x + 40, r.y + 8]; }})()"),
    );
    browser.click(&page, rect[0].as_f64().unwrap(), rect[1].as_f64().unwrap());
    browser.wait_for(&page, &format!("location.hash === '#L{other}'"), 5.0);
    assert_eq!(
        browser.hook(&page, "data-ger-selected-moves"),
        expected.to_string()
    );
    // A click on a move in the view: that move alone, its lines shown.
    let k = moves.len() / 2;
    let at = browser.eval(
        &page,
        &format!("(() => {{ const c = document.getElementById('gl'), r = c.getBoundingClientRect(); const m = view.moves, v = m.first[{k}]; const a = project(view.mvp, m.pos[v*3], m.pos[v*3+1], m.pos[v*3+2], c.width, c.height), b = project(view.mvp, m.pos[v*3+3], m.pos[v*3+4], m.pos[v*3+5], c.width, c.height); return [r.x + (a[0]+b[0])/2, r.y + (a[1]+b[1])/2]; }})()"),
    );
    browser.click(&page, at[0].as_f64().unwrap(), at[1].as_f64().unwrap());
    browser.wait_for(&page, "document.body.dataset.gerSelectedMoves === '1'", 5.0);
    let readout = browser.eval(&page, "document.getElementById('readout').textContent");
    let (_, move_line) = moves[browser
        .eval(&page, "[...view.selected][0]")
        .as_u64()
        .unwrap() as usize];
    assert!(
        readout
            .as_str()
            .unwrap()
            .contains(&format!(":{move_line} ")),
        "{readout}"
    );
    let lit = browser.eval(&page, "[...sourcePane.lit]");
    assert_eq!(lit, serde_json::json!([move_line]));
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn the_saved_page_makes_no_request() {
    let part = example("star_pocket.egc");
    let dir = tempfile::tempdir().unwrap();
    let url = saved_page(&part, dir.path());
    let (_one, mut browser, page) = one_browser();
    browser.call(Some(&page), "Network.enable", serde_json::json!({}));
    browser.navigate(&page, &url);
    ready(&mut browser, &page);
    // Played to the end and back, every control used once.
    browser.eval(
        &page,
        "document.querySelectorAll('button').forEach((b) => b.click())",
    );
    std::thread::sleep(std::time::Duration::from_millis(500));
    browser.eval(&page, "1");
    let requests: Vec<String> = browser
        .events
        .iter()
        .filter(|e| e["method"] == "Network.requestWillBeSent")
        .map(|e| {
            e["params"]["request"]["url"]
                .as_str()
                .unwrap_or("")
                .to_string()
        })
        .collect();
    assert!(requests.contains(&url), "{requests:?}");
    // The page itself, and data: URLs (the empty icon), never leave it.
    let others: Vec<_> = requests
        .iter()
        .filter(|u| **u != url && !u.starts_with("data:"))
        .collect();
    assert!(others.is_empty(), "requests: {others:?}");
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn each_preset_draws_as_its_reviewed_picture() {
    let part = example("star_pocket.egc");
    let dir = tempfile::tempdir().unwrap();
    let url = saved_page(&part, dir.path());
    let (_one, mut browser, page) = one_browser();
    browser.navigate(&page, &url);
    ready(&mut browser, &page);
    let r = browser.eval(
        &page,
        "(() => { const r = document.getElementById('gl').getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()",
    );
    let clip: [f64; 4] = std::array::from_fn(|i| r[i].as_f64().unwrap());
    let mut failures = Vec::new();
    for preset in ["top", "front", "side", "iso", "mid-way"] {
        match preset {
            "mid-way" => {
                browser.eval(&page, "preset('iso'); setTime(view.total / 2); 1");
            }
            name => {
                browser.eval(
                    &page,
                    &format!("document.querySelector('[data-preset={name}]').click(); 1"),
                );
            }
        }
        let golden = support::manifest().join(format!("tests/view/{preset}.png"));
        let bless = std::env::var_os("GER_BLESS").is_some();
        // Software WebGL under load now and then hands the compositor a
        // blank canvas (a white frame with a broken-image mark): a picture
        // unlike the golden one is taken again, drawn afresh, up to 3 times.
        let mut outcome = Err(String::new());
        for _ in 0..3 {
            let shot = picture(&mut browser, &page, clip);
            if bless {
                std::fs::write(&golden, &shot).unwrap();
                outcome = Ok(());
                break;
            }
            outcome = similar(&shot, &std::fs::read(&golden).unwrap()).map_err(|why| {
                let kept = dir.path().join(format!("{preset}.png"));
                std::fs::write(&kept, &shot).unwrap();
                format!("{preset}: {why} (got {})", kept.display())
            });
            if outcome.is_ok() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(500));
        }
        failures.extend(outcome.err());
    }
    if !failures.is_empty() {
        // Keep the pictures for a look.
        let _ = dir.keep();
        panic!("{}", failures.join("\n"));
    }
}

/// The canvas once the page is ready and has drawn two frames.
fn picture(browser: &mut Browser, page: &str, clip: [f64; 4]) -> Vec<u8> {
    ready(browser, page);
    browser.eval(
        page,
        "new Promise((r) => requestAnimationFrame(() => { draw(); requestAnimationFrame(() => r(1)); }))",
    );
    browser.capture(page, clip)
}

/// Two pictures alike: the same size, and at most 1% of the pixels
/// differing by more than 48 in a channel (software rendering's edges).
fn similar(a: &[u8], b: &[u8]) -> Result<(), String> {
    let (pa, wa, ha) = pixels(a);
    let (pb, wb, hb) = pixels(b);
    if (wa, ha) != (wb, hb) {
        return Err(format!("{wa}x{ha} against {wb}x{hb}"));
    }
    let differ = pa
        .chunks(4)
        .zip(pb.chunks(4))
        .filter(|(x, y)| x.iter().zip(y.iter()).any(|(p, q)| p.abs_diff(*q) > 48))
        .count();
    let share = differ as f64 / (wa * ha) as f64;
    if share > 0.01 {
        return Err(format!("{:.2}% of the pixels differ", share * 100.0));
    }
    Ok(())
}

/// RGBA pixels of a PNG, its width and height.
fn pixels(png_bytes: &[u8]) -> (Vec<u8>, usize, usize) {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    decoder.set_transformations(png::Transformations::ALPHA | png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (buf, info.width as usize, info.height as usize)
}

#[test]
#[cfg_attr(not(chromium), ignore = "chromium absent")]
fn a_changed_file_is_redrawn_in_place_and_errors_shown_over_it() {
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("part.egc");
    let text = std::fs::read_to_string(example("star_pocket.egc")).unwrap();
    std::fs::write(&part, &text).unwrap();
    let mut server = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["view", "--no-open", "--port", "0"])
        .arg(&part)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut url = String::new();
    std::io::BufReader::new(server.stdout.take().unwrap())
        .read_line(&mut url)
        .unwrap();
    let url = url.trim().to_string();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    let (_one, mut browser, page) = one_browser();
    browser.navigate(&page, &url);
    ready(&mut browser, &page);
    assert_eq!(browser.hook(&page, "data-ger-version"), "1");
    let deep = number(&mut browser, &page, "data-ger-removed-mm3");
    browser.eval(&page, "preset('top'); view.camera.distance *= 0.8; 1");
    let camera = browser.eval(&page, "JSON.stringify(view.camera)");
    // A shallower pocket: the page redraws with less removed.
    std::fs::write(&part, text.replace("Depth = -6", "Depth = -4")).unwrap();
    browser.wait_for(&page, "document.body.dataset.gerVersion === '2'", 10.0);
    let shallow = number(&mut browser, &page, "data-ger-removed-mm3");
    let moves = number(&mut browser, &page, "data-ger-moves");
    assert!(
        shallow < deep * 0.9,
        "{shallow} mm³ after, {deep} mm³ before"
    );
    assert_eq!(browser.eval(&page, "JSON.stringify(view.camera)"), camera);
    // An error: shown at its line, the last picture kept.
    std::fs::write(&part, text.replace("Depth = -6", "Depth = -6 +")).unwrap();
    browser.wait_for(&page, "document.body.dataset.gerVersion === '3'", 10.0);
    assert_eq!(browser.hook(&page, "data-ger-state"), "error");
    assert_eq!(number(&mut browser, &page, "data-ger-removed-mm3"), shallow);
    let banner = browser.eval(&page, "document.getElementById('banner').textContent");
    assert!(banner.as_str().unwrap().contains("22"), "{banner}");
    assert_eq!(browser.eval(&page, "sourcePane.marks.get(22)"), "error");
    // Listed, naming its line; the last picture's figures and notes kept.
    let listed = browser.eval(
        &page,
        "[...document.querySelectorAll('#diagnostics .diagnostic.error')].map((e) => e.textContent)",
    );
    assert!(
        listed
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e.as_str().unwrap().contains("part.egc:22: error:")),
        "{listed}"
    );
    let notes = browser.eval(&page, "document.getElementById('notes').textContent");
    assert!(notes.as_str().unwrap().contains("chords"), "{notes}");
    assert_eq!(number(&mut browser, &page, "data-ger-moves"), moves);
    server.kill().unwrap();
    server.wait().unwrap();
}

#[test]
fn ctrl_c_closes_the_server_and_ends_it_with_status_0() {
    let mut server = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["view", "--no-open", "--port", "0"])
        .arg(example("star_pocket.egc"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut url = String::new();
    std::io::BufReader::new(server.stdout.take().unwrap())
        .read_line(&mut url)
        .unwrap();
    let port: u16 = url
        .trim()
        .trim_start_matches("http://127.0.0.1:")
        .trim_end_matches('/')
        .parse()
        .unwrap();
    // Listening: a second listener on the port is refused.
    assert!(std::net::TcpListener::bind(("127.0.0.1", port)).is_err());
    let sent = Command::new("kill")
        .args(["-INT", &server.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = server.try_wait().unwrap() {
            break status;
        }
        if started.elapsed().as_secs() > 20 {
            server.kill().unwrap();
            panic!("ger view still running 20 s after SIGINT");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut server.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(status.success(), "{status:?}\n{stderr}");
    assert!(
        stderr.contains(&format!("127.0.0.1:{port} closed")),
        "{stderr}"
    );
    assert!(std::net::TcpListener::bind(("127.0.0.1", port)).is_ok());
}
