//! Refraction (docs/scene-format.md, Shading), checked against what follows
//! by hand: an ior-1 transmitter is invisible, and total internal
//! reflection keeps a ray inside a sphere with the weight reflectivity +
//! transmittance.

mod common;

use glam::DVec3;
use glint::cpu;
use glint::raster::diff::figures;
use glint::raster::Image;
use glint::scene::Scene;

fn renders(scene: &Scene) -> Vec<(&'static str, Image)> {
    let mut renders = vec![
        ("CPU f64", cpu::render::<f64>(scene)),
        ("CPU f32", cpu::render::<f32>(scene)),
    ];
    renders.extend(common::render_gpu_if_built(scene).map(|image| ("GPU f32", image)));
    renders
}

const BEHIND: &str = r#"
[image]
width = 80
height = 60
[render]
max_depth = 3
shadows = false
background = [0.2, 0.3, 0.4]
[camera]
eye = [0.0, 0.5, 6.0]
look_at = [0.0, 0.0, 0.0]
vfov = 40.0
[materials.red]
ambient = [0.1, 0.02, 0.02]
diffuse = [0.7, 0.1, 0.1]
specular = [0.5, 0.5, 0.5]
shininess = 20.0
[materials.floor]
diffuse = [0.5, 0.5, 0.5]
[[spheres]]
center = [0.3, 0.0, -3.0]
radius = 1.2
material = "red"
[[planes]]
point = [0.0, -1.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"
[[lights]]
type = "point"
position = [3.0, 5.0, 4.0]
ambient = [0.3, 0.3, 0.3]
diffuse = [0.9, 0.9, 0.9]
specular = [0.9, 0.9, 0.9]
"#;

/// `BEHIND` with a sphere of pure transmitter of index `ior` in front.
fn with_glass(ior: f64) -> Scene {
    common::scene(&format!(
        "{BEHIND}[materials.glass]\ntransmittance = 1.0\nior = {ior}\nshininess = 0.0\n\
         [[spheres]]\ncenter = [0.0, 0.2, 2.0]\nradius = 1.0\nmaterial = \"glass\"\n"
    ))
}

/// A sphere of index 1 that only transmits (no colour of its own, weight 1)
/// passes every ray straight through: the image is the scene behind it. Two
/// of the depth's three hits go to entering and leaving, which leaves one
/// for the scene behind, all it needs (nothing there reflects).
#[test]
fn a_transmitter_of_index_one_leaves_the_image_unchanged() {
    let without = renders(&common::scene(BEHIND));
    let with = renders(&with_glass(1.0));
    // The rays behind start from the sphere's far side, not the eye: the
    // hit points differ by rounding, f64's near 1e-16 and f32's near 1e-7,
    // which the shading (a specular power of 20) magnifies a little.
    for ((what, a), (_, b)) in without.iter().zip(&with) {
        let f = figures(b, a).unwrap();
        let bound = if *what == "CPU f64" { 1e-9 } else { 1e-4 };
        assert!(f.max_abs < bound, "{what}: {f:?}");
    }
    // The check can fail: glass of index 1.5 bends the scene behind.
    let bent = renders(&with_glass(1.5));
    for ((what, a), (_, b)) in without.iter().zip(&bent) {
        assert!(figures(b, a).unwrap().max_abs > 0.1, "{what}");
    }
}

const IOR: f64 = 2.0;
const KA: f64 = 0.1;
const DEPTH: u32 = 6;
const EYE: [f64; 3] = [0.8, 0.1, 0.0];

/// The eye inside a unit sphere of index 2 that reflects nothing and
/// transmits everything, lit by ambient light alone, on black. A chord of a
/// sphere meets the surface at the same angle at both ends, so a ray that
/// is totally reflected once is totally reflected at every hit, with weight
/// reflectivity + transmittance = 1: it adds Ka at each of the depth's hits.
/// A ray that is not leaves at its first hit into the black: Ka. Total
/// reflection happens where sin θ = h / R > 1/ior, h being the distance of
/// the ray's line from the centre.
#[test]
fn total_internal_reflection_inside_a_sphere() {
    let scene = common::scene(&format!(
        r#"
[image]
width = 64
height = 48
[render]
max_depth = {DEPTH}
shadows = false
background = [0.0, 0.0, 0.0]
[camera]
eye = [{}, {}, {}]
look_at = [0.0, 0.1, -1.0]
vfov = 100.0
[materials.glass]
ambient = [{KA}, {KA}, {KA}]
transmittance = 1.0
ior = {IOR}
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "glass"
[[lights]]
type = "directional"
direction = [0.0, -1.0, 0.0]
ambient = [1.0, 1.0, 1.0]
"#,
        EYE[0], EYE[1], EYE[2]
    ));
    let prepared = cpu::Prepared::<f64>::new(&scene, glint::accel::Accel::None);
    let eye = DVec3::from_array(EYE);
    let mut counts = [0usize; 2];
    for (what, image) in renders(&scene) {
        for y in 0..scene.height {
            for x in 0..scene.width {
                let d = prepared.eye_ray_direction(x, y, 0, 0);
                let h = (eye - d * eye.dot(d)).length();
                let sin = h * IOR;
                if (sin - 1.0).abs() < 1e-3 {
                    continue; // too near the critical angle to call
                }
                let tir = sin > 1.0;
                let want = if tir { KA * f64::from(DEPTH) } else { KA };
                let got = image.pixels[(y * scene.width + x) as usize];
                for c in got {
                    assert!(
                        (f64::from(c) - want).abs() < 1e-5,
                        "{what}: pixel ({x}, {y}): {c} against {want} (total reflection: {tir})"
                    );
                }
                if what == "CPU f64" {
                    counts[usize::from(tir)] += 1;
                }
            }
        }
    }
    // Both cases occur in the image.
    assert!(counts[0] > 100 && counts[1] > 100, "{counts:?}");
}

#[test]
fn transmittance_and_ior_are_checked() {
    let base = BEHIND.replace("[materials.floor]\n", "[materials.floor]\nSETTING\n");
    for (setting, key, words) in [
        (
            "transmittance = 1.5",
            "materials.floor.transmittance",
            "[0, 1]",
        ),
        (
            "transmittance = -0.1",
            "materials.floor.transmittance",
            "[0, 1]",
        ),
        ("ior = 0.0", "materials.floor.ior", "> 0"),
        ("ior = nan", "materials.floor.ior", "finite"),
    ] {
        let text = base.replace("SETTING", setting);
        let err = glint::scene::parse(&text, std::path::Path::new("bad.toml"), &Default::default())
            .expect_err(setting)
            .to_string();
        assert!(err.contains(key) && err.contains(words), "{setting}: {err}");
    }
}
