//! The textures of the hardware path (Kautz et al. §5.2.2: "We load the noise texture into
//! texture unit 0 (the green and blue component contain r1 and r2), the lookup texture
//! L(r1, r2) into texture unit 1, and the NDF into texture unit 3"), built from the scene's
//! `bump: Ndf(...)` for the engine's texture memory (`TextureSource::Ndf*`).

use bumpsim_hw::units::Texels;
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::surface::NdfSurface;
use crate::scene::{BumpMap, Scene};

/// Largest side of the lookup table `L`.
pub const MAX_LOOKUP_SIDE: u32 = 1024;
/// Largest side of the NDF texture.
pub const MAX_SHADING_SIDE: u32 = 1024;

/// How an entry of `L` is stored, for the DOT_PRODUCT stage's mapping: the source writes the
/// value that the mapping expands back to the normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LookupEntry {
    /// 3 lanes, 8-bit unsigned (`UnitUnsigned`) read by `Minus1To1Gl`: value
    /// `(n + 1) / 2 - 1/510`, so that `(2 c + 1) / 255 - 1` of the code is `n`.
    #[default]
    Rgb8,
    /// 2 lanes, 16-bit unsigned (`UnitUnsigned`) read by `HiloHemisphereGl` (`z`
    /// reconstructed by the stage): value `(n + 1) / 2 - 1/131070` for `n_x`, `n_y`.
    Hilo16,
    /// 3 lanes, `Rgb8` of the microfacet tangent `t_m` (the anisotropic variant's second
    /// table).
    Tangent8,
    /// 3 lanes, signed (`UnitSigned`, any width): the normal's components as they are
    /// (clamped to the codec's range), for units that read signed texels without a mapping
    /// (`Dot3`).
    Signed,
    /// `Signed` of the microfacet tangent `t_m`.
    TangentSigned,
}

/// The scene's synthesised surface, or the error of a source that needs one.
pub fn surface<'a>(scene: &'a Scene, what: &str) -> Result<&'a NdfSurface, String> {
    match &scene.bump {
        BumpMap::Ndf(s) => Ok(s),
        _ => Err(format!(
            "{what} needs the scene's bump to be Ndf(...) (NDF bump map synthesis): found another bump map"
        )),
    }
}

fn side(field: &str, size: u32, max: u32) -> Result<(), String> {
    if size.is_power_of_two() && (1..=max).contains(&size) {
        Ok(())
    } else {
        Err(format!(
            "{field} {size}: expected a power of two from 1 to {max}"
        ))
    }
}

/// Mip level `level` of the noise texture whose finest level is `size` texels a side: 3
/// lanes `(0, r1, r2)`, `level_octaves(level)` octaves.
pub fn noise(scene: &Scene, size: u32, level: u32) -> Result<Texels, String> {
    let s = surface(scene, "NdfNoise")?;
    side("size", size, 4096)?;
    if level > size.trailing_zeros() {
        return Err(format!(
            "level {level}: expected 0 to log2(size) = {}",
            size.trailing_zeros()
        ));
    }
    let finest = u64::from(s.spec.frequency) << (s.spec.octaves - 1);
    if finest * 2 > u64::from(size) {
        return Err(format!(
            "size {size}: the finest octave has {finest} cells per unit: expected a noise texture of at least 2 texels per cell ({} texels)",
            finest * 2
        ));
    }
    let (n, values) = s.noise_level(size, level);
    Ok(Texels {
        width: n,
        height: n,
        lanes: 3,
        values,
    })
}

/// The stored value of a normal component `x` in [-1, 1] for the GL expansion of `bits`-bit
/// codes.
fn gl_value(x: f64, bits: u32) -> f64 {
    ((x + 1.0) / 2.0 - 0.5 / f64::from((1u32 << bits) - 1)).clamp(0.0, 1.0)
}

/// The lookup table `L` of `size x size` entries in `entry` form.
pub fn lookup(scene: &Scene, size: u32, entry: LookupEntry) -> Result<Texels, String> {
    let s = surface(scene, "NdfLookup")?;
    side("size", size, MAX_LOOKUP_SIDE)?;
    let l = s.lookup(size);
    let (lanes, values) = match entry {
        LookupEntry::Rgb8 => (3, l.normals.iter().map(|n| rgb8(*n)).collect()),
        LookupEntry::Tangent8 => (3, l.tangents.iter().map(|n| rgb8(*n)).collect()),
        LookupEntry::Signed => (3, l.normals.iter().map(|n| signed(*n)).collect()),
        LookupEntry::TangentSigned => (3, l.tangents.iter().map(|n| signed(*n)).collect()),
        LookupEntry::Hilo16 => (
            2,
            l.normals
                .iter()
                .map(|n| [gl_value(n.x, 16), gl_value(n.y, 16), 0.0, 0.0])
                .collect(),
        ),
    };
    Ok(Texels {
        width: size,
        height: size,
        lanes,
        values,
    })
}

fn signed(n: DVec3) -> [f64; 4] {
    [n.x, n.y, n.z, 0.0]
}

fn rgb8(n: DVec3) -> [f64; 4] {
    [gl_value(n.x, 8), gl_value(n.y, 8), gl_value(n.z, 8), 0.0]
}

/// The colour of NDF value `d` in [0, 1] for light `light`: `ambient + color ⊙ specular d`,
/// clamped (the material's diffuse is not used: "All our renderings were done with the NDF
/// only", §6).
pub fn colour(scene: &Scene, light: usize, d: f64) -> Result<[f64; 4], String> {
    let l = scene.light(light)?;
    let (m, c) = (&scene.material, l.color());
    let mut v = [0.0; 4];
    for k in 0..3 {
        v[k] = (m.ambient[k] + c[k] * m.specular[k] * d).clamp(0.0, 1.0);
    }
    Ok(v)
}

/// The isotropic NDF as a 1-D texture of `size` texels (height 1) at `s = n_m · h`: texel
/// `i` holds the colour of `D(θ) / max D` at `cos θ = (i + 1/2) / size` (§5.2.2: "we store
/// the isotropic NDF p_i(n_m · h) in a 1D texture"). Read with `address: Clamp`. An
/// anisotropic NDF is an error that says why. `far`: the far level's shading
/// `NdfSurface::far_relative` in place of `D / max D`.
pub fn shading_1d(scene: &Scene, size: u32, light: usize, far: bool) -> Result<Texels, String> {
    let s = surface(scene, "NdfShading")?;
    side("size", size, MAX_SHADING_SIDE)?;
    if !s.ndf.is_isotropic() {
        return Err(format!(
            "the NDF {:?} is anisotropic: a 1-D texture at n_m . h holds isotropic NDFs only; \
             an anisotropic NDF is looked up at (n_m . h, t_m . h), which needs the microfacet \
             tangent from a second DEPENDENT_GB lookup and a second dot product, one stage more \
             than the 4 of the GeForce3 (Kautz et al. 5.2.1: \"since the texture shaders only \
             support four stages, we can perform shading with isotropic NDFs only\"): use \
             NdfShading2d on a 5-stage part",
            s.ndf.spec
        ));
    }
    let n = f64::from(size);
    let d = |c: f64| {
        if far {
            s.far_relative(c)
        } else {
            s.ndf.relative_iso(c)
        }
    };
    let values = (0..size)
        .map(|i| colour(scene, light, d((f64::from(i) + 0.5) / n)))
        .collect::<Result<_, _>>()?;
    Ok(Texels {
        width: size,
        height: 1,
        lanes: 3,
        values,
    })
}

/// The NDF as a 2-D texture at `(s, t) = (n_m · h, |t_m · h|)` for anisotropic NDFs that are
/// even in `b_m · h` (Ward's): texel `(i, j)` holds the colour of `D(h_m) / max D` at `h_m =
/// (t, ±sqrt(1 - s² - t²), s)` with `s = (i + 1/2) / size`, `t = (j + 1/2) / size` (0 where
/// `s² + t² > 1`). Read with `address: Mirror` (so `t_m · h < 0` reads `|t_m · h|`).
pub fn shading_2d(scene: &Scene, size: u32, light: usize) -> Result<Texels, String> {
    let s = surface(scene, "NdfShading2d")?;
    side("size", size, MAX_SHADING_SIDE)?;
    let n = f64::from(size);
    let mut values = Vec::with_capacity((size * size) as usize);
    for j in 0..size {
        for i in 0..size {
            let (c, t) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
            let r = 1.0 - c * c - t * t;
            let d = if r < 0.0 {
                0.0
            } else {
                s.ndf.relative(DVec3::new(t, r.sqrt(), c))
            };
            values.push(colour(scene, light, d)?);
        }
    }
    Ok(Texels {
        width: size,
        height: size,
        lanes: 3,
        values,
    })
}
