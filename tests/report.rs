//! `glint report` on small scenes: every file is written, the JSON holds
//! every variant, the reference has no error against itself, f32 has some,
//! every time is positive; and GPU f64 agrees with CPU f64 far closer than f32.

#![cfg(feature = "gpu")]

mod common;

use glint::cpu;
use glint::gpu::{GpuOptions, Precision, RenderSettings, Renderer};
use glint::raster::diff::figures;

#[test]
fn the_quick_report_writes_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::repo().join("scenes/seed-fig4.toml");
    common::cmd()
        .arg("report")
        .arg(&scene)
        .args(["--quick", "-o"])
        .arg(dir.path())
        .assert()
        .success();
    for f in [
        "report.md",
        "report.csv",
        "report.json",
        "error_vs_time.svg",
        "index.html",
        "img/seed-fig4-gpu.png",
        "img/seed-fig4-reference.png",
        "img/seed-fig4-diff.png",
    ] {
        let path = dir.path().join(f);
        assert!(
            std::fs::metadata(&path).is_ok_and(|m| m.len() > 0),
            "{f} missing or empty"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).unwrap())
            .unwrap();
    assert!(json["device"]["name"].as_str().is_some());
    assert!(json["machine"]["cpu"].as_str().is_some());
    let scenes = json["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 1);
    let ms = scenes[0]["measurements"].as_array().unwrap();
    let variant = |name: &str| {
        ms.iter()
            .find(|m| m["variant"] == name)
            .unwrap_or_else(|| panic!("no {name} in {ms:?}"))
    };
    for name in [
        "gpu f32 robust",
        "gpu f32 naive",
        "gpu f64",
        "cpu f32",
        "cpu f64",
    ] {
        let m = variant(name);
        assert!(m["time"]["median_s"].as_f64().unwrap() > 0.0, "{name}");
        assert!(m["time"]["rays_per_s"].as_f64().unwrap() > 0.0, "{name}");
        assert_eq!(m["error"]["nonfinite"], 0, "{name}");
    }
    assert_eq!(variant("cpu f64")["error"]["max_abs"], 0.0);
    assert_eq!(variant("cpu f64")["flip_mean"], 0.0);
    assert!(variant("cpu f32")["error"]["max_abs"].as_f64().unwrap() > 0.0);
    assert!(
        variant("gpu f32 robust")["error"]["max_abs"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(
        variant("gpu f32 robust")["time"]["dispatch_s"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(variant("gpu f32 robust")["setup"]["compile_s"]
        .as_f64()
        .is_some());
    // The generic shader renders the same image as the scene's own variant.
    assert_eq!(
        variant("gpu f32 generic")["error"],
        variant("gpu f32 robust")["error"]
    );
    // The reference is on the Pareto front (nothing is more accurate).
    assert_eq!(variant("cpu f64")["pareto"], true);
    // The CSV has a header and one row per measurement.
    let csv = std::fs::read_to_string(dir.path().join("report.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + ms.len());
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    assert!(html.contains("img/seed-fig4-diff.png") && html.contains("error_vs_time.svg"));
    let svg = std::fs::read_to_string(dir.path().join("error_vs_time.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("Pareto front"));
    // --quick does not measure the sampling axis, so neither its plot nor
    // a link to it is written (an empty front would claim a measurement).
    assert!(!dir.path().join("sampling_vs_time.svg").exists());
    assert!(!html.contains("sampling_vs_time.svg"));
}

#[test]
fn gpu_f64_is_far_closer_to_the_reference_than_f32() {
    let mut scene = common::scene_sized(common::SMALL, 160, 120);
    scene.samples = 2;
    let reference = cpu::render::<f64>(&scene);
    let mut f32r = Renderer::new(&GpuOptions {
        validate: true,
        ..GpuOptions::default()
    })
    .unwrap();
    let mut f64r = Renderer::new(&GpuOptions {
        validate: true,
        settings: RenderSettings {
            precision: Precision::F64,
            ..RenderSettings::default()
        },
        ..GpuOptions::default()
    })
    .unwrap();
    assert!(
        f64r.device_info().shader_float64,
        "lavapipe has shaderFloat64"
    );
    let e32 = figures(&f32r.render(&scene, &|_| {}).unwrap().0, &reference).unwrap();
    let e64 = figures(&f64r.render(&scene, &|_| {}).unwrap().0, &reference).unwrap();
    // f64 differs from the reference only by the f32 specular power and the
    // final rounding to f32.
    assert!(e64.rmse < 1e-6 && e64.max_abs < 1e-4, "{e64:?}");
    assert!(e64.rmse < e32.rmse / 3.0, "f64 {e64:?} against f32 {e32:?}");
}

/// A scene whose name holds a comma and quotes: the CSV quotes the field
/// (it reads back as the name, every row with every column) and the page
/// escapes it.
#[test]
fn names_with_commas_and_quotes_survive_the_csv_and_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let name = "fig,3 \"q\"";
    let scene = dir.path().join(format!("{name}.toml"));
    std::fs::copy(common::repo().join("scenes/seed-fig3.toml"), &scene).unwrap();
    let out = dir.path().join("out");
    let o = common::glint(&[
        "report",
        scene.to_str().unwrap(),
        "--quick",
        "-o",
        out.to_str().unwrap(),
    ]);
    common::assert_ok(&o);
    let mut reader = csv::Reader::from_path(out.join("report.csv")).unwrap();
    let columns = reader.headers().unwrap().len();
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert!(!rows.is_empty());
    for row in &rows {
        assert_eq!(row.len(), columns);
        assert_eq!(&row[0], name);
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("fig,3 &quot;q&quot;") && !html.contains(name));
}

/// `--sampling`: uniform 1x1 to 8x8, the adaptive settings and the
/// contrast settings (Mitchell's test and the range test), each against a
/// converged render; the uniform grids' error falls as they grow (it would
/// not against a wrong reference), and the axis has its own table, plot
/// and CSV rows.
#[test]
fn the_sampling_axis_is_measured_against_a_converged_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::repo().join("scenes/seed-fig3.toml");
    common::cmd()
        .arg("report")
        .arg(&scene)
        .args(["--quick", "--sampling", "--runs", "1", "-o"])
        .arg(dir.path())
        .assert()
        .success();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).unwrap())
            .unwrap();
    let scene = &json["scenes"][0];
    let axis = scene["sampling"].as_array().unwrap();
    let names: Vec<&str> = axis
        .iter()
        .map(|m| m["variant"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "gpu f32 uniform 1x1",
            "gpu f32 uniform 2x2",
            "gpu f32 uniform 4x4",
            "gpu f32 uniform 8x8",
            "gpu f32 adaptive 0.2/2",
            "gpu f32 adaptive 0.1/2",
            "gpu f32 adaptive 0.05/2",
            "gpu f32 adaptive 0.02/3",
            "gpu f32 contrast 0.2/17",
            "gpu f32 contrast 0.1/17",
            "gpu f32 contrast 0.05/17",
            "gpu f32 contrast 0.05/33",
            "gpu f32 range 0.05/17",
            "gpu f32 range 0.05/33",
            "gpu f32 range 0.03/33"
        ]
    );
    let rmse: Vec<f64> = axis
        .iter()
        .map(|m| m["error"]["rmse"].as_f64().unwrap())
        .collect();
    assert!(rmse[..4].windows(2).all(|w| w[1] < w[0]), "{rmse:?}");
    assert!(axis
        .iter()
        .all(|m| m["time"]["median_s"].as_f64().unwrap() > 0.0));
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(
        md.contains("### seed-fig3: the sampling axis, against CPU f64 at 16x16 uniform samples")
    );
    let svg = std::fs::read_to_string(dir.path().join("sampling_vs_time.svg")).unwrap();
    assert!(svg.contains("adaptive sampling") && svg.contains("at 16x16 samples"));
    assert!(svg.contains("contrast sampling") && svg.contains("range test"));
    // The axis's Pareto front is its own, inside the axes (the
    // main plot's front, of other times and errors, was drawn here, off
    // them), and each plot says what it shows. A front of one point (one
    // variant best in both) draws no line, so the check is over whatever
    // lines there are.
    let main = std::fs::read_to_string(dir.path().join("error_vs_time.svg")).unwrap();
    for plot in [&svg, &main] {
        let fronts: Vec<&str> = plot
            .split("<polyline points=\"")
            .skip(1)
            .map(|p| p.split('"').next().unwrap())
            .collect();
        for point in fronts.iter().flat_map(|f| f.split(' ')) {
            let (x, y) = point.split_once(',').unwrap();
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!(
                (80.0..=670.0).contains(&x) && (40.0..=540.0).contains(&y),
                "{point} is off the axes"
            );
        }
    }
    let title = |plot: &str| {
        plot.split("font-size=\"15\">")
            .nth(1)
            .unwrap()
            .split('<')
            .next()
            .unwrap()
            .to_owned()
    };
    assert_ne!(title(&svg), title(&main));
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    assert!(html.contains("sampling_vs_time.svg"));
    let csv = std::fs::read_to_string(dir.path().join("report.csv")).unwrap();
    let ms = scene["measurements"].as_array().unwrap().len();
    assert_eq!(csv.lines().count(), 1 + ms + axis.len());
    assert_eq!(
        csv.lines().filter(|l| l.ends_with(",converged")).count(),
        axis.len()
    );
}
