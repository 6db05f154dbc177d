//! Contrast sampling's keys (docs/scene-format.md, Rays): `[image]`'s
//! `thresholds` or `range`, `max_samples` and `compare_trees`, and their
//! checks. The algorithm, which both renderers share, is
//! `crate::sampling::contrast`.

use crate::input::error::SceneError;
use crate::input::field::{Triple, Validator};
use crate::input::locate::KeyPath;

/// Contrast sampling's settings (`[image]`'s `thresholds` or `range`,
/// `max_samples` and `compare_trees`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contrast {
    /// Per channel (r, g, b): the contrast (Imax − Imin)/(Imax + Imin)
    /// past which a pixel takes more samples.
    pub thresholds: [f64; 3],
    /// The most samples a pixel takes.
    pub max_samples: u32,
    /// Whether a pixel whose samples' ray trees differ goes on too,
    /// whatever their colours.
    pub compare_trees: bool,
    /// The range test in place of the contrast test, where given: a
    /// pixel goes on where a channel's range over its samples, divided by
    /// the square root of their count, passes this (`Contrast::next`).
    pub range: Option<f64>,
}

impl Default for Contrast {
    /// Mitchell's thresholds, `DEFAULT_MAX_SAMPLES`, trees compared: what
    /// a scene file that gives none of the keys samples with.
    fn default() -> Self {
        Self {
            thresholds: Self::DEFAULT_THRESHOLDS,
            max_samples: Self::DEFAULT_MAX_SAMPLES,
            compare_trees: true,
            range: None,
        }
    }
}

impl Contrast {
    /// Mitchell's thresholds, for red, green and blue.
    pub const DEFAULT_THRESHOLDS: [f64; 3] = [0.4, 0.3, 0.6];
    /// The most samples a pixel takes where the scene does not say.
    pub const DEFAULT_MAX_SAMPLES: u32 = 33;
    /// The least `max_samples` may be.
    pub const MIN_SAMPLES: u32 = 4;
    /// The most `max_samples` may be.
    pub const MAX_SAMPLES: u32 = 256;
}

impl Validator<'_> {
    /// `[image]`'s contrast sampling: its thresholds (default Mitchell's
    /// 0.4, 0.3, 0.6, each ≥ 0) or its `range` (≥ 0; not both), its
    /// `max_samples` (default 33, 4..=256) and `compare_trees` (default
    /// true); the keys are refused for another sampling.
    pub(crate) fn contrast(
        &self,
        path: &KeyPath,
        contrast: bool,
        keys: ContrastKeys,
        samples: u32,
    ) -> Result<Option<Contrast>, SceneError> {
        let ContrastKeys {
            thresholds,
            range,
            max_samples,
            compare_trees,
        } = keys;
        if !contrast {
            let given = [
                ("thresholds", thresholds.is_some()),
                ("range", range.is_some()),
                ("max_samples", max_samples.is_some()),
                ("compare_trees", compare_trees.is_some()),
            ];
            return self.none_given(path, "contrast", &given).map(|()| None);
        }
        if samples != 1 {
            return self.err(
                &path.key("sampling"),
                format!("\"contrast\" places its own samples: it takes samples = 1, got {samples}"),
            );
        }
        if thresholds.is_some() && range.is_some() {
            return self.err(
                &path.key("range"),
                "`range` and `thresholds` are two tests: give one".to_owned(),
            );
        }
        let range = range
            .map(|r| self.non_negative(&path.key("range"), r))
            .transpose()?;
        let defaults = Contrast::default();
        let thresholds = thresholds.map_or(defaults.thresholds, |t| t.0);
        for (i, t) in thresholds.iter().enumerate() {
            self.non_negative(&path.key("thresholds").index(i), *t)?;
        }
        let max_samples = self.int_in(
            &path.key("max_samples"),
            max_samples.unwrap_or(i64::from(defaults.max_samples)),
            Contrast::MIN_SAMPLES,
            Contrast::MAX_SAMPLES,
        )?;
        Ok(Some(Contrast {
            thresholds,
            max_samples,
            compare_trees: compare_trees.unwrap_or(defaults.compare_trees),
            range,
        }))
    }
}

/// `[image]`'s contrast keys as the file gives them.
pub(crate) struct ContrastKeys {
    pub thresholds: Option<Triple>,
    pub range: Option<f64>,
    pub max_samples: Option<i64>,
    pub compare_trees: Option<bool>,
}
