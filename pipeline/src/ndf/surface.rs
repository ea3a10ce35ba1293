//! The synthesised surface (Kautz et al. §3.3, §4): turbulence → indices `(r1, r2)` → `G`
//! → `M^-1`, `C^-1` → microfacet normal, with the NDF that also shades it. This is the scene's
//! bump map `Ndf(...)`; the float reference evaluates it per pixel ([`NdfSurface::normal`]),
//! the texture sources build the noise mip levels, `L` and the NDF textures from it.

use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::Path;

use super::ndf::{Distribution, Ndf, NdfSpec, MAX_MAP_SIDE, MIN_MAP_SIDE};
use super::noise::{NoiseMode, Turbulence, MAX_OCTAVES};
use super::tables::{tangent_frame, Lookup, NdfTables, NoiseCdf};
use crate::scene::{Scene, SceneError};

/// Largest first-octave lattice frequency (cells per unit of texture coordinate).
pub const MAX_FREQUENCY: u32 = 1 << 12;

/// The fields of the scene's `bump: Ndf(...)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SynthesisSpec {
    /// The NDF that distributes the normals and shades them.
    pub ndf: NdfSpec,
    /// `Ndf` (the method) or `Uniform` (Fig. 4 right's counter-example; shading still uses
    /// the NDF).
    #[serde(default)]
    pub normals: Distribution,
    /// Octaves of turbulence at the finest level, 1 to 12.
    pub octaves: u32,
    /// Lattice cells per unit of texture coordinate of the first (coarsest) octave, 1 to 4096;
    /// `frequency * 2^(octaves - 1)` at most 4096.
    pub frequency: u32,
    /// Permutation seed of r1 (r2 uses `seed + 1`); 0 is Perlin's permutation.
    #[serde(default)]
    pub seed: u64,
    /// Side of the NDF's hemispherical map (a power of two, 8 to 1024; 128 by default; a
    /// PNG NDF's own side wins).
    #[serde(default = "map_size")]
    pub map_size: u32,
}

fn map_size() -> u32 {
    128
}

/// The built surface.
#[derive(Debug, Clone)]
pub struct NdfSurface {
    pub spec: SynthesisSpec,
    pub ndf: Ndf,
    pub turbulence: Turbulence,
    /// The noise value mapped to index 0 and 1 is `∓ spread` (4 standard deviations of the
    /// measured turbulence): `r = clamp(1/2 + n / (2 spread), 0, 1)`.
    pub spread: f64,
    /// `g` and `G` of the indices.
    pub g: NoiseCdf,
    pub tables: NdfTables,
    /// The far level's microfacet samples, built on first use.
    far: std::sync::OnceLock<Vec<DVec3>>,
}

/// `field`'s rule broken.
fn bad(field: &str, msg: String) -> SceneError {
    SceneError::invalid(field.to_string(), msg)
}

impl SynthesisSpec {
    /// Check the fields (errors name `bump.Ndf.<field>` and the rule) and build the tables.
    pub fn build(&self, base_dir: &Path) -> Result<NdfSurface, SceneError> {
        let f = "bump.Ndf";
        if !(1..=MAX_OCTAVES).contains(&self.octaves) {
            return Err(bad(
                &format!("{f}.octaves"),
                format!("{}: expected 1 to {MAX_OCTAVES} octaves", self.octaves),
            ));
        }
        if !(1..=MAX_FREQUENCY).contains(&self.frequency) {
            return Err(bad(
                &format!("{f}.frequency"),
                format!("{}: expected 1 to {MAX_FREQUENCY} cells", self.frequency),
            ));
        }
        let finest = u64::from(self.frequency) << (self.octaves - 1);
        if finest > u64::from(MAX_FREQUENCY) {
            return Err(bad(
                &format!("{f}.octaves"),
                format!(
                    "frequency * 2^(octaves - 1) = {finest} cells: expected at most {MAX_FREQUENCY}"
                ),
            ));
        }
        let m = self.map_size;
        if !m.is_power_of_two() || !(MIN_MAP_SIDE..=MAX_MAP_SIDE).contains(&m) {
            return Err(bad(
                &format!("{f}.map_size"),
                format!("{m}: expected a power of two from {MIN_MAP_SIDE} to {MAX_MAP_SIDE}"),
            ));
        }
        let ndf = self.ndf.build(&format!("{f}.ndf"), base_dir)?;
        let turbulence = Turbulence::new(self.frequency, self.seed);
        // measure on a grid of about 4 samples per cell of the finest octave
        let side = (4 * finest).clamp(256, 1024) as u32;
        let mut raw = Vec::with_capacity(2 * (side * side) as usize);
        for j in 0..side {
            for i in 0..side {
                let u = (f64::from(i) + 0.5) / f64::from(side);
                let v = (f64::from(j) + 0.5) / f64::from(side);
                raw.extend(turbulence.eval(NoiseMode::Exact, u, v, self.octaves));
            }
        }
        let var = raw.iter().map(|x| x * x).sum::<f64>() / raw.len() as f64;
        let spread = 4.0 * var.sqrt().max(1e-9);
        let g = NoiseCdf::measure(raw.iter().map(|&n| index(n, spread)));
        let side = match &ndf.spec {
            NdfSpec::Png { .. } => ndf.image_side().unwrap_or(m),
            _ => m,
        };
        let map = ndf.map(side, self.normals);
        let tables = NdfTables::new(side, &map);
        Ok(NdfSurface {
            spec: self.clone(),
            ndf,
            turbulence,
            spread,
            g,
            tables,
            far: Default::default(),
        })
    }
}

/// A noise value as an index in [0, 1].
pub fn index(n: f64, spread: f64) -> f64 {
    (0.5 + n / (2.0 * spread)).clamp(0.0, 1.0)
}

impl NdfSurface {
    /// The indices `(r1, r2)` at `(u, v)` over `octaves` octaves (fractional: the next octave
    /// blended in), exact.
    pub fn indices(&self, u: f64, v: f64, octaves: f64) -> [f64; 2] {
        [0, 1].map(|w| index(self.turbulence.exact(w, u, v, octaves), self.spread))
    }

    /// The microfacet normal for indices `(r1, r2)`: `expand(M^-1(G(r1)), C^-1(G(r2) | x))`.
    pub fn normal_of(&self, r: [f64; 2]) -> DVec3 {
        self.tables.sample(self.g.g(r[0]), self.g.g(r[1]))
    }

    /// The exact tangent-space normal at `(u, v)` with every octave (the float reference).
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        self.normal_of(self.indices(u, v, f64::from(self.spec.octaves)))
    }

    /// Octaves of mip level `level`: the finest holds them all, "every coarser mipmap level
    /// contains one octave less" (§5.2.2), down to 0 (the index 1/2, normal ≈ (0, 0, 1)).
    pub fn level_octaves(&self, level: u32) -> u32 {
        self.spec.octaves.saturating_sub(level)
    }

    /// Texels `[0, r1, r2, 0]` (the noise texture: "the green and blue component contain r1
    /// and r2") of mip level `level` of a chain whose finest level is `side` texels a side.
    pub fn noise_level(&self, side: u32, level: u32) -> (u32, Vec<[f64; 4]>) {
        let s = (side >> level).max(1);
        let oct = self.level_octaves(level);
        let mut out = Vec::with_capacity((s * s) as usize);
        for j in 0..s {
            for i in 0..s {
                let u = (f64::from(i) + 0.5) / f64::from(s);
                let v = (f64::from(j) + 0.5) / f64::from(s);
                let r = if oct == 0 {
                    [0.5; 2]
                } else {
                    self.indices(u, v, f64::from(oct))
                };
                out.push([0.0, r[0], r[1], 0.0]);
            }
        }
        (s, out)
    }

    /// The lookup table `L` of `size x size` entries.
    pub fn lookup(&self, size: u32) -> Lookup {
        Lookup::new(size, &self.g, &self.tables)
    }

    /// The NDF shading value of microfacet normal `n` (unit, any frame) for the unit
    /// half-way vector `h` in the same frame: `D(h_m) / max D` with `h_m` = `h` in the
    /// microfacet's frame (§5.1: "project the half-way vector h into the microfacet's tangent
    /// frame"); the frame's tangent is `tangent` made orthogonal to `n`.
    pub fn shade(&self, n: DVec3, h: DVec3, tangent: DVec3) -> f64 {
        let c = n.dot(h);
        if self.ndf.is_isotropic() {
            return self.ndf.relative_iso(c);
        }
        let t = (tangent - n * n.dot(tangent)).normalize_or_zero();
        let t = if t == DVec3::ZERO {
            tangent_frame(n).0
        } else {
            t
        };
        let b = n.cross(t);
        self.ndf.relative(DVec3::new(h.dot(t), h.dot(b), c))
    }

    /// The float reference's colour of the synthesised surface at world position `p` with
    /// world microfacet normal `n` and view vector `v`: `ambient + Σ_lights a_i color_i ⊙
    /// specular · shade(n, H_i)` clamped to [0, 1] (the NDF only, as the hardware path's
    /// texture: §6 "All our renderings were done with the NDF only"). `tangent` is the
    /// surface's world `u` direction (the tangent frame's `T`), which the microfacet frame's
    /// tangent is made orthogonal to, as the engines do with `u` in tangent space.
    pub fn shade_colour(
        &self,
        n: DVec3,
        p: DVec3,
        v: DVec3,
        tangent: DVec3,
        scene: &Scene,
    ) -> DVec3 {
        let m = &scene.material;
        let mut c = DVec3::from(m.ambient);
        for light in &scene.lights {
            let h = (light.dir_from(p) + v).normalize_or_zero();
            let d = self.shade(n, h, tangent);
            c += light.color() * light.attenuation(p) * DVec3::from(m.specular) * d;
        }
        c.clamp(DVec3::ZERO, DVec3::ONE)
    }

    /// The mean NDF shading of a patch of `side²` texture coordinates at mip level `level`
    /// (its octaves) for a half-way vector tilted by `theta_h` radians from the macro normal
    /// toward `x`: the level-of-detail measure of `docs/studies/ndf-synthesis.md`.
    pub fn patch_shading(&self, level: u32, side: u32, theta_h: f64) -> f64 {
        let h = DVec3::new(theta_h.sin(), 0.0, theta_h.cos());
        let oct = self.level_octaves(level);
        let mut sum = 0.0;
        for j in 0..side {
            for i in 0..side {
                let u = (f64::from(i) + 0.5) / f64::from(side);
                let v = (f64::from(j) + 0.5) / f64::from(side);
                let r = if oct == 0 {
                    [0.5; 2]
                } else {
                    self.indices(u, v, f64::from(oct))
                };
                sum += self.shade(self.normal_of(r), h, DVec3::X);
            }
        }
        sum / f64::from(side * side)
    }

    /// The far level's shading of a flat surface, consistent with the bump levels: the mean
    /// of `D(h_m) / max D` over microfacet normals `m` distributed by the NDF, for the
    /// half-way vector at `cos θ_h = c` from the macro normal (isotropic NDFs). Shading
    /// microfacets distributed by `D` with `D` itself averages to the self-convolution of `D`,
    /// not to `D` (`docs/studies/ndf-synthesis.md`, "Shading consistency"), so a far level
    /// that shades the flat surface with the plain NDF, as §5.1 prescribes, is brighter and
    /// narrower than the bump levels before it. The normals are the tables' samples of a
    /// stratified `FAR_SAMPLES²` grid of uniform numbers (the exact inverse CDFs, not `L`).
    pub fn far_relative(&self, c: f64) -> f64 {
        let c = c.clamp(-1.0, 1.0);
        let h = DVec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
        let normals = self.far_normals();
        normals
            .iter()
            .map(|&m| self.ndf.relative_iso(m.dot(h)))
            .sum::<f64>()
            / normals.len() as f64
    }

    /// The flat far level's shading for a half-way vector tilted by `theta_h` radians from
    /// the macro normal toward `x`, as the texture-shader program computes it there: the
    /// normal `L(1/2, 1/2)` of the level's indices dotted with `h`, read in the far NDF.
    /// Beside [`NdfSurface::patch_shading`] in the study.
    pub fn far_shading(&self, theta_h: f64) -> f64 {
        let h = DVec3::new(theta_h.sin(), 0.0, theta_h.cos());
        self.far_relative(self.normal_of([0.5; 2]).dot(h))
    }

    /// The microfacet normals [`NdfSurface::far_relative`] averages over (built once).
    fn far_normals(&self) -> &[DVec3] {
        self.far.get_or_init(|| {
            let k = FAR_SAMPLES;
            (0..k * k)
                .map(|n| {
                    let (i, j) = (n % k, n / k);
                    self.tables.sample(
                        (f64::from(i) + 0.5) / f64::from(k),
                        (f64::from(j) + 0.5) / f64::from(k),
                    )
                })
                .collect()
        })
    }
}

/// Strata per axis of the far level's microfacet samples ([`NdfSurface::far_relative`]).
pub const FAR_SAMPLES: u32 = 64;
