//! Tables that answer shadow and eye rays without walking the tree: Haines
//! and Greenberg's light buffer ("The Light Buffer: A Shadow-Testing
//! Accelerator", IEEE CG&A 1986) and a screen-tile list (Weghorst, Hooper
//! and Greenberg, "Improved Computational Methods for Ray Tracing", ACM TOG
//! 1984), built once on the host from the BVH's leaves and read by both
//! renderers (shaders/tables.glsl, `cpu::intersect`).
//!
//! Every table is a grid of cells over what a ray's direction (or, for a
//! directional light, its origin) says, each cell a list of the BVH's leaf
//! words whose boxes such a ray can meet, sorted by a key that ends the
//! scan early:
//!
//! - a positioned light has a direction cube: six perspective grids
//!   around the light, one a face; a shadow ray reads the cell of its
//!   direction seen from the light, and stops at the first blocker or at
//!   the first leaf that starts farther from the light than its surface
//!   point;
//! - a directional light has a parallel grid across its direction; a
//!   shadow ray reads the cell of its origin, and stops at the first leaf
//!   that lies wholly behind the origin;
//! - the eye has one perspective grid over the virtual screen, one cell per
//!   tile of pixels; an eye ray reads its tile and stops once its hit is
//!   nearer than the next leaf's near distance.
//!
//! The lists are conservative: each leaf's box is padded by `pad` (2^-14 of
//! the scene's largest coordinate, far beyond what f32 rounding moves a ray
//! within `reach`), and its cell range by 2^-12 of a cell coordinate (far
//! beyond the rounding of the lookup). Where a primitive has a hull
//! (`prim::Hull`: a sphere's ball, a cone's end balls, a triangle's
//! corners), its balls grown by `pad` narrow the box's range and raise its
//! key (`spans::narrowed`): a sphere's range is its tangent cone's, not its
//! box's corners'. So a list holds every leaf that the
//! walk would have found a hit in, any hit ends a shadow ray whichever is
//! found first, and a tie between hits goes to the same primitive (the
//! lower key) in every order: the image is the tree walk's, bit for bit.
//! A cell whose list would be longer than `CELL_CAP`, a shadow ray from
//! beyond the table's reach, and a direction behind a perspective grid fall
//! back to the walk.

use glam::DVec3;

mod build;
mod lookup;

pub use build::build;
#[cfg(test)]
pub(crate) use build::leaves;
// The GPU's layout's alone.
#[cfg_attr(not(feature = "gpu"), allow(unused_imports))]
pub use build::device_bytes;
#[cfg(test)]
use lookup::cube_face;
pub use lookup::{Lookup, KEY_SLACK};

/// A cell's count that says "walk the tree": its list would be too long.
pub const WALK: u32 = u32::MAX;

/// Entries a cell lists at most; a longer list is left to the walk. (8 and
/// 24 walked most of rings' and balls' shadow rays again, and lost their
/// gain; docs/performance.md, Shadow and eye rays from tables.)
pub const CELL_CAP: usize = 96;

/// Pixels on a side of the eye grid's tiles, before the budget doubles
/// them: 2 tested 3.2 primitives an eye ray on tetra where 8 tested 5.5.
pub const TILE: u32 = 2;

/// A light grid's cells a side: this times the square root of the
/// primitives it sees (8 took balls' shadow rays from 8.3 tests and 2.2
/// node visits a ray at 2 to 4.5 tests), at most `MAX_SIDE` for a face of
/// a cube and four times that for a parallel grid.
const LIGHT_SCALE: f64 = 8.0;
const MAX_SIDE: u32 = 256;
/// The build's spans may take this many budgets of host memory; past it
/// the scene has no tables (the walk serves every ray, the same bits).
const WORK_FACTOR: usize = 4;
/// The least a grid takes on the device (`Counted::bytes` of one cell).
const MIN_GRID_BYTES: usize = 88;
/// How many plans are counted at once.
const COUNT_CHUNK: usize = 64;

/// How a grid reads a ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridForm {
    /// Rows take a point to (along, a, b): a directional light's grid.
    Parallel = 0,
    /// Rows take a direction to (λ, μ, ν), and (a, b) = (μ/λ, ν/λ).
    Perspective = 1,
}

/// One grid: how a ray finds its cell, and where its cells are.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// The rows of the map from a direction (perspective) or a point
    /// (parallel) to the grid's coordinates.
    pub rows: [[f32; 3]; 3],
    /// Where the cells start in a and b, and cells per unit of each.
    pub a0: f32,
    pub b0: f32,
    pub sa: f32,
    pub sb: f32,
    /// The first of its cells in `Tables::cells`, row by row (b) of `na`.
    pub first_cell: u32,
    pub na: u32,
    pub nb: u32,
    /// A shadow ray whose surface point is farther than this from the
    /// light (perspective), or has a coordinate larger than this
    /// (parallel), walks the tree: the padding covers rounding up to here.
    pub reach: f32,
    pub form: GridForm,
}

impl GridForm {
    /// Every form, with its name in the shader (`TABLE_<NAME>`).
    pub const ALL: [(GridForm, &'static str); 2] = [
        (GridForm::Parallel, "PARALLEL"),
        (GridForm::Perspective, "PERSPECTIVE"),
    ];
}

crate::base::interface::gpu_struct!(
    /// A grid as the shader reads it, f32 in both precisions: the first
    /// words of the tables' array, one record a grid (shaders/tables.glsl
    /// reads one with the generated `TABLE_GRID_AT`).
    pub mod grid_record: "TableGrid" {
        /// a0, b0, sa, sb
        range: float4,
        /// the first cell, na, nb, and the form (`GridForm` as a number)
        cells: uvec4,
        /// the map's rows (a cube's face reads none of them)
        row0: float4,
        row1: float4,
        row2: float4,
    }
);

impl Grid {
    /// Its record in the shader's tables.
    pub fn gpu(&self) -> grid_record::Values {
        let row = |r: [f32; 3]| [r[0], r[1], r[2], 0.0];
        grid_record::Values {
            range: [self.a0, self.b0, self.sa, self.sb],
            cells: [self.first_cell, self.na, self.nb, self.form as u32],
            row0: row(self.rows[0]),
            row1: row(self.rows[1]),
            row2: row(self.rows[2]),
        }
    }
}

/// A cell's list: where it starts in `Tables::entries` and how long it is
/// (or `WALK`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cell {
    pub first: u32,
    pub count: u32,
}

/// A list's entry: a BVH leaf word, and its key (near distance from the
/// apex for a perspective grid, minus the far end along the light for a
/// parallel one), rounded down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    pub leaf: u32,
    pub key: f32,
}

/// The tables of one scene and view.
#[derive(Debug, Clone, Default)]
pub struct Tables {
    pub grids: Vec<Grid>,
    pub cells: Vec<Cell>,
    pub entries: Vec<Entry>,
    /// Each light's first grid, where it has a table (a positioned
    /// light's six faces follow, +x, -x, +y, -y, +z, -z).
    pub lights: Vec<Option<u32>>,
    /// The eye grid, where eye rays read one.
    pub eye: Option<u32>,
    /// Seconds spent building them.
    pub build_s: f64,
}

/// A light, as the tables see it.
#[derive(Debug, Clone, Copy)]
pub struct LightSpec {
    /// Positioned lights: the position; else None.
    pub position: Option<DVec3>,
    /// A directional light's direction of travel.
    pub direction: DVec3,
    /// Whether it casts shadow rays at all.
    pub casts: bool,
}

/// The camera, as the tables see it (`Globals`' eye and screen vectors).
#[derive(Debug, Clone, Copy)]
pub struct CameraSpec {
    pub eye: DVec3,
    pub to_screen: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub width: u32,
    pub height: u32,
}

#[cfg(test)]
#[path = "tables_tests.rs"]
mod tests;
