//! The tool path as SVG, seen from above (SPEC §7): the stock outline,
//! feeds coloured by depth, feed rate or tool, rapids dashed (or hidden),
//! each path element titled with the source line it comes from. The moves
//! of one source line that look alike share one element.

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
    write_head(scene, stroke, out)?;
    let palette = Palette::new(path, scene, options.color);
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
    out.write_all(b"</g>\n</svg>\n")
}

/// The SVG element, sized in millimetres, the stock's outline, and the
/// group the paths go in.
fn write_head(scene: &Scene, stroke: f64, out: &mut impl Write) -> std::io::Result<()> {
    let mm = crate::ir::Units::mm_per(scene.units);
    let s = &scene.stock;
    let (w, h) = (s.max[0] - s.min[0], s.max[1] - s.min[1]);
    let mut text = String::new();
    let _ = writeln!(
        text,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{} {} {} {}" width="{}mm" height="{}mm">"#,
        num(s.min[0]),
        num(-s.max[1]),
        num(w),
        num(h),
        num(w * mm),
        num(h * mm),
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

    fn color(&self, m: &Move) -> String {
        match (m.kind, self.by) {
            (MoveKind::Rapid, _) => RAPID.to_string(),
            (_, ColorBy::Depth) => {
                let z = m.start[2].min(m.end[2]) * self.scale;
                hex(depth_color((self.top - z) / (self.top - self.bottom)))
            }
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
    let dash = if color == RAPID {
        format!(
            r#" stroke-dasharray="{} {}""#,
            num(stroke * 4.0),
            num(stroke * 3.0)
        )
    } else {
        String::new()
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
