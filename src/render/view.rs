//! `ger render --view top|iso|front|side` (SPEC §7): the carved part as a
//! lit 3D picture, drawn in software. The grid is taken in blocks of about
//! a pixel ([`Grid::reduced`]); each block is a column of material: a top
//! face lit by the surface's slope and coloured by its depth (uncut stock
//! plain), and walls where its neighbour is lower, the stock's sides
//! among them. A block cut through has neither, so a hole shows what lies
//! behind it. The faces are projected orthographically and filled with a
//! depth buffer; the tool path may be drawn over them.
//! Must not carve, or know more of the program than the lines it is given.

use super::carve::Grid;
use super::image::{depth_color, Legend, STOCK};
use crate::ir::Units;
use std::io::Write;

/// Where the part is seen from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// From above, X to the right.
    Top,
    /// From the front, the right and above (the isometric corner).
    Iso,
    /// From the front (-Y), level.
    Front,
    /// From the right (+X), level.
    Side,
}

/// A move of the tool path to draw over the part: its tip's ends, in the
/// grid's units, and whether it is a rapid.
pub type PathLine = ([f64; 3], [f64; 3], bool);

/// The picture's long side when none is asked for: it fits a screen.
pub const DEFAULT_SIZE: usize = 1600;

/// At most this long a side (a `--size` beyond it is refused by the CLI).
pub const MAX_SIZE: usize = 16_000;

const BACKGROUND: [u8; 3] = [246, 246, 246];
const FEED: [u8; 3] = [200, 30, 30];
const RAPID: [u8; 3] = [60, 60, 60];

/// The camera: unit vectors to the right and up on the screen, and towards
/// the viewer, in world coordinates.
struct Camera {
    right: [f64; 3],
    up: [f64; 3],
    toward: [f64; 3],
}

impl Camera {
    fn of(view: View) -> Camera {
        let (s2, s3, s6) = (2f64.sqrt(), 3f64.sqrt(), 6f64.sqrt());
        let (right, up, toward) = match view {
            View::Top => ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            View::Iso => (
                [1.0 / s2, 1.0 / s2, 0.0],
                [-1.0 / s6, 1.0 / s6, 2.0 / s6],
                [1.0 / s3, -1.0 / s3, 1.0 / s3],
            ),
            View::Front => ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]),
            View::Side => ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        };
        Camera { right, up, toward }
    }

    /// Light from the viewer's upper left; in the isometric view from high
    /// in front, so that the two sides seen differ and neither is black.
    fn light(&self, view: View) -> [f64; 3] {
        let l: [f64; 3] = match view {
            View::Iso => [0.25, -0.55, 1.0],
            View::Top | View::Front | View::Side => std::array::from_fn(|k| {
                -0.35 * self.right[k] + 0.5 * self.up[k] + 0.8 * self.toward[k]
            }),
        };
        let n = dot(l, l).sqrt();
        l.map(|v| v / n)
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Colour buffer and depth buffer (larger depth: nearer the viewer).
struct Canvas {
    width: usize,
    height: usize,
    rgb: Vec<[u8; 3]>,
    depth: Vec<f64>,
}

impl Canvas {
    fn new(width: usize, height: usize) -> Canvas {
        Canvas {
            width,
            height,
            rgb: vec![BACKGROUND; width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
        }
    }

    /// Fill a triangle of screen points (x, y, depth) in one colour.
    fn triangle(&mut self, p: [[f64; 3]; 3], color: [u8; 3]) {
        let edge = |a: [f64; 3], b: [f64; 3], x: f64, y: f64| {
            (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])
        };
        let area = edge(p[0], p[1], p[2][0], p[2][1]);
        if area.abs() < 1e-12 {
            return;
        }
        let lo = |k: usize| p.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min);
        let hi = |k: usize| p.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max);
        let x0 = (lo(0) - 0.5).ceil().max(0.0) as usize;
        let y0 = (lo(1) - 0.5).ceil().max(0.0) as usize;
        let x1 = ((hi(0) - 0.5).floor().min(self.width as f64 - 1.0)).max(-1.0);
        let y1 = ((hi(1) - 0.5).floor().min(self.height as f64 - 1.0)).max(-1.0);
        if x1 < 0.0 || y1 < 0.0 {
            return;
        }
        for y in y0..=y1 as usize {
            let py = y as f64 + 0.5;
            for x in x0..=x1 as usize {
                let px = x as f64 + 0.5;
                let w0 = edge(p[1], p[2], px, py) / area;
                let w1 = edge(p[2], p[0], px, py) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let depth = w0 * p[0][2] + w1 * p[1][2] + w2 * p[2][2];
                let k = y * self.width + x;
                if depth > self.depth[k] {
                    self.depth[k] = depth;
                    self.rgb[k] = color;
                }
            }
        }
    }

    /// A quad a b c d (in turn round it) as two triangles.
    fn quad(&mut self, q: [[f64; 3]; 4], color: [u8; 3]) {
        self.triangle([q[0], q[1], q[2]], color);
        self.triangle([q[0], q[2], q[3]], color);
    }

    /// A line of screen points, drawn where nothing is more than `bias`
    /// nearer; dashed when asked.
    fn line(&mut self, a: [f64; 3], b: [f64; 3], color: [u8; 3], bias: f64, dashed: bool) {
        let steps = (b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil().min(1e6) as usize;
        for s in 0..=steps {
            if dashed && (s / 4) % 2 == 1 {
                continue;
            }
            let t = if steps == 0 {
                0.0
            } else {
                s as f64 / steps as f64
            };
            let p: [f64; 3] = std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t);
            if p[0] < 0.0 || p[1] < 0.0 {
                continue;
            }
            let (x, y) = (p[0] as usize, p[1] as usize);
            if x >= self.width || y >= self.height {
                continue;
            }
            let k = y * self.width + x;
            if p[2] + bias >= self.depth[k] {
                self.rgb[k] = color;
            }
        }
    }
}

/// How world points land on the canvas.
struct Projection {
    camera: Camera,
    light: [f64; 3],
    /// Pixels per unit.
    scale: f64,
    /// Screen position of the world's origin.
    origin: [f64; 2],
}

impl Projection {
    fn at(&self, p: [f64; 3]) -> [f64; 3] {
        let c = &self.camera;
        [
            self.origin[0] + dot(p, c.right) * self.scale,
            self.origin[1] - dot(p, c.up) * self.scale,
            dot(p, c.toward),
        ]
    }
}

/// Draw the part seen from `view`, its long side `size` pixels (legend
/// included), with `lines` over it, as an RGB PNG.
pub fn write(
    grid: &Grid,
    units: Option<Units>,
    view: View,
    size: usize,
    lines: &[PathLine],
    out: impl Write,
) -> std::io::Result<()> {
    let size = size.clamp(64, MAX_SIZE);
    let f = grid.frame;
    let (x1, y1) = (f.x0 + f.nx as f64 * f.cell, f.y0 + f.ny as f64 * f.cell);
    let camera = Camera::of(view);
    // The stock's corners on the screen's axes, in units.
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                if k & 1 == 0 { f.x0 } else { x1 },
                if k & 2 == 0 { f.y0 } else { y1 },
                if k & 4 == 0 { grid.bottom } else { grid.top },
            ]
        })
        .collect();
    let span = |axis: [f64; 3]| {
        let v = corners.iter().map(|&p| dot(p, axis));
        let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        (lo, (hi - lo).max(1e-9))
    };
    let ((left, wide), (bottom, tall)) = (span(camera.right), span(camera.up));
    let margin = (size / 40).max(4) as f64;
    let legend = Legend::new(grid, size, units);
    // The larger scale that fits both ways, the legend beside the part.
    let scale = ((size as f64 - legend.width as f64 - 2.0 * margin) / wide)
        .min((size as f64 - 2.0 * margin) / tall)
        .max(1e-9);
    let width = ((wide * scale + 2.0 * margin).ceil() as usize).max(1);
    let height = ((tall * scale + 2.0 * margin).ceil() as usize).max(1);
    let projection = Projection {
        light: camera.light(view),
        camera,
        scale,
        origin: [margin - left * scale, margin + (bottom + tall) * scale],
    };
    let mut canvas = Canvas::new(width, height);
    // About a block a pixel: finer would be lost, coarser would show.
    let b = ((1.0 / (f.cell * scale)).floor() as usize).max(1);
    let blocks = grid.reduced(b);
    draw_part(&mut canvas, &blocks, &projection);
    let bias = 3.0 * blocks.frame.cell;
    for &(a, z, rapid) in lines {
        let color = if rapid { RAPID } else { FEED };
        canvas.line(projection.at(a), projection.at(z), color, bias, rapid);
    }
    let legend = Legend::new(grid, height, units);
    let full = width + legend.width;
    let mut rgb = vec![255u8; full * height * 3];
    for (y, row) in rgb.chunks_exact_mut(full * 3).enumerate() {
        for (x, px) in canvas.rgb[y * width..(y + 1) * width].iter().enumerate() {
            row[x * 3..x * 3 + 3].copy_from_slice(px);
        }
        legend.draw_row(y, &mut row[width * 3..]);
    }
    super::image::write_rgb(full, height, &rgb, out)
}

/// Every block's top face and the walls it shows where a neighbour (or the
/// outside) is lower.
fn draw_part(canvas: &mut Canvas, g: &Grid, projection: &Projection) {
    let f = g.frame;
    let (nx, ny) = (f.nx, f.ny);
    let bottom = g.bottom as f32;
    // A block's height; cut through and outside are the stock's bottom.
    let h = |i: isize, j: isize| -> f32 {
        if i < 0 || j < 0 || i as usize >= nx || j as usize >= ny {
            return bottom;
        }
        let z = g.at(i as usize, j as usize);
        if g.through(z) {
            bottom
        } else {
            z
        }
    };
    let camera = &projection.camera;
    let light = projection.light;
    let x_at = |i: isize| f.x0 + i as f64 * f.cell;
    let y_at = |j: isize| f.y0 + j as f64 * f.cell;
    let span = g.top - g.bottom;
    let top_visible = camera.toward[2] > 1e-9;
    let lit = |n: [f64; 3]| 0.35 + 0.65 * dot(n, light).max(0.0);
    let shaded = |c: [u8; 3], s: f64| c.map(|v| (f64::from(v) * s).round().clamp(0.0, 255.0) as u8);
    for j in 0..ny as isize {
        for i in 0..nx as isize {
            let z = h(i, j);
            if z <= bottom {
                continue;
            }
            let zf = f64::from(z);
            if top_visible {
                let n = slope_normal(&h, i, j, f.cell);
                let depth = (g.top - zf) / span;
                let base = if depth < 1e-6 {
                    STOCK
                } else {
                    depth_color(depth)
                };
                let q = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                    .map(|(a, b)| projection.at([x_at(a), y_at(b), zf]));
                canvas.quad(q, shaded(base, lit(n)));
            }
            // The four sides: (neighbour, outward normal, the side's ends).
            let sides = [
                ((i + 1, j), [1.0, 0.0, 0.0], [(i + 1, j), (i + 1, j + 1)]),
                ((i - 1, j), [-1.0, 0.0, 0.0], [(i, j + 1), (i, j)]),
                ((i, j + 1), [0.0, 1.0, 0.0], [(i + 1, j + 1), (i, j + 1)]),
                ((i, j - 1), [0.0, -1.0, 0.0], [(i, j), (i + 1, j)]),
            ];
            for ((ni, nj), n, [(ax, ay), (bx, by)]) in sides {
                let low = h(ni, nj);
                if low >= z || dot(n, camera.toward) <= 1e-9 {
                    continue;
                }
                let low = f64::from(low);
                let q = [
                    projection.at([x_at(ax), y_at(ay), low]),
                    projection.at([x_at(bx), y_at(by), low]),
                    projection.at([x_at(bx), y_at(by), zf]),
                    projection.at([x_at(ax), y_at(ay), zf]),
                ];
                canvas.quad(q, shaded(STOCK, lit(wall_normal(&h, i, j, n))));
            }
        }
    }
}

/// The top's normal from its neighbours' heights; a neighbour across a
/// wall (steeper than 3:1) counts as level, so floors beside walls stay
/// lit as floors.
fn slope_normal(h: &dyn Fn(isize, isize) -> f32, i: isize, j: isize, cell: f64) -> [f64; 3] {
    let z = f64::from(h(i, j));
    let near = |a: isize, b: isize| {
        let v = f64::from(h(a, b));
        if (v - z).abs() > 3.0 * cell {
            z
        } else {
            v
        }
    };
    let dzdx = (near(i + 1, j) - near(i - 1, j)) / (2.0 * cell);
    let dzdy = (near(i, j + 1) - near(i, j - 1)) / (2.0 * cell);
    let n = (dzdx * dzdx + dzdy * dzdy + 1.0).sqrt();
    [-dzdx / n, -dzdy / n, 1.0 / n]
}

/// A wall's normal for its light: the way the heights fall over the
/// blocks round it, when that is near the wall's own side (a round wall
/// drawn as a staircase of sides is lit as the round wall it is).
fn wall_normal(h: &dyn Fn(isize, isize) -> f32, i: isize, j: isize, side: [f64; 3]) -> [f64; 3] {
    let (mut gx, mut gy) = (0.0, 0.0);
    for dj in -2..=2isize {
        for di in -2..=2isize {
            let v = f64::from(h(i + di, j + dj));
            gx += v * di as f64;
            gy += v * dj as f64;
        }
    }
    let n = gx.hypot(gy);
    if n == 0.0 {
        return side;
    }
    let falls = [-gx / n, -gy / n, 0.0];
    if dot(falls, side) > 0.3 {
        falls
    } else {
        side
    }
}

/// The tool path's moves as lines over the part: arcs in short chords.
pub fn path_lines(path: &crate::toolpath::ToolPath, units: Option<Units>) -> Vec<PathLine> {
    use crate::toolpath::MoveKind;
    let scale = 1.0 / Units::mm_per(units);
    let mut lines = Vec::with_capacity(path.moves.len());
    for (index, m) in path.moves.iter().enumerate() {
        let (before, after) = super::unknown_ends(path, index);
        if before.iter().chain(&after).any(|&g| g) {
            continue;
        }
        let rapid = matches!(m.kind, MoveKind::Rapid);
        let pieces = match m.kind {
            MoveKind::Arc(_) => ((m.sweep() / 0.2).ceil() as usize).clamp(1, 64),
            MoveKind::Rapid | MoveKind::Feed => 1,
        };
        let mut from = m.start.map(|v| v * scale);
        for k in 1..=pieces {
            let to = m.at(k as f64 / pieces as f64).map(|v| v * scale);
            lines.push((from, to, rapid));
            from = to;
        }
    }
    lines
}
