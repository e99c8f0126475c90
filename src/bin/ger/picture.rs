//! `ger render`: compile, simulate, write the picture (PNG, SVG or STL,
//! by the output's name), printing the notes and warnings on the way.

use crate::args::{ColorArg, Options, PictureArgs, RapidsArg, ViewArg};
use crate::load;
use ger::diagnostic::render;
use ger::driver::output::{same_file, write_file};
use ger::driver::Job;
use std::path::Path;
use std::process::ExitCode;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Picture {
    Png,
    Svg,
    Stl,
}

/// `ger render`: compile, simulate, write the picture.
pub fn render_part(
    input: &str,
    output: &Path,
    options: &Options,
    picture: &PictureArgs,
) -> ExitCode {
    use ger::render::Scene;
    if input != "-" && same_file(Path::new(input), output) {
        eprintln!("error: the output file is the input file; refusing to overwrite it");
        return ExitCode::from(2);
    }
    let (format, mut render_options) = match picture_request(output, picture) {
        Ok(request) => request,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    let mut clock = Laps::new(options.timings);
    let Some((job, path)) = compiled_path(input, options) else {
        return ExitCode::from(1);
    };
    clock.lap("compile");
    // The cutters the program's own comments describe (CAM headers).
    let text = job.sources.text(job.file);
    render_options.described = ger::render::described::described_tools(text, path.units);
    let scene = match Scene::new(&path, &render_options) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    };
    eprint!("{}", render(&job.sources, &diagnostics_of(&scene.warnings)));
    clock.lap("scene");
    let drawn = Drawn {
        job: &job,
        path: &path,
        scene: &scene,
        options: &render_options,
    };
    let written = match format {
        Picture::Svg => write_svg(&drawn, output, picture),
        Picture::Png | Picture::Stl => {
            let Some(written) =
                write_carved(&drawn, format, input, output, options, picture, &mut clock)
            else {
                return ExitCode::from(1);
            };
            written
        }
    };
    clock.lap("write");
    clock.report();
    match written {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: cannot write `{}`: {e}", output.display());
            ExitCode::from(2)
        }
    }
}

/// A compiled program and the scene it is drawn in.
struct Drawn<'a> {
    job: &'a Job,
    path: &'a ger::toolpath::ToolPath,
    scene: &'a ger::render::Scene,
    options: &'a ger::render::RenderOptions,
}

/// The picture's format (from the output's name) and its options, or what
/// is wrong with the request.
fn picture_request(
    output: &Path,
    picture: &PictureArgs,
) -> Result<(Picture, ger::render::RenderOptions), &'static str> {
    let extension = output
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let format = match extension.as_deref() {
        Some("png") => Picture::Png,
        Some("svg") => Picture::Svg,
        Some("stl") => Picture::Stl,
        _ => return Err("the picture's format comes from the output's name: .png, .svg or .stl"),
    };
    if (picture.shade || picture.diff.is_some() || picture.view.is_some()) && format != Picture::Png
    {
        return Err("--shade, --view and --diff make a PNG: give -o NAME.png");
    }
    if [
        picture.shade,
        picture.diff.is_some(),
        picture.view.is_some(),
    ]
    .iter()
    .filter(|&&on| on)
    .count()
        > 1
    {
        return Err("--shade, --view and --diff each make a picture of their own: give one");
    }
    if picture.toolpath && picture.view.is_none() {
        return Err("--toolpath draws the tool path over a --view picture: give --view too");
    }
    if !(64..=ger::render::view::MAX_SIZE).contains(&picture.size) {
        return Err("--size takes a number of pixels from 64 to 16000");
    }
    let stock = match picture.stock.as_deref().map(parse_stock) {
        None => None,
        Some(Some(size)) => Some(size),
        Some(None) => return Err("--stock takes three positive sizes, X,Y,Z"),
    };
    if picture
        .resolution
        .is_some_and(|r| !(r.is_finite() && r > 0.0))
    {
        return Err("--resolution must be a positive number");
    }
    let render_options = ger::render::RenderOptions {
        resolution: picture.resolution,
        max_cells: picture.max_cells,
        stock,
        described: Vec::new(),
    };
    Ok((format, render_options))
}

/// The tool path as an SVG drawing, each segment titled with its line.
fn write_svg(drawn: &Drawn, output: &Path, picture: &PictureArgs) -> std::io::Result<()> {
    use ger::render::svg;
    let sources = &drawn.job.sources;
    let title = |span: ger::source::Span| {
        let text = sources.text(span.file_id()).get(span.range()).unwrap_or("");
        let text: String = text.trim().chars().take(80).collect();
        format!("line {}: {text}", span.line)
    };
    let svg_options = svg::SvgOptions {
        color: match picture.color {
            ColorArg::Depth => svg::ColorBy::Depth,
            ColorArg::Feed => svg::ColorBy::Feed,
            ColorArg::Tool => svg::ColorBy::Tool,
        },
        rapids: picture.rapids == RapidsArg::Show,
    };
    write_file(output, |out| {
        svg::write(drawn.path, drawn.scene, svg_options, &title, out)
    })
}

/// The stock carved by the tool path, written as a PNG (depth, shaded or
/// the difference from `--diff`'s program) or an STL mesh. `None` when it
/// cannot be carved (the error is printed).
fn write_carved(
    drawn: &Drawn,
    format: Picture,
    input: &str,
    output: &Path,
    options: &Options,
    picture: &PictureArgs,
    clock: &mut Laps,
) -> Option<std::io::Result<()>> {
    use ger::render::{image, stl};
    let mut grid = match drawn.scene.grid() {
        Ok(grid) => grid,
        Err(e) => {
            eprintln!("error: {e}");
            return None;
        }
    };
    if let Some(note) = &drawn.scene.coarser {
        eprintln!("note: {note}");
    }
    let other = match &picture.diff {
        Some(other) => Some(carve_other(other, &grid, options, drawn.options)?),
        None => None,
    };
    clock.lap("grid");
    let cuts = drawn.scene.carve(&mut grid, drawn.path, &progress_bar());
    eprint!("{}", render(&drawn.job.sources, &diagnostics_of(&cuts)));
    clock.lap("carve");
    let units = drawn.scene.units;
    Some(match (format, other) {
        (Picture::Stl, _) => {
            let mesh = stl::mesh(&grid);
            if mesh.block > 1 {
                eprintln!(
                    "note: the mesh takes the lowest of each {0}x{0} cells (a surface of more than {1} runs of one height)",
                    mesh.block,
                    stl::MAX_RUNS
                );
            }
            if mesh.raised > 0 {
                eprintln!(
                    "note: {} cells raised to the height beside them, where two columns met only along an edge",
                    mesh.raised
                );
            }
            write_file(output, |out| stl::write(&mesh, out))
        }
        (_, Some(other)) => {
            let tolerance = grid.frame.cell * 0.01;
            write_file(output, |out| {
                image::write_difference(&grid, &other, tolerance, units, out)
            })
            .map(|(differ, largest)| {
                if differ == 0 {
                    eprintln!("note: the two programs cut the same part");
                } else {
                    eprintln!(
                        "note: {differ} cells differ, by up to {} (red: `{input}` cuts deeper; blue: the other)",
                        ger::render::length(largest, units)
                    );
                }
            })
        }
        (_, None) if picture.shade => write_file(output, |out| {
            image::write_shaded(&grid, units, picture.size, out)
        }),
        (_, None) if picture.view.is_some() => {
            use ger::render::view::{self, View};
            let side = match picture.view {
                Some(ViewArg::Top) => View::Top,
                Some(ViewArg::Front) => View::Front,
                Some(ViewArg::Side) => View::Side,
                Some(ViewArg::Iso) | None => View::Iso,
            };
            let lines = match picture.toolpath {
                true => view::path_lines(drawn.path, units),
                false => Vec::new(),
            };
            write_file(output, |out| {
                view::write(&grid, units, side, picture.size, &lines, out)
            })
        }
        (_, None) => write_file(output, |out| image::write_depth(&grid, units, out)),
    })
}

/// `--diff`'s program carved in a copy of `grid`; `None` when it cannot be
/// (the error is printed).
fn carve_other(
    other: &str,
    grid: &ger::render::carve::Grid,
    options: &Options,
    render_options: &ger::render::RenderOptions,
) -> Option<ger::render::carve::Grid> {
    let (other_job, other_path) = compiled_path(other, options)?;
    let text = other_job.sources.text(other_job.file);
    let render_options = ger::render::RenderOptions {
        described: ger::render::described::described_tools(text, other_path.units),
        ..render_options.clone()
    };
    let other_scene = match ger::render::Scene::new(&other_path, &render_options) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("error: {other}: {e}");
            return None;
        }
    };
    let mut other_grid = grid.clone();
    let cuts = other_scene.carve(&mut other_grid, &other_path, &progress_bar());
    eprint!("{}", render(&other_job.sources, &diagnostics_of(&cuts)));
    Some(other_grid)
}

/// `--timings` for a render: the time of each step, on stderr.
struct Laps {
    on: bool,
    started: std::time::Instant,
    last: std::time::Instant,
    laps: Vec<(&'static str, std::time::Duration)>,
}

impl Laps {
    fn new(on: bool) -> Laps {
        let now = std::time::Instant::now();
        Laps {
            on,
            started: now,
            last: now,
            laps: Vec::new(),
        }
    }

    fn lap(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        self.laps.push((name, now - self.last));
        self.last = now;
    }

    fn report(&self) {
        if self.on {
            for (name, took) in &self.laps {
                eprintln!("{name:>8}: {:8.2} ms", took.as_secs_f64() * 1e3);
            }
            eprintln!(
                "   total: {:8.2} ms",
                self.started.elapsed().as_secs_f64() * 1e3
            );
        }
    }
}

fn diagnostics_of(warnings: &[ger::render::RenderWarning]) -> Vec<ger::diagnostic::Diagnostic> {
    warnings.iter().map(|w| w.to_diagnostic()).collect()
}

/// `X,Y,Z`, each positive.
pub fn parse_stock(text: &str) -> Option<[f64; 3]> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
        })
        .collect::<Option<_>>()?;
    values.try_into().ok()
}

/// Compile `input` to its tool path, printing the diagnostics; `None` when
/// it has errors.
fn compiled_path(input: &str, options: &Options) -> Option<(Job, ger::toolpath::ToolPath)> {
    let mut job = load(input, options, None).ok()?;
    // The picture draws the tip: tool length offsets do not move it.
    job.options.lower.tip_path = true;
    let (path, diagnostics) = job.tool_path();
    eprint!("{}", render(&job.sources, &diagnostics));
    Some((job, path?))
}

/// The progress of a render, on stderr once it has run a second, and only
/// on a terminal.
fn progress_bar() -> impl Fn(usize, usize) + Sync {
    use std::io::IsTerminal;
    let terminal = std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let bar = indicatif::ProgressBar::hidden();
    move |done, total| {
        if !terminal || started.elapsed() < std::time::Duration::from_secs(1) {
            return;
        }
        if bar.is_hidden() {
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("carving {bar:40} {percent:>3}% {eta}")
            {
                bar.set_style(style);
            }
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        if done == total {
            bar.finish_and_clear();
        }
    }
}
