//! A scene whose image follows from docs/scene-format.md, Shading by hand: the eye at the centre
//! of a sphere of radius R with a point light there too. Every eye ray meets
//! the sphere at distance R facing the light head on: N·L = N·H = 1,
//! att = 1/(c + l R + q R²), no shadow (the shadow ray's only hit is the far
//! side, at 2R > R), so local = att (Ia Ka + Id Kd + Is Ks). Each reflection
//! goes back through the centre to the opposite side, which looks the same:
//! the pixel is local (1 + kr + ... + kr^(depth-1)).

mod common;

use glint::cpu;

const R: f64 = 3.0;
const KA: [f64; 3] = [0.1, 0.2, 0.3];
const KD: [f64; 3] = [0.5, 0.4, 0.3];
const KS: [f64; 3] = [0.2, 0.25, 0.3];
const IA: [f64; 3] = [0.5, 0.4, 0.3];
const ID: [f64; 3] = [1.0, 0.9, 0.8];
const IS: [f64; 3] = [0.7, 0.8, 0.9];
const ATT: [f64; 3] = [1.0, 0.1, 0.01];
const KR: f64 = 0.5;

fn scene_text(depth: u32, shadows: bool) -> String {
    let v = |a: [f64; 3]| format!("[{}, {}, {}]", a[0], a[1], a[2]);
    format!(
        r#"
[image]
width = 40
height = 30
[render]
max_depth = {depth}
shadows = {shadows}
[camera]
eye = [0.0, 0.0, 0.0]
screen_center = [0.0, 0.0, -1.0]
screen_right = [1.0, 0.0, 0.0]
screen_up = [0.0, 0.75, 0.0]
[materials.m]
ambient = {ka}
diffuse = {kd}
specular = {ks}
shininess = 50.0
reflectivity = {KR}
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = {R}
material = "m"
[[lights]]
type = "point"
position = [0.0, 0.0, 0.0]
ambient = {ia}
diffuse = {id}
specular = {is}
attenuation = {att}
"#,
        ka = v(KA),
        kd = v(KD),
        ks = v(KS),
        ia = v(IA),
        id = v(ID),
        is = v(IS),
        att = v(ATT),
    )
}

fn expected(depth: u32) -> [f64; 3] {
    let att = 1.0 / (ATT[0] + ATT[1] * R + ATT[2] * R * R);
    let series: f64 = (0..depth).map(|k| KR.powi(k as i32)).sum();
    [0, 1, 2].map(|c| att * (IA[c] * KA[c] + ID[c] * KD[c] + IS[c] * KS[c]) * series)
}

#[test]
fn eye_and_light_at_the_centre_of_a_sphere() {
    for (depth, shadows) in [(1, true), (3, true), (3, false), (8, true)] {
        let scene = common::scene(&scene_text(depth, shadows));
        let want = expected(depth);
        // f64 agrees to its own rounding (and the final cast to f32); f32 to
        // a few ulp per operation along the ray.
        common::assert_uniform(&cpu::render::<f64>(&scene), want, 1e-7, "CPU f64");
        common::assert_uniform(&cpu::render::<f32>(&scene), want, 1e-5, "CPU f32");
        #[cfg(feature = "gpu")]
        common::assert_uniform(&common::render_gpu(&scene), want, 1e-5, "GPU f32");
    }
}

#[test]
fn the_hand_value_is_not_trivial() {
    // Guards the test above against a scene that renders black and a
    // formula that gives black too.
    let want = expected(3);
    assert!(want.iter().all(|c| *c > 0.1));
    let image = cpu::render::<f64>(&common::scene(&scene_text(3, true)));
    assert_ne!(image.pixels[0], [0.0; 3]);
}
