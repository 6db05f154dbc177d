//! What a ray costs through a built tree: the bounds on a render's time
//! (the GPU's watchdog, the CPU's bound on its work) are taken from the
//! tree that was built, not from the tree a good scene would have. A
//! million identical faces cannot be split: every box overlaps every
//! other, and a ray tests them all.

use glam::DVec3;

use super::bvh::{Bvh, Child};
use crate::base::aabb::Aabb;

fn area((lo, hi): ([f32; 3], [f32; 3])) -> f64 {
    let v = |c: [f32; 3]| DVec3::new(c[0].into(), c[1].into(), c[2].into());
    Aabb {
        lo: v(lo),
        hi: v(hi),
    }
    .half_area()
}

impl Bvh {
    /// The node visits and primitive tests a ray that crosses the root's
    /// box makes on average, by the surface-area measure (a ray through a
    /// box crosses a box inside it with the ratio of their areas): about
    /// 10–60 for the scenes here, the primitive count where every box
    /// overlaps. Where the root's box is flat (every primitive in one
    /// plane), every box counts in full.
    pub fn ray_cost(&self) -> f64 {
        let Some(root) = self.nodes.first() else {
            return 0.0;
        };
        let root_area: f64 = (0..4)
            .filter(|&k| root.child[k] != super::bvh::EMPTY)
            .map(|k| area(root.child_box(k)))
            .fold(0.0, f64::max);
        let share = |b| {
            if root_area > 0.0 {
                (area(b) / root_area).min(1.0)
            } else {
                1.0
            }
        };
        let mut cost = 0.0;
        let mut stack = vec![(0usize, 1.0f64)];
        while let Some((index, p)) = stack.pop() {
            // A visit tests the node's four boxes: one visit.
            cost += p;
            let node = &self.nodes[index];
            for k in 0..4 {
                match Child::of(node.child[k]) {
                    Child::Inner(i) => stack.push((i, share(node.child_box(k)))),
                    Child::Leaf(_, range) => cost += share(node.child_box(k)) * range.len() as f64,
                    Child::Empty => {}
                }
            }
        }
        cost
    }
}

#[cfg(test)]
mod tests {
    use crate::accel::bvh::build;
    use crate::base::aabb::Aabb;
    use glam::DVec3;

    fn unit_box(at: DVec3) -> Aabb {
        Aabb {
            lo: at - 0.5,
            hi: at + 0.5,
        }
    }

    #[test]
    fn identical_boxes_cost_their_count_and_a_grid_its_logarithm() {
        let same: Vec<Aabb> = (0..4096).map(|_| unit_box(DVec3::ZERO)).collect();
        let cost = build(&same, &vec![0; same.len()]).ray_cost();
        assert!(cost >= 4096.0, "{cost}");
        let grid: Vec<Aabb> = (0..4096)
            .map(|i| {
                unit_box(DVec3::new(
                    (i % 16) as f64 * 2.0,
                    (i / 16 % 16) as f64 * 2.0,
                    (i / 256) as f64 * 2.0,
                ))
            })
            .collect();
        let cost = build(&grid, &vec![0; grid.len()]).ray_cost();
        assert!(cost < 200.0, "{cost}");
    }
}
