//! The camera: a right-handed look-at view and an OpenGL-convention projection
//! (clip-space z in [-w, w], NDC depth in [-1, 1], looking down -z in eye space).

use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};

use super::SceneError;

/// Smallest `near` distance (a smaller one loses the depth buffer's precision entirely).
pub const MIN_NEAR: f64 = 1e-9;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Eye position, world space.
    pub eye: [f64; 3],
    /// Point looked at, world space; must differ from `eye`.
    pub target: [f64; 3],
    /// Up direction, world space; must not be parallel to `target - eye`.
    pub up: [f64; 3],
    /// Vertical field of view in degrees, in (0, 180). Unused when `ortho_height` is set.
    pub fov_y_deg: f64,
    /// Distance to the near clip plane, > 0.
    pub near: f64,
    /// Distance to the far clip plane, > `near`.
    pub far: f64,
    /// If set, an orthographic projection whose view volume is this tall (world units,
    /// > 0) and `aspect` times as wide, centred on the view axis.
    #[serde(default)]
    pub ortho_height: Option<f64>,
}

impl Camera {
    /// World-to-eye transform (right-handed look-at, as `gluLookAt`): the eye looks down -z,
    /// `up` maps into the +y half-plane. Rows are `s`, `u`, `-f` with
    /// `f = normalize(target - eye)`, `s = normalize(f × up)`, `u = s × f`.
    pub fn view(&self) -> DMat4 {
        let eye = self.eye();
        let f = (DVec3::from(self.target) - eye).normalize();
        let s = f.cross(DVec3::from(self.up)).normalize();
        let u = s.cross(f);
        DMat4::from_cols(
            DVec4::new(s.x, u.x, -f.x, 0.0),
            DVec4::new(s.y, u.y, -f.y, 0.0),
            DVec4::new(s.z, u.z, -f.z, 0.0),
            DVec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
        )
    }

    /// Eye-to-clip transform for a viewport `aspect = width / height`, OpenGL conventions
    /// (right-handed eye space, NDC z in [-1, 1] with -1 at `near`): `gluPerspective`, or
    /// `glOrtho(-h a/2, h a/2, -h/2, h/2, near, far)` when `ortho_height = h` is set.
    pub fn proj(&self, aspect: f64) -> DMat4 {
        let (n, f) = (self.near, self.far);
        match self.ortho_height {
            Some(h) => {
                let (t, r) = (0.5 * h, 0.5 * h * aspect);
                DMat4::from_cols(
                    DVec4::new(1.0 / r, 0.0, 0.0, 0.0),
                    DVec4::new(0.0, 1.0 / t, 0.0, 0.0),
                    DVec4::new(0.0, 0.0, -2.0 / (f - n), 0.0),
                    DVec4::new(0.0, 0.0, -(f + n) / (f - n), 1.0),
                )
            }
            None => {
                let g = 1.0 / (0.5 * self.fov_y_deg.to_radians()).tan();
                DMat4::from_cols(
                    DVec4::new(g / aspect, 0.0, 0.0, 0.0),
                    DVec4::new(0.0, g, 0.0, 0.0),
                    DVec4::new(0.0, 0.0, (f + n) / (n - f), -1.0),
                    DVec4::new(0.0, 0.0, 2.0 * f * n / (n - f), 0.0),
                )
            }
        }
    }

    /// Check the parameters; errors name `field.<member>`.
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        for (name, v) in [("eye", self.eye), ("target", self.target), ("up", self.up)] {
            if !DVec3::from(v).is_finite() {
                return Err(SceneError::invalid(
                    format!("{field}.{name}"),
                    format!("expected finite coordinates, found {v:?}"),
                ));
            }
            if let Some(x) = v.iter().find(|x| x.abs() > super::MAX_COORD) {
                return Err(SceneError::invalid(
                    format!("{field}.{name}"),
                    format!(
                        "coordinate {x:e} is out of range: expected each coordinate within \
                         ±{:e} (larger values overflow the view transform)",
                        super::MAX_COORD
                    ),
                ));
            }
        }
        let dir = DVec3::from(self.target) - self.eye();
        if dir.length() <= 1e-12 * self.eye().length().max(1.0) {
            return Err(SceneError::invalid(
                format!("{field}.target"),
                "expected a target different from the eye",
            ));
        }
        let up = DVec3::from(self.up);
        if up.length() == 0.0 || dir.normalize().cross(up.normalize()).length() < 1e-9 {
            return Err(SceneError::invalid(
                format!("{field}.up"),
                format!(
                    "expected a non-zero up vector not parallel to the view direction, found {:?}",
                    self.up
                ),
            ));
        }
        if self.ortho_height.is_none() && !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(SceneError::invalid(
                format!("{field}.fov_y_deg"),
                format!(
                    "expected a field of view in (0, 180) degrees, found {}",
                    self.fov_y_deg
                ),
            ));
        }
        if let Some(h) = self.ortho_height {
            if !(h.is_finite() && h > 0.0) {
                return Err(SceneError::invalid(
                    format!("{field}.ortho_height"),
                    format!("expected a finite height > 0, found {h}"),
                ));
            }
        }
        if let Some(h) = self.ortho_height {
            if h > super::MAX_COORD {
                return Err(SceneError::invalid(
                    format!("{field}.ortho_height"),
                    format!(
                        "expected a height of at most {:e}, found {h:e}",
                        super::MAX_COORD
                    ),
                ));
            }
        }
        if !(self.near.is_finite() && self.near > 0.0) {
            return Err(SceneError::invalid(
                format!("{field}.near"),
                format!("expected a finite distance > 0, found {}", self.near),
            ));
        }
        if self.near < MIN_NEAR || self.near > super::MAX_COORD {
            return Err(SceneError::invalid(
                format!("{field}.near"),
                format!(
                    "near {:e} is out of range: expected {MIN_NEAR:e} to {:e}",
                    self.near,
                    super::MAX_COORD
                ),
            ));
        }
        // a larger far (1e308) overflows the projection (2 far near): no pixel is covered
        if self.far.is_finite() && self.far > super::MAX_COORD {
            return Err(SceneError::invalid(
                format!("{field}.far"),
                format!(
                    "far {:e} is out of range: expected at most {:e} (larger values overflow \
                     the projection and cover no pixel)",
                    self.far,
                    super::MAX_COORD
                ),
            ));
        }
        if !(self.far.is_finite() && self.far > self.near) {
            return Err(SceneError::invalid(
                format!("{field}.far"),
                format!(
                    "expected a finite distance > near ({}), found {}",
                    self.near, self.far
                ),
            ));
        }
        Ok(())
    }

    /// The eye position.
    /// Unit vector from a world point toward the viewer: toward the eye for a perspective
    /// camera, the constant direction `eye - target` for an orthographic one (a parallel viewer).
    pub fn view_dir(&self, p: DVec3) -> DVec3 {
        let to = if self.ortho_height.is_some() {
            DVec3::from(self.target)
        } else {
            p
        };
        (self.eye() - to).normalize_or_zero()
    }

    pub fn eye(&self) -> DVec3 {
        DVec3::from(self.eye)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera {
            eye: [0.0, 0.0, 5.0],
            target: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 90.0,
            near: 1.0,
            far: 10.0,
            ortho_height: None,
        }
    }

    fn ndc(m: DMat4, p: DVec3) -> DVec3 {
        let c = m * DVec4::new(p.x, p.y, p.z, 1.0);
        c.truncate() / c.w
    }

    #[test]
    fn view_and_perspective_numbers() {
        let c = cam();
        let v = c.view();
        // The target lies 5 units down -z in eye space; world +x stays +x.
        assert!((v.transform_point3(DVec3::ZERO) - DVec3::new(0.0, 0.0, -5.0)).length() < 1e-15);
        assert!((v.transform_vector3(DVec3::X) - DVec3::X).length() < 1e-15);
        let m = c.proj(2.0) * v;
        // Near plane centre -> NDC z = -1, far -> +1.
        assert!((ndc(m, DVec3::new(0.0, 0.0, 4.0)).z + 1.0).abs() < 1e-12);
        assert!((ndc(m, DVec3::new(0.0, 0.0, -5.0)).z - 1.0).abs() < 1e-12);
        // fov 90: at distance 5 the top of the view is y = 5; aspect 2: right edge x = 10.
        let top = ndc(m, DVec3::new(0.0, 5.0, 0.0));
        assert!((top.y - 1.0).abs() < 1e-12, "{top}");
        let right = ndc(m, DVec3::new(10.0, 0.0, 0.0));
        assert!((right.x - 1.0).abs() < 1e-12, "{right}");
        // Depth at distance 5: OpenGL (f + n)/(f - n) - 2fn/((f - n) d).
        let z = ndc(m, DVec3::ZERO).z;
        assert!((z - (11.0 / 9.0 - 20.0 / (9.0 * 5.0))).abs() < 1e-12, "{z}");
    }

    #[test]
    fn orthographic_numbers() {
        let c = Camera {
            ortho_height: Some(4.0),
            ..cam()
        };
        let m = c.proj(1.5) * c.view();
        let p = ndc(m, DVec3::new(3.0, 2.0, 0.0));
        assert!(
            (p.x - 1.0).abs() < 1e-12 && (p.y - 1.0).abs() < 1e-12,
            "{p}"
        );
        // Linear depth: distance 5 in [1, 10] -> -1 + 2 * 4 / 9.
        assert!((p.z - (-1.0 + 8.0 / 9.0)).abs() < 1e-12, "{p}");
        assert!(c.validate("camera").is_ok());
    }

    #[test]
    fn validate_rejects_bad_cameras() {
        assert!(cam().validate("camera").is_ok());
        let cases = [
            (
                Camera {
                    eye: [f64::NAN, 0.0, 0.0],
                    ..cam()
                },
                "camera.eye",
            ),
            (
                Camera {
                    target: [0.0, 0.0, 5.0],
                    ..cam()
                },
                "camera.target",
            ),
            (
                Camera {
                    up: [0.0, 0.0, 2.0],
                    ..cam()
                },
                "camera.up",
            ),
            (
                Camera {
                    up: [0.0, 0.0, 0.0],
                    ..cam()
                },
                "camera.up",
            ),
            (
                Camera {
                    fov_y_deg: 180.0,
                    ..cam()
                },
                "camera.fov_y_deg",
            ),
            (
                Camera {
                    fov_y_deg: f64::NAN,
                    ..cam()
                },
                "camera.fov_y_deg",
            ),
            (Camera { near: 0.0, ..cam() }, "camera.near"),
            (Camera { far: 1.0, ..cam() }, "camera.far"),
            (
                Camera {
                    ortho_height: Some(-1.0),
                    ..cam()
                },
                "camera.ortho_height",
            ),
        ];
        for (c, field) in cases {
            match c.validate("camera") {
                Err(SceneError::Invalid { field: f, .. }) => assert_eq!(f, field, "{c:?}"),
                other => panic!("{c:?}: expected an error for {field}, got {other:?}"),
            }
        }
    }

    #[test]
    fn serde_defaults_and_unknown_fields() {
        let json =
            r#"{"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":45,"near":0.5,"far":50}"#;
        let c: Camera = serde_json::from_str(json).unwrap();
        assert_eq!(c.ortho_height, None);
        assert_eq!(c.fov_y_deg, 45.0);
        let bad = r#"{"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":45,"near":0.5,"far":50,"zoom":2}"#;
        assert!(serde_json::from_str::<Camera>(bad).is_err());
    }
}
