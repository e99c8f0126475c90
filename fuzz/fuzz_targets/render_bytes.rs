//! Arbitrary bytes as a program, drawn: compiled to a tool path, carved
//! into a small grid, written as PNG, SVG and STL. ger must not panic,
//! hang or run out of memory; it draws or reports.
#![no_main]

use ger::driver::{tool_path, CompileOptions};
use ger::eval::EvalOptions;
use ger::render::{image, stl, svg, view, RenderOptions, Scene};
use ger::source::{decode, Sources};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = decode(bytes.to_vec()) else { return };
    let mut sources = Sources::new();
    let file = sources.add("fuzz.egc", text);
    let mut options = CompileOptions {
        eval: EvalOptions {
            max_iterations: 10_000,
            max_statements: 20_000,
            ..EvalOptions::default()
        },
        ..CompileOptions::default()
    };
    options.lower.tip_path = true;
    let Some(path) = tool_path(&sources, file, &options, None).0 else { return };
    // A small grid keeps each run short; the limits themselves are tested.
    let render = RenderOptions {
        max_cells: 20_000,
        ..RenderOptions::default()
    };
    let Ok(scene) = Scene::new(&path, &render) else { return };
    let mut out = Vec::new();
    let _ = svg::write(&path, &scene, svg::SvgOptions::default(), &|_| String::new(), &mut out);
    let Ok(mut grid) = scene.grid() else { return };
    let _ = scene.carve(&mut grid, &path, &|_, _| {});
    let _ = image::write_depth(&grid, scene.units, &mut out);
    let _ = image::write_shaded(&grid, scene.units, 200, &mut out);
    let _ = view::write(&grid, scene.units, view::View::Iso, 200, &[], &mut out);
    let _ = stl::write(&stl::mesh(&grid), &mut out);
});
