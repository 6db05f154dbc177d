//! Cylinders and cones (docs/scene-format.md, Cylinders and cones): the
//! scene renders alike on both renderers, and bad tables are named. The
//! intersect's own tests are unit tests (src/prim/cylinder_tests.rs).

mod common;

#[cfg(feature = "gpu")]
use glint::cpu;
#[cfg(feature = "gpu")]
use glint::raster::diff::figures;

/// scenes/cylinders.toml: the GPU and the CPU f32 agree with the f64
/// reference, and a cylinder moved by a tenth of its radius fails the check.
#[test]
#[cfg(feature = "gpu")]
fn the_cylinders_scene_agrees_and_a_moved_cylinder_does_not() {
    let path = common::repo().join("scenes/cylinders.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = common::scene_sized(&text, 200, 150);
    let reference = cpu::render::<f64>(&scene);
    let gpu = common::render_gpu(&scene);
    let tolerance = glint::raster::diff::Tolerance::default();
    let f = figures(&gpu, &reference).unwrap();
    assert!(tolerance.violations(&f).is_empty(), "{f:?}");
    let moved = common::scene_sized(
        &text.replace("base = [2.6, -1.0, 0.5]", "base = [2.65, -1.0, 0.5]"),
        200,
        150,
    );
    let f = figures(&cpu::render::<f64>(&moved), &reference).unwrap();
    assert!(!tolerance.violations(&f).is_empty(), "{f:?}");
}

#[test]
fn bad_cylinders_are_named() {
    let head = "[image]\nwidth = 8\nheight = 8\n[camera]\neye = [0.0, 0.0, 5.0]\n\
                look_at = [0.0, 0.0, 0.0]\nvfov = 40.0\n[materials.m]\ndiffuse = [1.0, 1.0, 1.0]\n";
    for (table, key, words) in [
        (
            "base = [0, 0, 0]\nbase_radius = 1.0\napex = [0, 0, 0]\napex_radius = 1.0\n",
            "cylinders[0].apex",
            "no length",
        ),
        (
            "base = [0, 0, 0]\nbase_radius = -1.0\napex = [0, 1, 0]\napex_radius = 1.0\n",
            "cylinders[0].base_radius",
            "from 0",
        ),
        (
            "base = [0, 0, 0]\nbase_radius = 0.0\napex = [0, 1, 0]\napex_radius = 0.0\n",
            "cylinders[0].base_radius",
            "both 0",
        ),
        (
            "base = [0, 0, 0]\nbase_radius = 1.0\napex = [0, 1, 0]\nradius = 1.0\n",
            "cylinders[0]",
            "unknown field",
        ),
    ] {
        let text = format!("{head}[[cylinders]]\n{table}material = \"m\"\n");
        let msg =
            match glint::scene::parse(&text, std::path::Path::new("bad.toml"), &Default::default())
            {
                Ok(_) => panic!("accepted:\n{text}"),
                Err(e) => e.to_string(),
            };
        assert!(msg.contains("bad.toml:"), "{msg}");
        assert!(msg.contains(key), "expected {key}: {msg}");
        assert!(msg.contains(words), "expected {words:?}: {msg}");
    }
}
