//! The tables read (src/accel/tables.rs says what they are): the CPU's
//! twin of shaders/tables.glsl, a shadow or eye ray's list or the walk.

use super::{Grid, GridForm, Tables, WALK};
use crate::base::real::{Real, Vec3};

/// What a ray reads: a list to scan, with the bound that ends it, or the
/// walk.
pub enum Lookup<R> {
    Walk,
    /// The entries' range in `Tables::entries`; the scan ends at the first
    /// entry whose key is over `bound` (and, for a nearest hit, over the
    /// nearest so far with `KEY_SLACK`).
    List(std::ops::Range<usize>, R),
}

/// The slack on a perspective key's bound: far beyond the rounding of a
/// distance.
pub const KEY_SLACK: f64 = 1.0 + 1.0 / 4096.0;

impl Tables {
    /// The entries of the cell at (a, b) of `g`; None where it walks.
    fn cell_of<R: Real>(&self, g: &Grid, a: R, b: R) -> Option<std::ops::Range<usize>> {
        let index = |x: R, x0: f32, s: f32, n: u32| -> u32 {
            let c = ((x - R::of(x0.into())) * R::of(s.into())).floor();
            let c = c.max(R::zero()).min(R::of(f64::from(n - 1)));
            c.to_f64() as u32
        };
        let i = index(a, g.a0, g.sa, g.na);
        let j = index(b, g.b0, g.sb, g.nb);
        let cell = self.cells[(g.first_cell + j * g.na + i) as usize];
        let first = cell.first as usize;
        (cell.count != WALK).then(|| first..first + cell.count as usize)
    }

    fn row<R: Real>(g: &Grid, k: usize, v: Vec3<R>) -> R {
        let r = g.rows[k];
        Vec3::new(R::of(r[0].into()), R::of(r[1].into()), R::of(r[2].into())).dot(v)
    }

    /// A perspective grid's cell for direction `d`; None behind its apex.
    fn perspective<R: Real>(&self, g: &Grid, d: Vec3<R>) -> Option<std::ops::Range<usize>> {
        let lam = Self::row(g, 0, d);
        if lam.is_nan() || lam <= R::zero() {
            return None;
        }
        self.cell_of(g, Self::row(g, 1, d) / lam, Self::row(g, 2, d) / lam)
    }

    /// What a shadow ray from `p` to light `light` (unit direction `l`, at
    /// distance `dist`) reads: None where the light has no buffer, so that
    /// no cell is read.
    pub fn shadow<R: Real>(
        &self,
        light: usize,
        p: Vec3<R>,
        l: Vec3<R>,
        dist: R,
    ) -> Option<Lookup<R>> {
        let first = self.lights.get(light).copied().flatten()? as usize;
        let g = &self.grids[first];
        let list = match g.form {
            GridForm::Perspective => {
                let d = -l;
                let within = dist <= R::of(g.reach.into());
                within
                    .then(|| self.perspective(&self.grids[first + cube_face(d)], d))
                    .flatten()
                    .map(|r| Lookup::List(r, dist * R::of(KEY_SLACK)))
            }
            GridForm::Parallel => {
                let big = p.x.abs().max(p.y.abs()).max(p.z.abs());
                let within = big <= R::of(g.reach.into());
                within
                    .then(|| self.cell_of(g, Self::row(g, 1, p), Self::row(g, 2, p)))
                    .flatten()
                    .map(|r| Lookup::List(r, -Self::row(g, 0, p)))
            }
        };
        Some(list.unwrap_or(Lookup::Walk))
    }

    /// What an eye ray of direction `d` reads: None where the eye has no
    /// tiles. A list has no bound of its own (infinity): a nearest-hit scan
    /// ends beyond its nearest hit so far (`KEY_SLACK`).
    pub fn eye<R: Real>(&self, d: Vec3<R>) -> Option<Lookup<R>> {
        let g = &self.grids[self.eye? as usize];
        let range = self.perspective(g, d);
        Some(range.map_or(Lookup::Walk, |r| Lookup::List(r, R::infinity())))
    }
}

/// The face of the direction cube that `d` leaves through: the axis of its
/// largest component (ties to the earlier axis), then its sign.
pub fn cube_face<R: Real>(d: Vec3<R>) -> usize {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let axis = if x >= y && x >= z {
        0
    } else if y >= z {
        1
    } else {
        2
    };
    let c = [d.x, d.y, d.z][axis];
    2 * axis + usize::from(c < R::zero())
}
