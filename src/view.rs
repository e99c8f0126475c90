//! `ger view`'s data: a compiled [`Job`] turned into the compact scene
//! the browser page draws ([`Studio`]), and the page itself ([`page`]).
//! The scene holds the moves (end points quantised and delta-encoded, the
//! tool, the source and output line, the time at each move's end), the
//! stock carved exactly as `ger render` carves it (the same [`Scene`],
//! cutters and heightmap) kept as checkpoints over the run, with what the
//! page needs to sweep on from one exactly, the
//! diagnostics, and the figures `ger stats` gives. Whatever the page
//! draws simplified (arcs as chords, the stock on a coarser grid than
//! `ger render`'s default) is listed in the scene's notes, which the page
//! shows.
//!
//! Architecture Invariant: no HTTP, no files, no threads of its own: the
//! binary serves or writes what this module makes; it calls the driver,
//! render and plan, and nothing in the library calls it.

mod moves;
mod stock;

use crate::diagnostic::Diagnostic;
use crate::driver::Job;
use crate::emit::Numbering;
use crate::ir::Units;
use crate::plan::{plan_with_clock, Limits};
use crate::render::{RenderOptions, Scene};
use crate::toolpath::ToolPath;
use codespan_reporting::diagnostic::Severity;
use serde_json::{json, Value};

/// The page's code, embedded: the project's own, no third-party script.
const PAGE_HTML: &str = include_str!("view/page/index.html");
const PAGE_JS: &str = include_str!("view/page/view.js");
const PAGE_CSS: &str = include_str!("view/page/view.css");

/// What the page is sent for one compile.
pub struct Studio {
    /// The scene, deflated and base64-encoded (what the page decodes).
    pub payload: String,
    /// The moves drawn (the tool path's, every one).
    pub moves: usize,
    /// The run time, as `ger stats` gives it.
    pub time_s: Option<f64>,
    /// Material removed by the whole program, mm³, from the exact grid.
    pub removed_mm3: Option<f64>,
    /// The program has errors: no moves, the diagnostics only.
    pub failed: bool,
    /// The diagnostics as `ger render` prints them.
    pub rendered: String,
}

/// The scene of `job`: compiled (output and diagnostics), its tool path
/// planned on `limits` (`ger stats`' run time) and carved as `ger render`
/// carves it with `render`'s options.
pub fn studio(job: &mut Job, limits: Option<&Limits>, render: &RenderOptions) -> Studio {
    let compiled = job.compile();
    let mut diagnostics = compiled.diagnostics;
    let mut header = json!({
        "format": 1,
        "source": {"name": job.sources.name(job.file), "text": job.sources.text(job.file)},
        "output": compiled.output,
        "files": files_of(job),
        "notes": [],
    });
    let mut binary = Vec::new();
    let Some(output) = compiled.output.as_deref() else {
        return failed(job, header, &diagnostics);
    };
    let output_lines = output_lines(job, output);
    let (machine_path, more) = job.tool_path();
    diagnostics.extend(more);
    let Some(machine_path) = machine_path else {
        return failed(job, header, &diagnostics);
    };
    let tip_path = tip_path(job, &machine_path);
    let path = tip_path.as_ref().unwrap_or(&machine_path);
    let (figures, clock) = plan_with_clock(&machine_path, limits);
    let time_s = figures.time_s.unwrap_or(figures.feed_time_s);
    let mut notes = Vec::new();
    let moves_json = moves::encode(path, &clock, &output_lines, &mut binary, &mut notes);
    let text = job.sources.text(job.file);
    let render = RenderOptions {
        described: crate::render::described::described_tools(text, path.units),
        ..render.clone()
    };
    let (stock_json, removed) = match Scene::new(path, &render) {
        Ok(scene) => {
            diagnostics.extend(scene.warnings.iter().map(|w| w.to_diagnostic()));
            let quantum = moves_json["quantum_mm"].as_f64().unwrap_or(0.001);
            let carved = stock::carve(&scene, path, &render, quantum, &mut binary, &mut notes);
            diagnostics.extend(carved.warnings.iter().map(|w| w.to_diagnostic()));
            (carved.json, carved.removed_mm3)
        }
        Err(e) => {
            notes.push(format!("no stock drawn: {e}"));
            (Value::Null, None)
        }
    };
    header["moves"] = moves_json;
    header["stock"] = stock_json;
    header["tools"] = tools_json(&scene_tools(path, &render), Units::mm_per(path.units));
    header["time_s"] = json!(time_s);
    header["time_basis"] = json!(match figures.time_s {
        Some(_) => "planned on the machine of ger.toml",
        None => "length / feed, rapids not timed (no [machine] in ger.toml)",
    });
    header["figures"] = serde_json::to_value(&figures).unwrap_or(Value::Null);
    header["units"] = json!(match path.units {
        Some(Units::Inch) => "inch",
        Some(Units::Mm) | None => "mm",
    });
    header["notes"] = json!(notes);
    header["diagnostics"] = diagnostics_json(job, &diagnostics);
    Studio {
        payload: pack(&header, &binary),
        moves: path.moves.len(),
        time_s: Some(time_s),
        removed_mm3: removed,
        failed: false,
        rendered: crate::diagnostic::render(&job.sources, &diagnostics),
    }
}

/// The scene of a program with errors: its source and diagnostics.
fn failed(job: &Job, mut header: Value, diagnostics: &[Diagnostic]) -> Studio {
    header["diagnostics"] = diagnostics_json(job, diagnostics);
    Studio {
        payload: pack(&header, &[]),
        moves: 0,
        time_s: None,
        removed_mm3: None,
        failed: true,
        rendered: crate::diagnostic::render(&job.sources, diagnostics),
    }
}

/// The scene packed: a little-endian u32 with the header's length, the
/// header as JSON, the binary sections; deflated, then base64.
fn pack(header: &Value, binary: &[u8]) -> String {
    let text = header.to_string();
    let mut raw = Vec::with_capacity(4 + text.len() + binary.len());
    raw.extend_from_slice(&(text.len() as u32).to_le_bytes());
    raw.extend_from_slice(text.as_bytes());
    raw.extend_from_slice(binary);
    base64(&deflate(&raw))
}

/// The page. With `payload`, the scene is in the file (`ger view -o`);
/// without, the page asks its server for it.
pub fn page(payload: Option<&str>) -> String {
    let data = match payload {
        Some(p) => {
            format!("<script id=\"ger-data\" type=\"application/octet-stream\">{p}</script>")
        }
        None => String::new(),
    };
    PAGE_HTML
        .replace("/*GER_CSS*/", PAGE_CSS)
        .replace("<!--GER_DATA-->", &data)
        .replace("/*GER_JS*/", PAGE_JS)
}

/// The tool path of the tip, when tool lengths move the machine's away
/// from it (the picture draws the tip, as `ger render` does).
fn tip_path(job: &mut Job, machine: &ToolPath) -> Option<ToolPath> {
    if !machine.lengths_given {
        return None;
    }
    let before = job.options.lower.tip_path;
    job.options.lower.tip_path = true;
    let (path, _) = job.tool_path();
    job.options.lower.tip_path = before;
    path.filter(|p| p.moves.len() == machine.moves.len())
}

/// Each output line's source line: the N words of the output numbered
/// by source line (compiled again so when the user asked for others).
fn output_lines(job: &mut Job, output: &str) -> Vec<u32> {
    let numbered = match job.options.emit.numbering {
        Numbering::Source => None,
        _ => {
            let before = job.options.emit.numbering;
            job.options.emit.numbering = Numbering::Source;
            let again = job.compile().output;
            job.options.emit.numbering = before;
            again
        }
    };
    numbered
        .as_deref()
        .unwrap_or(output)
        .lines()
        .map(|line| {
            let line = line.trim_start();
            let digits: String = line
                .strip_prefix(['N', 'n'])
                .unwrap_or("")
                .chars()
                .take_while(char::is_ascii_digit)
                .collect();
            digits.parse().unwrap_or(0)
        })
        .collect()
}

fn files_of(job: &Job) -> Value {
    let mut names = Vec::new();
    let mut id = 0;
    while job.sources.get(id).is_some() {
        names.push(job.sources.name(id).to_string());
        id += 1;
    }
    json!(names)
}

/// The cutters by tool number, as the picture draws them.
fn scene_tools(
    path: &ToolPath,
    render: &RenderOptions,
) -> Vec<(u32, crate::render::cutter::Cutter)> {
    let scale = 1.0 / Units::mm_per(path.units);
    crate::render::cutters_by_tool(path, scale, &render.described)
}

/// The cutters, lengths in mm (the scene's are in the output units).
fn tools_json(tools: &[(u32, crate::render::cutter::Cutter)], mm_per: f64) -> Value {
    use crate::render::cutter::Profile;
    Value::Array(
        tools
            .iter()
            .map(|(number, c)| {
                let (profile, rise) = match c.profile {
                    Profile::Flat => ("flat", 0.0),
                    Profile::Ball => ("ball", 0.0),
                    Profile::Cone { rise } => ("cone", rise),
                };
                json!({"number": number, "radius": c.radius * mm_per, "profile": profile, "rise": rise})
            })
            .collect(),
    )
}

/// The diagnostics with their file, line and rendered text.
fn diagnostics_json(job: &Job, diagnostics: &[Diagnostic]) -> Value {
    Value::Array(
        diagnostics
            .iter()
            .map(|d| {
                let place = d.labels.first().map(|l| {
                    let line = job
                        .sources
                        .get(l.file_id)
                        .map_or(0, |f| f.line_of(l.range.start));
                    (l.file_id, line)
                });
                let severity = match d.severity {
                    Severity::Bug | Severity::Error => "error",
                    Severity::Warning => "warning",
                    Severity::Note | Severity::Help => "note",
                };
                json!({
                    "severity": severity,
                    "message": d.message,
                    "file": place.map(|p| p.0),
                    "line": place.map(|p| p.1),
                    "rendered": crate::diagnostic::render(&job.sources, std::slice::from_ref(d)),
                })
            })
            .collect(),
    )
}

fn deflate(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing to a Vec cannot fail.
    let _ = encoder.write_all(bytes);
    encoder.finish().unwrap_or_default()
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::fs::Memory;
    use crate::driver::{CompileOptions, Program, Session};

    #[test]
    fn the_playback_clock_is_planned_on_the_machine() {
        // 100 mm at 100 mm/s: 1 s by length / feed; at 10 mm/s² a
        // triangle peaking at √(10 · 100) mm/s, 2 · √1000 / 10 = 6.32 s.
        let fs = Memory::new();
        let session = Session::new(&fs, CompileOptions::default(), Default::default()).unwrap();
        let program = || Program::Text {
            name: "part.nc",
            path: None,
            text: "G21 G90\nG1 X100 F6000\nM30\n".to_string(),
        };
        let limits = Limits {
            controller: crate::driver::machine::Controller::Grbl,
            max_rate: [100.0; 3],
            max_accel: [10.0; 3],
            rapid_rate: None,
            max_path_rate: f64::INFINITY,
            max_path_accel: f64::INFINITY,
            junction_deviation: 0.01,
            path_tolerance: 0.0,
            arc_tolerance: 0.002,
            blocks: 16,
            tool_change_s: 0.0,
            spindle_start_s: 0.0,
            steps_per_mm: [None; 3],
        };
        let render = RenderOptions::default();
        let job = || session.load(program()).ok().unwrap();
        let plain = studio(&mut job(), None, &render);
        assert!(
            (plain.time_s.unwrap() - 1.0).abs() < 1e-9,
            "{:?}",
            plain.time_s
        );
        let planned = studio(&mut job(), Some(&limits), &render);
        let expected = 2.0 * 1000.0_f64.sqrt() / 10.0;
        assert!(
            (planned.time_s.unwrap() - expected).abs() < 1e-9,
            "{:?}",
            planned.time_s
        );
    }

    #[test]
    fn base64_matches_the_standard_alphabet_and_padding() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }
}
