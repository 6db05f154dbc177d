//! How a pixel is sampled (docs/scene-format.md, Rays): the `sampling` of
//! `[image]`, and Whitted's adaptive antialiasing with its checks.

use serde::{Deserialize, Serialize};

use crate::input::error::SceneError;
use crate::input::field::Validator;
use crate::input::locate::KeyPath;

/// Where a pixel's eye rays go (docs/scene-format.md, Rays).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// samples × samples rays through the centres of a grid over the pixel.
    #[default]
    Centers,
    /// One ray through each pixel corner, (w+1)×(h+1), four averaged per
    /// pixel: the SPD's procedure.
    Corners,
    /// Whitted's adaptive antialiasing: the corners, and a pixel whose
    /// corners differ by more than a threshold split into four, again
    /// and again up to a level (`crate::scene::Adaptive`).
    Adaptive,
    /// Mitchell's contrast sampling: one sample at each pixel's centre,
    /// then more, level by level, where they or a neighbour's differ
    /// (`crate::scene::Contrast`).
    Contrast,
}

/// Whitted's adaptive antialiasing (docs/scene-format.md, Rays): a square
/// of a pixel whose corners' contrast passes `threshold` is split into
/// four, at most `levels` times from the pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adaptive {
    /// The largest difference between two corners in one channel that a
    /// square keeps unsplit.
    pub threshold: f64,
    /// How many times a pixel may be split: 1..=`MAX_LEVELS`.
    pub levels: u32,
}

impl Adaptive {
    /// The deepest split allowed: 4⁴ = 256 squares to a pixel.
    pub const MAX_LEVELS: u32 = 4;

    /// The most eye rays one pixel can add to its corners: 5 a split, and
    /// (4^levels − 1)/3 splits.
    pub fn most_rays_per_pixel(&self) -> f64 {
        5.0 * (4f64.powi(self.levels as i32) - 1.0) / 3.0
    }
}

impl Validator<'_> {
    /// Refuses the first of `given`, `[image]`'s keys that only `sampling
    /// = "<sampling>"` takes, that the file gives: for another sampling.
    pub(crate) fn none_given(
        &self,
        path: &KeyPath,
        sampling: &str,
        given: &[(&str, bool)],
    ) -> Result<(), SceneError> {
        match given.iter().find(|(_, given)| *given) {
            Some((key, _)) => self.err(
                &path.key(key),
                format!("only sampling = \"{sampling}\" takes it"),
            ),
            None => Ok(()),
        }
    }

    /// `[image]`'s adaptive sampling: its threshold (default 0.1, ≥ 0) and
    /// its levels (default 2, 1..=4); those keys are refused for another
    /// sampling.
    /// `keys`: `[image]`'s sampling, threshold and max_level.
    pub(crate) fn adaptive(
        &self,
        path: &KeyPath,
        (sampling, threshold, max_level): (Sampling, Option<f64>, Option<i64>),
        samples: u32,
    ) -> Result<Option<Adaptive>, SceneError> {
        if sampling != Sampling::Adaptive {
            let given = [
                ("threshold", threshold.is_some()),
                ("max_level", max_level.is_some()),
            ];
            return self.none_given(path, "adaptive", &given).map(|()| None);
        }
        if samples != 1 {
            return self.err(
                &path.key("sampling"),
                format!("\"adaptive\" starts from one ray per pixel corner: it takes samples = 1, got {samples}"),
            );
        }
        let threshold = self.non_negative(&path.key("threshold"), threshold.unwrap_or(0.1))?;
        let levels = self.int_in(
            &path.key("max_level"),
            max_level.unwrap_or(2),
            1,
            Adaptive::MAX_LEVELS,
        )?;
        Ok(Some(Adaptive { threshold, levels }))
    }
}
