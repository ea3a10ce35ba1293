//! The textures units read, built from the scene: texel fetch sources, bump heights and the
//! baked object-space normals.

use super::checks::check_size;
use super::BuildCtx;
use crate::scene::{NormalMethod, Scene};
use bumpsim_hw::units::Texels;
use bumpsim_hw::Encoding;
use serde::{Deserialize, Serialize};

/// What a texel fetch unit reads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum TextureSource {
    /// The scene's bump map as a tangent-space normal map of `size` x `size` texels, baked by
    /// `method` (from heights) or resampled (from a normal PNG).
    BumpNormals { size: u32, method: NormalMethod },
    /// [`TextureSource::BumpNormals`] as a HILO texture: 2 lanes `(x, y)` of the tangent-space
    /// normal, `z` left to the reader (SIGNED_HILO16 with a hemisphere dot mapping, Wang et
    /// al. §3: "Such a 2D vector corresponds to a 3D vector (HI, LO, sqrt(1 - HI² - LO²))").
    BumpHilo { size: u32, method: NormalMethod },
    /// The scene's bump map as heights in [0, 1] (normalised to the map's range).
    BumpHeights { size: u32 },
    /// The scene's colour texture (RGB in [0, 1]); its sides must be powers of two.
    ColorTexture,
    /// The mesh's perturbed normals in object space, baked by rasterising the mesh in uv space
    /// (`scene/bake.rs`): a bump map "containing the computed surface normals ... plus the
    /// bump-structure" (Ernst et al. §5.4.2, Fig. 8).
    ObjectNormals { size: u32 },
    /// A lighting table for a dependent lookup at (N·L, N·H) of light `light` (the
    /// DOT_PRODUCT_TEXTURE_2D use of NV20 texture shaders): texel (i, j) holds the scene
    /// material's Blinn-Phong colour at s = (i + 1/2) / size, t = (j + 1/2) / size,
    /// `ambient + color (diffuse s + specular t^shininess)` (no specular where s is 0), each
    /// channel clamped to [0, 1]. Read it with `address: Clamp` so that s = 1 reads the last
    /// column.
    LightingTable { size: u32, light: usize },
    /// The scene's bump map as its height gradient `(Fu, Fv)` per unit of texture coordinate,
    /// two lanes at texel centres: the "precalculated derivatives, offset vectors, stored in a
    /// bump map" of VISA+ and Texram (Ernst et al. §3.2), read by the per-pixel perturbation
    /// engines (`Perturb`). Analytic for height fields; from a normal map's texels as
    /// `(-x / z, -y / z)` (z at least 1/64). `height: true` adds a third lane, the height
    /// normalised to [0, 1] as in `BumpHeights` (a DSDT8_MAG8-style texel: the magnitude of
    /// Direct3D 6's BUMPENVMAPLUMINANCE, Ernst et al. §3.3, dark in the grooves); it needs a
    /// height map.
    BumpGradient {
        size: u32,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        height: bool,
    },
    /// A diffuse and specular lighting map of light `light` in sphere-map form, for Direct3D
    /// 6 environment-mapped bump mapping (Ernst et al. §3.3: "the lighting environment of the
    /// scene ... represented in an image environment map"): texel `(i, j)` at
    /// `(x, y) = (2 (i + 1/2) / size - 1, 2 (j + 1/2) / size - 1)` (moved to the unit circle
    /// where outside it)
    /// holds the scene material's Blinn-Phong colour for the view-space normal `(x, y,
    /// sqrt(1 - x² - y²))`, a parallel viewer along +z and the light's direction from the
    /// camera's target, each channel clamped to [0, 1]. Read at `AttrSource::SphereMap`
    /// coordinates, with `address: Clamp`. The map holds the light: it must be rebuilt when
    /// the light or the material changes. `built_for: Some((x, y, z))`: the map was built for
    /// a light in that world-space direction (toward the light) and not rebuilt since the
    /// light moved to where the scene has it (a stale map; `None`, the default: rebuilt).
    SphereLighting {
        size: u32,
        light: usize,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        built_for: Option<(f64, f64, f64)>,
    },
    /// Mip level `level` of the noise texture of the scene's `bump: Ndf(...)` whose finest
    /// level is `size` texels a side (Kautz et al. §5.2.2: "the finest mipmap level contains
    /// the most octaves, every coarser mipmap level contains one octave less"): 3 lanes
    /// `(0, r1, r2)`. `mips: false` (the default): that level alone, so a config binds the
    /// level its distance needs (`docs/units/ndf.md`); `mips: true`: that level and every
    /// coarser one down to 1x1 (the flat levels hold `(0, 1/2, 1/2)`), for a texture-shader
    /// part with `lod: true`.
    NdfNoise {
        size: u32,
        level: u32,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        mips: bool,
    },
    /// The lookup table `L(r1, r2)` of the scene's NDF bump (§4), `size` x `size` entries
    /// stored as `entry` (`crate::ndf::sources::LookupEntry`).
    NdfLookup {
        size: u32,
        entry: crate::ndf::sources::LookupEntry,
    },
    /// The isotropic NDF of the scene's NDF bump as a 1-D texture of `size` texels at
    /// `n_m · h`, coloured for light `light` (§5.2.2); an anisotropic NDF is an error.
    /// `far: true` stores the far level's shading instead (`NdfSurface::far_relative`: the
    /// NDF convolved with its own microfacets), for the draw of the flat surface beyond the
    /// bump levels, so that the switch to it keeps the bump levels' mean shading.
    NdfShading {
        size: u32,
        light: usize,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        far: bool,
    },
    /// The NDF as a 2-D texture at `(n_m · h, |t_m · h|)` (the anisotropic variant).
    NdfShading2d { size: u32, light: usize },
    /// A cube map of six `size` x `size` faces holding one lighting term of light `light`
    /// for the world-space direction `d` of each texel centre (faces +X, -X, +Y, -Y, +Z, -Z
    /// by OpenGL 1.3 table 3.19, the inverse of `bumpsim_hw::sampler::cube_face`), each
    /// channel clamped to [0, 1]: the "lighting environment in a cube map" that NV20 texture
    /// shaders read with DOT_PRODUCT_DIFFUSE_CUBE_MAP at the world normal and
    /// DOT_PRODUCT_REFLECT_CUBE_MAP at the reflected eye vector. A directional light's
    /// direction, a point light's direction from the camera's target (a cube map holds
    /// distant lighting). `term`: see [`CubeTerm`]. A cube map is read by a texture-shader
    /// stage with a cube-map program only, with `address: Clamp` (a direction on the edge
    /// of two faces reads s or t = 1 exactly, which `Wrap` takes to the far side of the
    /// face); faces are at most 512 texels a side.
    CubeLighting {
        size: u32,
        light: usize,
        term: CubeTerm,
        /// The Specular term's exponent (default `None`: the scene's shininess / 4); above 0,
        /// at most 10^4.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        exponent: Option<f64>,
    },
}

/// The lighting term a [`TextureSource::CubeLighting`] map holds at direction `d` (unit), with
/// `L` the light's direction, `c` its colour and the scene material's colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CubeTerm {
    /// `ambient + c diffuse max(d . L, 0)`: read at the normal.
    Diffuse,
    /// `c specular max(d . L, 0)^(shininess / 4)` (or the source's `exponent`): read at the
    /// reflected eye vector `R`, the
    /// Phong lobe `(R . L)^n` with the exponent that approximates the scene's Blinn-Phong
    /// `(N . H)^shininess` (the angle between `R` and `L` is about twice the angle between `N`
    /// and `H`, so `n = shininess / 4` gives a highlight of about the same width; Fisher and
    /// Woo, "R.E versus N.H specular highlights", Graphics Gems IV, 1994).
    Specular,
}

/// The largest side of a cube map's faces (6 x 512^2 texels).
pub const MAX_CUBE_SIDE: u32 = 512;

/// The world-space direction (not normalised, major axis 1) of `face` (0 to 5, +X, -X, +Y,
/// -Y, +Z, -Z) at face coordinates `(s, t)` in [0, 1]: the inverse of OpenGL 1.3 table 3.19
/// (`bumpsim_hw::sampler::cube_face`).
pub fn cube_direction(face: usize, s: f64, t: f64) -> glam::DVec3 {
    let (sc, tc) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    let [x, y, z] = match face {
        0 => [1.0, -tc, -sc],
        1 => [-1.0, -tc, sc],
        2 => [sc, 1.0, tc],
        3 => [sc, -1.0, -tc],
        4 => [sc, -tc, 1.0],
        _ => [-sc, -tc, -1.0],
    };
    glam::DVec3::new(x, y, z)
}

impl TextureSource {
    /// Whether the texels follow the frame's inputs (lights, camera, material): the host
    /// builds the texture again for every frame.
    pub fn per_frame(&self) -> bool {
        matches!(
            self,
            TextureSource::LightingTable { .. }
                | TextureSource::SphereLighting { .. }
                | TextureSource::NdfShading { .. }
                | TextureSource::NdfShading2d { .. }
                | TextureSource::CubeLighting { .. }
        )
    }
    /// Whether the source is a cube map (`cube_faces`).
    pub fn is_cube(&self) -> bool {
        matches!(self, TextureSource::CubeLighting { .. })
    }
}

/// The six faces of a cube-map source (+X, -X, +Y, -Y, +Z, -Z), its size checked.
pub(super) fn cube_faces(source: &TextureSource, ctx: &BuildCtx) -> Result<Vec<Texels>, String> {
    let TextureSource::CubeLighting {
        size,
        light,
        term,
        exponent,
    } = *source
    else {
        return Err(format!("{source:?}: expected a cube-map source"));
    };
    if !size.is_power_of_two() || size > MAX_CUBE_SIDE {
        return Err(format!(
            "size {size}: expected a power of two from 1 to {MAX_CUBE_SIDE} (a cube map's face)"
        ));
    }
    let scene = ctx.scene;
    let l = scene.light(light)?;
    let dir = l.dir_from(glam::DVec3::from(scene.camera.target));
    let (m, color) = (&scene.material, l.color());
    let exponent = exponent.unwrap_or(m.shininess / 4.0);
    if !(exponent > 0.0 && exponent <= 1e4) {
        return Err(format!(
            "exponent {exponent}: expected a number above 0, at most 10000"
        ));
    }
    let n = f64::from(size);
    let face = |f: usize| {
        let values = (0..size)
            .flat_map(|j| (0..size).map(move |i| (i, j)))
            .map(|(i, j)| {
                let d = cube_direction(f, (f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n)
                    .normalize();
                let dl = d.dot(dir).max(0.0);
                let mut v = [0.0; 4];
                for c in 0..3 {
                    v[c] = match term {
                        CubeTerm::Diffuse => m.ambient[c] + color[c] * m.diffuse[c] * dl,
                        CubeTerm::Specular => color[c] * m.specular[c] * dl.powf(exponent),
                    }
                    .clamp(0.0, 1.0);
                }
                v
            })
            .collect();
        square(size, 3, values)
    };
    Ok((0..6).map(face).collect())
}

/// The texels of `source` (its size checked).
pub(super) fn texels(source: &TextureSource, ctx: &BuildCtx) -> Result<Texels, String> {
    match *source {
        TextureSource::BumpNormals { size, method } => {
            check_size(size)?;
            let nm = super::baked::tangent_normals(ctx, size, method);
            let values = nm.iter().map(|n| [n.x, n.y, n.z, 0.0]).collect();
            Ok(square(size, 3, values))
        }
        TextureSource::BumpHilo { size, method } => {
            check_size(size)?;
            let nm = super::baked::tangent_normals(ctx, size, method);
            let values = nm.iter().map(|n| [n.x, n.y, 0.0, 0.0]).collect();
            Ok(square(size, 2, values))
        }
        TextureSource::BumpHeights { size } => {
            check_size(size)?;
            let values = normalise_heights(&heights(ctx, size)?)
                .into_iter()
                .map(|x| [x, 0.0, 0.0, 0.0])
                .collect();
            Ok(square(size, 1, values))
        }
        TextureSource::BumpGradient { size, height } => {
            check_size(size)?;
            let h = if height {
                normalise_heights(&heights(ctx, size)?)
            } else {
                Vec::new()
            };
            let bump = &ctx.scene.bump;
            let n = f64::from(size);
            let values = (0..size)
                .flat_map(|j| (0..size).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let (u, v) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                    let g = bump.grad(u, v).unwrap_or_else(|| {
                        let t = bump.normal_ts(u, v);
                        let z = t.z.max(1.0 / 64.0);
                        glam::DVec2::new(-t.x / z, -t.y / z)
                    });
                    [
                        g.x,
                        g.y,
                        h.get((j * size + i) as usize).copied().unwrap_or(0.0),
                        0.0,
                    ]
                })
                .collect();
            Ok(square(size, if height { 3 } else { 2 }, values))
        }
        TextureSource::SphereLighting {
            size,
            light,
            built_for,
        } => {
            check_size(size)?;
            let scene = ctx.scene;
            let l = scene.light(light)?;
            let view = glam::DMat3::from_mat4(scene.camera.view());
            let world = match built_for {
                Some((x, y, z)) => {
                    let d = glam::DVec3::new(x, y, z);
                    if !(d.is_finite() && d.length() > 1e-9) {
                        return Err(format!(
                            "built_for: ({x}, {y}, {z}): expected a finite, non-zero direction"
                        ));
                    }
                    d
                }
                None => l.dir_from(glam::DVec3::from(scene.camera.target)),
            };
            let dir = (view * world).normalize();
            let half = (dir + glam::DVec3::Z).normalize_or_zero();
            let m = &scene.material;
            let color = l.color();
            let n = f64::from(size);
            let values = (0..size)
                .flat_map(|j| (0..size).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let xy = glam::DVec2::new(
                        2.0 * (f64::from(i) + 0.5) / n - 1.0,
                        2.0 * (f64::from(j) + 0.5) / n - 1.0,
                    );
                    let xy = if xy.length() > 1.0 {
                        xy.normalize()
                    } else {
                        xy
                    };
                    let nrm = xy.extend((1.0 - xy.length_squared()).max(0.0).sqrt());
                    let d = nrm.dot(dir);
                    let spec = if d > 0.0 {
                        nrm.dot(half).max(0.0).powf(m.shininess)
                    } else {
                        0.0
                    };
                    let mut v = [0.0; 4];
                    for c in 0..3 {
                        v[c] = (m.ambient[c]
                            + color[c] * (m.diffuse[c] * d.max(0.0) + m.specular[c] * spec))
                            .clamp(0.0, 1.0);
                    }
                    v
                })
                .collect();
            Ok(square(size, 3, values))
        }
        TextureSource::ObjectNormals { size } => {
            check_size(size)?;
            let values = super::baked::object_normals(ctx, size)
                .iter()
                .map(|n| [n.x, n.y, n.z, 0.0])
                .collect();
            Ok(square(size, 3, values))
        }
        TextureSource::LightingTable { size, light } => {
            check_size(size)?;
            let scene = ctx.scene;
            let l = scene.light(light)?;
            let m = &scene.material;
            let color = l.color();
            let n = f64::from(size);
            let values = (0..size)
                .flat_map(|j| (0..size).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let (s, t) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                    let spec = if s > 0.0 { t.powf(m.shininess) } else { 0.0 };
                    let mut v = [0.0; 4];
                    for c in 0..3 {
                        v[c] = (m.ambient[c]
                            + color[c] * (m.diffuse[c] * s + m.specular[c] * spec))
                            .clamp(0.0, 1.0);
                    }
                    v
                })
                .collect();
            Ok(square(size, 3, values))
        }
        TextureSource::NdfNoise { size, level, .. } => {
            crate::ndf::sources::noise(ctx.scene, size, level)
        }
        TextureSource::NdfLookup { size, entry } => {
            crate::ndf::sources::lookup(ctx.scene, size, entry)
        }
        TextureSource::NdfShading { size, light, far } => {
            crate::ndf::sources::shading_1d(ctx.scene, size, light, far)
        }
        TextureSource::NdfShading2d { size, light } => {
            crate::ndf::sources::shading_2d(ctx.scene, size, light)
        }
        TextureSource::CubeLighting { .. } => Err(
            "a cube map: expected it bound to a texture-shader stage with a cube-map program"
                .into(),
        ),
        TextureSource::ColorTexture => {
            let img =
                ctx.scene.color_texture.as_ref().ok_or(
                    "the scene has no color_texture: expected one for source ColorTexture",
                )?;
            let values = img
                .pixels()
                .map(|p| {
                    [
                        p.0[0] as f64 / 255.0,
                        p.0[1] as f64 / 255.0,
                        p.0[2] as f64 / 255.0,
                        0.0,
                    ]
                })
                .collect();
            Ok(Texels {
                width: img.width(),
                height: img.height(),
                lanes: 3,
                values,
            })
        }
    }
}

/// The mip levels below level 0 of `source`'s texture (coarsest last; none for most sources).
pub(super) fn mip_levels(source: &TextureSource, ctx: &BuildCtx) -> Result<Vec<Texels>, String> {
    match *source {
        TextureSource::NdfNoise {
            size,
            level,
            mips: true,
        } => (level + 1..=size.trailing_zeros())
            .map(|k| crate::ndf::sources::noise(ctx.scene, size, k))
            .collect(),
        _ => Ok(Vec::new()),
    }
}

/// The texture memory's key of the texture of `source` stored in `texel` words (as indices
/// into a palette of `palette` entries): units asking for one key share one texture.
pub(super) fn key(source: &TextureSource, texel: &Encoding, palette: Option<u32>) -> String {
    format!("{source:?} {texel:?} palette {palette:?}")
}

/// A `size` x `size` texture of `lanes` lanes.
fn square(size: u32, lanes: u8, values: Vec<[f64; 4]>) -> Texels {
    Texels {
        width: size,
        height: size,
        lanes,
        values,
    }
}

/// The scene's bump map baked to `size` x `size` heights (as they are, not normalised).
pub(super) fn heights(ctx: &BuildCtx, size: u32) -> Result<Vec<f64>, String> {
    scene_heights(ctx.scene, size)
}

/// [`heights`] of a scene.
pub(super) fn scene_heights(scene: &Scene, size: u32) -> Result<Vec<f64>, String> {
    scene.bump.bake_heights(size, size).ok_or_else(|| {
        "the scene's bump map holds normals, not heights: expected a height map".into()
    })
}

/// Smallest and largest height.
pub(super) fn height_range(h: &[f64]) -> (f64, f64) {
    h.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// Heights rescaled to [0, 1] over the map's range (a constant map becomes 0.5).
pub(super) fn normalise_heights(h: &[f64]) -> Vec<f64> {
    let (lo, hi) = height_range(h);
    if hi - lo < 1e-300 {
        return vec![0.5; h.len()];
    }
    h.iter().map(|x| (x - lo) / (hi - lo)).collect()
}

#[cfg(test)]
mod tests {
    use super::cube_direction;
    use bumpsim_hw::sampler::cube_face;

    #[test]
    fn cube_directions_invert_the_face_table() {
        // every texel centre of every face of an 8 x 8 cube map, and the corners' neighbours
        let n = 8.0;
        for face in 0..6 {
            for j in 0..8 {
                for i in 0..8 {
                    let (s, t) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                    let d = cube_direction(face, s, t);
                    let (f, s2, t2) = cube_face(d.to_array());
                    assert_eq!(f, face, "{face} {i} {j} {d}");
                    assert!(
                        (s2 - s).abs() < 1e-12 && (t2 - t).abs() < 1e-12,
                        "{face} {i} {j}"
                    );
                }
            }
        }
        // neighbouring faces meet: +X's edge s = 1 is -Z's edge s = 0 (x = 1, z = -1), -X's
        // edge s = 1 is +Z's edge s = 0 (x = -1, z = 1)
        assert_eq!(cube_direction(0, 1.0, 0.5), cube_direction(5, 0.0, 0.5));
        assert_eq!(cube_direction(1, 1.0, 0.5), cube_direction(4, 0.0, 0.5));
    }
}
