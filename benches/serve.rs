//! `cargo bench --bench serve [-- --runs N]`: for seed-fig4 and seed-fig5 at
//! 800x600, the time from a saved edit (a material's colour, the file
//! renamed over as an editor saves) to the new GPU image on `glint serve`'s
//! page in headless Chromium (the image's `load` event), against the wall
//! time of a `glint render` process of the same scene. Each edit waits for
//! the previous one's reference and verdict, so that the background
//! reference does not share the cores with the render it times. The goal: at
//! most 1.5 times render's time plus 100 ms.

// The tests' own driver of the page, whose other helpers this leaves unused.
#[allow(dead_code)]
#[path = "../tests/common/page.rs"]
mod page;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use page::{first_material, recolour, scene_copy, Browser, Served};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn now_ms() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .expect("after 1970")
        .as_secs_f64()
        * 1e3
}

const SIZE: &[&str] = &["--width", "800", "--height", "600"];

/// Wall times of `glint render SCENE` at 800x600, its shader cached.
fn render_times(scene: &Path, out: &Path, runs: usize) -> Vec<f64> {
    (0..=runs)
        .map(|_| {
            let start = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_glint"))
                .arg("render")
                .arg(scene)
                .args(SIZE)
                .arg("-o")
                .arg(out)
                .output()
                .expect("glint render");
            assert!(
                status.status.success(),
                "{}",
                String::from_utf8_lossy(&status.stderr)
            );
            start.elapsed().as_secs_f64()
        })
        // The first compiles and caches the shader.
        .skip(1)
        .collect()
}

/// Seconds from each of `runs` saved edits to its image on the page.
fn edit_to_page(scene: &Path, tmp: &Path, runs: usize) -> Vec<f64> {
    let served = Served::start(scene, SIZE, tmp);
    let mut b = Browser::open(&served.url);
    b.until(
        "document.body.dataset.judged === 'yes'",
        "the first judged render",
    );
    let material = first_material(scene);
    let colours = ["0.9, 0.1, 0.6", "0.1, 0.8, 0.3"];
    (0..runs)
        .map(|i| {
            let generation = i + 2;
            std::thread::sleep(Duration::from_millis(200));
            let edited = now_ms();
            recolour(scene, &material, colours[i % 2]);
            b.until(
                &format!("window.shown['{generation}'] !== undefined"),
                "the edited image",
            );
            let shown = b.eval(&format!("window.shown['{generation}']")).as_f64().unwrap();
            b.until(
                &format!("document.body.dataset.judged === 'yes' && document.body.dataset.generation === '{generation}'"),
                "its verdict",
            );
            (shown - edited) / 1e3
        })
        .collect()
}

fn main() {
    let mut runs = 5;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--runs" {
            runs = args.next().and_then(|n| n.parse().ok()).unwrap_or(runs);
        }
    }
    println!("scene        render (process)  edit to page   ratio   goal (1.5 x render + 0.1 s)");
    for name in ["seed-fig4.toml", "seed-fig5.toml"] {
        let dir = tempfile::tempdir().unwrap();
        let tmp = dir.path().join("tmp");
        std::fs::create_dir(&tmp).unwrap();
        let scene = scene_copy(dir.path(), name);
        let render = median(render_times(&scene, &dir.path().join("x.png"), runs));
        let page = median(edit_to_page(&scene, &tmp, runs));
        let goal = 1.5 * render + 0.1;
        println!(
            "{:<12} {:>10.3} s {:>13.3} s {:>8.2}   {:.3} s: {}",
            name.trim_end_matches(".toml"),
            render,
            page,
            page / render,
            goal,
            if page <= goal { "met" } else { "not met" }
        );
    }
    println!("(medians of {runs}; render's shader cached; each edit after the last one's verdict)");
}
