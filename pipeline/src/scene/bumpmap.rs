//! Bump maps: procedural and image height fields, and tangent-space normal maps.
//!
//! # Units and conventions
//!
//! * Every height field tiles with period 1 in `u` and in `v`; the mesh's `uv_repeat`
//!   produces the repetition over a surface.
//! * Heights are in *texture-space units*: the tangent-space perturbed normal for orthonormal
//!   unit `Pu`, `Pv` is `normalize(-F_u, -F_v, 1)` (Ernst 1998 Eq. 1 with k = 1, equal to
//!   Blinn's `N + D` on a unit-parameterised flat quad). A ramp rising by `depth` over a whole
//!   tile therefore has slope `depth`; a feature of width `1/n` and height `depth` has slope of
//!   the order of `n * depth`.
//! * Image maps (PNG) put PNG row 0 (the top) at `v` in `[0, 1/h)`: `v` increases down the
//!   image (see `normals`).

use std::fmt;
use std::path::Path;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::centre_grads::CentreGrads;
use super::check_count;
use super::normals::{is_16bit, read_png};
use super::{NormalMap, NormalMethod, SceneError};

/// A scalar height field `F(u, v)`, periodic with period 1 in `u` and `v`.
pub trait HeightField: Send + Sync {
    /// `F(u, v)` in texture-space units.
    fn height(&self, u: f64, v: f64) -> f64;
    /// `(∂F/∂u, ∂F/∂v)`, analytic where possible.
    fn grad(&self, u: f64, v: f64) -> DVec2;
    /// `grad` at every texel centre of a `w x h` map, if the field has a cheaper way to
    /// compute them than one call per texel (bit-identical to those calls).
    fn centre_grads(&self, _w: u32, _h: u32) -> Option<CentreGrads> {
        None
    }
}

/// A bump map as written in a scene config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum BumpSpec {
    /// No bumps: `F = 0`, every normal `(0, 0, 1)`.
    Flat,
    /// Running-bond brick wall: `rows` courses of `cols` bricks per unit square, odd rows
    /// shifted by half a brick. The brick faces are at height `depth`, the mortar at 0, joined
    /// by a smoothstep bevel so the gradient is finite everywhere.
    Bricks {
        /// Courses per unit `v`; even (>= 2) so that the running bond tiles.
        rows: u32,
        /// Bricks per course per unit `u` (>= 1).
        cols: u32,
        /// Mortar joint width as a fraction of the brick height `1/rows` (>= 0). The same
        /// absolute width is used for the vertical joints.
        mortar: f64,
        /// Width of the smoothstep bevel from mortar to face on each side of a joint, as a
        /// fraction of the brick height (> 0). Needs `mortar + 2 bevel <= 1` and
        /// `(mortar + 2 bevel) / rows <= 1 / cols`.
        bevel: f64,
        /// Face height above the mortar, texture-space units (finite; negative engraves).
        depth: f64,
    },
    /// A lattice of Ricker wavelets ("Mexican hats", Ernst 1998 Fig. 9),
    /// `depth * (1 - r²/σ²) exp(-r²/(2σ²))` centred in every cell and summed over the
    /// neighbouring cells, so the field tiles seamlessly.
    MexicanHat {
        /// Cells per unit square along each axis (>= 1).
        cells: u32,
        /// Wavelet width `σ` as a fraction of the cell size, in (0, 0.5].
        sigma: f64,
        /// Height of the central peak, texture-space units (finite).
        depth: f64,
    },
    /// One spherical cap per cell (Ernst 1998 Fig. 4): a hemisphere profile
    /// `depth * sqrt(1 - t²)` with `t = r / radius`, rolled off to 0 by a smoothstep over
    /// `t` in [0.8, 1] so that the gradient stays finite at the rim.
    SphereCaps {
        /// Cells per unit square along each axis (>= 1).
        cells: u32,
        /// Cap radius as a fraction of the cell size, in (0, 0.5].
        radius: f64,
        /// Cap height at the centre, texture-space units (finite).
        depth: f64,
    },
    /// Perlin improved noise (2002) as fBm: `depth * Σ_k 0.5^k n(2^k f u, 2^k f v)` for
    /// `k < octaves`, each octave's lattice wrapped at `2^k f` cells so the sum has period 1.
    Noise {
        /// Number of octaves, 1..=16.
        octaves: u32,
        /// Lattice cells per unit for the first octave, >= 1; `frequency * 2^(octaves-1)`
        /// must not exceed 2^24.
        frequency: u32,
        /// Amplitude of the first octave, texture-space units (finite).
        depth: f64,
        /// Permutation seed: 0 is Perlin's reference permutation, any other value shuffles
        /// it (Fisher-Yates driven by SplitMix64).
        seed: u64,
    },
    /// Heights from an 8/16-bit grey PNG (RGB converted to Rec. 709 luminance
    /// `0.2126 R + 0.7152 G + 0.0722 B`; alpha ignored): `depth * value / max`, sampled
    /// bilinearly with wrap; the gradient is the central difference of the bilinear
    /// interpolant at texel spacing.
    HeightPng {
        /// File path, relative to the scene's directory.
        path: String,
        /// Height of a white texel, texture-space units (finite).
        depth: f64,
    },
    /// A tangent-space normal map PNG, RGB `c / max * 2 - 1`, renormalised (see
    /// [`NormalMap::from_png`] for the channel conventions).
    NormalPng {
        /// File path, relative to the scene's directory.
        path: String,
    },
    /// The face-space normal map baked with the mesh: needs `mesh: Baked(...)`
    /// (`crate::wang::scene`).
    Baked,
    /// NDF-based bump map synthesis (Kautz et al. 2001): normals from turbulence through the
    /// inverse CDFs of `ndf`, shaded with the same NDF (`crate::ndf`, `docs/units/ndf.md`;
    /// the fields are those of [`crate::ndf::SynthesisSpec`]).
    Ndf {
        ndf: crate::ndf::NdfSpec,
        #[serde(default)]
        normals: crate::ndf::Distribution,
        octaves: u32,
        frequency: u32,
        #[serde(default)]
        seed: u64,
        #[serde(default = "ndf_map_size")]
        map_size: u32,
    },
}

fn ndf_map_size() -> u32 {
    128
}

/// A built bump map.
pub enum BumpMap {
    Height(Box<dyn HeightField>),
    Normals(NormalMap),
    /// A synthesised surface, shaded with its NDF (`crate::ndf`).
    Ndf(Box<crate::ndf::NdfSurface>),
}

impl fmt::Debug for BumpMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BumpMap::Height(field) => write!(
                f,
                "BumpMap::Height(F(0.5, 0.5) = {}, ∇F(0.5, 0.5) = {})",
                field.height(0.5, 0.5),
                field.grad(0.5, 0.5)
            ),
            BumpMap::Normals(m) => write!(f, "BumpMap::Normals({} x {})", m.width, m.height),
            BumpMap::Ndf(s) => write!(f, "BumpMap::Ndf({:?})", s.spec),
        }
    }
}

fn finite(field: String, name: &str, x: f64) -> Result<(), SceneError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("expected a finite {name}, found {x}"),
        ))
    }
}

fn fraction(field: String, x: f64, what: &str) -> Result<(), SceneError> {
    if x.is_finite() && x > 0.0 && x <= 0.5 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("expected {what} in (0, 0.5] of a cell, found {x}"),
        ))
    }
}

/// Largest cell or lattice count accepted.
const MAX_CELLS: u32 = 1 << 16;

impl BumpSpec {
    /// Check the parameters and build the map. `base_dir` resolves relative PNG paths.
    /// Errors name the field (`bump.<Variant>.<field>`) or the file.
    pub fn build(&self, base_dir: &Path) -> Result<BumpMap, SceneError> {
        match self {
            BumpSpec::Flat => Ok(BumpMap::Height(Box::new(FlatField))),
            &BumpSpec::Bricks {
                rows,
                cols,
                mortar,
                bevel,
                depth,
            } => {
                check_count("bump.Bricks.rows".into(), rows, 2, MAX_CELLS)?;
                if rows % 2 != 0 {
                    return Err(SceneError::invalid(
                        "bump.Bricks.rows",
                        format!("expected an even number so the running bond tiles, found {rows}"),
                    ));
                }
                check_count("bump.Bricks.cols".into(), cols, 1, MAX_CELLS)?;
                if !(mortar.is_finite() && mortar >= 0.0) {
                    return Err(SceneError::invalid(
                        "bump.Bricks.mortar",
                        format!(
                            "expected a finite fraction >= 0 of the brick height, found {mortar}"
                        ),
                    ));
                }
                if !(bevel.is_finite() && bevel > 0.0) {
                    return Err(SceneError::invalid(
                        "bump.Bricks.bevel",
                        format!(
                            "expected a finite fraction > 0 of the brick height, found {bevel}"
                        ),
                    ));
                }
                let bh = 1.0 / f64::from(rows);
                let bw = 1.0 / f64::from(cols);
                let joint = mortar + 2.0 * bevel;
                if joint > 1.0 || joint * bh > bw {
                    return Err(SceneError::invalid(
                        "bump.Bricks.bevel",
                        format!(
                            "mortar + 2 * bevel = {joint} brick heights leaves no flat face: it must \
                             be <= 1 and <= the brick width {} brick heights",
                            bw / bh
                        ),
                    ));
                }
                finite("bump.Bricks.depth".into(), "depth", depth)?;
                Ok(BumpMap::Height(Box::new(Bricks {
                    rows: f64::from(rows),
                    cols: f64::from(cols),
                    bw,
                    bh,
                    half_mortar: 0.5 * mortar * bh,
                    bevel: bevel * bh,
                    depth,
                })))
            }
            &BumpSpec::MexicanHat {
                cells,
                sigma,
                depth,
            } => {
                check_count("bump.MexicanHat.cells".into(), cells, 1, MAX_CELLS)?;
                fraction("bump.MexicanHat.sigma".into(), sigma, "a width")?;
                finite("bump.MexicanHat.depth".into(), "depth", depth)?;
                Ok(BumpMap::Height(Box::new(MexicanHat::new(
                    cells, sigma, depth,
                ))))
            }
            &BumpSpec::SphereCaps {
                cells,
                radius,
                depth,
            } => {
                check_count("bump.SphereCaps.cells".into(), cells, 1, MAX_CELLS)?;
                fraction("bump.SphereCaps.radius".into(), radius, "a radius")?;
                finite("bump.SphereCaps.depth".into(), "depth", depth)?;
                Ok(BumpMap::Height(Box::new(SphereCaps {
                    cells: f64::from(cells),
                    radius,
                    depth,
                })))
            }
            &BumpSpec::Noise {
                octaves,
                frequency,
                depth,
                seed,
            } => {
                check_count("bump.Noise.octaves".into(), octaves, 1, 16)?;
                check_count("bump.Noise.frequency".into(), frequency, 1, 1 << 24)?;
                if u64::from(frequency) << (octaves - 1) > 1 << 24 {
                    return Err(SceneError::invalid(
                        "bump.Noise.frequency",
                        format!(
                            "frequency * 2^(octaves - 1) = {} exceeds 2^24",
                            u64::from(frequency) << (octaves - 1)
                        ),
                    ));
                }
                finite("bump.Noise.depth".into(), "depth", depth)?;
                Ok(BumpMap::Height(Box::new(Noise {
                    octaves,
                    frequency,
                    depth,
                    perm: permutation(seed),
                })))
            }
            BumpSpec::HeightPng { path, depth } => {
                finite("bump.HeightPng.depth".into(), "depth", *depth)?;
                let full = base_dir.join(path);
                Ok(BumpMap::Height(Box::new(HeightImage::from_png(
                    &full, *depth,
                )?)))
            }
            BumpSpec::Baked => Err(SceneError::invalid(
                "bump.Baked",
                "expected mesh: Baked(...), whose bake makes this map; the mesh is not baked",
            )),
            BumpSpec::NormalPng { path } => {
                let full = base_dir.join(path);
                Ok(BumpMap::Normals(NormalMap::from_png(&full)?))
            }
            BumpSpec::Ndf {
                ndf,
                normals,
                octaves,
                frequency,
                seed,
                map_size,
            } => Ok(BumpMap::Ndf(Box::new(
                crate::ndf::SynthesisSpec {
                    ndf: ndf.clone(),
                    normals: *normals,
                    octaves: *octaves,
                    frequency: *frequency,
                    seed: *seed,
                    map_size: *map_size,
                }
                .build(base_dir)?,
            ))),
        }
    }
}

impl BumpMap {
    /// Exact tangent-space unit normal at `(u, v)` (wrap): `normalize(-F_u, -F_v, 1)` from the
    /// analytic gradient for height fields, bilinear + renormalise for normal maps. Used by
    /// the float reference.
    pub fn normal_ts(&self, u: f64, v: f64) -> DVec3 {
        match self {
            BumpMap::Height(f) => normal_from_grad(f.grad(u, v)),
            BumpMap::Normals(m) => m.sample_bilinear(u, v),
            BumpMap::Ndf(s) => s.normal(u, v),
        }
    }

    /// Height-field gradient at `(u, v)` if this is a height field (None for normal maps).
    pub fn grad(&self, u: f64, v: f64) -> Option<DVec2> {
        match self {
            BumpMap::Height(f) => Some(f.grad(u, v)),
            BumpMap::Normals(_) | BumpMap::Ndf(_) => None,
        }
    }

    /// Height-field gradients at the texel centres of a `w x h` map, where the field computes
    /// them faster than one [`Self::grad`] per texel (bit-identical); None otherwise and for
    /// normal maps.
    pub fn centre_grads(&self, w: u32, h: u32) -> Option<CentreGrads> {
        match self {
            BumpMap::Height(f) => f.centre_grads(w, h),
            BumpMap::Normals(_) | BumpMap::Ndf(_) => None,
        }
    }

    /// Heights sampled at texel centres `((i + 0.5)/w, (j + 0.5)/h)`, row-major, row `j = 0`
    /// is `v` in `[0, 1/h)`. None for normal maps.
    pub fn bake_heights(&self, w: u32, h: u32) -> Option<Vec<f64>> {
        match self {
            BumpMap::Height(f) => {
                let mut out = Vec::with_capacity(w as usize * h as usize);
                for (u, v) in texel_centres(w, h) {
                    out.push(f.height(u, v));
                }
                Some(out)
            }
            BumpMap::Normals(_) | BumpMap::Ndf(_) => None,
        }
    }

    /// A `w x h` tangent-space normal map: for height fields by `method` (`Analytic` uses the
    /// exact gradient at the texel centres, the others [`NormalMap::from_heights`] on
    /// [`BumpMap::bake_heights`]); for normal maps the map itself if the size matches, else
    /// bilinearly resampled at the new texel centres and renormalised (`method` is ignored).
    pub fn bake_normals(&self, w: u32, h: u32, method: NormalMethod) -> NormalMap {
        match self {
            BumpMap::Height(f) => {
                if method == NormalMethod::Analytic {
                    // each texel is its own pure function of its centre: baked in parallel
                    // (rows in order, so the map is the same at any thread count)
                    use rayon::prelude::*;
                    let grads = f.centre_grads(w, h);
                    let texels = (0..h)
                        .into_par_iter()
                        .flat_map_iter(|j| {
                            let grads = grads.as_ref();
                            texel_centres_row(w, h, j).zip(0..).map(move |((u, v), i)| {
                                let g = grads.and_then(|g| g.at(i, j));
                                normal_from_grad(g.unwrap_or_else(|| f.grad(u, v)))
                            })
                        })
                        .collect();
                    NormalMap {
                        width: w,
                        height: h,
                        texels,
                    }
                } else {
                    let heights = self.bake_heights(w, h).unwrap_or_default();
                    NormalMap::from_heights(&heights, w, h, method)
                }
            }
            BumpMap::Ndf(s) => NormalMap {
                width: w,
                height: h,
                texels: texel_centres(w, h).map(|(u, v)| s.normal(u, v)).collect(),
            },
            BumpMap::Normals(m) => {
                if m.width == w && m.height == h {
                    m.clone()
                } else {
                    let texels = texel_centres(w, h)
                        .map(|(u, v)| m.sample_bilinear(u, v))
                        .collect();
                    NormalMap {
                        width: w,
                        height: h,
                        texels,
                    }
                }
            }
        }
    }
}

/// `(u, v)` of the texel centres of a `w x h` map, row-major.
fn texel_centres(w: u32, h: u32) -> impl Iterator<Item = (f64, f64)> {
    (0..h).flat_map(move |j| texel_centres_row(w, h, j))
}

/// `(u, v)` of the texel centres of row `j` of a `w x h` map.
fn texel_centres_row(w: u32, h: u32, j: u32) -> impl Iterator<Item = (f64, f64)> {
    (0..w).map(move |i| {
        (
            (f64::from(i) + 0.5) / f64::from(w),
            (f64::from(j) + 0.5) / f64::from(h),
        )
    })
}

/// `normalize(-F_u, -F_v, 1)`; a non-finite gradient gives `(0, 0, 1)`.
fn normal_from_grad(g: DVec2) -> DVec3 {
    let n = DVec3::new(-g.x, -g.y, 1.0).normalize();
    if n.is_finite() {
        n
    } else {
        DVec3::Z
    }
}

/// `x` wrapped into `[0, 1)`. (`rem_euclid` can return exactly 1.0 for tiny negative x.)
fn wrap01(x: f64) -> f64 {
    let r = x.rem_euclid(1.0);
    if r >= 1.0 {
        0.0
    } else {
        r
    }
}

/// `x` in cell units, split into the integer cell and the fraction in `[0, 1)`.
fn cell_split(x: f64, cells: f64) -> (i64, f64) {
    let y = wrap01(x) * cells;
    let c = y.floor();
    let mut f = y - c;
    let mut c = c as i64;
    if f >= 1.0 {
        f = 0.0;
        c += 1;
    }
    (c, f)
}

fn smoothstep(x: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else {
        x * x * (3.0 - 2.0 * x)
    }
}

fn smoothstep_d(x: f64) -> f64 {
    if x <= 0.0 || x >= 1.0 {
        0.0
    } else {
        6.0 * x * (1.0 - x)
    }
}

struct FlatField;

impl HeightField for FlatField {
    fn height(&self, _u: f64, _v: f64) -> f64 {
        0.0
    }
    fn grad(&self, _u: f64, _v: f64) -> DVec2 {
        DVec2::ZERO
    }
}

/// Running-bond bricks; lengths in texture units.
struct Bricks {
    rows: f64,
    cols: f64,
    bw: f64,
    bh: f64,
    half_mortar: f64,
    bevel: f64,
    depth: f64,
}

impl Bricks {
    /// Per-axis profile: `(s, ds/du, s_v, ds_v/dv)` from the distances to the nearest joints.
    fn profile(&self, u: f64, v: f64) -> (f64, f64, f64, f64) {
        let (row, fy) = cell_split(v, self.rows);
        let (ev, sv) = if fy < 0.5 {
            (fy * self.bh, 1.0)
        } else {
            ((1.0 - fy) * self.bh, -1.0)
        };
        let shift = if row % 2 == 1 { 0.5 / self.cols } else { 0.0 };
        let (_, fx) = cell_split(u - shift, self.cols);
        let (eu, su) = if fx < 0.5 {
            (fx * self.bw, 1.0)
        } else {
            ((1.0 - fx) * self.bw, -1.0)
        };
        let xu = (eu - self.half_mortar) / self.bevel;
        let xv = (ev - self.half_mortar) / self.bevel;
        (
            smoothstep(xu),
            su * smoothstep_d(xu) / self.bevel,
            smoothstep(xv),
            sv * smoothstep_d(xv) / self.bevel,
        )
    }
}

impl HeightField for Bricks {
    fn height(&self, u: f64, v: f64) -> f64 {
        let (a, _, b, _) = self.profile(u, v);
        self.depth * a * b
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        let (a, da, b, db) = self.profile(u, v);
        DVec2::new(self.depth * da * b, self.depth * a * db)
    }
}

/// Ricker wavelets on a lattice, summed over the cells within reach.
struct MexicanHat {
    cells: f64,
    /// σ in cell units.
    sigma: f64,
    depth: f64,
    /// Neighbouring cells summed on each side of the cell holding the point.
    reach: i64,
}

/// Terms with `r²/σ² > CUTOFF` (`r > 12σ`) are below `143 e^-72` and are skipped.
const RICKER_CUTOFF: f64 = 144.0;

impl MexicanHat {
    fn new(cells: u32, sigma: f64, depth: f64) -> MexicanHat {
        // Cells further than `reach` are at least reach + 0.5 cells >= 12σ away.
        let reach = ((RICKER_CUTOFF.sqrt() * sigma - 0.5).ceil() as i64).max(1);
        MexicanHat {
            cells: f64::from(cells),
            sigma,
            depth,
            reach,
        }
    }

    /// `(Σψ, Σ∂ψ/∂x, Σ∂ψ/∂y)` in cell units.
    fn eval(&self, u: f64, v: f64) -> (f64, f64, f64) {
        self.eval_frac(cell_split(u, self.cells).1, cell_split(v, self.cells).1)
    }

    /// [`Self::eval`] at the fractions `(fx, fy)` within a cell.
    fn eval_frac(&self, fx: f64, fy: f64) -> (f64, f64, f64) {
        let inv_s2 = 1.0 / (self.sigma * self.sigma);
        let (mut h, mut gx, mut gy) = (0.0, 0.0, 0.0);
        for dj in -self.reach..=self.reach {
            let dy = fy - (dj as f64 + 0.5);
            for di in -self.reach..=self.reach {
                let dx = fx - (di as f64 + 0.5);
                let s = (dx * dx + dy * dy) * inv_s2;
                if s > RICKER_CUTOFF {
                    continue;
                }
                let e = (-0.5 * s).exp();
                h += (1.0 - s) * e;
                // dψ/ds = e (s - 3) / 2 and ds/dx = 2 x / σ².
                let k = e * (s - 3.0) * inv_s2;
                gx += k * dx;
                gy += k * dy;
            }
        }
        (h, gx, gy)
    }
}

impl HeightField for MexicanHat {
    fn height(&self, u: f64, v: f64) -> f64 {
        self.depth * self.eval(u, v).0
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        let (_, gx, gy) = self.eval(u, v);
        DVec2::new(gx, gy) * (self.depth * self.cells)
    }
    fn centre_grads(&self, w: u32, h: u32) -> Option<CentreGrads> {
        let split = |x| cell_split(x, self.cells).1;
        CentreGrads::lattice(w, h, split, |fx, fy| {
            let (_, gx, gy) = self.eval_frac(fx, fy);
            DVec2::new(gx, gy) * (self.depth * self.cells)
        })
    }
}

/// One cap per cell.
struct SphereCaps {
    cells: f64,
    /// Radius in cell units.
    radius: f64,
    depth: f64,
}

/// Start of the rim roll-off, as a fraction of the cap radius.
const CAP_ROLLOFF: f64 = 0.8;

impl SphereCaps {
    /// `(p(t), dp/dt)` for the cap profile `sqrt(1 - t²) (1 - smoothstep((t - 0.8) / 0.2))`.
    fn profile(t: f64) -> (f64, f64) {
        if t >= 1.0 {
            return (0.0, 0.0);
        }
        let root = (1.0 - t * t).sqrt();
        let x = (t - CAP_ROLLOFF) / (1.0 - CAP_ROLLOFF);
        let g = 1.0 - smoothstep(x);
        let dg = -smoothstep_d(x) / (1.0 - CAP_ROLLOFF);
        (root * g, -t / root * g + root * dg)
    }

    /// `(h, ∂h/∂u, ∂h/∂v)`.
    fn eval(&self, u: f64, v: f64) -> (f64, f64, f64) {
        self.eval_frac(cell_split(u, self.cells).1, cell_split(v, self.cells).1)
    }

    /// [`Self::eval`] at the fractions `(fx, fy)` within a cell.
    fn eval_frac(&self, fx: f64, fy: f64) -> (f64, f64, f64) {
        let (dx, dy) = (fx - 0.5, fy - 0.5);
        let r = (dx * dx + dy * dy).sqrt();
        let (p, dp) = Self::profile(r / self.radius);
        if r == 0.0 {
            return (self.depth * p, 0.0, 0.0);
        }
        // dt/dx = x / (r R) in cell units; d/du = cells * d/dx.
        let k = self.depth * dp / (r * self.radius) * self.cells;
        (self.depth * p, k * dx, k * dy)
    }
}

impl HeightField for SphereCaps {
    fn height(&self, u: f64, v: f64) -> f64 {
        self.eval(u, v).0
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        let (_, gu, gv) = self.eval(u, v);
        DVec2::new(gu, gv)
    }
    fn centre_grads(&self, w: u32, h: u32) -> Option<CentreGrads> {
        let split = |x| cell_split(x, self.cells).1;
        CentreGrads::lattice(w, h, split, |fx, fy| {
            let (_, gu, gv) = self.eval_frac(fx, fy);
            DVec2::new(gu, gv)
        })
    }
}

// Perlin's permutation for `seed` 0, else a Fisher-Yates shuffle of it driven by SplitMix64:
// the one the NDF noise unit uses.
use bumpsim_hw::units::ndf_noise::permutation;

/// fBm of periodic 2-D Perlin improved noise.
struct Noise {
    octaves: u32,
    frequency: u32,
    depth: f64,
    perm: [u8; 256],
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn fade_d(t: f64) -> f64 {
    30.0 * t * t * (t * (t - 2.0) + 1.0)
}

/// Perlin's 2002 `grad(hash, x, y, z)` at `z = 0`, as the vector `(gx, gy)` with
/// `grad = gx x + gy y`: the 12 cube-edge directions padded to 16, projected on `z = 0`.
fn grad_vec(hash: u8) -> DVec2 {
    let h = hash & 15;
    let mut g = DVec2::ZERO;
    let su = if h & 1 == 0 { 1.0 } else { -1.0 };
    let sv = if h & 2 == 0 { 1.0 } else { -1.0 };
    if h < 8 {
        g.x += su;
    } else {
        g.y += su;
    }
    if h < 4 {
        g.y += sv;
    } else if h == 12 || h == 14 {
        g.x += sv;
    } // else v = z = 0
    g
}

impl Noise {
    /// One octave of improved noise at `(x, y)` with the lattice wrapped at `period` cells:
    /// `(n, ∂n/∂x, ∂n/∂y)`. This is Perlin's 3-D improved noise on the plane `z = 0`
    /// (lattice `Z = 0`, where `fade(0) = 0` selects the `Z = 0` corners only).
    fn octave(&self, x: f64, y: f64, period: u64) -> (f64, f64, f64) {
        let (xf, yf) = (x.floor(), y.floor());
        let (fx, fy) = (x - xf, y - yf);
        let p = period as i64;
        let xi = (xf as i64).rem_euclid(p);
        let yi = (yf as i64).rem_euclid(p);
        let x1 = (xi + 1) % p;
        let y1 = (yi + 1) % p;
        let perm = &self.perm;
        // Perlin's p[p[p[X] + Y] + Z] with Z = 0 on the doubled table.
        let hash = |i: i64, j: i64| -> u8 {
            let a = perm[(i & 255) as usize] as usize + (j & 255) as usize;
            let b = perm[a & 255] as usize;
            perm[b & 255]
        };
        let g00 = grad_vec(hash(xi, yi));
        let g10 = grad_vec(hash(x1, yi));
        let g01 = grad_vec(hash(xi, y1));
        let g11 = grad_vec(hash(x1, y1));
        let n00 = g00.dot(DVec2::new(fx, fy));
        let n10 = g10.dot(DVec2::new(fx - 1.0, fy));
        let n01 = g01.dot(DVec2::new(fx, fy - 1.0));
        let n11 = g11.dot(DVec2::new(fx - 1.0, fy - 1.0));
        let (a, b) = (fade(fx), fade(fy));
        let (da, db) = (fade_d(fx), fade_d(fy));
        let lerp = |t: f64, p: f64, q: f64| p + t * (q - p);
        let r0 = lerp(a, n00, n10);
        let r1 = lerp(a, n01, n11);
        let n = lerp(b, r0, r1);
        // ∂/∂x: the corner terms' own x-derivatives are the gradient x-components.
        let r0x = da * (n10 - n00) + lerp(a, g00.x, g10.x);
        let r1x = da * (n11 - n01) + lerp(a, g01.x, g11.x);
        let nx = lerp(b, r0x, r1x);
        let r0y = lerp(a, g00.y, g10.y);
        let r1y = lerp(a, g01.y, g11.y);
        let ny = db * (r1 - r0) + lerp(b, r0y, r1y);
        (n, nx, ny)
    }

    /// `(F, F_u, F_v)`.
    fn eval(&self, u: f64, v: f64) -> (f64, f64, f64) {
        let (u, v) = (wrap01(u), wrap01(v));
        let (mut h, mut gu, mut gv) = (0.0, 0.0, 0.0);
        let mut amp = self.depth;
        for k in 0..self.octaves {
            let period = u64::from(self.frequency) << k;
            let f = period as f64;
            let (n, nx, ny) = self.octave(u * f, v * f, period);
            h += amp * n;
            gu += amp * f * nx;
            gv += amp * f * ny;
            amp *= 0.5;
        }
        (h, gu, gv)
    }
}

impl HeightField for Noise {
    fn height(&self, u: f64, v: f64) -> f64 {
        self.eval(u, v).0
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        let (_, gu, gv) = self.eval(u, v);
        DVec2::new(gu, gv)
    }
}

/// Heights from an image, sampled bilinearly with wrap.
struct HeightImage {
    w: u32,
    h: u32,
    /// `depth * value / max`, row-major.
    data: Vec<f64>,
}

impl HeightImage {
    fn from_png(path: &Path, depth: f64) -> Result<HeightImage, SceneError> {
        let img = read_png(path)?;
        let (w, h) = (img.width(), img.height());
        let grey = !img.color().has_color();
        let data: Vec<f64> = match (grey, is_16bit(&img)) {
            (true, true) => img
                .to_luma16()
                .pixels()
                .map(|p| depth * f64::from(p[0]) / 65535.0)
                .collect(),
            (true, false) => img
                .to_luma8()
                .pixels()
                .map(|p| depth * f64::from(p[0]) / 255.0)
                .collect(),
            (false, true) => img
                .to_rgb16()
                .pixels()
                .map(|p| depth * luminance(p.0.map(f64::from)) / 65535.0)
                .collect(),
            (false, false) => img
                .to_rgb8()
                .pixels()
                .map(|p| depth * luminance(p.0.map(f64::from)) / 255.0)
                .collect(),
        };
        Ok(HeightImage { w, h, data })
    }

    fn texel(&self, i: i64, j: i64) -> f64 {
        let i = i.rem_euclid(i64::from(self.w)) as usize;
        let j = j.rem_euclid(i64::from(self.h)) as usize;
        self.data[j * self.w as usize + i]
    }

    fn bilinear(&self, u: f64, v: f64) -> f64 {
        if !(u.is_finite() && v.is_finite()) {
            return 0.0;
        }
        let x = wrap01(u) * f64::from(self.w) - 0.5;
        let y = wrap01(v) * f64::from(self.h) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j) * (1.0 - fx) + self.texel(i + 1, j) * fx;
        let bottom = self.texel(i, j + 1) * (1.0 - fx) + self.texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// Rec. 709 luminance of (R, G, B) stored values.
fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl HeightField for HeightImage {
    fn height(&self, u: f64, v: f64) -> f64 {
        self.bilinear(u, v)
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        let du = 1.0 / f64::from(self.w);
        let dv = 1.0 / f64::from(self.h);
        DVec2::new(
            (self.bilinear(u + du, v) - self.bilinear(u - du, v)) / (2.0 * du),
            (self.bilinear(u, v + dv) - self.bilinear(u, v - dv)) / (2.0 * dv),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small deterministic generator for test points in [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn build(spec: &BumpSpec) -> BumpMap {
        spec.build(Path::new(".")).unwrap()
    }

    fn field(spec: &BumpSpec) -> Box<dyn HeightField> {
        match build(spec) {
            BumpMap::Height(f) => f,
            BumpMap::Normals(_) | BumpMap::Ndf(_) => panic!("not a height field"),
        }
    }

    fn procedural_specs() -> Vec<BumpSpec> {
        vec![
            BumpSpec::Bricks {
                rows: 8,
                cols: 4,
                mortar: 0.1,
                bevel: 0.15,
                depth: 0.01,
            },
            BumpSpec::MexicanHat {
                cells: 4,
                sigma: 0.15,
                depth: 0.02,
            },
            BumpSpec::MexicanHat {
                cells: 1,
                sigma: 0.5,
                depth: 0.1,
            },
            BumpSpec::SphereCaps {
                cells: 6,
                radius: 0.4,
                depth: 0.03,
            },
            BumpSpec::Noise {
                octaves: 4,
                frequency: 4,
                depth: 0.02,
                seed: 0,
            },
            BumpSpec::Noise {
                octaves: 3,
                frequency: 3,
                depth: 0.05,
                seed: 12345,
            },
        ]
    }

    #[test]
    fn gradients_match_central_differences_of_height() {
        let eps = 1e-7;
        for spec in procedural_specs() {
            let f = field(&spec);
            let mut rng = Lcg(7);
            let mut max_grad: f64 = 0.0;
            for _ in 0..2000 {
                let (u, v) = (rng.next(), rng.next());
                let g = f.grad(u, v);
                let num = DVec2::new(
                    (f.height(u + eps, v) - f.height(u - eps, v)) / (2.0 * eps),
                    (f.height(u, v + eps) - f.height(u, v - eps)) / (2.0 * eps),
                );
                let scale = g.length().max(1e-3);
                assert!(
                    (num - g).length() <= 1e-5 * scale,
                    "{spec:?} at ({u}, {v}): analytic {g}, numeric {num}"
                );
                max_grad = max_grad.max(g.length());
            }
            // The fields really are bumpy (the test above is not comparing zeros).
            assert!(max_grad > 0.05, "{spec:?}: max |grad| {max_grad}");
        }
    }

    #[test]
    fn fields_tile_with_period_one() {
        for spec in procedural_specs() {
            let f = field(&spec);
            let mut rng = Lcg(99);
            for _ in 0..500 {
                let (u, v) = (rng.next(), rng.next());
                let h = f.height(u, v);
                for (du, dv) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (3.0, -2.0)] {
                    let h2 = f.height(u + du, v + dv);
                    assert!(
                        (h - h2).abs() <= 1e-12,
                        "{spec:?} ({u},{v})+({du},{dv}): {h} vs {h2}"
                    );
                    let g = f.grad(u, v);
                    let g2 = f.grad(u + du, v + dv);
                    assert!(
                        (g - g2).length() <= 1e-9 * g.length().max(1.0),
                        "{spec:?} grad"
                    );
                }
            }
            // And across the seam: continuity between u = 1 - δ and u = δ.
            let d = 1e-9;
            for k in 0..20 {
                let t = f64::from(k) / 20.0 + 0.013;
                assert!(
                    (f.height(1.0 - d, t) - f.height(d, t)).abs() < 1e-6,
                    "{spec:?} seam u"
                );
                assert!(
                    (f.height(t, 1.0 - d) - f.height(t, d)).abs() < 1e-6,
                    "{spec:?} seam v"
                );
            }
        }
    }

    #[test]
    fn brick_heights_and_running_bond() {
        let f = field(&BumpSpec::Bricks {
            rows: 4,
            cols: 2,
            mortar: 0.2,
            bevel: 0.1,
            depth: 0.5,
        });
        // Row 0: bricks [0, 0.5) and [0.5, 1) in u; brick height 0.25 in v.
        assert_eq!(f.height(0.25, 0.125), 0.5); // face centre
        assert_eq!(f.height(0.5, 0.125), 0.0); // vertical joint of row 0
        assert_eq!(f.height(0.25, 0.0), 0.0); // horizontal joint
        assert_eq!(f.height(0.25, 0.25), 0.0);
        // Row 1 is shifted by half a brick: joint at u = 0.25, face at u = 0.5.
        assert_eq!(f.height(0.25, 0.375), 0.0);
        assert_eq!(f.height(0.5, 0.375), 0.5);
        // Half mortar = 0.1 * 0.25 = 0.025, bevel = 0.025: midway up the bevel the profile is
        // smoothstep(0.5) = 0.5 and the slope is depth * 1.5 / 0.025 = 30.
        let u = 0.5 + 0.025 + 0.0125;
        assert!((f.height(u, 0.125) - 0.25).abs() < 1e-12);
        assert!((f.grad(u, 0.125) - DVec2::new(30.0, 0.0)).length() < 1e-9);
        let u = 0.5 - 0.025 - 0.0125; // the other side of the joint slopes down toward it
        assert!((f.grad(u, 0.125) - DVec2::new(-30.0, 0.0)).length() < 1e-9);
        // v bevel near the bottom of row 0 (v just below 0.25): slope -30 in v.
        assert!((f.grad(0.25, 0.25 - 0.0375) - DVec2::new(0.0, -30.0)).length() < 1e-9);
    }

    #[test]
    fn mexican_hat_and_caps_values() {
        // σ = 0.1 cell: the neighbouring cells' tails are below 1e-13 everywhere used here.
        let f = field(&BumpSpec::MexicanHat {
            cells: 4,
            sigma: 0.1,
            depth: 0.02,
        });
        assert!((f.height(0.125, 0.125) - 0.02).abs() < 1e-14);
        assert!(f.grad(0.125, 0.375).length() < 1e-12); // centre of another cell
                                                        // At r = σ (in cell units; 0.1 / 4 in u) the wavelet crosses zero.
        let r = 0.1 / 4.0;
        assert!(f.height(0.125 + r, 0.125).abs() < 1e-14);
        // d/du there: depth * cells * e^-0.5 * (1 - 3) * σ / σ² = -0.02 * 4 * 2 e^-0.5 / 0.1.
        let want = -0.02 * 4.0 * 2.0 * (-0.5f64).exp() / 0.1;
        assert!((f.grad(0.125 + r, 0.125).x - want).abs() < 1e-10);
        // At r = sqrt(3) σ it is at its minimum: ψ = -2 e^-1.5 and the gradient vanishes.
        let r = 3f64.sqrt() * 0.1 / 4.0;
        let want = 0.02 * -2.0 * (-1.5f64).exp();
        assert!((f.height(0.125, 0.125 + r) - want).abs() < 1e-14);
        assert!(f.grad(0.125, 0.125 + r).length() < 1e-10);

        let c = field(&BumpSpec::SphereCaps {
            cells: 2,
            radius: 0.4,
            depth: 0.1,
        });
        assert!((c.height(0.25, 0.25) - 0.1).abs() < 1e-15);
        assert_eq!(c.grad(0.25, 0.25), DVec2::ZERO);
        // t = 0.5: r = 0.5 * 0.4 cells = 0.1 in u. h = depth sqrt(0.75),
        // dh/du = depth * (-t / sqrt(1 - t²)) / R_tex with R_tex = 0.4 / 2 = 0.2.
        let h = c.height(0.25 + 0.1, 0.25);
        assert!((h - 0.1 * 0.75f64.sqrt()).abs() < 1e-12, "{h}");
        let g = c.grad(0.25 + 0.1, 0.25);
        let want = 0.1 * (-0.5 / 0.75f64.sqrt()) / 0.2;
        assert!(
            (g.x - want).abs() < 1e-12 && g.y.abs() < 1e-15,
            "{g} vs {want}"
        );
        // Outside the cap (t >= 1) everything is 0, and the rim is smooth.
        assert_eq!(c.height(0.25 + 0.22, 0.25), 0.0);
        assert_eq!(c.grad(0.25 + 0.22, 0.25), DVec2::ZERO);
        assert!(c.grad(0.25 + 0.2 - 1e-9, 0.25).length() < 1e-6);
        let mut rng = Lcg(3);
        for _ in 0..1000 {
            assert!(c.grad(rng.next(), rng.next()).length() < 10.0);
        }
    }

    /// A literal port of Perlin's 2002 reference `noise(x, y, z)` for comparison.
    fn perlin_reference(x: f64, y: f64, z: f64) -> f64 {
        let p: Vec<usize> = (0..512).map(|i| permutation(0)[i % 256] as usize).collect();
        let (xi, yi, zi) = (
            (x.floor() as i64 & 255) as usize,
            (y.floor() as i64 & 255) as usize,
            (z.floor() as i64 & 255) as usize,
        );
        let (x, y, z) = (x - x.floor(), y - y.floor(), z - z.floor());
        let (u, v, w) = (fade(x), fade(y), fade(z));
        let grad = |hash: usize, x: f64, y: f64, z: f64| {
            let h = hash & 15;
            let u = if h < 8 { x } else { y };
            let v = if h < 4 {
                y
            } else if h == 12 || h == 14 {
                x
            } else {
                z
            };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        };
        let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
        let a = p[xi] + yi;
        let aa = p[a] + zi;
        let ab = p[a + 1] + zi;
        let b = p[xi + 1] + yi;
        let ba = p[b] + zi;
        let bb = p[b + 1] + zi;
        lerp(
            w,
            lerp(
                v,
                lerp(u, grad(p[aa], x, y, z), grad(p[ba], x - 1.0, y, z)),
                lerp(
                    u,
                    grad(p[ab], x, y - 1.0, z),
                    grad(p[bb], x - 1.0, y - 1.0, z),
                ),
            ),
            lerp(
                v,
                lerp(
                    u,
                    grad(p[aa + 1], x, y, z - 1.0),
                    grad(p[ba + 1], x - 1.0, y, z - 1.0),
                ),
                lerp(
                    u,
                    grad(p[ab + 1], x, y - 1.0, z - 1.0),
                    grad(p[bb + 1], x - 1.0, y - 1.0, z - 1.0),
                ),
            ),
        )
    }

    #[test]
    fn noise_matches_perlin_reference_on_z0() {
        let mut sorted = permutation(0);
        sorted.sort_unstable();
        assert!(sorted.iter().enumerate().all(|(i, &x)| x as usize == i));
        let mut shuffled = permutation(42);
        assert_ne!(shuffled, permutation(0));
        shuffled.sort_unstable();
        assert_eq!(shuffled, sorted);

        let noise = Noise {
            octaves: 1,
            frequency: 256,
            depth: 1.0,
            perm: permutation(0),
        };
        let mut rng = Lcg(5);
        let mut max_abs: f64 = 0.0;
        for _ in 0..500 {
            let (x, y) = (rng.next() * 40.0, rng.next() * 40.0);
            let (n, _, _) = noise.octave(x, y, 256);
            let r = perlin_reference(x, y, 0.0);
            assert!((n - r).abs() < 1e-12, "({x},{y}): {n} vs {r}");
            max_abs = max_abs.max(n.abs());
        }
        assert!(max_abs > 0.3 && max_abs <= 1.0, "{max_abs}");
    }

    #[test]
    fn noise_lattice_points_and_seeds() {
        let spec = |seed, octaves| BumpSpec::Noise {
            octaves,
            frequency: 5,
            depth: 0.1,
            seed,
        };
        let f = field(&spec(0, 3));
        // Every octave vanishes on the first octave's lattice.
        for k in 0..5 {
            for l in 0..5 {
                assert!(f.height(f64::from(k) / 5.0, f64::from(l) / 5.0).abs() < 1e-15);
            }
        }
        // One octave: the gradient at a lattice point is depth * f * (a cube-edge direction
        // projected on z = 0), each component -1, 0 or 1, not both 0.
        let one = field(&spec(0, 1));
        for k in 0..5 {
            let g = one.grad(f64::from(k) / 5.0, 0.6) / (0.1 * 5.0);
            for c in [g.x, g.y] {
                assert!(
                    [-1.0, 0.0, 1.0].iter().any(|&e| (c - e).abs() < 1e-12),
                    "{g}"
                );
            }
            assert!(g.length() > 0.5);
        }
        // Different seeds give different fields.
        let a = field(&spec(1, 2));
        let b = field(&spec(2, 2));
        assert!((a.height(0.31, 0.77) - b.height(0.31, 0.77)).abs() > 1e-6);
    }

    /// A fresh, empty directory (removed when dropped).
    fn temp_dir() -> crate::scratch::Scratch {
        crate::scratch::Scratch::dir()
    }

    #[test]
    fn height_png_sampling_and_gradient() {
        let dir = temp_dir();
        // 4 x 2 grey image: row 0 = 0, 64, 128, 255; row 1 = 10, 20, 30, 40.
        let mut img = image::GrayImage::new(4, 2);
        for (i, &v) in [0u8, 64, 128, 255].iter().enumerate() {
            img.put_pixel(i as u32, 0, image::Luma([v]));
        }
        for (i, &v) in [10u8, 20, 30, 40].iter().enumerate() {
            img.put_pixel(i as u32, 1, image::Luma([v]));
        }
        img.save(dir.join("h.png")).unwrap();
        let spec = BumpSpec::HeightPng {
            path: "h.png".into(),
            depth: 0.2,
        };
        let map = spec.build(&dir).unwrap();
        let d = |x: f64| 0.2 * x / 255.0;
        // Texel centres are exact.
        let heights = map.bake_heights(4, 2).unwrap();
        let want = [0.0, 64.0, 128.0, 255.0, 10.0, 20.0, 30.0, 40.0].map(d);
        for (a, b) in heights.iter().zip(want.iter()) {
            assert!((a - b).abs() < 1e-15, "{heights:?}");
        }
        // Bilinear between texel centres, wrapping at u = 1 (between 255 and 0).
        let f = match &map {
            BumpMap::Height(f) => f,
            _ => unreachable!(),
        };
        assert!((f.height(0.25, 0.25) - d(32.0)).abs() < 1e-15);
        assert!((f.height(1.0, 0.25) - d(127.5)).abs() < 1e-15);
        assert!((f.height(0.5, 0.5) - d((128.0 + 64.0 + 30.0 + 20.0) / 4.0)).abs() < 1e-15);
        // Gradient at texel (1, 0): central difference over texels 0 and 2, du = 1/4;
        // in v: texel (1, 1) on both sides (period 2), so 0.
        let g = map.grad(0.375, 0.25).unwrap();
        assert!((g.x - (d(128.0) - d(0.0)) / 0.5).abs() < 1e-12, "{g}");
        assert!(g.y.abs() < 1e-15, "{g}");
        // The Analytic bake uses that gradient.
        let n = map.bake_normals(4, 2, NormalMethod::Analytic).texel(1, 0);
        assert!((n - DVec3::new(-g.x, 0.0, 1.0).normalize()).length() < 1e-12);

        // RGB -> Rec. 709 luminance; 16-bit grey.
        let rgb = image::RgbImage::from_pixel(1, 1, image::Rgb([255, 0, 0]));
        rgb.save(dir.join("rgb.png")).unwrap();
        let m = BumpSpec::HeightPng {
            path: "rgb.png".into(),
            depth: 1.0,
        }
        .build(&dir)
        .unwrap();
        assert!((m.bake_heights(1, 1).unwrap()[0] - 0.2126).abs() < 1e-15);
        let g16: image::ImageBuffer<image::Luma<u16>, Vec<u16>> =
            image::ImageBuffer::from_pixel(1, 1, image::Luma([1000]));
        g16.save(dir.join("g16.png")).unwrap();
        let m = BumpSpec::HeightPng {
            path: "g16.png".into(),
            depth: 2.0,
        }
        .build(&dir)
        .unwrap();
        assert!((m.bake_heights(1, 1).unwrap()[0] - 2000.0 / 65535.0).abs() < 1e-15);
    }

    #[test]
    fn png_errors_name_the_path() {
        let dir = temp_dir();
        std::fs::write(dir.join("garbage.png"), b"definitely not a PNG file").unwrap();
        for spec in [
            BumpSpec::HeightPng {
                path: "garbage.png".into(),
                depth: 1.0,
            },
            BumpSpec::NormalPng {
                path: "garbage.png".into(),
            },
        ] {
            match spec.build(&dir) {
                Err(SceneError::File { path, message }) => {
                    assert_eq!(path, dir.join("garbage.png").display().to_string());
                    assert!(message.starts_with("could not decode PNG"), "{message}");
                }
                other => panic!("expected a file error, got {other:?}"),
            }
        }
        match (BumpSpec::NormalPng {
            path: "missing.png".into(),
        })
        .build(&dir)
        {
            Err(SceneError::File { path, .. }) => assert!(path.ends_with("missing.png")),
            other => panic!("expected a file error, got {other:?}"),
        }
    }

    #[test]
    fn normal_png_bump_map() {
        let dir = temp_dir();
        let mut img = image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 255]));
        img.put_pixel(1, 0, image::Rgb([255, 128, 128]));
        img.save(dir.join("n.png")).unwrap();
        let map = BumpSpec::NormalPng {
            path: "n.png".into(),
        }
        .build(&dir)
        .unwrap();
        assert!(map.grad(0.5, 0.5).is_none());
        assert!(map.bake_heights(2, 2).is_none());
        let e = 128.0 / 255.0 * 2.0 - 1.0;
        let tilted = DVec3::new(1.0, e, e).normalize();
        assert!((map.normal_ts(0.75, 0.25) - tilted).length() < 1e-12);
        // Same size: the map itself; 4 x 4: resampled at the new centres.
        let same = map.bake_normals(2, 2, NormalMethod::CentralDifference);
        assert!((same.texel(1, 0) - tilted).length() < 1e-12);
        let big = map.bake_normals(4, 4, NormalMethod::Analytic);
        assert_eq!(big.texels.len(), 16);
        // New texel (2, 0) at u = 0.625, v = 0.125: 3/4 of (1,0)-ish mixes; check against
        // sample_bilinear directly and that it is unit length.
        let direct = map.normal_ts(0.625, 0.125);
        assert!((big.texel(2, 0) - direct).length() < 1e-15);
        assert!((direct.length() - 1.0).abs() < 1e-12 && direct.x > 0.3);
    }

    #[test]
    fn bake_and_normals_from_height_fields() {
        let map = build(&BumpSpec::SphereCaps {
            cells: 2,
            radius: 0.4,
            depth: 0.05,
        });
        let hs = map.bake_heights(8, 4).unwrap();
        assert_eq!(hs.len(), 32);
        // Texel (1, 0) is at (0.1875, 0.125): offset (-0.125, -0.25) cell units from the
        // centre of cell (0, 0), t ≈ 0.70, inside the cap.
        let f = match &map {
            BumpMap::Height(f) => f,
            _ => unreachable!(),
        };
        assert_eq!(hs[1], f.height(0.1875, 0.125));
        assert!(hs[1] > 0.0);
        let analytic = map.bake_normals(8, 4, NormalMethod::Analytic);
        let g = f.grad(0.1875, 0.125);
        assert_eq!(
            analytic.texel(1, 0),
            DVec3::new(-g.x, -g.y, 1.0).normalize()
        );
        assert!((map.normal_ts(0.1875, 0.125) - analytic.texel(1, 0)).length() < 1e-15);
        let cd = map.bake_normals(8, 4, NormalMethod::CentralDifference);
        assert_eq!(
            cd,
            NormalMap::from_heights(&hs, 8, 4, NormalMethod::CentralDifference)
        );
        // Flat: all (0,0,1).
        let flat = build(&BumpSpec::Flat);
        assert_eq!(flat.normal_ts(0.3, 0.4), DVec3::Z);
        assert!(flat
            .bake_normals(3, 3, NormalMethod::Schlag { w: 1.0 })
            .texels
            .iter()
            .all(|&n| n == DVec3::Z));
        assert!(format!("{flat:?}").starts_with("BumpMap::Height"));
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        let cases: Vec<(BumpSpec, &str)> = vec![
            (
                BumpSpec::Bricks {
                    rows: 3,
                    cols: 4,
                    mortar: 0.1,
                    bevel: 0.1,
                    depth: 0.1,
                },
                "bump.Bricks.rows",
            ),
            (
                BumpSpec::Bricks {
                    rows: 4,
                    cols: 0,
                    mortar: 0.1,
                    bevel: 0.1,
                    depth: 0.1,
                },
                "bump.Bricks.cols",
            ),
            (
                BumpSpec::Bricks {
                    rows: 4,
                    cols: 4,
                    mortar: 0.1,
                    bevel: 0.0,
                    depth: 0.1,
                },
                "bump.Bricks.bevel",
            ),
            (
                BumpSpec::Bricks {
                    rows: 4,
                    cols: 4,
                    mortar: 0.5,
                    bevel: 0.3,
                    depth: 0.1,
                },
                "bump.Bricks.bevel",
            ),
            (
                BumpSpec::Bricks {
                    rows: 4,
                    cols: 4,
                    mortar: -0.1,
                    bevel: 0.1,
                    depth: 0.1,
                },
                "bump.Bricks.mortar",
            ),
            (
                BumpSpec::Bricks {
                    rows: 4,
                    cols: 4,
                    mortar: 0.1,
                    bevel: 0.1,
                    depth: f64::NAN,
                },
                "bump.Bricks.depth",
            ),
            (
                BumpSpec::MexicanHat {
                    cells: 0,
                    sigma: 0.1,
                    depth: 0.1,
                },
                "bump.MexicanHat.cells",
            ),
            (
                BumpSpec::MexicanHat {
                    cells: 2,
                    sigma: 0.6,
                    depth: 0.1,
                },
                "bump.MexicanHat.sigma",
            ),
            (
                BumpSpec::SphereCaps {
                    cells: 2,
                    radius: 0.0,
                    depth: 0.1,
                },
                "bump.SphereCaps.radius",
            ),
            (
                BumpSpec::SphereCaps {
                    cells: 2,
                    radius: 0.3,
                    depth: f64::INFINITY,
                },
                "bump.SphereCaps.depth",
            ),
            (
                BumpSpec::Noise {
                    octaves: 0,
                    frequency: 4,
                    depth: 0.1,
                    seed: 0,
                },
                "bump.Noise.octaves",
            ),
            (
                BumpSpec::Noise {
                    octaves: 16,
                    frequency: 1024,
                    depth: 0.1,
                    seed: 0,
                },
                "bump.Noise.frequency",
            ),
            (
                BumpSpec::HeightPng {
                    path: "x.png".into(),
                    depth: f64::NAN,
                },
                "bump.HeightPng.depth",
            ),
        ];
        for (spec, field) in cases {
            match spec.build(Path::new(".")) {
                Err(SceneError::Invalid { field: f, message }) => {
                    assert_eq!(f, field, "{spec:?}: {message}");
                    assert!(!message.is_empty());
                }
                other => panic!("{spec:?}: expected an invalid-field error, got {other:?}"),
            }
        }
    }

    #[test]
    fn serde_round_trip_and_unknown_fields() {
        let spec = BumpSpec::Bricks {
            rows: 8,
            cols: 4,
            mortar: 0.1,
            bevel: 0.15,
            depth: 0.01,
        };
        let json = serde_json::to_string(&spec).unwrap();
        assert_eq!(
            json,
            r#"{"Bricks":{"rows":8,"cols":4,"mortar":0.1,"bevel":0.15,"depth":0.01}}"#
        );
        assert_eq!(serde_json::from_str::<BumpSpec>(&json).unwrap(), spec);
        let bad =
            r#"{"Bricks":{"rows":8,"cols":4,"mortar":0.1,"bevel":0.15,"depth":0.01,"colour":1}}"#;
        assert!(serde_json::from_str::<BumpSpec>(bad).is_err());
        assert_eq!(
            serde_json::from_str::<BumpSpec>(r#""Flat""#).unwrap(),
            BumpSpec::Flat
        );
    }
}
