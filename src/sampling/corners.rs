//! Corner sampling (docs/scene-format.md, Rays): the SPD's procedure traces
//! one eye ray through each pixel corner, (w+1)×(h+1) of them, and averages
//! each pixel's four. A corner of a w-pixel row sits at u = 2x/w − 1, which
//! is the centre of pixel x of a (w+1)-pixel row whose screen is wider by
//! (w+1)/w: so both renderers trace the corners as the centres of that
//! larger image, and [`Image::corner_mean`] averages them.

use crate::raster::Image;
use crate::scene::{Sampling, Scene};

impl Scene {
    /// The image of `self`'s pixel corners, sampled at its pixel centres;
    /// None where `self` samples centres itself.
    pub fn corner_grid(&self) -> Option<Scene> {
        if !super::mode(self.sampling).corners {
            return None;
        }
        let mut grid = self.clone();
        grid.width = self.width + 1;
        grid.height = self.height + 1;
        grid.sampling = Sampling::Centers;
        grid.camera.screen_right *= f64::from(grid.width) / f64::from(self.width);
        grid.camera.screen_up *= f64::from(grid.height) / f64::from(self.height);
        Some(grid)
    }
}

impl Image {
    /// The corners of pixel (x, y) in the image of the corners: top-left,
    /// top-right, bottom-left, bottom-right.
    pub fn corners_of(&self, x: u32, y: u32) -> [[f32; 3]; 4] {
        [
            self.get(x, y),
            self.get(x + 1, y),
            self.get(x, y + 1),
            self.get(x + 1, y + 1),
        ]
    }

    /// The mean of each pixel's four corners, from the image of the corners
    /// ([`Scene::corner_grid`]): one pixel narrower and lower.
    pub fn corner_mean(&self) -> Image {
        let (w, h) = (self.width - 1, self.height - 1);
        let mut pixels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            for x in 0..w {
                let corners = [
                    self.get(x, y),
                    self.get(x + 1, y),
                    self.get(x, y + 1),
                    self.get(x + 1, y + 1),
                ];
                pixels.push(std::array::from_fn(|c| {
                    (corners.iter().map(|p| f64::from(p[c])).sum::<f64>() / 4.0) as f32
                }));
            }
        }
        Image::new(w, h, pixels)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::scene::{parse, Overrides};

    #[test]
    fn the_grid_centres_are_the_pixel_corners() {
        let text =
            "[image]\nwidth = 4\nheight = 2\nsampling = \"corners\"\n[camera]\neye = [0, 0, 5]\n\
                    screen_center = [0, 0, 0]\nscreen_right = [4, 0, 0]\nscreen_up = [0, 2, 0]\n";
        let scene = parse(text, Path::new("t.toml"), &Overrides::default()).unwrap();
        let grid = scene.corner_grid().unwrap();
        assert_eq!((grid.width, grid.height), (5, 3));
        // Grid pixel 0's centre, u' = 1/5 − 1, is the left edge u = −1.
        let u = (2.0 * 0.5 / 5.0 - 1.0) * grid.camera.screen_right.x;
        assert_eq!(u, -4.0);
        let v = (1.0 - 2.0 * 1.5 / 3.0) * grid.camera.screen_up.y;
        assert_eq!(v, 0.0);
    }
}
