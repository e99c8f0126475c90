//! PNG pictures of a carved grid (SPEC §7): the 16-bit depth image (one
//! pixel per cell, row 0 at the stock's largest Y, 65535 at the stock top
//! and 0 at its bottom, with its scale in tEXt and pHYs chunks), a
//! hill-shaded colour image with a depth legend, and the difference of two
//! grids.

use super::carve::Grid;
use crate::ir::Units;
use std::io::Write;

fn png_error(e: png::EncodingError) -> std::io::Error {
    match e {
        png::EncodingError::IoError(e) => e,
        other => std::io::Error::other(other.to_string()),
    }
}

/// An encoder for a `width` x `height` picture of `grid`, with its scale.
fn encoder<W: Write>(
    out: W,
    grid: &Grid,
    units: Option<Units>,
    width: usize,
    color: png::ColorType,
    depth: png::BitDepth,
) -> std::io::Result<png::Writer<W>> {
    let too_big = || std::io::Error::other("the picture is too large for a PNG");
    let width = u32::try_from(width).map_err(|_| too_big())?;
    let height = u32::try_from(grid.frame.ny).map_err(|_| too_big())?;
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    // A heightmap is mostly flat runs: fast deflate packs them nearly as
    // well as the default, in a fraction of the time (the PNG is written on
    // one core, after the carving on all of them).
    encoder.set_compression(png::Compression::Fast);
    let mm = Units::mm_per(units);
    let per_metre = (1000.0 / (grid.frame.cell * mm))
        .round()
        .clamp(1.0, f64::from(u32::MAX));
    encoder.set_pixel_dims(Some(png::PixelDimensions {
        xppu: per_metre as u32,
        yppu: per_metre as u32,
        unit: png::Unit::Meter,
    }));
    let unit_name = match units {
        Some(Units::Mm) => "mm",
        Some(Units::Inch) => "inch",
        None => "unknown (taken as mm)",
    };
    for (key, value) in [
        ("ger:cell", grid.frame.cell.to_string()),
        ("ger:z-top", grid.top.to_string()),
        ("ger:z-bottom", grid.bottom.to_string()),
        ("ger:x-min", grid.frame.x0.to_string()),
        ("ger:y-min", grid.frame.y0.to_string()),
        ("ger:units", unit_name.to_string()),
    ] {
        encoder
            .add_text_chunk(key.to_string(), value)
            .map_err(png_error)?;
    }
    encoder.write_header().map_err(png_error)
}

/// The 16-bit grayscale depth image.
pub fn write_depth(grid: &Grid, units: Option<Units>, out: impl Write) -> std::io::Result<()> {
    let nx = grid.frame.nx;
    let mut writer = encoder(
        out,
        grid,
        units,
        nx,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
    )?;
    let mut stream = writer.stream_writer().map_err(png_error)?;
    let per_unit = 65535.0 / (grid.top - grid.bottom);
    let mut row = vec![0u8; nx * 2];
    for j in (0..grid.frame.ny).rev() {
        let heights = &grid.z[j * nx..(j + 1) * nx];
        for (px, &z) in row.chunks_exact_mut(2).zip(heights) {
            // Rounded to the nearest step (the cast saturates at 0 and 65535).
            let v = ((f64::from(z) - grid.bottom) * per_unit + 0.5) as u16;
            px.copy_from_slice(&v.to_be_bytes());
        }
        stream.write_all(&row)?;
    }
    stream.finish().map_err(png_error)
}

/// Light from the north-west, 45° up.
const LIGHT: [f64; 3] = [-0.5, 0.5, std::f64::consts::FRAC_1_SQRT_2];

/// The colour of uncut stock.
pub(super) const STOCK: [u8; 3] = [214, 206, 190];

/// An RGB picture with no scale of its own (a view of the part).
pub(super) fn write_rgb(
    width: usize,
    height: usize,
    rgb: &[u8],
    out: impl Write,
) -> std::io::Result<()> {
    let too_big = || std::io::Error::other("the picture is too large for a PNG");
    let width = u32::try_from(width).map_err(|_| too_big())?;
    let height = u32::try_from(height).map_err(|_| too_big())?;
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(png_error)?;
    writer.write_image_data(rgb).map_err(png_error)?;
    writer.finish().map_err(png_error)
}

/// How many cells a side the shaded picture takes as one pixel, so that
/// its long side (legend included) is at most `size` pixels.
pub fn shaded_block(grid: &Grid, units: Option<Units>, size: usize) -> usize {
    let (nx, ny) = (grid.frame.nx, grid.frame.ny);
    let mut b = nx.max(ny).div_ceil(size.max(1)).max(1);
    while b < nx.max(ny) {
        let height = ny.div_ceil(b);
        let width = nx.div_ceil(b) + Legend::new(grid, height, units).width;
        if width.max(height) <= size {
            break;
        }
        b += 1;
    }
    b
}

/// The hill-shaded colour image: depth coloured (uncut stock plain), lit
/// from the north-west, with a legend of depths on the right; its long
/// side at most `size` pixels (blocks of cells, each at its lowest).
pub fn write_shaded(
    grid: &Grid,
    units: Option<Units>,
    size: usize,
    out: impl Write,
) -> std::io::Result<()> {
    let reduced;
    let grid = match shaded_block(grid, units, size) {
        1 => grid,
        b => {
            reduced = grid.reduced(b);
            &reduced
        }
    };
    let (nx, ny) = (grid.frame.nx, grid.frame.ny);
    let legend = Legend::new(grid, ny, units);
    let width = nx + legend.width;
    let mut writer = encoder(
        out,
        grid,
        units,
        width,
        png::ColorType::Rgb,
        png::BitDepth::Eight,
    )?;
    let mut stream = writer.stream_writer().map_err(png_error)?;
    let span = grid.top - grid.bottom;
    let cell = grid.frame.cell;
    let mut row = vec![0u8; width * 3];
    for (y, j) in (0..ny).rev().enumerate() {
        for i in 0..nx {
            let z = |i: usize, j: usize| f64::from(grid.at(i.min(nx - 1), j.min(ny - 1)));
            let dzdx = (z(i + 1, j) - z(i.saturating_sub(1), j)) / (2.0 * cell);
            let dzdy = (z(i, j + 1) - z(i, j.saturating_sub(1))) / (2.0 * cell);
            let norm = (dzdx * dzdx + dzdy * dzdy + 1.0).sqrt();
            let lit = (-dzdx * LIGHT[0] - dzdy * LIGHT[1] + LIGHT[2]) / norm;
            let shade = 0.45 + 0.55 * lit.max(0.0);
            let depth = (grid.top - z(i, j)) / span;
            let base = if depth < 1e-6 {
                STOCK
            } else if grid.through(grid.at(i, j)) {
                // A hole: what lies under the part, not a colour of depth.
                for k in 0..3 {
                    row[i * 3 + k] = 255;
                }
                continue;
            } else {
                depth_color(depth)
            };
            for k in 0..3 {
                row[i * 3 + k] = (f64::from(base[k]) * shade).round().clamp(0.0, 255.0) as u8;
            }
        }
        legend.draw_row(y, &mut row[nx * 3..]);
        stream.write_all(&row)?;
    }
    stream.finish().map_err(png_error)
}

/// The colour of a depth, 0 (the top) to 1 (the bottom).
pub fn depth_color(t: f64) -> [u8; 3] {
    colorous::VIRIDIS
        .eval_continuous(1.0 - t.clamp(0.0, 1.0))
        .as_array()
}

/// Where two grids over the same stock differ: the first program's part in
/// gray, red where it cuts deeper than the other, blue where the other
/// does. Returns the cells that differ by more than `tolerance`, and the
/// largest difference.
pub fn write_difference(
    a: &Grid,
    b: &Grid,
    tolerance: f64,
    units: Option<Units>,
    out: impl Write,
) -> std::io::Result<(usize, f64)> {
    let (nx, ny) = (a.frame.nx, a.frame.ny);
    let mut writer = encoder(out, a, units, nx, png::ColorType::Rgb, png::BitDepth::Eight)?;
    let mut stream = writer.stream_writer().map_err(png_error)?;
    let span = a.top - a.bottom;
    let (mut differ, mut largest) = (0, 0.0f64);
    let mut row = vec![0u8; nx * 3];
    for j in (0..ny).rev() {
        for i in 0..nx {
            let (za, zb) = (f64::from(a.at(i, j)), f64::from(b.at(i, j)));
            let px = if (za - zb).abs() <= tolerance {
                let g = (90.0 + 140.0 * ((za - a.bottom) / span).clamp(0.0, 1.0)) as u8;
                [g, g, g]
            } else {
                differ += 1;
                largest = largest.max((za - zb).abs());
                if za < zb {
                    [220, 40, 40]
                } else {
                    [40, 80, 220]
                }
            };
            row[i * 3..i * 3 + 3].copy_from_slice(&px);
        }
        stream.write_all(&row)?;
    }
    stream.finish().map_err(png_error)?;
    Ok((differ, largest))
}

/// The depth legend: a colour bar with the depths written beside it in a
/// small bitmap font, scaled to the picture's height.
pub(super) struct Legend {
    pub(super) width: usize,
    height: usize,
    scale: usize,
    /// (row of the label's middle, text).
    labels: Vec<(usize, String)>,
}

/// A 5-row font for the legend's numbers and units: each row of a glyph
/// is `width` bits, the highest on the left.
const GLYPHS: [(char, usize, [u8; 5]); 16] = [
    ('0', 3, [7, 5, 5, 5, 7]),
    ('1', 3, [2, 6, 2, 2, 7]),
    ('2', 3, [7, 1, 7, 4, 7]),
    ('3', 3, [7, 1, 7, 1, 7]),
    ('4', 3, [5, 5, 7, 1, 1]),
    ('5', 3, [7, 4, 7, 1, 7]),
    ('6', 3, [7, 4, 7, 5, 7]),
    ('7', 3, [7, 1, 1, 1, 1]),
    ('8', 3, [7, 5, 7, 5, 7]),
    ('9', 3, [7, 5, 7, 1, 7]),
    ('-', 3, [0, 0, 7, 0, 0]),
    ('.', 1, [0, 0, 0, 0, 1]),
    (' ', 2, [0, 0, 0, 0, 0]),
    ('m', 5, [0, 0, 26, 21, 21]),
    ('i', 1, [1, 0, 1, 1, 1]),
    ('n', 3, [0, 0, 6, 5, 5]),
];

/// The width of a text in font pixels (a column between glyphs).
fn text_width(text: &str) -> usize {
    text.chars()
        .map(|c| GLYPHS.iter().find(|g| g.0 == c).map_or(0, |g| g.1 + 1))
        .sum()
}

const BAR: usize = 6;
const MARGIN: usize = 4;

impl Legend {
    pub(super) fn new(grid: &Grid, height: usize, units: Option<Units>) -> Legend {
        let scale = (height / 200).clamp(1, 4);
        let steps = if height >= 12 * 5 * scale { 4 } else { 1 };
        let labels: Vec<(usize, String)> = (0..=steps)
            .map(|k| {
                let t = k as f64 / steps as f64;
                let z = grid.top + (grid.bottom - grid.top) * t;
                let row = ((height.saturating_sub(1)) as f64 * t).round() as usize;
                (row, super::length(z, units))
            })
            .collect();
        let text = labels.iter().map(|(_, s)| text_width(s)).max().unwrap_or(0) * scale;
        Legend {
            width: MARGIN * scale + BAR * scale + MARGIN * scale + text + MARGIN * scale,
            height,
            scale,
            labels,
        }
    }

    pub(super) fn draw_row(&self, y: usize, out: &mut [u8]) {
        out.fill(255);
        let s = self.scale;
        let t = y as f64 / (self.height.max(2) - 1) as f64;
        let color = depth_color(t);
        for x in MARGIN * s..(MARGIN + BAR) * s {
            out[x * 3..x * 3 + 3].copy_from_slice(&color);
        }
        let text_x = (MARGIN + BAR + MARGIN) * s;
        for (middle, text) in &self.labels {
            // Keep the label inside the picture.
            let top = middle
                .saturating_sub(5 * s / 2)
                .min(self.height.saturating_sub(5 * s));
            if y < top || y >= top + 5 * s {
                continue;
            }
            let glyph_row = (y - top) / s;
            let mut column = 0;
            for c in text.chars() {
                let Some(&(_, width, rows)) = GLYPHS.iter().find(|g| g.0 == c) else {
                    continue;
                };
                for bit in 0..width {
                    if rows[glyph_row] & (1 << (width - 1 - bit)) != 0 {
                        for dx in 0..s {
                            let x = text_x + (column + bit) * s + dx;
                            if let Some(px) = out.get_mut(x * 3..x * 3 + 3) {
                                px.fill(0);
                            }
                        }
                    }
                }
                column += width + 1;
            }
        }
    }
}
