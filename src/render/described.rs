//! The cutters a program's comments describe, as CAM posts write them,
//! for a picture drawn without a tool table: Fusion's `(T1 D=2.7 CR=0. -
//! ZMIN=… - flat end mill)`, Estlcam's `T1 M06 (Change tool: HSS 1-Flute
//! Endmill, 3.175mm)`, FlatCAM's `(Tool: 1 -> Dia: 0.8)`, Carbide Create's
//! APT `(TOOL/MILL,0.25,0.125,…)`, and a tool-change line's comment that
//! names a size (`T3 M06 ( 20mm 390 ENDMILL )`, `(Tool: 1/4 in Carbide End
//! Mill)`). Only what a comment states is taken; a comment that gives no
//! size gives nothing (the picture then says which cutter it assumed).

use crate::ir::{Tool, ToolShape, Units};

/// A cutter a comment describes.
#[derive(Clone, Debug, PartialEq)]
pub struct Described {
    /// The tool number it is for: named in it or on its line, else the
    /// `T` word just before it or the next one; `None`: the program has
    /// none (then it is for the program's only tool).
    pub tool: Option<u32>,
    /// In the output units.
    pub cutter: Tool,
    /// The 1-based line of the comment.
    pub line: u32,
    /// The comment's words, as a person finds it again.
    pub text: String,
}

/// The cutters described in `text`, in order; sizes written without a
/// unit are taken in `units` (the program's, which are the output's).
pub fn described_tools(text: &str, units: Option<Units>) -> Vec<Described> {
    let mut found = Vec::new();
    // The lines' T words, for descriptions that name no tool.
    let mut t_words: Vec<(usize, u32)> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line_tool = tool_word(code_part(line));
        if let Some(t) = line_tool {
            t_words.push((n, t));
        }
        for comment in comments(line) {
            if let Some(d) = describe(comment, line_tool, units) {
                found.push(Described {
                    line: n as u32 + 1,
                    text: comment.trim().to_string(),
                    ..d
                });
            }
        }
    }
    for d in found.iter_mut().filter(|d| d.tool.is_none()) {
        d.tool = nearby_tool(&t_words, d.line as usize - 1);
    }
    found
}

/// The tool a description that names none is about: a `T` word a few
/// lines before it (a tool-change block: `T1`, `M5`, the message, `M0`),
/// else the next `T` word after it (a header before the change).
fn nearby_tool(t_words: &[(usize, u32)], line: usize) -> Option<u32> {
    const BLOCK: usize = 6;
    let before = t_words
        .iter()
        .rev()
        .find(|&&(n, _)| n <= line && line - n <= BLOCK);
    let after = t_words.iter().find(|&&(n, _)| n > line);
    before.or(after).map(|&(_, t)| t)
}

/// The line without its comments (for its `T` word).
fn code_part(line: &str) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => break,
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// The `T` word of a line's code, if any.
fn tool_word(code: String) -> Option<u32> {
    let upper = code.to_ascii_uppercase();
    let at = upper
        .char_indices()
        .find(|&(i, c)| c == 'T' && !preceded_by_letter(&upper, i))?
        .0;
    let digits: String = upper[at + 1..]
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

fn preceded_by_letter(text: &str, at: usize) -> bool {
    text[..at]
        .chars()
        .next_back()
        .is_some_and(|c| c.is_ascii_alphabetic())
}

/// The comments of a line: `( … )` and `; …`.
fn comments(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(open) = rest.find(['(', ';']) {
        if rest.as_bytes()[open] == b';' {
            out.push(&rest[open + 1..]);
            break;
        }
        let body = &rest[open + 1..];
        let close = body.find(')').unwrap_or(body.len());
        out.push(&body[..close]);
        rest = &body[(close + 1).min(body.len())..];
    }
    out
}

/// The cutter one comment describes, for the tool of its line.
fn describe(comment: &str, line_tool: Option<u32>, units: Option<Units>) -> Option<Described> {
    let upper = comment.to_ascii_uppercase();
    let (tool, diameter) = fusion(&upper)
        .or_else(|| flatcam(&upper))
        .or_else(|| apt(&upper).map(|d| (None, d)))
        .or_else(|| sized(&upper, units).map(|d| (line_tool, d)))?;
    let diameter = diameter.filter(|d| d.is_finite() && *d > 0.0 && *d < 10_000.0)?;
    let shape = shape_of(&upper, diameter);
    Some(Described {
        tool: tool.or(line_tool),
        cutter: Tool {
            diameter,
            length: None,
            shape,
        },
        line: 0,
        text: String::new(),
    })
}

/// Fusion's `T1 D=2.7 CR=0 …`: the tool and its diameter (program units).
fn fusion(upper: &str) -> Option<(Option<u32>, Option<f64>)> {
    let at = upper.find("D=")?;
    let tool = upper.trim_start().strip_prefix('T').and_then(|r| {
        let digits: String = r.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().ok()
    });
    tool?;
    Some((tool, number_at(&upper[at + 2..])))
}

/// FlatCAM's `Tool: 1 -> Dia: 0.8`.
fn flatcam(upper: &str) -> Option<(Option<u32>, Option<f64>)> {
    let rest = upper.trim_start().strip_prefix("TOOL:")?;
    let (number, dia) = rest.split_once("->")?;
    let tool = number.trim().parse().ok();
    let dia = dia.trim().strip_prefix("DIA:")?;
    Some((tool, number_at(dia.trim_start())))
}

/// APT's `TOOL/MILL,diameter,corner radius,length,angle`.
fn apt(upper: &str) -> Option<Option<f64>> {
    let rest = upper.trim_start().strip_prefix("TOOL/MILL,")?;
    Some(rest.split(',').next().and_then(|d| d.trim().parse().ok()))
}

/// A size written with its unit (`3.175mm`, `20 MM`, `1/4 IN`, `0.125"`,
/// `0.0314961INCH`), or after `DIAMETER:` or `DIA:` in the program's
/// units — only in a comment that speaks of a cutter and of nothing else
/// with a size.
fn sized(upper: &str, units: Option<Units>) -> Option<Option<f64>> {
    const CUTTERS: [&str; 8] = [
        "MILL", "DRILL", "TOOL", "BIT", "CUTTER", "ENDMILL", "ENGRAV", "V-",
    ];
    // Sizes of other things a CAM header states beside the tool's.
    const NOT_THE_CUTTER: [&str; 12] = [
        "STEP",
        "DEPTH",
        "FEED",
        "HEIGHT",
        "SPEED",
        "PASS",
        "OFFSET",
        "CLEARANCE",
        "STOCK",
        "MARGIN",
        "RETRACT",
        "TOLERANCE",
    ];
    if !CUTTERS.iter().any(|w| upper.contains(w))
        || NOT_THE_CUTTER.iter().any(|w| upper.contains(w))
    {
        return None;
    }
    let to = |from: Units| from.factor(units.unwrap_or(Units::Mm));
    for (i, _) in upper.char_indices() {
        let rest = &upper[i..];
        if i > 0 && !upper[..i].ends_with([' ', ',', ':', '(', '=']) {
            continue;
        }
        let Some((value, after)) = fraction_or_number(rest) else {
            continue;
        };
        let after = after.trim_start();
        if after.starts_with("MM") {
            return Some(Some(value * to(Units::Mm)));
        }
        if after.starts_with("INCH")
            || after.starts_with("IN ")
            || after == "IN"
            || after.starts_with('"')
        {
            return Some(Some(value * to(Units::Inch)));
        }
    }
    // After these a bare number is the size (after `TOOL:` it may be the
    // tool's number: only with a unit, above).
    for key in ["DIAMETER:", "DIA:", "DIA="] {
        if let Some(at) = upper.find(key) {
            if let Some((value, after)) = fraction_or_number(upper[at + key.len()..].trim_start()) {
                let after = after.trim_start();
                let value = match after {
                    a if a.starts_with("MM") => value * to(Units::Mm),
                    a if a.starts_with("IN") || a.starts_with('"') => value * to(Units::Inch),
                    _ => value,
                };
                return Some(Some(value));
            }
        }
    }
    None
}

/// A number (`3.175`, `.5`) or a fraction (`1/4`) at the start of `text`,
/// and what follows it.
fn fraction_or_number(text: &str) -> Option<(f64, &str)> {
    let end = text
        .char_indices()
        .find(|&(_, c)| !(c.is_ascii_digit() || c == '.' || c == '/'))
        .map_or(text.len(), |(i, _)| i);
    let word = &text[..end];
    let value = match word.split_once('/') {
        Some((a, b)) => a.parse::<f64>().ok()? / b.parse::<f64>().ok()?,
        None => word.parse().ok()?,
    };
    Some((value, &text[end..]))
}

/// The number at the start of `text` (`2.7`, `3.175`).
fn number_at(text: &str) -> Option<f64> {
    fraction_or_number(text.trim_start()).map(|(v, _)| v)
}

/// The cutter's shape from the comment's words: a drill, a ball end (or
/// a corner radius of half the diameter), a V-bit, else flat.
fn shape_of(upper: &str, diameter: f64) -> ToolShape {
    let apt_corner = upper
        .trim_start()
        .strip_prefix("TOOL/MILL,")
        .and_then(|r| r.split(',').nth(1))
        .and_then(|r| r.trim().parse::<f64>().ok());
    let corner = upper
        .find("CR=")
        .and_then(|at| number_at(&upper[at + 3..]))
        .or(apt_corner);
    if upper.contains("DRILL") {
        ToolShape::Drill
    } else if upper.contains("BALL") || corner.is_some_and(|r| (r - diameter / 2.0).abs() < 1e-9) {
        ToolShape::Ball
    } else if upper.contains("V-BIT")
        || upper.contains("VBIT")
        || upper.contains("CHAMFER")
        || upper.contains("ENGRAV")
    {
        ToolShape::Vee(90.0)
    } else {
        ToolShape::Flat
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_description_naming_no_tool_is_for_the_tool_change_it_stands_in() {
        let text = "(TOOL/MILL,0.1,0.05,0.000,0)\nG20\nT1 M6\nG0 Z1\nT2\nM5\n\
                    (MSG, Change tool bit to drill size 0.0394094inch)\nM0\n";
        let tools: Vec<_> = described_tools(text, Some(Units::Inch))
            .iter()
            .map(|d| (d.tool, d.line))
            .collect();
        assert_eq!(tools, [(Some(1), 1), (Some(2), 7)]);
    }

    fn one(line: &str, units: Units) -> Option<(Option<u32>, f64, ToolShape)> {
        let found = described_tools(line, Some(units));
        found
            .first()
            .map(|d| (d.tool, d.cutter.diameter, d.cutter.shape))
    }

    #[test]
    fn the_forms_cam_posts_write() {
        let mm = Units::Mm;
        assert_eq!(
            one("(T1  D=2.7 CR=0 - ZMIN=-12.55 - flat end mill)", mm),
            Some((Some(1), 2.7, ToolShape::Flat))
        );
        assert_eq!(
            one(
                "(  T1 D=3.175 CR=0 TAPER=118deg - ZMIN=-13.392 - drill )",
                mm
            ),
            Some((Some(1), 3.175, ToolShape::Drill))
        );
        assert_eq!(
            one("(T2 D=6 CR=3 - ball end mill)", mm),
            Some((Some(2), 6.0, ToolShape::Ball))
        );
        assert_eq!(
            one("T1 M06 (Change tool: HSS 1-Flute Endmill, 3.175mm)", mm),
            Some((Some(1), 3.175, ToolShape::Flat))
        );
        assert_eq!(
            one("T2 M06 (Change tool: HSS Twist Drill, 4.5mm R)", mm),
            Some((Some(2), 4.5, ToolShape::Drill))
        );
        assert_eq!(
            one("(Tool: 3 -> Dia: 2.2)", mm),
            Some((Some(3), 2.2, ToolShape::Flat))
        );
        assert_eq!(
            one("(TOOL/MILL,0.25,0.125,0.000,0)", Units::Inch),
            Some((None, 0.25, ToolShape::Ball))
        );
        assert_eq!(
            one("(TOOL DIAMETER: 3.1 mm)", mm),
            Some((None, 3.1, ToolShape::Flat))
        );
        assert_eq!(one("; Tool: 3.0mm", mm), Some((None, 3.0, ToolShape::Flat)));
        assert_eq!(
            one("N110 T3 M06 ( 20mm 390 ENDMILL )", mm),
            Some((Some(3), 20.0, ToolShape::Flat))
        );
        let quarter = one("(Tool: 1/4 in Carbide End Mill)", mm).unwrap();
        assert!((quarter.1 - 6.35).abs() < 1e-12, "{quarter:?}");
        let inch = one(
            "(MSG, Change tool bit to drill size 0.0314961inch)",
            Units::Inch,
        )
        .unwrap();
        assert!((inch.1 - 0.0314961).abs() < 1e-12 && inch.2 == ToolShape::Drill);
    }

    #[test]
    fn comments_that_state_no_size_give_nothing() {
        for line in [
            "G40 (disable tool radius compensation)",
            "(Tool step over: 0.3mm)",
            "; Tool step over: 0.3mm",
            "(Tool: 1/8 in Carbide End Mill, depth per pass 1mm)",
            "G00 Z1.00000 (Retract to tool change height)",
            "(milling depth = -0.2540)",
            "(boxBackDrill - Milling - Tool: 1 -  drill)",
            "G1 X3mm",
        ] {
            let found = described_tools(line, Some(Units::Mm));
            assert!(found.is_empty(), "{line}: {found:?}");
        }
    }
}
