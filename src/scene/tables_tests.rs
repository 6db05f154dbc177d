use glam::DVec3;

use crate::accel::scene_bvh;
use crate::accel::tables::{build, device_bytes, leaves, LightSpec, Lookup};
use crate::base::real::Vec3;
use crate::scene::{Overrides, Scene};

fn scene(text: &str) -> Scene {
    super::super::parse(text, std::path::Path::new("t.toml"), &Overrides::default()).unwrap()
}

/// 64 small spheres in a ring around a point light, and a directional one.
fn ring() -> Scene {
    let mut text = String::from(
        "[image]\nwidth = 32\nheight = 24\n[camera]\neye = [0, 2, 12]\nlook_at = [0, 0, 0]\nvfov = 50\n\
         [materials.m]\ndiffuse = [1, 1, 1]\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\ndiffuse = [1, 1, 1]\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0.3, -1, 0.2]\ndiffuse = [1, 1, 1]\n",
    );
    for i in 0..64 {
        let a = f64::from(i) * std::f64::consts::TAU / 64.0;
        text += &format!(
            "[[spheres]]\ncenter = [{}, {}, {}]\nradius = 0.2\nmaterial = \"m\"\n",
            4.0 * a.cos(),
            (f64::from(i) * 0.37).sin(),
            4.0 * a.sin()
        );
    }
    scene(&text)
}

/// Every leaf a ray from the light's side can meet is in the list the ray
/// reads: for rays towards many points around the ring, the leaves whose
/// spheres the segment meets (sampled densely) are all listed, with keys
/// under the bound.
#[test]
fn the_lists_hold_every_leaf_a_shadow_ray_crosses() {
    let s = ring();
    let tree = scene_bvh(&s.prims);
    let t = s.tables(&tree, glam::DVec3::ZERO, (32, 24)).unwrap();
    assert_eq!(t.lights.len(), 2);
    assert!(t.lights.iter().all(Option::is_some) && t.eye.is_some());
    let all = leaves(
        &tree,
        &crate::accel::prim_boxes(&s.prims, glam::DVec3::ZERO),
        &s.prims.relative_hulls(glam::DVec3::ZERO),
    );
    let light = DVec3::ZERO;
    let mut listed_somewhere = 0;
    for k in 0..2000 {
        let a = f64::from(k) * 0.0137;
        let p = DVec3::new(6.0 * a.cos(), (a * 3.1).sin() * 0.8, 6.0 * a.sin());
        let to = light - p;
        let dist = to.length();
        let l = to / dist;
        let pr = Vec3::<f64>::of(p);
        let lr = Vec3::<f64>::of(l);
        let Some(Lookup::List(range, bound)) = t.shadow(0, pr, lr, dist) else {
            continue;
        };
        let listed: Vec<u32> = t.entries[range.clone()]
            .iter()
            .filter(|e| f64::from(e.key) <= bound)
            .map(|e| e.leaf)
            .collect();
        listed_somewhere += listed.len();
        for leaf in &all {
            // The ring's spheres: a leaf's hull is its sphere.
            let &[(c, r)] = leaf.hull.balls() else {
                panic!("a sphere's hull is one ball");
            };
            let meets = (0..=400).any(|i| {
                let q = p + l * (dist * f64::from(i) / 400.0);
                (q - c).length() <= r
            });
            if meets {
                assert!(
                    listed.contains(&leaf.word),
                    "ray {k} meets leaf {:#x} unlisted",
                    leaf.word
                );
            }
        }
    }
    assert!(listed_somewhere > 0, "no ray read a non-empty list");
}

/// The tables fit the budget they are given: a budget under what the
/// finest resolution takes gets coarser grids that fit it, not more bytes,
/// and one too small for any resolution gets none.
#[test]
fn the_tables_fit_their_budget_or_are_not_built() {
    let s = ring();
    let tree = scene_bvh(&s.prims);
    let lights = [LightSpec {
        position: Some(DVec3::ZERO),
        direction: DVec3::Y,
        casts: true,
    }];
    let boxes = crate::accel::prim_boxes(&s.prims, glam::DVec3::ZERO);
    let hulls = s.prims.relative_hulls(glam::DVec3::ZERO);
    let fine = build(&tree, &boxes, &hulls, &lights, None, 1 << 20).unwrap();
    let fine_bytes = device_bytes(&fine);
    assert!(fine_bytes <= 1 << 20);
    let budget = fine_bytes / 3;
    let coarse = build(&tree, &boxes, &hulls, &lights, None, budget).unwrap();
    assert!(
        device_bytes(&coarse) <= budget,
        "{} > {budget}",
        device_bytes(&coarse)
    );
    assert!(coarse.cells.len() < fine.cells.len());
    assert!(build(&tree, &boxes, &hulls, &lights, None, 16).is_none());
}
