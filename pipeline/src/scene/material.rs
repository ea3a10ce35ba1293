//! Materials: OpenGL-style coefficients, the lighting model that shades them, and several
//! materials on one object (Tarini et al. 1999 §6, "Multiple lighting models").
//!
//! A scene has material 0 (`scene.material`) and, optionally, [`Regions`]: up to seven more
//! materials and a [`RegionRule`] that says which material covers a surface point. The rule
//! reads the texture coordinates (wrapped into `[0, 1)`) or the object-space perturbed
//! normal, so the float reference (per pixel) and a baked normal map (per texel) agree on it.
//!
//! The lighting model ([`Shading`]) is part of the material: the float reference renders it
//! exactly per pixel, and the quantized normal map engine evaluates the same function on its
//! table of normals (`hw/src/units/palette_builder.rs`). The Gouraud and SGI engines shade
//! Blinn-Phong (or Lambert) with material 0 only.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::SceneError;

/// Material ids are `0..MAX_MATERIALS`: a 3-bit material field (Tarini §6: "2 or 3 is
/// usually enough, but values of 8 or more are sometime useful").
pub const MAX_MATERIALS: usize = 8;

/// Surface material (OpenGL-style coefficients, linear RGB in [0, 1]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    pub ambient: [f64; 3],
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
    pub shininess: f64,
    /// The lighting model (Blinn-Phong unless said otherwise).
    #[serde(default)]
    pub model: Shading,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            ambient: [0.1; 3],
            diffuse: [0.8; 3],
            specular: [0.5; 3],
            shininess: 32.0,
            model: Shading::Phong,
        }
    }
}

/// A lighting model `f(N) -> colour` (Tarini §5.1's list). Every model is evaluated per
/// pixel by the float reference with the exact perturbed normal; see
/// `crate::reference::shade_with_view` for the formulas.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Shading {
    /// Ambient + Lambert + Blinn-Phong specular over every light.
    #[default]
    Phong,
    /// Ambient + Lambert over every light (§5.1 item 1); `specular` and `shininess` unused.
    Lambert,
    /// Cartoon (§5.1 item 4): the Lambert term falls into one of `bands` flat levels.
    Cartoon { bands: u32 },
    /// Phong with the angle between the reflected light and the viewer doubled (Fig. 6),
    /// with the first light.
    DoubledAnglePhong,
    /// Chrome (Fig. 7): the reflection of a landscape, `ground` colour straight down
    /// (world `-y`) blending into the `sky` colour straight up (`+y`). Lights unused.
    Chrome { sky: [f64; 3], ground: [f64; 3] },
    /// Environment map (§5.1 item 3, Fig. 5): the reflected ray reads an OpenGL sphere map,
    /// an RGB PNG (path relative to the config file), in the camera's eye frame. Lights
    /// unused.
    EnvMap { image: String },
}

impl Shading {
    /// Short name for reports and errors.
    pub fn name(&self) -> &'static str {
        match self {
            Shading::Phong => "Phong",
            Shading::Lambert => "Lambert",
            Shading::Cartoon { .. } => "Cartoon",
            Shading::DoubledAnglePhong => "DoubledAnglePhong",
            Shading::Chrome { .. } => "Chrome",
            Shading::EnvMap { .. } => "EnvMap",
        }
    }
}

/// What a [`RegionRule`] reads at a surface point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Coord {
    /// Texture coordinate `u`, wrapped into `[0, 1)`.
    U,
    /// Texture coordinate `v`, wrapped into `[0, 1)`.
    V,
    /// A component of the object-space perturbed unit normal.
    NormalX,
    NormalY,
    NormalZ,
}

/// Which material covers a surface point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum RegionRule {
    /// Material 1 where the coordinate is at least `at`, material 0 below (Fig. 8: "most of
    /// the normals pointing up are metal, while most of those pointing down are not").
    Split { of: Coord, at: f64 },
    /// Bands of `width` along the coordinate, cycling through materials `0..count`: material
    /// `floor(c / width) mod count` (Fig. 10's painted vase).
    Bands { of: Coord, width: f64, count: u32 },
}

/// Materials after material 0, and the rule that places them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Regions {
    /// Materials 1, 2, ...: at most seven.
    pub materials: Vec<Material>,
    pub rule: RegionRule,
}

impl Regions {
    /// The material id at a point with texture coordinates `uv` and object-space unit
    /// perturbed normal `n_obj`.
    pub fn material_at(&self, uv: DVec2, n_obj: DVec3) -> u8 {
        let coord = |c: Coord| match c {
            Coord::U => uv.x.rem_euclid(1.0),
            Coord::V => uv.y.rem_euclid(1.0),
            Coord::NormalX => n_obj.x,
            Coord::NormalY => n_obj.y,
            Coord::NormalZ => n_obj.z,
        };
        let id = match self.rule {
            RegionRule::Split { of, at } => u8::from(coord(of) >= at),
            RegionRule::Bands { of, width, count } => {
                let k = (coord(of) / width).floor();
                if k.is_finite() {
                    (k as i64).rem_euclid(i64::from(count)) as u8
                } else {
                    0
                }
            }
        };
        id.min(self.materials.len() as u8)
    }

    /// Check the materials and the rule; `field` is the config path (`scene.regions`).
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        let n = self.materials.len();
        if !(1..MAX_MATERIALS).contains(&n) {
            return Err(SceneError::invalid(
                format!("{field}.materials"),
                format!(
                    "{n} materials after scene.material ({} in all): expected 1 to {} (a \
                     3-bit material field holds {MAX_MATERIALS}, Tarini §6)",
                    n + 1,
                    MAX_MATERIALS - 1
                ),
            ));
        }
        for (i, m) in self.materials.iter().enumerate() {
            m.validate(&format!("{field}.materials[{i}]"))?;
        }
        match self.rule {
            RegionRule::Split { at, .. } if !at.is_finite() => Err(SceneError::invalid(
                format!("{field}.rule.at"),
                format!("expected a finite number, found {at}"),
            )),
            RegionRule::Bands { width, count, .. } => {
                if !(width.is_finite() && width > 0.0) {
                    return Err(SceneError::invalid(
                        format!("{field}.rule.width"),
                        format!("expected a finite number above 0, found {width}"),
                    ));
                }
                if !(2..=n as u32 + 1).contains(&count) {
                    return Err(SceneError::invalid(
                        format!("{field}.rule.count"),
                        format!(
                            "expected 2 to {} (the number of materials), found {count}",
                            n + 1
                        ),
                    ));
                }
                Ok(())
            }
            RegionRule::Split { .. } => Ok(()),
        }
    }
}

impl Material {
    /// Check a material from a config; `field` is its path (`scene.material`).
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        if !(self.shininess.is_finite() && self.shininess > 0.0) {
            return Err(SceneError::invalid(
                format!("{field}.shininess"),
                format!("expected a number above 0, found {}", self.shininess),
            ));
        }
        let unit = |name: &str, v: [f64; 3]| {
            if v.iter().all(|x| (0.0..=1.0).contains(x)) {
                Ok(())
            } else {
                Err(SceneError::invalid(
                    format!("{field}.{name}"),
                    format!("expected values in [0, 1], found {v:?}"),
                ))
            }
        };
        unit("ambient", self.ambient)?;
        unit("diffuse", self.diffuse)?;
        unit("specular", self.specular)?;
        match &self.model {
            Shading::Cartoon { bands } if !(2..=256).contains(bands) => Err(SceneError::invalid(
                format!("{field}.model.bands"),
                format!("expected 2 to 256 bands, found {bands}"),
            )),
            Shading::Chrome { sky, ground } => {
                unit("model.sky", *sky)?;
                unit("model.ground", *ground)
            }
            Shading::EnvMap { image } if image.is_empty() => Err(SceneError::invalid(
                format!("{field}.model.image"),
                "expected the path of an RGB PNG sphere map, found an empty string",
            )),
            _ => Ok(()),
        }
    }
}

/// A sphere map loaded from a PNG: linear RGB `c / 255`, rows top to bottom as in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f64; 3]>,
}

impl EnvImage {
    /// Load `path`; errors name the file and what was expected.
    pub fn load(path: &std::path::Path) -> Result<EnvImage, SceneError> {
        let img = super::files::read_png(path, super::files::MAX_PNG_SIDE)
            .map_err(|e| match e {
                SceneError::File { path, message } => SceneError::File {
                    path,
                    message: format!(
                        "cannot read the environment map: {message} (expected an RGB PNG)"
                    ),
                },
                other => other,
            })?
            .to_rgb8();
        let (width, height) = img.dimensions();
        if !(1..=4096).contains(&width) || !(1..=4096).contains(&height) {
            return Err(SceneError::file(
                path.display(),
                format!("environment map {width}x{height}: expected 1 to 4096 texels a side"),
            ));
        }
        let texels = img
            .pixels()
            .map(|p| p.0.map(|c| f64::from(c) / 255.0))
            .collect();
        Ok(EnvImage {
            width,
            height,
            texels,
        })
    }

    /// The OpenGL sphere-map texel a reflected ray `r` (in the eye frame: `x` right, `y` up,
    /// `z` towards the viewer) reads, nearest, clamped: `m = 2 sqrt(r_x^2 + r_y^2 + (r_z +
    /// 1)^2)`, `(s, t) = (r_x / m + 1/2, r_y / m + 1/2)`, `t = 0` the bottom row of the image.
    pub fn sphere_lookup(&self, r: DVec3) -> DVec3 {
        let m = 2.0 * (r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0)).sqrt();
        let (s, t) = if m > 0.0 {
            (r.x / m + 0.5, r.y / m + 0.5)
        } else {
            (0.5, 0.5)
        };
        let (w, h) = (self.width as f64, self.height as f64);
        let i = ((s * w).floor().max(0.0) as usize).min(self.width as usize - 1);
        let j = ((t * h).floor().max(0.0) as usize).min(self.height as usize - 1);
        let row = self.height as usize - 1 - j;
        DVec3::from(self.texels[row * self.width as usize + i])
    }

    /// The texels bottom row first (the builder's `t`-major order).
    pub fn rows_bottom_up(&self) -> Vec<[f64; 3]> {
        let w = self.width as usize;
        self.texels
            .chunks(w)
            .rev()
            .flat_map(|r| r.iter().copied())
            .collect()
    }
}

/// The materials of a built scene with what they load (environment maps), by id.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Looks {
    /// Materials 1.. and their rule; `None`: material 0 everywhere.
    pub regions: Option<Regions>,
    /// Per material id (0 first), its environment map if its model is `EnvMap`.
    pub env_maps: Vec<Option<EnvImage>>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn regions(rule: RegionRule, n: usize) -> Regions {
        Regions {
            materials: vec![Material::default(); n],
            rule,
        }
    }

    #[test]
    fn split_and_bands_pick_materials() {
        let r = regions(
            RegionRule::Split {
                of: Coord::NormalY,
                at: 0.0,
            },
            1,
        );
        assert_eq!(r.material_at(DVec2::ZERO, DVec3::Y), 1);
        assert_eq!(r.material_at(DVec2::ZERO, -DVec3::Y), 0);
        assert_eq!(r.material_at(DVec2::ZERO, DVec3::X), 1); // at the threshold
        let b = regions(
            RegionRule::Bands {
                of: Coord::V,
                width: 0.1,
                count: 3,
            },
            2,
        );
        let ids: Vec<u8> = (0..10)
            .map(|k| b.material_at(DVec2::new(0.0, k as f64 * 0.1 + 0.05), DVec3::Z))
            .collect();
        assert_eq!(ids, [0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        // uv wraps into [0, 1)
        assert_eq!(
            b.material_at(DVec2::new(0.0, 1.15), DVec3::Z),
            b.material_at(DVec2::new(0.0, 0.15), DVec3::Z)
        );
    }

    #[test]
    fn regions_validation_names_the_field() {
        let too_many = regions(
            RegionRule::Split {
                of: Coord::U,
                at: 0.5,
            },
            8,
        );
        let e = too_many.validate("scene.regions").unwrap_err().to_string();
        assert!(
            e.contains("scene.regions.materials") && e.contains("9 in all"),
            "{e}"
        );
        let bands = regions(
            RegionRule::Bands {
                of: Coord::U,
                width: 0.5,
                count: 4,
            },
            2,
        );
        let e = bands.validate("scene.regions").unwrap_err().to_string();
        assert!(e.contains("scene.regions.rule.count"), "{e}");
        let mut bad = regions(
            RegionRule::Split {
                of: Coord::U,
                at: 0.5,
            },
            1,
        );
        bad.materials[0].model = Shading::Cartoon { bands: 1 };
        let e = bad.validate("scene.regions").unwrap_err().to_string();
        assert!(e.contains("scene.regions.materials[0].model.bands"), "{e}");
    }

    #[test]
    fn sphere_lookup_centre_and_edges() {
        // 4x4 image, texel value = its index / 15, file rows top to bottom
        let img = EnvImage {
            width: 4,
            height: 4,
            texels: (0..16).map(|i| [i as f64 / 15.0; 3]).collect(),
        };
        // r = +z (back at the viewer): the centre, (s, t) = (1/2, 1/2) -> column 2, row
        // from the bottom 2 -> file row 1
        assert_eq!(img.sphere_lookup(DVec3::Z).x, 6.0 / 15.0);
        // r = +y: (1/2, 1/2 + 1/(2 sqrt 2)) = t 0.85 -> bottom-up row 3 -> file row 0
        assert_eq!(img.sphere_lookup(DVec3::Y).x, 2.0 / 15.0);
        assert_eq!(img.rows_bottom_up()[0], [12.0 / 15.0; 3]);
    }

    #[test]
    fn env_map_load_errors_name_the_file() {
        let e = EnvImage::load(std::path::Path::new("/nonexistent/env.png"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/env.png") && e.contains("RGB PNG"),
            "{e}"
        );
        let p = crate::scratch::Scratch::file("not-an-image.png");
        std::fs::write(&p, b"plain text").unwrap();
        let e = EnvImage::load(&p).unwrap_err().to_string();
        assert!(e.contains("not-an-image"), "{e}");
    }
}
