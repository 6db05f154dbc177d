use super::*;
use crate::accel::spans::f32_down;
use crate::base::real::Vec3;

#[test]
fn f32_down_never_rounds_up() {
    for x in [0.1, 1.0 / 3.0, -0.7, 1e-30, 3.0, 1e38] {
        let f = f32_down(x);
        assert!(f64::from(f) <= x, "{x}");
        assert!(f64::from(f.next_up()) > x, "{x}");
    }
}

#[test]
fn a_direction_leaves_through_the_face_of_its_largest_component() {
    let v = |x: f64, y: f64, z: f64| Vec3::<f64>::new(x, y, z);
    assert_eq!(cube_face(v(1.0, 0.5, -0.5)), 0);
    assert_eq!(cube_face(v(-1.0, 0.5, -0.5)), 1);
    assert_eq!(cube_face(v(0.1, 0.5, -0.2)), 2);
    assert_eq!(cube_face(v(0.1, -0.5, -0.2)), 3);
    assert_eq!(cube_face(v(0.1, 0.2, 0.3)), 4);
    assert_eq!(cube_face(v(0.1, 0.2, -0.3)), 5);
    // A tie goes to the earlier axis.
    assert_eq!(cube_face(v(0.5, 0.5, 0.5)), 0);
}
