//! `cargo bench --bench render [-- SCENE... --runs N]`: per scene, the median
//! of N warm renders on the GPU with the scene's own shader variant and with
//! the generic shader (upload + dispatch + readback; device, shader compile
//! and pipeline apart, and a first render apart, which on lavapipe includes
//! the LLVM compile of the shader), and on the CPU in f32 and f64, with the
//! GPU's error against CPU f64.

use std::path::PathBuf;
use std::time::Instant;

use glint::gpu::{GpuOptions, Renderer};
use glint::raster::diff;
use glint::scene::{Overrides, Scene};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let mut scenes = Vec::new();
    let mut runs = 5;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--runs" => runs = args.next().and_then(|n| n.parse().ok()).unwrap_or(runs),
            "--bench" => {}
            other => scenes.push(PathBuf::from(other)),
        }
    }
    if scenes.is_empty() {
        let mut all: Vec<_> = std::fs::read_dir("scenes")?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        all.sort();
        scenes = all;
    }
    let mut options = GpuOptions::from_env(None);
    // GLINT_SHADER_DIR: measure a modified shader without rebuilding.
    options
        .include_dirs
        .extend(std::env::var_os("GLINT_SHADER_DIR").map(PathBuf::from));
    let mut own = Renderer::new(&options)?;
    let mut generic = Renderer::new(&GpuOptions {
        settings: glint::gpu::RenderSettings {
            generic: true,
            ..options.settings
        },
        ..options
    })?;
    let info = own.device_info();
    println!(
        "device: {} ({})   cpu threads: {}   runs: {runs}",
        info.name,
        info.driver,
        rayon::current_num_threads()
    );
    println!(
        "{:<20} {:>8} {:>8} {:>8} {:>8} {:>9} {:>8} {:>8} {:>9} {:>9}",
        "scene",
        "compile",
        "1st gpu",
        "gpu f32",
        "generic",
        "own/gen",
        "cpu f32",
        "cpu f64",
        "cpu32/gpu",
        "gpu rmse"
    );
    for path in &scenes {
        let scene = Scene::load(path, &Overrides::default())?;
        // The first render: preparing (less the compile, shown apart: the
        // driver's own compile at the first dispatch stays in) and rendering.
        let t = Instant::now();
        let mut own_scene = own.prepare(&scene, &own.settings())?;
        let first_render = own_scene.render(None, &|_| {})?;
        let setup = first_render.times.setup;
        let compile = setup.compile_s + setup.pipeline_s;
        let first = t.elapsed().as_secs_f64() - compile;
        let mut generic_scene = generic.prepare(&scene, &generic.settings())?;
        let gpu_img = first_render.image;
        generic_scene.render(None, &|_| {})?;
        let (mut g, mut gen, mut c32, mut c64) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut reference = None;
        for _ in 0..runs {
            g.push(own_scene.render(None, &|_| {})?.times.total_s());
            gen.push(generic_scene.render(None, &|_| {})?.times.total_s());
            let t = Instant::now();
            let _ = glint::cpu::render::<f32>(&scene);
            c32.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            reference = Some(glint::cpu::render::<f64>(&scene));
            c64.push(t.elapsed().as_secs_f64());
        }
        let err = diff::figures(&gpu_img, reference.as_ref().expect("runs >= 1"))?;
        let (g, gen, f32_s, f64_s) = (median(g), median(gen), median(c32), median(c64));
        let name = path.file_stem().unwrap_or_default().to_string_lossy();
        println!(
            "{name:<20} {compile:>7.3}s {first:>7.3}s {g:>7.3}s {gen:>7.3}s {:>8.2}x {f32_s:>7.3}s {f64_s:>7.3}s {:>8.2}x {:>9.2e}",
            g / gen,
            f32_s / g,
            err.rmse
        );
    }
    Ok(())
}
