//! `cargo bench --bench render [-- SCENE... --runs N]`: per scene, the median
//! of N warm renders on the GPU (upload + dispatch + readback; device,
//! shader compile and pipeline apart, and a first render apart, which on
//! lavapipe includes the LLVM compile of the shader) and on the CPU in f32
//! and f64, with the GPU's error against CPU f64.

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
    let mut renderer = Renderer::new(&options)?;
    println!(
        "device: {} ({})   cpu threads: {}   runs: {runs}",
        renderer.device_info().name,
        renderer.device_info().driver,
        rayon::current_num_threads()
    );
    println!(
        "{:<28} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>10}",
        "scene", "compile", "1st gpu", "gpu f32", "cpu f32", "cpu f64", "cpu32/gpu", "gpu rmse"
    );
    for path in &scenes {
        let scene = Scene::load(path, &Overrides::default())?;
        renderer.prepare_for(&scene)?;
        let compile = renderer.setup.compile_s + renderer.setup.pipeline_s;
        let t = Instant::now();
        let (gpu_img, _) = renderer.render(&scene, &|_| {})?;
        let first = t.elapsed().as_secs_f64();
        let mut gpu = Vec::new();
        let mut c32 = Vec::new();
        let mut c64 = Vec::new();
        let mut reference = None;
        for _ in 0..runs {
            gpu.push(renderer.render(&scene, &|_| {})?.1.total_s());
            let t = Instant::now();
            let _ = glint::cpu::render::<f32>(&scene);
            c32.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            reference = Some(glint::cpu::render::<f64>(&scene));
            c64.push(t.elapsed().as_secs_f64());
        }
        let err = diff::figures(&gpu_img, reference.as_ref().expect("runs >= 1"))?;
        let (g, f32_s, f64_s) = (median(gpu), median(c32), median(c64));
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        println!(
            "{name:<28} {compile:>8.3}s {first:>8.3}s {g:>8.3}s {f32_s:>8.3}s {f64_s:>8.3}s {:>8.2}x {:>10.2e}",
            f32_s / g,
            err.rmse
        );
    }
    Ok(())
}
