//! The camera (docs/scene-format.md, Camera): its table in either form,
//! its checks, and the eye and virtual screen both renderers take.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::input::error::SceneError;
use crate::input::field::{Triple, Validator};
use crate::input::locate::KeyPath;

type Result<T> = std::result::Result<T, SceneError>;

/// Both camera forms share one table; which keys are present picks the form.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    /// Where every eye ray starts.
    pub eye: Triple,
    /// Form (a): the screen's centre.
    pub screen_center: Option<Triple>,
    /// Form (a): from the centre to the middle of the right edge.
    pub screen_right: Option<Triple>,
    /// Form (a): from the centre to the middle of the top edge.
    pub screen_up: Option<Triple>,
    /// Form (b): where the eye looks.
    pub look_at: Option<Triple>,
    /// Form (b): the way up (default +y).
    pub up: Option<Triple>,
    /// Form (b): the vertical field of view, in degrees.
    pub vfov: Option<f64>,
}

/// The camera of form (a) in docs/scene-format.md: an eye and a virtual
/// screen. Form (b) is converted to
/// this on load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Where every eye ray starts.
    pub eye: DVec3,
    /// The screen's centre.
    pub screen_center: DVec3,
    /// From the centre to the middle of the screen's right edge.
    pub screen_right: DVec3,
    /// From the centre to the middle of the screen's top edge.
    pub screen_up: DVec3,
}

impl Validator<'_> {
    /// The camera at `path`, either form, as an eye and a screen of
    /// `aspect` (width over height).
    pub(crate) fn camera(&self, path: &KeyPath, c: &CameraFile, aspect: f64) -> Result<Camera> {
        let eye = self.position(&path.key("eye"), c.eye)?;
        let screen_form = [
            ("screen_center", c.screen_center),
            ("screen_right", c.screen_right),
            ("screen_up", c.screen_up),
        ];
        let look_form = [
            ("look_at", c.look_at.is_some()),
            ("up", c.up.is_some()),
            ("vfov", c.vfov.is_some()),
        ];
        let is_screen = screen_form.iter().any(|(_, v)| v.is_some());
        let is_look = look_form.iter().any(|(_, present)| *present);
        if is_screen && is_look {
            let key = look_form
                .iter()
                .find(|(_, p)| *p)
                .map_or("look_at", |(k, _)| k);
            return self.err(
                &path.key(key),
                "mixes the two camera forms: use screen_center/screen_right/screen_up or look_at/up/vfov",
            );
        }
        if is_screen {
            for (key, v) in screen_form {
                if v.is_none() {
                    return self.err(path, format!("missing key `{key}` (the screen camera needs screen_center, screen_right and screen_up)"));
                }
            }
            let center = self.position(
                &path.key("screen_center"),
                c.screen_center.unwrap_or_default(),
            )?;
            let right = self.position(
                &path.key("screen_right"),
                c.screen_right.unwrap_or_default(),
            )?;
            let up = self.position(&path.key("screen_up"), c.screen_up.unwrap_or_default())?;
            let normal = right.cross(up);
            if normal.length() == 0.0 || !normal.is_finite() {
                return self.err(
                    &path.key("screen_up"),
                    "screen_right and screen_up must be non-zero and not parallel",
                );
            }
            if (eye - center).dot(normal) == 0.0 {
                return self.err(&path.key("eye"), "the eye lies in the plane of the screen");
            }
            return Ok(Camera {
                eye,
                screen_center: center,
                screen_right: right,
                screen_up: up,
            });
        }
        let Some(look_at) = c.look_at else {
            return self.err(path, "missing key `screen_center` or `look_at` (a camera needs either screen_center/screen_right/screen_up or look_at/vfov)");
        };
        let look_at = self.position(&path.key("look_at"), look_at)?;
        let Some(vfov) = c.vfov else {
            return self.err(path, "missing key `vfov` (required with look_at)");
        };
        let vfov = self.finite(&path.key("vfov"), vfov)?;
        if !(vfov > 0.0 && vfov < 180.0) {
            return self.err(
                &path.key("vfov"),
                format!(
                    "must be in (0, 180) degrees, got {}",
                    crate::printable::number(vfov)
                ),
            );
        }
        let up = self.direction(&path.key("up"), c.up.unwrap_or(Triple([0.0, 1.0, 0.0])))?;
        let fwd = (look_at - eye).normalize_or_zero();
        if fwd == DVec3::ZERO {
            return self.err(&path.key("look_at"), "must differ from eye");
        }
        let right = fwd.cross(up).normalize_or_zero();
        if right == DVec3::ZERO {
            return self.err(
                &path.key("up"),
                "must not be parallel to the view direction",
            );
        }
        let true_up = right.cross(fwd);
        let half_height = (vfov.to_radians() / 2.0).tan();
        Ok(Camera {
            eye,
            screen_center: eye + fwd,
            screen_right: right * (aspect * half_height),
            screen_up: true_up * half_height,
        })
    }
}
