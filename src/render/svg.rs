//! The tool path as SVG, seen from above (SPEC §7): the stock outline,
//! feeds coloured by depth, feed rate or tool, feeds above the stock
//! dotted as air moves, rapids dashed (or hidden), a circle of the
//! cutter's size where it plunges (a hole drilled is a point seen from
//! above), and a legend beside the stock. Each path element is titled with
//! the source line it comes from; the moves of one source line that look
//! alike share one element.

use super::image::depth_color;
use super::Scene;
use crate::ir::Plane;
use crate::source::Span;
use crate::toolpath::{Move, MoveKind, ToolPath};
use std::fmt::Write as _;
use std::io::Write;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorBy {
    #[default]
    Depth,
    Feed,
    Tool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SvgOptions {
    pub color: ColorBy,
    pub rapids: bool,
}

impl Default for SvgOptions {
    fn default() -> SvgOptions {
        SvgOptions {
            color: ColorBy::Depth,
            rapids: true,
        }
    }
}

/// Colours for tools, in turn.
const TOOL_COLORS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
];

const RAPID: &str = "#8a8a8a";

/// Feeds that stay above the stock: they cut nothing.
const AIR: &str = "#3d8fd1";

/// Write the picture. `title` names a source line (`line 12: G1 X10`).
pub fn write(
    path: &ToolPath,
    scene: &Scene,
    options: SvgOptions,
    title: &dyn Fn(Span) -> String,
    out: &mut impl Write,
) -> std::io::Result<()> {
    let scale = 1.0 / crate::ir::Units::mm_per(scene.units);
    let s = &scene.stock;
    let stroke = (s.max[0] - s.min[0]).max(s.max[1] - s.min[1]) / 400.0;
    let font = (s.max[0] - s.min[0]).max(s.max[1] - s.min[1]) / 40.0;
    write_head(scene, stroke, font, out)?;
    let palette = Palette::new(path, scene, options.color);
    let legend = Legend::new(path, scene, &palette);
    // The element being drawn: its source line, colour and path data.
    let mut element: Option<(Span, String, String)> = None;
    for (index, m) in path.moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Rapid) && !options.rapids {
            continue;
        }
        let c = palette.color(m);
        // From an unknown place (the first move, or after G28/G53): the
        // path starts where the move ends.
        let (before, _) = super::unknown_ends(path, index);
        if before[0] || before[1] {
            write_element(element.take(), stroke, title, out)?;
            continue;
        }
        let joins = matches!(&element, Some((span, color, _)) if *span == m.span && *color == c);
        if !joins {
            write_element(element.take(), stroke, title, out)?;
            let d = format!("M{} {}", num(m.start[0] * scale), num(-m.start[1] * scale));
            element = Some((m.span, c, d));
        }
        if let Some((_, _, d)) = &mut element {
            trace(m, scale, d);
        }
    }
    write_element(element.take(), stroke, title, out)?;
    out.write_all(b"</g>\n")?;
    write_plunges(path, scene, &palette, stroke, title, out)?;
    legend.write(scene, font, stroke, options.rapids, out)?;
    out.write_all(b"</svg>\n")
}

/// A circle of the cutter's size where a feed goes straight down into the
/// stock, once per place and cutter (at its deepest), titled with the
/// line of the first.
fn write_plunges(
    path: &ToolPath,
    scene: &Scene,
    palette: &Palette,
    stroke: f64,
    title: &dyn Fn(Span) -> String,
    out: &mut impl Write,
) -> std::io::Result<()> {
    let scale = palette.scale;
    let mut cutter_of = vec![None; path.moves.len()];
    for segment in &scene.segments {
        cutter_of[segment.move_index] = Some(segment.cutter);
    }
    let mut plunges: Vec<([f64; 2], usize, f64, Span)> = Vec::new();
    let mut seen = std::collections::HashMap::new();
    for (m, cutter) in path.moves.iter().zip(cutter_of) {
        let Some(cutter) = cutter else { continue };
        let (start, end) = (m.start.map(|v| v * scale), m.end.map(|v| v * scale));
        let level = (end[0] - start[0]).hypot(end[1] - start[1]) <= 1e-9;
        if !matches!(m.kind, MoveKind::Feed)
            || !level
            || end[2] >= start[2]
            || end[2] >= scene.stock.top
        {
            continue;
        }
        let key = (num(end[0]), num(end[1]), cutter);
        match seen.get(&key) {
            Some(&k) => {
                let p: &mut ([f64; 2], usize, f64, Span) = &mut plunges[k];
                p.2 = p.2.min(end[2]);
            }
            None => {
                seen.insert(key, plunges.len());
                plunges.push(([end[0], end[1]], cutter, end[2], m.span));
            }
        }
    }
    if plunges.is_empty() {
        return Ok(());
    }
    writeln!(
        out,
        r#"<g fill-opacity="0.45" stroke-width="{}">"#,
        num(stroke)
    )?;
    for (at, cutter, z, span) in plunges {
        let color = palette.depth(z);
        writeln!(
            out,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{color}" stroke="{color}"><title>{}</title></circle>"#,
            num(at[0]),
            num(-at[1]),
            num(scene.cutters[cutter].radius.max(stroke)),
            escape(&title(span))
        )?;
    }
    out.write_all(b"</g>\n")
}

/// The legend's width and height, in fonts.
const LEGEND: [f64; 2] = [15.0, 10.0];

/// The SVG element, sized in millimetres (the stock and the legend beside
/// it), the stock's outline, and the group the paths go in.
fn write_head(scene: &Scene, stroke: f64, font: f64, out: &mut impl Write) -> std::io::Result<()> {
    let mm = crate::ir::Units::mm_per(scene.units);
    let s = &scene.stock;
    let (w, h) = (s.max[0] - s.min[0], s.max[1] - s.min[1]);
    let (all_w, all_h) = (w + font * (1.0 + LEGEND[0]), h.max(font * LEGEND[1]));
    let mut text = String::new();
    let _ = writeln!(
        text,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{} {} {} {}" width="{}mm" height="{}mm">"#,
        num(s.min[0]),
        num(-s.max[1]),
        num(all_w),
        num(all_h),
        num(all_w * mm),
        num(all_h * mm),
    );
    let _ = writeln!(
        text,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#f4f1ea" stroke="#b9b2a2" stroke-width="{}"/>"##,
        num(s.min[0]),
        num(-s.max[1]),
        num(w),
        num(h),
        num(stroke)
    );
    let _ = writeln!(
        text,
        r#"<g fill="none" stroke-width="{}" stroke-linecap="round" stroke-linejoin="round">"#,
        num(stroke)
    );
    out.write_all(text.as_bytes())
}

/// How a move is coloured: by its depth in the stock, its feed within the
/// program's range of feeds, or its tool; rapids grey.
struct Palette {
    by: ColorBy,
    /// From the path's units to the stock's (millimetres).
    scale: f64,
    top: f64,
    bottom: f64,
    /// The slowest and fastest feed of the path's feed moves.
    slow: f64,
    fast: f64,
}

impl Palette {
    fn new(path: &ToolPath, scene: &Scene, by: ColorBy) -> Palette {
        let feeds = path
            .moves
            .iter()
            .filter(|m| !matches!(m.kind, MoveKind::Rapid))
            .map(|m| m.state.feed);
        let (slow, fast) = feeds.fold((f64::INFINITY, 0.0f64), |(a, b), f| (a.min(f), b.max(f)));
        Palette {
            by,
            scale: 1.0 / crate::ir::Units::mm_per(scene.units),
            top: scene.stock.top,
            bottom: scene.stock.bottom,
            slow,
            fast,
        }
    }

    /// The colour of a depth (in the scene's units).
    fn depth(&self, z: f64) -> String {
        hex(depth_color((self.top - z) / (self.top - self.bottom)))
    }

    fn color(&self, m: &Move) -> String {
        let low = m.start[2].min(m.end[2]) * self.scale;
        match (m.kind, self.by) {
            (MoveKind::Rapid, _) => RAPID.to_string(),
            _ if low >= self.top => AIR.to_string(),
            (_, ColorBy::Depth) => self.depth(low),
            (_, ColorBy::Feed) => {
                let t = if self.fast > self.slow {
                    (m.state.feed - self.slow) / (self.fast - self.slow)
                } else {
                    0.5
                };
                hex(colorous::PLASMA
                    .eval_continuous(t.clamp(0.0, 1.0) * 0.9)
                    .as_array())
            }
            (_, ColorBy::Tool) => {
                TOOL_COLORS[m.state.tool as usize % TOOL_COLORS.len()].to_string()
            }
        }
    }
}

/// One path element, titled with its source line; rapids dashed.
fn write_element(
    element: Option<(Span, String, String)>,
    stroke: f64,
    title: &dyn Fn(Span) -> String,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let Some((span, color, d)) = element else {
        return Ok(());
    };
    let dash = match color.as_str() {
        RAPID => format!(
            r#" stroke-dasharray="{} {}""#,
            num(stroke * 4.0),
            num(stroke * 3.0)
        ),
        AIR => format!(
            r#" stroke-dasharray="{} {}""#,
            num(stroke),
            num(stroke * 2.0)
        ),
        _ => String::new(),
    };
    writeln!(
        out,
        r#"<path d="{d}" stroke="{color}"{dash}><title>{}</title></path>"#,
        escape(&title(span))
    )
}

/// Append the move's path (from its start) to `d`.
fn trace(m: &Move, scale: f64, d: &mut String) {
    match m.kind {
        MoveKind::Arc(a) if a.plane == Plane::XY => {
            // Pieces of at most a quarter turn, each an SVG arc; y is
            // flipped, so a clockwise arc is SVG's positive sweep.
            let r = (m.start[0] - a.center[0]).hypot(m.start[1] - a.center[1]) * scale;
            let pieces = ((m.sweep() / std::f64::consts::FRAC_PI_2).ceil() as usize).clamp(1, 4096);
            for k in 1..=pieces {
                let p = m.at(k as f64 / pieces as f64);
                let _ = write!(
                    d,
                    " A{} {} 0 0 {} {} {}",
                    num(r),
                    num(r),
                    u8::from(a.clockwise),
                    num(p[0] * scale),
                    num(-p[1] * scale)
                );
            }
        }
        MoveKind::Arc(_) => {
            for k in 1..=32 {
                let p = m.at(f64::from(k) / 32.0);
                let _ = write!(d, " L{} {}", num(p[0] * scale), num(-p[1] * scale));
            }
        }
        MoveKind::Rapid | MoveKind::Feed => {
            let _ = write!(d, " L{} {}", num(m.end[0] * scale), num(-m.end[1] * scale));
        }
    }
}

/// A coordinate: 4 decimals, no trailing zeros.
fn num(v: f64) -> String {
    let text = format!("{v:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" | "" => "0".to_string(),
        t => t.to_string(),
    }
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// What the colours and marks mean, beside the stock: the colour scale
/// (depths, feeds or tools), rapids, air moves, plunges.
struct Legend {
    /// The scale's stops and its two ends' labels, or the tools' swatches.
    scale: Scale,
}

enum Scale {
    Gradient {
        title: &'static str,
        stops: Vec<String>,
        ends: [String; 2],
    },
    Tools(Vec<(u32, String)>),
}

impl Legend {
    fn new(path: &ToolPath, scene: &Scene, palette: &Palette) -> Legend {
        let units = scene.units;
        let scale = match palette.by {
            ColorBy::Depth => Scale::Gradient {
                title: "depth",
                stops: (0..=4)
                    .map(|k| hex(depth_color(f64::from(k) / 4.0)))
                    .collect(),
                ends: [palette.top, palette.bottom].map(|z| super::length(z, units)),
            },
            ColorBy::Feed => Scale::Gradient {
                title: "feed",
                stops: (0..=4)
                    .map(|k| {
                        hex(colorous::PLASMA
                            .eval_continuous(f64::from(k) / 4.0 * 0.9)
                            .as_array())
                    })
                    .collect(),
                ends: [palette.slow, palette.fast].map(|f| {
                    let f = if f.is_finite() {
                        f * palette.scale
                    } else {
                        0.0
                    };
                    format!("{} {}/min", super::significant(f), super::unit_name(units))
                }),
            },
            ColorBy::Tool => {
                let mut tools: Vec<u32> = path.moves.iter().map(|m| m.state.tool).collect();
                tools.sort_unstable();
                tools.dedup();
                Scale::Tools(
                    tools
                        .into_iter()
                        .map(|t| (t, TOOL_COLORS[t as usize % TOOL_COLORS.len()].to_string()))
                        .collect(),
                )
            }
        };
        Legend { scale }
    }

    fn write(
        &self,
        scene: &Scene,
        font: f64,
        stroke: f64,
        rapids: bool,
        out: &mut impl Write,
    ) -> std::io::Result<()> {
        let x = scene.stock.max[0] + font;
        let mut y = -scene.stock.max[1] + font;
        let mut text = String::new();
        let _ = writeln!(
            text,
            r##"<g font-family="sans-serif" font-size="{}" fill="#333">"##,
            num(font)
        );
        let label = |text: &mut String, y: f64, words: &str| {
            let _ = writeln!(
                text,
                r#"<text x="{}" y="{}">{}</text>"#,
                num(x + 3.0 * font),
                num(y + 0.35 * font),
                escape(words)
            );
        };
        match &self.scale {
            Scale::Gradient { title, stops, ends } => {
                let _ = writeln!(
                    text,
                    r#"<linearGradient id="scale" x1="0" y1="0" x2="0" y2="1">"#
                );
                for (k, c) in stops.iter().enumerate() {
                    let _ = writeln!(
                        text,
                        r#"<stop offset="{}" stop-color="{c}"/>"#,
                        k as f64 / 4.0
                    );
                }
                let _ = writeln!(text, "</linearGradient>");
                let _ = writeln!(
                    text,
                    r#"<rect x="{}" y="{}" width="{}" height="{}" fill="url(#scale)"/>"#,
                    num(x),
                    num(y - 0.5 * font),
                    num(2.0 * font),
                    num(4.0 * font)
                );
                label(&mut text, y, &format!("{title} {}", ends[0]));
                label(&mut text, y + 3.0 * font, &ends[1]);
                y += 5.0 * font;
            }
            Scale::Tools(tools) => {
                for (tool, color) in tools {
                    let _ = writeln!(
                        text,
                        r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{color}"/>"#,
                        num(x),
                        num(y - 0.4 * font),
                        num(2.0 * font),
                        num(0.8 * font)
                    );
                    label(&mut text, y, &format!("T{tool}"));
                    y += 1.5 * font;
                }
            }
        }
        for (color, dash, words) in [
            (RAPID, [4.0, 3.0], "rapid"),
            (AIR, [1.0, 2.0], "feed in the air"),
        ] {
            if color == RAPID && !rapids {
                continue;
            }
            let _ = writeln!(
                text,
                r#"<path d="M{} {} h{}" stroke="{color}" stroke-width="{}" stroke-dasharray="{} {}"/>"#,
                num(x),
                num(y),
                num(2.0 * font),
                num(stroke),
                num(stroke * dash[0]),
                num(stroke * dash[1])
            );
            label(&mut text, y, words);
            y += 1.5 * font;
        }
        let _ = writeln!(
            text,
            r##"<circle cx="{}" cy="{}" r="{}" fill="#888" fill-opacity="0.45" stroke="#888" stroke-width="{}"/>"##,
            num(x + font),
            num(y),
            num(0.6 * font),
            num(stroke)
        );
        label(&mut text, y, "plunge (the cutter's size)");
        text.push_str("</g>\n");
        out.write_all(text.as_bytes())
    }
}
