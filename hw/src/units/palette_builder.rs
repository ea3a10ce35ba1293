//! Per-frame colour-table builder of the quantized normal maps engine.
//!
//! Tarini, Cignoni, Rocchini, Scopigno, §5.1: "The color table C is produced by applying to
//! each normal n in the set N a function f(n) -> c". The normals of `N` are unit vectors in
//! object space; the light and view directions are handed to the builder already in object
//! space (§5: they "are first transformed using the inverse of the current modeling
//! transformation", the caller's job) and are normalised here. §6: several lighting models on
//! one object are contiguous intervals of `N` (the pairs (material, normal) are sorted by
//! material), one [`LightingFn`] per interval.
//!
//! # Not a per-fragment unit
//! The builder runs once per frame over the `s_N` entries and has no per-fragment ports, so it
//! does not implement [`crate::unit::Unit`]: it is a plain struct with [`PaletteBuilder::build`]
//! (the table `C` in either mode, as a [`PaletteTable`]), [`PaletteBuilder::cycles_per_frame`]
//! and [`PaletteBuilder::gates`]. The pipeline hands the table to
//! [`crate::units::PaletteLut`] and charges the build cycles as the LUT's frame work.
//!
//! # Datapath assumed
//! `entries_per_clock` identical pipelines, each with: a normal read from the normal-table
//! SRAM (`entries x 3 x normal width`), one 3-term dot-product unit (`normal x vector`
//! multipliers, exact sum), an intensity clamp/cast, one power generator
//! ([`SpecularGenerator`], shared configuration), and an RGB multiply-accumulate (3
//! `intensity x coefficient` multipliers and 3 accumulators) ending in a cast to the entry
//! encoding. Light, half-way and view vectors and the colour coefficients sit in registers
//! loaded by the host; the half-way vectors `H = normalize(L + V)` are computed by the host
//! per frame, like `L` and `V`. The dot-product unit is used once per clock, so
//! `cycles_per_entry` is the number of dot products (plus the extra steps below); the power
//! lookup and the MAC of one step overlap the next dot product. Pipeline fill (a few clocks)
//! is not counted. Per material interval of `m` entries: `ceil(m / entries_per_clock) x
//! cycles_per_entry`, summed over the intervals; with one material this is
//! `ceil(entries / entries_per_clock) x cycles_per_entry`. The builder never sees the indexed
//! normal texture, so its time does not depend on the texture size (§1: "rendering time does
//! not depend much on texture size").
//!
//! | function | cycles per entry |
//! |---|---|
//! | Lambert, `L` lights | `max(1, L)`: one `N.L` and one MAC per light |
//! | Specular, `L` lights | `max(1, 2L)`: `N.L` and `N.H` per light |
//! | Cartoon, `L` lights | `L + 1`: the dot products, then the band select |
//! | DoubledAnglePhong | 3: `N.L`, `N.V`, then `2 (R.V)^2 - 1` and the power |
//! | SpecularSplit, `L` lights | `max(1, 2L)`: as Specular |
//! | Chrome | 2: `N.V`, `N.up`, then `R.up` and the lerp overlapped |
//! | EnvMap | 4: `N.V`, then `N.x`, `N.y`, `N.z` forming `R` in the eye frame; the address and the texel read overlapped |
//!
//! # The functions (exact mode; `sat` clamps each channel to [0, 1], alpha is always 1)
//! * `Lambert`: `c = sat(ambient + diffuse . sum_l color_l max(0, N.L_l))`.
//! * `Specular` (Blinn-Phong, per-light `H_l = normalize(L_l + V)`): Lambert `+ specular .
//!   sum_l color_l max(0, N.H_l)^shininess`.
//! * `Cartoon`: the scalar Lambert term `d = min(1, sum_l max(0, N.L_l))` falls into band
//!   `k = min(floor(d bands), bands - 1)` and `c = sat(ambient + diffuse k / (bands - 1))`: at
//!   most `bands` distinct colours (the band colours are a `bands`-entry table loaded by the
//!   host, so this also holds bit-accurately).
//! * `DoubledAnglePhong` (Fig. 6): with `R = 2 (N.L) N - L` and `cos a = R.V`, the Phong term
//!   uses the doubled angle: `s = max(0, cos 2a)^shininess = max(0, 2 (R.V)^2 - 1)^shininess`
//!   for `R.V > 0`, and 0 for `R.V <= 0` (angles beyond 90 degrees); `c = sat(ambient + diffuse
//!   . color max(0, N.L) + specular . color s)`.
//! * `Chrome` (Fig. 7, "brown below, and blue above"): `R = 2 (N.V) N - V`; object-space `+z`
//!   is up; `t = clamp((1 + R_z) / 2, 0, 1)` and `c = ground + t (sky - ground)`: a gradient from
//!   the ground colour (reflection straight down) to the sky colour (straight up).
//! * `EnvMap` (§5.1 item 3): sphere map with its axis along object `+z` (OpenGL's eye-space
//!   sphere map for a viewer on `+z`): `m = 2 sqrt(R_x^2 + R_y^2 + (R_z + 1)^2)`, `s = R_x/m +
//!   1/2`, `t = R_y/m + 1/2`, nearest texel `(floor(s w), floor(t h))` clamped, row `t`.
//!
//! # Bit-accurate mode
//! The normal is quantized to `normal` per component, the (normalised) light, half-way and
//! view vectors to `vector`; dot products and reflection vectors are exact ([`Acc`]); each
//! intensity is clamped to [0, 1] and cast to `intensity`; powers come from the
//! [`SpecularGenerator`] (`power`) reading `intensity` words; colour coefficients (ambient,
//! diffuse, specular, light colours, sky, ground, environment texels) are words of the entry
//! encoding; the sum of products is exact and cast once to the entry encoding (whose
//! saturation is the final clamp). `EnvMap`'s sphere-map address: the host loads the eye
//! frame's axes `x = unit(up x V)`, `y = V x x`, `z = V` as vector registers; `R.a = 2 (N.V)
//! (N.a) - V.a` per axis, exact, cast into s2.`r_frac` (truncated, saturated: never acts on
//! unit vectors); `q = R_x^2 + R_y^2 + (R_z + 1)^2` exact; `1 / sqrt(q) ~ rho 2^k` from
//! Normalize's reciprocal-square-root table ([`SphereAddress`], default s2.14 reflections and a
//! 1024 x 16-bit table: leading-one detect, even shift, table); the texel is `floor(w (1 + R_x
//! rho 2^k) / 2)` clamped to `0..w` (and `t` likewise), `floor(w / 2)` for `q = 0`. Against the
//! f64 address of the same exact `R` it is within one texel where `q >= 1/16` and equal for 95
//! % of random reflections (test `sphere_address_is_the_formula_within_a_texel`). The cartoon band colours are
//! words the host computes ([`band_codes`]) and loads, as it loads the other colour words.

use std::ops::Range;

use crate::arith::Acc;
use crate::format::Encoding;
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget, TableRole};
use crate::unit::Mode;
use crate::units::normalize::{shift_pow2, Rsqrt};
use crate::units::palette_lut::PaletteTable;
use crate::units::specgen::{SpecGen, SpecularGenerator};

/// A light: (direction towards the light in object space, RGB colour).
pub type Light = ([f64; 3], [f64; 3]);

/// The function `f(n) -> c` of one material. See the module documentation.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LightingFn {
    Lambert {
        ambient: [f64; 3],
        diffuse: [f64; 3],
        lights: Vec<Light>,
    },
    Specular {
        ambient: [f64; 3],
        diffuse: [f64; 3],
        specular: [f64; 3],
        shininess: f64,
        view: [f64; 3],
        lights: Vec<Light>,
    },
    Cartoon {
        bands: u32,
        ambient: [f64; 3],
        diffuse: [f64; 3],
        lights: Vec<Light>,
    },
    DoubledAnglePhong {
        ambient: [f64; 3],
        diffuse: [f64; 3],
        specular: [f64; 3],
        shininess: f64,
        view: [f64; 3],
        light: Light,
    },
    Chrome {
        view: [f64; 3],
        /// The landscape's up direction (object space).
        up: [f64; 3],
        sky: [f64; 3],
        ground: [f64; 3],
    },
    EnvMap {
        view: [f64; 3],
        /// The viewer's up direction (object space): with `view` it fixes the sphere map's
        /// eye frame.
        up: [f64; 3],
        image: Vec<[f64; 3]>,
        width: u32,
        height: u32,
    },
    /// Tarini §7.1: the Lambert intensity in alpha and the specular colour in RGB, for a
    /// blend with a base colour ([`crate::units::FbBlend`]).
    SpecularSplit {
        ambient: f64,
        diffuse: f64,
        specular: [f64; 3],
        shininess: f64,
        view: [f64; 3],
        lights: Vec<Light>,
        /// A Lambert material's split form: no specular term (`specular` zero, and kept zero
        /// by [`LightingFn::with_frame`]).
        #[serde(default)]
        lambert: bool,
    },
}

impl LightingFn {
    /// Clocks per entry on one pipeline (module documentation).
    pub fn cycles_per_entry(&self) -> u64 {
        match self {
            LightingFn::Lambert { lights, .. } => (lights.len() as u64).max(1),
            LightingFn::Specular { lights, .. } | LightingFn::SpecularSplit { lights, .. } => {
                (2 * lights.len() as u64).max(1)
            }
            LightingFn::Cartoon { lights, .. } => lights.len() as u64 + 1,
            LightingFn::DoubledAnglePhong { .. } => 3,
            LightingFn::Chrome { .. } => 2,
            LightingFn::EnvMap { .. } => 4,
        }
    }
    fn shininess(&self) -> Option<f64> {
        match self {
            LightingFn::Specular { shininess, .. }
            | LightingFn::SpecularSplit { shininess, .. }
            | LightingFn::DoubledAnglePhong { shininess, .. } => Some(*shininess),
            _ => None,
        }
    }
    fn validate(&self) -> Result<(), String> {
        let dir = |v: &[f64; 3], what: &str| {
            let l = norm(*v);
            if l.is_finite() && l > 0.0 {
                Ok(())
            } else {
                Err(format!("{what} {v:?}: expected a finite non-zero vector"))
            }
        };
        let fin = |v: &[f64; 3], what: &str| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(format!("{what} {v:?}: expected finite values"))
            }
        };
        let lights_ok = |ls: &[Light]| {
            ls.iter().try_for_each(|(d, c)| {
                dir(d, "light direction")?;
                fin(c, "light colour")
            })
        };
        // the specular coefficients, the viewer and every light's half-way vector
        let specular_ok = |specular: &[f64; 3], view: &[f64; 3], lights: &[Light]| {
            fin(specular, "specular")?;
            dir(view, "view")?;
            lights_ok(lights)?;
            lights.iter().try_for_each(|(l, _)| {
                dir(
                    &add(unit(*l), unit(*view)),
                    "light + view (half-way vector)",
                )
            })
        };
        match self {
            LightingFn::Lambert {
                ambient,
                diffuse,
                lights,
            } => {
                fin(ambient, "ambient")?;
                fin(diffuse, "diffuse")?;
                lights_ok(lights)
            }
            LightingFn::Specular {
                ambient,
                diffuse,
                specular,
                view,
                lights,
                ..
            } => {
                fin(ambient, "ambient")?;
                fin(diffuse, "diffuse")?;
                specular_ok(specular, view, lights)
            }
            LightingFn::Cartoon {
                bands,
                ambient,
                diffuse,
                lights,
            } => {
                if !(2..=256).contains(bands) {
                    return Err(format!("bands {bands}: expected 2 to 256"));
                }
                fin(ambient, "ambient")?;
                fin(diffuse, "diffuse")?;
                lights_ok(lights)
            }
            LightingFn::DoubledAnglePhong {
                ambient,
                diffuse,
                specular,
                view,
                light,
                ..
            } => {
                fin(ambient, "ambient")?;
                fin(diffuse, "diffuse")?;
                fin(specular, "specular")?;
                dir(view, "view")?;
                lights_ok(std::slice::from_ref(light))
            }
            LightingFn::Chrome {
                view,
                up,
                sky,
                ground,
            } => {
                dir(view, "view")?;
                dir(up, "up")?;
                fin(sky, "sky")?;
                fin(ground, "ground")
            }
            LightingFn::SpecularSplit {
                ambient,
                diffuse,
                specular,
                view,
                lights,
                ..
            } => {
                fin(&[*ambient, *diffuse, 0.0], "ambient and diffuse")?;
                specular_ok(specular, view, lights)
            }
            LightingFn::EnvMap {
                view,
                up,
                image,
                width,
                height,
            } => {
                dir(view, "view")?;
                dir(up, "up")?;
                dir(&cross(unit(*up), unit(*view)), "up x view (eye frame)")?;
                if *width == 0 || *height == 0 || *width > 4096 || *height > 4096 {
                    return Err(format!(
                        "environment map {width}x{height}: expected 1 to 4096 texels a side"
                    ));
                }
                if image.len() != (*width as usize) * (*height as usize) {
                    return Err(format!(
                        "environment map has {} texels: expected {width}x{height}",
                        image.len()
                    ));
                }
                image.iter().try_for_each(|t| fin(t, "environment texel"))
            }
        }
    }
}

/// Encodings of the builder's datapath.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BuilderFormats {
    /// A normal component (e.g. signed 10-bit).
    pub normal: Encoding,
    /// A light, half-way or view vector component.
    pub vector: Encoding,
    /// An intensity after the dot product (unsigned, holds 1.0 e.g. `UnitUnsigned` 10).
    pub intensity: Encoding,
    /// The power generator reading intensities.
    pub power: SpecGen,
    /// Each RGBA lane of an entry of `C` (the [`crate::units::PaletteLut`] entry encoding);
    /// also the encoding of the colour coefficients.
    pub entry: Encoding,
    /// The sphere-map address's reciprocal square root (`EnvMap` only).
    pub sphere: SphereAddress,
}

/// The `EnvMap` function's sphere-map address datapath: `R`'s words (`r_frac` fraction bits,
/// truncated, saturated to `[-2, 2)`: the host's unit vectors keep `|R.a|` near 1, so the
/// saturation never acts on them) and Normalize's reciprocal-square-root table
/// ([`crate::units::normalize`]) of `2^table_bits` entries of `value_bits`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereAddress {
    pub r_frac: u32,
    pub table_bits: u32,
    pub value_bits: u32,
}

impl Default for SphereAddress {
    /// s2.14 reflections; 1024 entries of 16 bits: the bin's relative error `2^-10` moves an
    /// address by at most `w 2^-11` texels (an eighth of a texel on a 256-texel map).
    fn default() -> Self {
        SphereAddress {
            r_frac: 14,
            table_bits: 10,
            value_bits: 16,
        }
    }
}

impl SphereAddress {
    /// The encoding of a reflection component: s2.`r_frac`, truncated, saturating.
    pub fn r_encoding(&self) -> Encoding {
        Encoding {
            format: crate::format::Format::s(self.r_frac as u8 + 2, self.r_frac as u8),
            quant: crate::format::Quant::Trn,
            overflow: crate::format::Overflow::Sat,
            codec: crate::format::Codec::Fixed,
        }
    }
}

/// The per-frame colour-table builder. See the module documentation.
#[derive(Debug, Clone)]
pub struct PaletteBuilder {
    normals: Vec<[f64; 3]>,
    materials: Vec<(Range<usize>, LightingFn)>,
    /// Each material's id in the frame's materials ([`FrameInputs::materials`]).
    ids: Vec<usize>,
    gens: Vec<Option<SpecularGenerator>>,
    f: BuilderFormats,
    entries_per_clock: u32,
    /// The sphere-map address's table, when a material is `EnvMap`.
    sphere: Option<Rsqrt>,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    a.map(|x| x / l)
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// `r` in the eye frame of a viewer along `view` with `up`: `(r.x, r.y, r.z)` with `z = view`,
/// `x = normalize(up x z)`, `y = z x x`.
fn eye_frame(r: [f64; 3], view: [f64; 3], up: [f64; 3]) -> [f64; 3] {
    eye_axes(view, up).map(|a| dot(r, a))
}
/// The sphere map's eye frame: `x = unit(up x z)`, `y = z x x`, `z = unit(view)`.
pub(crate) fn eye_axes(view: [f64; 3], up: [f64; 3]) -> [[f64; 3]; 3] {
    let z = unit(view);
    let x = unit(cross(up, z));
    let y = cross(z, x);
    [x, y, z]
}
/// The bit-accurate sphere-map address of an exact eye-frame reflection `r`: `q = r_x^2 +
/// r_y^2 + (r_z + 1)^2` exact, `1 / sqrt(q) ~ rho 2^k` from the table ([`Rsqrt::lookup`]),
/// and per axis `floor(n (1 + r_a rho 2^k) / 2)` (the model's `floor(n (r_a / m + 1/2))`
/// with `m = 2 sqrt(q)`) clamped to `0..n`; `q = 0` gives `floor(n / 2)`. Returns `(i, j)`.
pub(crate) fn sphere_address(rs: &Rsqrt, r: [Acc; 3], width: u32, height: u32) -> (usize, usize) {
    let z1 = r[2].add(Acc::new(1, 0));
    let q = r[0].mul(r[0]).add(r[1].mul(r[1])).add(z1.mul(z1));
    let look = rs.lookup(q);
    let coord = |c: Acc, n: u32| -> usize {
        let t = match look {
            Some((rho, k)) => shift_pow2(c.mul(rho), k),
            None => Acc::ZERO,
        };
        let s = Acc::new(1, 0).add(t).scale(n as i128).shr(1);
        s.round_int(crate::format::Quant::Trn)
            .clamp(0, n as i128 - 1) as usize
    };
    (coord(r[0], width), coord(r[1], height))
}
/// The sphere-map address's widest intermediate fits the model's 128 bits: `R.a = 2 (N.V)
/// (N.a) - V.a` before its cast, with twice the normal's and the vector's readings' fraction
/// bits, its value below `2 (3 |n| |v|)^2 + 3 |v|^2`.
fn check_sphere_widths(f: &BuilderFormats) -> Result<(), String> {
    let reading = |e: &Encoding| {
        let top = Acc::from_code(e.format.max_raw(), e);
        let bottom = Acc::from_code(e.format.min_raw(), e);
        (top.frac, top.to_f64().abs().max(bottom.to_f64().abs()))
    };
    let ((fn_, n), (fv, v)) = (reading(&f.normal), reading(&f.vector));
    let r = 2.0 * (3.0 * n * v) * (3.0 * n * v) + 3.0 * v * v;
    let r_bits = (r + 1.0).log2().ceil() as u32 + 1 + 2 * (fn_ + fv);
    if r_bits > 124 {
        return Err(format!(
            "EnvMap: the reflection R = 2 (N.V) N - V needs {r_bits} bits of the model's \
             128-bit intermediate: expected narrower normal and vector words"
        ));
    }
    Ok(())
}
/// Each material's power generator, for the functions with a shininess.
fn generators(
    materials: &[(Range<usize>, LightingFn)],
    formats: &BuilderFormats,
) -> Result<Vec<Option<SpecularGenerator>>, String> {
    materials
        .iter()
        .map(|(_, f)| {
            f.shininess()
                .map(|s| SpecularGenerator::new(formats.power, s, formats.intensity))
                .transpose()
        })
        .collect()
}
fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] + b[i])
}
/// `2 (n.v) n - v`.
fn reflect(n: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let k = 2.0 * dot(n, v);
    std::array::from_fn(|i| k * n[i] - v[i])
}
fn adot(a: [Acc; 3], b: [Acc; 3]) -> Acc {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}
fn sphere_texel(r: [f64; 3], width: u32, height: u32) -> usize {
    let m = 2.0 * (r[0] * r[0] + r[1] * r[1] + (r[2] + 1.0) * (r[2] + 1.0)).sqrt();
    let (s, t) = if m > 0.0 {
        (r[0] / m + 0.5, r[1] / m + 0.5)
    } else {
        (0.5, 0.5)
    };
    let i = ((s * width as f64).floor().max(0.0) as usize).min(width as usize - 1);
    let j = ((t * height as f64).floor().max(0.0) as usize).min(height as usize - 1);
    j * width as usize + i
}

impl PaletteBuilder {
    /// `normals`: the table `N` (1 to `2^MAX_INDEX_BITS` = 65536 finite vectors, normalised
    /// here); `materials`:
    /// contiguous intervals covering `0..normals.len()` in order, each with its function;
    /// `entries_per_clock`: parallel pipelines (1 to 64). Errors name what was expected.
    pub fn new(
        normals: Vec<[f64; 3]>,
        materials: Vec<(Range<usize>, LightingFn)>,
        formats: BuilderFormats,
        entries_per_clock: u32,
    ) -> Result<Self, String> {
        let n = normals.len();
        let most = 1usize << crate::units::palette_lut::MAX_INDEX_BITS;
        if !(1..=most).contains(&n) {
            return Err(format!("normal table of {n} entries: expected 1 to {most}"));
        }
        if let Some(v) = normals
            .iter()
            .find(|v| !(norm(**v).is_finite() && norm(**v) > 0.0))
        {
            return Err(format!("normal {v:?}: expected a finite non-zero vector"));
        }
        if !(1..=64).contains(&entries_per_clock) {
            return Err(format!(
                "entries_per_clock {entries_per_clock}: expected 1 to 64"
            ));
        }
        formats.normal.validate()?;
        formats.vector.validate()?;
        formats.intensity.validate()?;
        formats.entry.validate()?;
        if formats.intensity.format.signed {
            return Err("intensity encoding: expected an unsigned format".into());
        }
        if formats.intensity.decode(formats.intensity.format.max_raw()) < 1.0 {
            return Err(format!(
                "intensity encoding {}: expected one that holds 1.0",
                formats.intensity
            ));
        }
        let mut next = 0;
        for (r, f) in &materials {
            if r.start != next || r.end <= r.start {
                return Err(format!(
                    "material interval {r:?}: expected a non-empty interval starting at {next}"
                ));
            }
            next = r.end;
            f.validate()?;
        }
        if next != n {
            return Err(format!(
                "material intervals end at {next}: expected them to cover 0..{n}"
            ));
        }
        let gens = generators(&materials, &formats)?;
        let sphere = if materials
            .iter()
            .any(|(_, f)| matches!(f, LightingFn::EnvMap { .. }))
        {
            let s = formats.sphere;
            if !(2..=30).contains(&s.r_frac) {
                return Err(format!(
                    "sphere-map r_frac {}: expected 2 to 30 fraction bits",
                    s.r_frac
                ));
            }
            check_sphere_widths(&formats)?;
            Some(
                Rsqrt::new(s.table_bits, s.value_bits)
                    .map_err(|e| format!("sphere-map rsqrt: {e}"))?,
            )
        } else {
            None
        };
        Ok(PaletteBuilder {
            normals: normals.into_iter().map(unit).collect(),
            ids: (0..materials.len()).collect(),
            materials,
            gens,
            f: formats,
            entries_per_clock,
            sphere,
        })
    }

    /// One function over the whole table.
    pub fn single(
        normals: Vec<[f64; 3]>,
        f: LightingFn,
        formats: BuilderFormats,
        entries_per_clock: u32,
    ) -> Result<Self, String> {
        let n = normals.len();
        Self::new(normals, vec![(0..n, f)], formats, entries_per_clock)
    }

    /// The materials' ids in the frame ([`FrameInputs::materials`]), in interval order; by
    /// default 0, 1, ...
    pub fn with_material_ids(mut self, ids: Vec<usize>) -> Result<Self, String> {
        if ids.len() != self.materials.len() {
            return Err(format!(
                "{} material ids for {} materials",
                ids.len(),
                self.materials.len()
            ));
        }
        self.ids = ids;
        Ok(self)
    }

    /// Take the frame's inputs: every material's function for frame `f`
    /// ([`LightingFn::with_frame`]) and its power generator; the table is built from them
    /// ([`PaletteBuilder::build`]) in the frame's work. Errors when a function shading with
    /// every bump light was built for another number of lights.
    pub fn begin_frame(&mut self, f: &FrameInputs) -> Result<(), String> {
        let materials = self
            .materials
            .iter()
            .zip(&self.ids)
            .map(|((r, lf), &id)| {
                if let Some(n) = lf.light_passes() {
                    f.expect_lights(n, "the palette builder")?;
                }
                let lf = lf.with_frame(f, id)?;
                lf.validate()?;
                Ok((r.clone(), lf))
            })
            .collect::<Result<Vec<_>, String>>()?;
        self.gens = generators(&materials, &self.f)?;
        self.materials = materials;
        Ok(())
    }

    pub fn entries(&self) -> usize {
        self.normals.len()
    }
    pub fn formats(&self) -> &BuilderFormats {
        &self.f
    }
    /// The table `N` (normalised).
    pub fn normals(&self) -> &[[f64; 3]] {
        &self.normals
    }
    /// The table `N` as the words its memory holds: each component's `normal` code, packed
    /// from bit 0 (x, y, z), `3 x normal` bits an entry; what a ROM of it (`cost.tables =
    /// Rom`) is priced by.
    pub fn normal_words(&self) -> Vec<i64> {
        let e = &self.f.normal;
        let codes: Vec<[i64; 3]> = self
            .normals
            .iter()
            .map(|n| n.map(|x| e.encode(x)))
            .collect();
        crate::gates::packed_words(&codes, e.width())
    }
    /// The material intervals and their functions.
    pub fn materials(&self) -> &[(Range<usize>, LightingFn)] {
        &self.materials
    }
    /// Each material's power generator (`None` for a function without one).
    /// The sphere-map address's reciprocal-square-root table (a material is `EnvMap`).
    pub(crate) fn sphere(&self) -> Option<&Rsqrt> {
        self.sphere.as_ref()
    }
    pub fn generators(&self) -> &[Option<SpecularGenerator>] {
        &self.gens
    }
    pub fn entries_per_clock(&self) -> u32 {
        self.entries_per_clock
    }
    /// The normal words of entry `k` (codes of `normal`), as the normal table holds them.
    pub fn normal_codes(&self, k: usize) -> [i64; 3] {
        self.normals[k].map(|x| self.f.normal.encode(x))
    }
    /// A host-loaded vector register's codes: `v` normalised, in `vector` (the light and
    /// view registers).
    pub fn vector_codes(&self, v: [f64; 3]) -> [i64; 3] {
        unit(v).map(|x| self.f.vector.encode(x))
    }
    /// The half-way register of light direction `l` and viewer `view`: `normalize(unit(l) +
    /// unit(view))` in `vector`.
    pub fn halfway_codes(&self, l: [f64; 3], view: [f64; 3]) -> [i64; 3] {
        self.vector_codes(add(unit(l), unit(view)))
    }

    /// The colour table `C`: in exact mode the f64 values (words encoded for traces), in
    /// bit-accurate mode the hardware's words (values decoded).
    pub fn build(&self, mode: Mode) -> PaletteTable {
        match mode {
            Mode::Exact => PaletteTable::from_values(&self.f.entry, self.build_exact()),
            Mode::BitAccurate => PaletteTable::from_codes(&self.f.entry, self.build_codes()),
        }
    }

    /// Exact mode: `f(n)` in f64 for every entry.
    pub fn build_exact(&self) -> Vec<[f64; 4]> {
        let mut out = Vec::with_capacity(self.entries());
        for (r, f) in &self.materials {
            for n in &self.normals[r.clone()] {
                out.push(exact_entry(f, *n));
            }
        }
        out
    }

    /// Bit-accurate mode: the entry words for every entry.
    pub fn build_codes(&self) -> Vec<[i64; 4]> {
        let mut out = Vec::with_capacity(self.entries());
        for ((r, f), g) in self.materials.iter().zip(&self.gens) {
            let dp = Datapath::new(&self.f, g.as_ref(), self.sphere.as_ref());
            for n in &self.normals[r.clone()] {
                out.push(dp.entry(f, *n));
            }
        }
        out
    }

    /// Clocks to build the table: per interval `ceil(m / entries_per_clock) x
    /// cycles_per_entry`, summed.
    pub fn cycles_per_frame(&self) -> u64 {
        let p = self.entries_per_clock as u64;
        self.materials
            .iter()
            .map(|(r, f)| (r.len() as u64).div_ceil(p) * f.cycles_per_entry())
            .sum()
    }

    /// The environment images the `EnvMap` materials read, one texel per entry per frame:
    /// textures of the engine's texture memory (the builder reads them through its port), not
    /// tables of the builder. Named `environment` (`environment.k` for material interval `k`
    /// when several materials have one).
    pub fn frame_reads(&self) -> Vec<crate::unit::FrameRead> {
        let bits = 3 * self.f.entry.width();
        let envs: Vec<(usize, u64, [u32; 2])> = self
            .materials
            .iter()
            .enumerate()
            .filter_map(|(k, (r, f))| match f {
                LightingFn::EnvMap { width, height, .. } => {
                    Some((k, r.len() as u64, [*width, *height]))
                }
                _ => None,
            })
            .collect();
        let several = envs.len() > 1;
        envs.into_iter()
            .map(|(k, texels, size)| crate::unit::FrameRead {
                name: if several {
                    format!("environment.{k}")
                } else {
                    "environment".to_string()
                },
                size,
                bits_per_texel: bits,
                texels_per_frame: texels,
            })
            .collect()
    }

    /// Gate estimate: the normal table, the host-loaded registers, and `entries_per_clock`
    /// pipelines with what the functions in use need. With one pipeline and a function with a
    /// Verilog generator in every material, the list of `builder_gates` (priced as the
    /// generated netlist); otherwise (`EnvMap`, several pipelines, the other power generators)
    /// the first estimate below.
    pub fn gates(&self, t: &CostTable) -> GateBudget {
        if let Some(g) = crate::units::builder_gates::pipelined(self, t) {
            return g;
        }
        let (wn, wv, wi, we) = (
            self.f.normal.width(),
            self.f.vector.width(),
            self.f.intensity.width(),
            self.f.entry.width(),
        );
        let p = self.entries_per_clock;
        let n = self.entries() as u64;
        let mut g = GateBudget::new();
        g.add_memory(
            format!("normal table {n}x{} (loadable)", 3 * wn),
            1,
            t.for_table(TableRole::Normals)
                .table_of(&self.normal_words(), 3 * wn),
        );
        // host-loaded registers: every vector and colour of every material
        let (mut vecs, mut cols) = (0u32, 0u32);
        let (mut power, mut refl, mut band, mut lerp) = (false, false, false, false);
        let mut env = false;
        for (_, f) in &self.materials {
            match f {
                LightingFn::Lambert { lights, .. } => {
                    vecs += lights.len() as u32;
                    cols += 2 + lights.len() as u32;
                }
                LightingFn::Specular { lights, .. } | LightingFn::SpecularSplit { lights, .. } => {
                    vecs += 2 * lights.len() as u32;
                    cols += 3 + lights.len() as u32;
                    power = true;
                }
                LightingFn::Cartoon { bands, lights, .. } => {
                    vecs += lights.len() as u32;
                    cols += *bands;
                    band = true;
                }
                LightingFn::DoubledAnglePhong { .. } => {
                    vecs += 2;
                    cols += 4;
                    power = true;
                    refl = true;
                }
                LightingFn::Chrome { .. } => {
                    vecs += 2;
                    cols += 2;
                    refl = true;
                    lerp = true;
                }
                LightingFn::EnvMap { .. } => {
                    vecs += 2;
                    refl = true;
                    env = true;
                }
            }
        }
        g.add(format!("vector registers 3x{wv}"), vecs, t.register(3 * wv));
        g.add(format!("colour registers 3x{we}"), cols, t.register(3 * we));
        // the environment images lie in the engine's texture memory ([`PaletteBuilder::frame_reads`])
        let wd = wn + wv + 2; // exact dot-product width
        g.add(format!("normal register {}", 3 * wn), p, t.register(3 * wn));
        g.add(
            format!("dot multiplier {wn}x{wv}"),
            3 * p,
            t.multiplier(wn, wv),
        );
        g.add(format!("dot adder {wd}"), 2 * p, t.adder(wd));
        g.add(format!("intensity clamp {wi}"), p, t.clamp(wi));
        if refl {
            // 2 (n.v) n - v: the scalar register, 3 multipliers and 3 subtractors
            g.add(format!("dot register {wd}"), p, t.register(wd));
            g.add(
                format!("reflect multiplier {wd}x{wn}"),
                3 * p,
                t.multiplier(wd, wn),
            );
            g.add(
                format!("reflect subtractor {}", wd + wn),
                3 * p,
                t.adder(wd + wn),
            );
        }
        if power {
            if let Some(gen) = self.gens.iter().flatten().next() {
                g.add_part("", p, gen.gates(t));
            }
            // doubled angle: 2 x^2 - 1
            if self
                .materials
                .iter()
                .any(|(_, f)| matches!(f, LightingFn::DoubledAnglePhong { .. }))
            {
                g.add(format!("doubled-angle squarer {wd}"), p, t.squarer(wd));
            }
        }
        if band {
            g.add(
                format!("band select multiplier {wi}x8"),
                p,
                t.multiplier(wi, 8),
            );
            g.add(format!("band colour mux 3x{we}"), p, t.mux(3 * we, 2));
        }
        if lerp {
            g.add(format!("gradient adder {we}"), 3 * p, t.adder(we + 1));
        }
        if env {
            // sphere-map address as first designed (not the model's integer address, which
            // `builder_gates_envmap` prices): 1/m from a 1024 x 12 ROM (priced by its contents)
            // and two multipliers
            g.add_rom(
                "sphere-map 1/m table 1024x12",
                p,
                t.rom_of(sphere_map_recip_table(), SPHERE_RECIP_BITS),
            );
            g.add(
                format!("sphere-map address multiplier {wd}x12"),
                2 * p,
                t.multiplier(wd, 12),
            );
        }
        g.add(
            format!("colour multiplier {wi}x{we}"),
            3 * p,
            t.multiplier(wi, we),
        );
        g.add(
            format!("colour accumulator {}", wi + we + 2),
            3 * p,
            t.adder(wi + we + 2),
        );
        g.add(
            format!("accumulator register {}", wi + we + 2),
            3 * p,
            t.register(wi + we + 2),
        );
        g.add(format!("entry saturation {we}"), 3 * p, t.clamp(we));
        g.add(format!("entry register {}", 4 * we), p, t.register(4 * we));
        g
    }
}

/// Address bits of the sphere map's 1/m table ([`sphere_map_recip_table`]).
pub const SPHERE_RECIP_INDEX_BITS: u32 = 10;
/// Word width of the sphere map's 1/m table: u1.11.
pub const SPHERE_RECIP_BITS: u32 = 12;

/// The sphere map's 1/m table of the first, f64-addressed EnvMap design, as a ROM would hold
/// it. No model reads it: the model addresses the sphere map in integers through Normalize's
/// reciprocal-square-root table ([`SphereAddress`]), which the generated gate list
/// (`builder_gates_envmap`) prices; this table is left only in the first estimate of
/// [`PaletteBuilder::gates`] (several pipelines, or EnvMap beside another function, which
/// have no generator) and as a ROM calibration point (`hw/tests/gates_yosys.rs`). For a unit
/// reflection `R`, `m = 2
/// sqrt(R_x^2 + R_y^2 + (R_z + 1)^2) = 4 sqrt(u)` with `u = (1 + R_z) / 2` in [0, 1]; entry
/// `i` is `1 / m` at the bin centre `u = (i + 1/2) / 1024`, in u1.11, saturated (`m <= 1/2`,
/// the reflections within 15 degrees of straight down).
pub fn sphere_map_recip_table() -> &'static [i64] {
    static TABLE: std::sync::OnceLock<Vec<i64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let n = 1u32 << SPHERE_RECIP_INDEX_BITS;
        let frac = SPHERE_RECIP_BITS - 1;
        let max = (1i64 << SPHERE_RECIP_BITS) - 1;
        (0..n)
            .map(|i| {
                let u = (f64::from(i) + 0.5) / f64::from(n);
                let r = 1.0 / (4.0 * u.sqrt());
                ((r * f64::from(1u32 << frac)).round() as i64).min(max)
            })
            .collect()
    })
}

/// `sum_l color_l max(0, N.L_l)` per channel.
fn exact_lambert(n: [f64; 3], lights: &[Light]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (d, col) in lights {
        let k = dot(n, unit(*d)).max(0.0);
        for i in 0..3 {
            s[i] += col[i] * k;
        }
    }
    s
}

/// `sum_l color_l max(0, N.H_l)^shininess` per channel, `H_l = normalize(L_l + V)`.
fn exact_specular(n: [f64; 3], lights: &[Light], view: [f64; 3], shininess: f64) -> [f64; 3] {
    let v = unit(view);
    let mut sp = [0.0; 3];
    for (d, col) in lights {
        let h = unit(add(unit(*d), v));
        let k = dot(n, h).clamp(0.0, 1.0).powf(shininess);
        for i in 0..3 {
            sp[i] += col[i] * k;
        }
    }
    sp
}

/// The mean of a colour's channels: the scalar weight of a light in the split form.
fn mean(c: [f64; 3]) -> f64 {
    (c[0] + c[1] + c[2]) / 3.0
}

/// One entry of `C` in f64: RGBA, alpha 1 except for the split form (Lambert intensity).
fn exact_entry(f: &LightingFn, n: [f64; 3]) -> [f64; 4] {
    let c = exact_rgb(f, n);
    let a = match f {
        LightingFn::SpecularSplit {
            ambient,
            diffuse,
            lights,
            ..
        } => {
            let d: f64 = lights
                .iter()
                .map(|(l, col)| mean(*col) * dot(n, unit(*l)).max(0.0))
                .sum();
            (ambient + diffuse * d).clamp(0.0, 1.0)
        }
        _ => 1.0,
    };
    [c[0], c[1], c[2], a]
}

fn exact_rgb(f: &LightingFn, n: [f64; 3]) -> [f64; 3] {
    let sat = |c: [f64; 3]| c.map(|x| x.clamp(0.0, 1.0));
    let lambert = |lights: &[Light]| exact_lambert(n, lights);
    match f {
        LightingFn::Lambert {
            ambient,
            diffuse,
            lights,
        } => {
            let s = lambert(lights);
            sat(std::array::from_fn(|i| ambient[i] + diffuse[i] * s[i]))
        }
        LightingFn::Specular {
            ambient,
            diffuse,
            specular,
            shininess,
            view,
            lights,
        } => {
            let s = lambert(lights);
            let sp = exact_specular(n, lights, *view, *shininess);
            sat(std::array::from_fn(|i| {
                ambient[i] + diffuse[i] * s[i] + specular[i] * sp[i]
            }))
        }
        LightingFn::Cartoon {
            bands,
            ambient,
            diffuse,
            lights,
        } => {
            let d: f64 = lights
                .iter()
                .map(|(l, _)| dot(n, unit(*l)).max(0.0))
                .sum::<f64>()
                .min(1.0);
            let k = ((d * *bands as f64).floor() as u32).min(bands - 1);
            band_colour(*ambient, *diffuse, k, *bands)
        }
        LightingFn::DoubledAnglePhong {
            ambient,
            diffuse,
            specular,
            shininess,
            view,
            light: (l, col),
        } => {
            let l = unit(*l);
            let nl = dot(n, l);
            let rv = dot(reflect(n, l), unit(*view));
            let s = if rv > 0.0 {
                (2.0 * rv * rv - 1.0).clamp(0.0, 1.0).powf(*shininess)
            } else {
                0.0
            };
            sat(std::array::from_fn(|i| {
                ambient[i] + diffuse[i] * col[i] * nl.max(0.0) + specular[i] * col[i] * s
            }))
        }
        LightingFn::Chrome {
            view,
            up,
            sky,
            ground,
        } => {
            let r = reflect(n, unit(*view));
            let t = ((1.0 + dot(r, unit(*up))) / 2.0).clamp(0.0, 1.0);
            sat(std::array::from_fn(|i| {
                ground[i] + t * (sky[i] - ground[i])
            }))
        }
        LightingFn::EnvMap {
            view,
            up,
            image,
            width,
            height,
        } => {
            let r = eye_frame(reflect(n, unit(*view)), *view, *up);
            sat(image[sphere_texel(r, *width, *height)])
        }
        LightingFn::SpecularSplit {
            specular,
            shininess,
            view,
            lights,
            ..
        } => {
            let sp = exact_specular(n, lights, *view, *shininess);
            sat(std::array::from_fn(|i| specular[i] * sp[i]))
        }
    }
}

/// The entry words of a cartoon function's `bands` band colours (RGB), as the host loads
/// them: band `k` is `sat(ambient + diffuse k / (bands - 1))` in `entry`.
pub fn band_codes(
    entry: &Encoding,
    ambient: [f64; 3],
    diffuse: [f64; 3],
    bands: u32,
) -> Vec<[i64; 3]> {
    (0..bands)
        .map(|k| band_colour(ambient, diffuse, k, bands).map(|x| entry.encode(x)))
        .collect()
}

/// Band `k` of `bands`: `sat(ambient + diffuse k / (bands - 1))`.
fn band_colour(ambient: [f64; 3], diffuse: [f64; 3], k: u32, bands: u32) -> [f64; 3] {
    let q = k as f64 / (bands - 1) as f64;
    std::array::from_fn(|i| (ambient[i] + diffuse[i] * q).clamp(0.0, 1.0))
}

/// The bit-accurate datapath for one material: its registers, loaded once.
struct Datapath<'a> {
    f: &'a BuilderFormats,
    gen: Option<&'a SpecularGenerator>,
    sphere: Option<&'a Rsqrt>,
}

impl<'a> Datapath<'a> {
    fn new(
        f: &'a BuilderFormats,
        gen: Option<&'a SpecularGenerator>,
        sphere: Option<&'a Rsqrt>,
    ) -> Self {
        Datapath { f, gen, sphere }
    }
    /// A register vector: normalised by the host, quantized to `vector`
    /// ([`PaletteBuilder::vector_codes`]).
    fn vreg(&self, v: [f64; 3]) -> [Acc; 3] {
        let e = &self.f.vector;
        unit(v).map(|x| Acc::from_code(e.encode(x), e))
    }
    /// A colour coefficient register: an entry word.
    fn creg(&self, c: [f64; 3]) -> [Acc; 3] {
        let e = &self.f.entry;
        c.map(|x| Acc::from_code(e.encode(x), e))
    }
    /// Clamp to [0, 1] and cast to the intensity encoding: (word, value read back).
    fn intensity(&self, x: Acc) -> (i64, Acc) {
        let e = &self.f.intensity;
        let raw = x.clamp(Acc::ZERO, Acc::new(1, 0)).to_code(e);
        (raw, Acc::from_code(raw, e))
    }
    fn out(&self, c: [Acc; 3]) -> [i64; 3] {
        c.map(|x| x.to_code(&self.f.entry))
    }
    fn lambert(&self, nq: [Acc; 3], lights: &[Light]) -> [Acc; 3] {
        let mut s = [Acc::ZERO; 3];
        for (d, col) in lights {
            let (_, k) = self.intensity(adot(nq, self.vreg(*d)));
            let c = self.creg(*col);
            for i in 0..3 {
                s[i] = s[i].add(c[i].mul(k));
            }
        }
        s
    }

    /// `sum_l color_l . P(N.H_l)` per channel, `P` the power generator.
    fn specular(&self, nq: [Acc; 3], lights: &[Light], view: [f64; 3]) -> [Acc; 3] {
        let v = unit(view);
        let gen = self.gen.expect("a specular function has a generator");
        let mut sp = [Acc::ZERO; 3];
        for (l, col) in lights {
            let h = self.vreg(add(unit(*l), v));
            let (raw, _) = self.intensity(adot(nq, h));
            let k = gen.bits(raw);
            let c = self.creg(*col);
            for i in 0..3 {
                sp[i] = sp[i].add(c[i].mul(k));
            }
        }
        sp
    }

    /// One entry word per lane (RGBA).
    fn entry(&self, f: &LightingFn, n: [f64; 3]) -> [i64; 4] {
        let ne = &self.f.normal;
        let nq = n.map(|x| Acc::from_code(ne.encode(x), ne));
        let e = &self.f.entry;
        if let LightingFn::SpecularSplit {
            ambient,
            diffuse,
            specular,
            view,
            lights,
            ..
        } = f
        {
            // alpha: a + d sum_l w_l I(N.L_l), the weights w_l = mean(colour_l) entry words
            let word = |x: f64| Acc::from_code(e.encode(x), e);
            let mut sum = Acc::ZERO;
            for (l, col) in lights {
                let (_, k) = self.intensity(adot(nq, self.vreg(*l)));
                sum = sum.add(word(mean(*col)).mul(k));
            }
            let alpha = word(*ambient).add(word(*diffuse).mul(sum)).to_code(e);
            let (sc, sp) = (self.creg(*specular), self.specular(nq, lights, *view));
            let c = self.out(std::array::from_fn(|i| sc[i].mul(sp[i])));
            return [c[0], c[1], c[2], alpha];
        }
        let c = self.rgb(f, nq);
        [c[0], c[1], c[2], e.encode(1.0)]
    }

    fn rgb(&self, f: &LightingFn, nq: [Acc; 3]) -> [i64; 3] {
        match f {
            LightingFn::Lambert {
                ambient,
                diffuse,
                lights,
            } => {
                let (a, d) = (self.creg(*ambient), self.creg(*diffuse));
                let s = self.lambert(nq, lights);
                self.out(std::array::from_fn(|i| a[i].add(d[i].mul(s[i]))))
            }
            LightingFn::Specular {
                ambient,
                diffuse,
                specular,
                view,
                lights,
                ..
            } => {
                let (a, d, sc) = (
                    self.creg(*ambient),
                    self.creg(*diffuse),
                    self.creg(*specular),
                );
                let s = self.lambert(nq, lights);
                let sp = self.specular(nq, lights, *view);
                self.out(std::array::from_fn(|i| {
                    a[i].add(d[i].mul(s[i])).add(sc[i].mul(sp[i]))
                }))
            }
            LightingFn::Cartoon {
                bands,
                ambient,
                diffuse,
                lights,
            } => {
                let mut sum = Acc::ZERO;
                for (l, _) in lights {
                    sum = sum.add(adot(nq, self.vreg(*l)).clamp(Acc::ZERO, Acc::new(1, 0)));
                }
                let (_, d) = self.intensity(sum);
                let k = d
                    .scale(*bands as i128)
                    .round_int(crate::format::Quant::Trn)
                    .clamp(0, *bands as i128 - 1) as u32;
                // the host loads the band colours as entry words ([`band_codes`])
                band_colour(*ambient, *diffuse, k, *bands).map(|x| self.f.entry.encode(x))
            }
            LightingFn::DoubledAnglePhong {
                ambient,
                diffuse,
                specular,
                view,
                light: (l, col),
                ..
            } => {
                let (a, d, sc, c) = (
                    self.creg(*ambient),
                    self.creg(*diffuse),
                    self.creg(*specular),
                    self.creg(*col),
                );
                let (lq, vq) = (self.vreg(*l), self.vreg(*view));
                let nl = adot(nq, lq);
                let nv = adot(nq, vq);
                // R.V = 2 (N.L)(N.V) - L.V
                let rv = nl.mul(nv).scale(2).sub(adot(lq, vq));
                let s = if Acc::ZERO.lt(rv) {
                    let (raw, _) = self.intensity(rv.mul(rv).scale(2).sub(Acc::new(1, 0)));
                    self.gen.expect("phong has a generator").bits(raw)
                } else {
                    Acc::ZERO
                };
                let (_, kd) = self.intensity(nl);
                self.out(std::array::from_fn(|i| {
                    a[i].add(d[i].mul(c[i]).mul(kd)).add(sc[i].mul(c[i]).mul(s))
                }))
            }
            LightingFn::Chrome {
                view,
                up,
                sky,
                ground,
            } => {
                let (vq, uq) = (self.vreg(*view), self.vreg(*up));
                // R.up = 2 (N.V)(N.up) - V.up
                let ru = adot(nq, vq).scale(2).mul(adot(nq, uq)).sub(adot(vq, uq));
                let (_, t) = self.intensity(Acc::new(1, 0).add(ru).shr(1));
                let (s, g) = (self.creg(*sky), self.creg(*ground));
                self.out(std::array::from_fn(|i| g[i].add(s[i].sub(g[i]).mul(t))))
            }
            LightingFn::EnvMap {
                view,
                up,
                image,
                width,
                height,
            } => {
                // R in the eye frame: R.a = 2 (N.V)(N.a) - V.a for the host's axes a = x, y,
                // z (vector registers; z is V), exact
                let vq = self.vreg(*view);
                let nv = adot(nq, vq).scale(2);
                let re = self.f.sphere.r_encoding();
                let r = eye_axes(*view, *up).map(|a| {
                    let aq = self.vreg(a);
                    let r = nv.mul(adot(nq, aq)).sub(adot(vq, aq));
                    Acc::from_code(r.to_code(&re), &re)
                });
                let rs = self.sphere.expect("an EnvMap builder has its rsqrt table");
                let (i, j) = sphere_address(rs, r, *width, *height);
                image[j * *width as usize + i].map(|x| self.f.entry.encode(x))
            }
            LightingFn::SpecularSplit { .. } => [0; 3], // entry() handles the split form
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::format::{Codec, Format};
    use crate::units::PaletteLut;

    pub(crate) fn formats() -> BuilderFormats {
        BuilderFormats {
            normal: Encoding::texel(Codec::UnitSigned, true, 10),
            vector: Encoding::texel(Codec::UnitSigned, true, 10),
            intensity: Encoding::texel(Codec::UnitUnsigned, false, 10),
            power: SpecGen::Table {
                index_bits: 10,
                value_bits: 12,
            },
            entry: Encoding::texel(Codec::UnitUnsigned, false, 8),
            sphere: Default::default(),
        }
    }
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }
    fn random_normals(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut s = seed;
        (0..n)
            .map(|_| loop {
                let v: [f64; 3] = std::array::from_fn(|_| 2.0 * lcg(&mut s) - 1.0);
                let l = norm(v);
                if l > 0.1 && l <= 1.0 {
                    break unit(v);
                }
            })
            .collect()
    }
    fn axes() -> Vec<[f64; 3]> {
        vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ]
    }
    fn lambert() -> LightingFn {
        LightingFn::Lambert {
            ambient: [0.1, 0.1, 0.1],
            diffuse: [0.8, 0.6, 0.4],
            lights: vec![([0.0, 0.0, 2.0], [1.0, 1.0, 1.0])],
        }
    }
    fn specular(view: [f64; 3]) -> LightingFn {
        LightingFn::Specular {
            ambient: [0.1, 0.1, 0.1],
            diffuse: [0.5, 0.4, 0.3],
            specular: [0.4, 0.4, 0.4],
            shininess: 16.0,
            view,
            lights: vec![([0.3, 0.2, 1.0], [1.0, 1.0, 1.0])],
        }
    }

    #[test]
    fn palette_builder_lambert_axis_normals_by_hand() {
        let b = PaletteBuilder::single(axes(), lambert(), formats(), 1).unwrap();
        let e = b.build_exact();
        for (i, c) in e.iter().enumerate() {
            let want = if i == 4 {
                [0.9, 0.7, 0.5, 1.0]
            } else {
                [0.1, 0.1, 0.1, 1.0]
            };
            for l in 0..4 {
                assert!((c[l] - want[l]).abs() < 1e-12, "{i} {l}");
            }
        }
        // words: ambient 26/255, diffuse 204, 153, 102 /255. Signed 10-bit (c / 512) has no
        // 1.0: n_z = l_z = 511/512, N.L = 0.996098 -> intensity round(1019.01) = 1019/1023;
        // R = 26 + 204 x 0.996090 = 229.2 -> 229, G = 26 + 153 x 0.99609 = 178.4 -> 178,
        // B = 26 + 102 x 0.99609 = 127.6 -> 128
        let w = b.build_codes();
        assert_eq!(w[4], [229, 178, 128, 255]);
        for i in [0, 1, 2, 3, 5] {
            assert_eq!(w[i], [26, 26, 26, 255], "{i}");
        }
        // s1.8 fixed vectors hold 1.0: N.L = 1 and the words are the rounded hand values
        let mut f = formats();
        f.normal = Encoding::fixed(Format::s(10, 8));
        f.vector = f.normal;
        let b = PaletteBuilder::single(axes(), lambert(), f, 1).unwrap();
        assert_eq!(b.build_codes()[4], [230, 179, 128, 255]);
    }

    /// Bound for one `coef x intensity` term: the coefficient word (half an entry step, plus
    /// the bit-replication read), the intensity's input error `dx`, and the product of both.
    fn term(f: &BuilderFormats, dx: f64) -> f64 {
        let ec = f.entry.max_error() + (-2.0 * f.entry.width() as f64).exp2();
        ec + dx + ec * dx
    }

    #[test]
    fn palette_builder_exact_and_bit_accurate_agree_within_the_derived_bound() {
        let f = formats();
        let normals = random_normals(2048, 11);
        // dot product error of quantized unit vectors: |dn.l| + |n.dl| + |dn.dl|
        let (en, ev) = (f.normal.max_error(), f.vector.max_error());
        let edot = 3f64.sqrt() * (en + ev) + 3.0 * en * ev;
        let ei = f.intensity.max_error() + (-2.0 * f.intensity.width() as f64).exp2();
        let eout = f.entry.max_error();
        let ecoef = f.entry.max_error() + (-2.0 * f.entry.width() as f64).exp2();

        // Lambert: ambient word + diffuse x (colour x intensity) + the output cast
        let lam_bound = ecoef + term(&f, term(&f, edot + ei)) + eout;
        let b = PaletteBuilder::single(normals.clone(), lambert(), f, 2).unwrap();
        let (e, w) = (b.build(Mode::Exact), b.build(Mode::BitAccurate));
        let mut worst: f64 = 0.0;
        for (x, y) in e.values.iter().zip(&w.values) {
            for l in 0..4 {
                worst = worst.max((x[l] - y[l]).abs());
            }
        }
        println!("lambert: worst {worst:.5} bound {lam_bound:.5}");
        assert!(worst <= lam_bound, "lambert {worst} > {lam_bound}");

        // Specular: plus the power term, the generator's bound and its slope n on the input
        // error (the half-way vector is one more quantized vector: edot covers it)
        let func = specular([0.0, 0.3, 1.0]);
        let b = PaletteBuilder::single(normals, func, f, 1).unwrap();
        let gen = SpecularGenerator::new(f.power, 16.0, f.intensity).unwrap();
        let epow = gen.error_bound() + 16.0 * (edot + f.intensity.max_error());
        let spec_bound = ecoef + term(&f, term(&f, edot + ei)) + term(&f, term(&f, epow)) + eout;
        let (e, w) = (b.build(Mode::Exact), b.build(Mode::BitAccurate));
        let mut worst: f64 = 0.0;
        for (x, y) in e.values.iter().zip(&w.values) {
            for l in 0..4 {
                worst = worst.max((x[l] - y[l]).abs());
            }
        }
        println!("specular: worst {worst:.5} bound {spec_bound:.5}");
        assert!(worst <= spec_bound, "specular {worst} > {spec_bound}");
    }

    #[test]
    fn palette_builder_cartoon_has_at_most_bands_values() {
        let normals = random_normals(2048, 5);
        for bands in [2u32, 3, 4] {
            let func = LightingFn::Cartoon {
                bands,
                ambient: [0.1, 0.1, 0.2],
                diffuse: [0.7, 0.5, 0.3],
                lights: vec![([0.2, 0.5, 1.0], [1.0, 1.0, 1.0])],
            };
            let b = PaletteBuilder::single(normals.clone(), func, formats(), 4).unwrap();
            for mode in [Mode::Exact, Mode::BitAccurate] {
                let mut distinct: Vec<[i64; 4]> = b.build(mode).codes;
                distinct.sort();
                distinct.dedup();
                assert!(distinct.len() <= bands as usize, "{bands} {mode:?}");
                assert!(distinct.len() >= 2, "{bands} {mode:?}");
            }
            let mut xs: Vec<String> = b.build_exact().iter().map(|c| format!("{c:?}")).collect();
            xs.sort();
            xs.dedup();
            assert!(xs.len() <= bands as usize);
        }
    }

    #[test]
    fn palette_builder_doubled_angle_phong_at_two_angles() {
        // light = normal = +z, so R = +z; the view at angle a from z gives R.V = cos a
        let at = |deg: f64| {
            let a = deg.to_radians();
            let func = LightingFn::DoubledAnglePhong {
                ambient: [0.0; 3],
                diffuse: [0.0; 3],
                specular: [1.0; 3],
                shininess: 2.0,
                view: [a.sin(), 0.0, a.cos()],
                light: ([0.0, 0.0, 1.0], [1.0; 3]),
            };
            // s1.10 vectors: 1.0 and 0.5 exact, cos 30 = 887/1024 (error 1.8e-4)
            let mut f = formats();
            f.normal = Encoding::fixed(Format::s(12, 10));
            f.vector = f.normal;
            let b = PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], func, f, 1).unwrap();
            (
                b.build_exact()[0][0],
                b.build(Mode::BitAccurate).values[0][0],
            )
        };
        // 0 degrees: cos 0 = 1; 30 degrees: cos 60 = 0.5, squared 0.25; 60: cos 120 < 0
        for (deg, want) in [(0.0, 1.0), (30.0, 0.25), (60.0, 0.0)] {
            let (e, b) = at(deg);
            assert!((e - want).abs() < 1e-12, "{deg}: {e}");
            assert!((b - want).abs() <= 2.0 / 255.0, "{deg}: {b}");
        }
    }

    #[test]
    fn palette_builder_chrome_sky_above_ground_below() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let (sky, ground) = ([0.2, 0.4, 1.0], [0.5, 0.3, 0.1]);
        let func = LightingFn::Chrome {
            view: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            sky,
            ground,
        };
        // n = (1,0,1)/sqrt2 reflects V = +x to +z (up); n = (1,0,-1)/sqrt2 to -z (down)
        let b =
            PaletteBuilder::single(vec![[s, 0.0, s], [s, 0.0, -s]], func, formats(), 1).unwrap();
        let e = b.build_exact();
        let w = b.build(Mode::BitAccurate).values;
        for (i, want) in [sky, ground].iter().enumerate() {
            for l in 0..3 {
                assert!((e[i][l] - want[l]).abs() < 1e-12, "{i} {l}");
                assert!((w[i][l] - want[l]).abs() <= 2.0 / 255.0, "{i} {l}");
            }
        }
    }

    #[test]
    fn palette_builder_env_map_reads_the_reflected_texel() {
        // 2x2 map: R = +z (looking back at the viewer) hits the centre: texel (1, 1)
        let image = vec![[0.0; 3], [0.25; 3], [0.5; 3], [1.0, 0.0, 0.0]];
        let func = LightingFn::EnvMap {
            view: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            image,
            width: 2,
            height: 2,
        };
        let b = PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], func, formats(), 1).unwrap();
        assert_eq!(b.build_exact()[0], [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(b.build_codes()[0], [255, 0, 0, 255]);
    }

    #[test]
    fn environment_images_are_textures_the_frame_work_reads_not_tables_of_the_unit() {
        let env = |w: u32, h: u32| LightingFn::EnvMap {
            view: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            image: vec![[0.5; 3]; (w * h) as usize],
            width: w,
            height: h,
        };
        let normals = vec![[0.0, 0.0, 1.0]; 7];
        let read = |name: &str, size: [u32; 2], texels: u64| crate::unit::FrameRead {
            name: name.to_string(),
            size,
            bits_per_texel: 24,
            texels_per_frame: texels,
        };
        // one texel per entry per frame, 3 x 8 bits a texel
        let one = PaletteBuilder::single(normals.clone(), env(4, 2), formats(), 1).unwrap();
        assert_eq!(one.frame_reads(), [read("environment", [4, 2], 7)]);
        // two materials with a map each (and one without): named by their interval
        let lambert = LightingFn::Lambert {
            ambient: [0.1; 3],
            diffuse: [0.5; 3],
            lights: vec![([0.0, 0.0, 1.0], [1.0; 3])],
        };
        let materials = vec![(0..3, env(4, 2)), (3..5, lambert), (5..7, env(16, 16))];
        let b = PaletteBuilder::new(normals, materials, formats(), 1).unwrap();
        assert_eq!(
            b.frame_reads(),
            [
                read("environment.0", [4, 2], 3),
                read("environment.2", [16, 16], 2)
            ]
        );
        // the images are no memory of the unit: a 1 x 1 map and a 4 x 2 one take the same
        // (the normal table and the rsqrt ROM; the address logic scales with the side)
        let t = CostTable::default();
        let small = PaletteBuilder::single(vec![[0.0, 0.0, 1.0]; 7], env(1, 1), formats(), 1);
        let memory = |b: &PaletteBuilder| b.gates(&t).memory();
        assert_eq!(memory(&small.unwrap()), memory(&one));
        assert!(one
            .gates(&t)
            .items
            .iter()
            .all(|i| !i.what.contains("environment")));
    }

    #[test]
    fn palette_builder_env_map_follows_the_eye_frame() {
        // 4x4 map, one bright texel per quadrant row; a viewer on +x with up +z sees the
        // same texel for n = +x (R = V, the map's centre) as a viewer on +z with up +y for
        // n = +z, and a normal tilted towards `up` reads a texel above the centre.
        let image: Vec<[f64; 3]> = (0..16).map(|i| [i as f64 / 15.0; 3]).collect();
        let env = |view, up| LightingFn::EnvMap {
            view,
            up,
            image: image.clone(),
            width: 4,
            height: 4,
        };
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let at = |f: LightingFn, n: [f64; 3]| {
            PaletteBuilder::single(vec![n], f, formats(), 1)
                .unwrap()
                .build_exact()[0][0]
        };
        let centre = at(env([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(centre, 10.0 / 15.0); // s = t = 1/2 -> texel (2, 2)
        assert_eq!(
            at(env([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]),
            centre
        );
        // n halfway between V = +x and up = +z: R = +z, straight up: t = 1 -> last row
        let up = at(env([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]), [s, 0.0, s]);
        assert_eq!(up, 14.0 / 15.0); // (s, t) = (1/2, 1) -> texel (2, 3)
    }

    #[test]
    fn palette_builder_split_form_holds_lambert_in_alpha_and_specular_in_rgb() {
        let f = LightingFn::SpecularSplit {
            ambient: 0.1,
            diffuse: 0.8,
            specular: [1.0, 0.5, 0.25],
            shininess: 16.0,
            view: [0.0, 0.0, 1.0],
            lights: vec![([0.0, 0.0, 1.0], [1.0, 1.0, 1.0])],
            lambert: false,
        };
        let normals = random_normals(256, 5);
        let b = PaletteBuilder::single(normals.clone(), f, formats(), 1).unwrap();
        let (e, w) = (b.build_exact(), b.build(Mode::BitAccurate).values);
        for (i, n) in normals.iter().enumerate() {
            let nz = n[2].max(0.0);
            let want = [nz.powf(16.0), 0.5 * nz.powf(16.0), 0.25 * nz.powf(16.0)];
            for l in 0..3 {
                assert!((e[i][l] - want[l]).abs() < 1e-12, "{i} {l}");
            }
            assert!((e[i][3] - (0.1 + 0.8 * nz).min(1.0)).abs() < 1e-12, "{i}");
            // a dot product of 10-bit words is off by at most d = 4/1023; x^16 has slope
            // <= 16, so the specular lanes are within 16 d + 1 LSB, alpha within d + 1 LSB
            let d = 4.0 / 1023.0;
            for l in 0..3 {
                assert!(
                    (w[i][l] - e[i][l]).abs() <= 16.0 * d + 1.0 / 255.0,
                    "{i} {l}"
                );
            }
            assert!((w[i][3] - e[i][3]).abs() <= d + 1.0 / 255.0, "{i} alpha");
        }
        assert_eq!(b.cycles_per_frame(), 2 * 256);
    }

    #[test]
    fn palette_builder_cycles_grow_linearly_and_ignore_texture_size() {
        let env = |w: u32| LightingFn::EnvMap {
            view: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            image: vec![[0.5; 3]; (w * w) as usize],
            width: w,
            height: w,
        };
        for p in [1u32, 4] {
            let c = |n: usize, f: LightingFn| {
                PaletteBuilder::single(random_normals(n, 3), f, formats(), p)
                    .unwrap()
                    .cycles_per_frame()
            };
            let c1 = c(1024, lambert());
            assert_eq!(c1, 1024 / p as u64);
            assert_eq!(c(2048, lambert()), 2 * c1);
            assert_eq!(c(4096, lambert()), 4 * c1);
            assert_eq!(c(2048, specular([0.0, 0.0, 1.0])), 2 * 2048 / p as u64);
            assert_eq!(c(2048, env(4)), c(2048, env(64)));
            assert_eq!(c(2048, env(4)), 4 * 2048 / p as u64);
        }
        assert_eq!(
            PaletteBuilder::single(random_normals(10, 3), lambert(), formats(), 4)
                .unwrap()
                .cycles_per_frame(),
            3
        );
    }

    #[test]
    fn palette_builder_materials_apply_to_their_intervals_only() {
        let normals = random_normals(64, 9);
        let chrome = LightingFn::Chrome {
            view: [0.0, 0.2, 1.0],
            up: [0.0, 0.0, 1.0],
            sky: [0.2, 0.4, 1.0],
            ground: [0.5, 0.3, 0.1],
        };
        let f = formats();
        let mixed = PaletteBuilder::new(
            normals.clone(),
            vec![(0..20, lambert()), (20..64, chrome.clone())],
            f,
            2,
        )
        .unwrap();
        let a = PaletteBuilder::single(normals.clone(), lambert(), f, 2).unwrap();
        let c = PaletteBuilder::single(normals, chrome, f, 2).unwrap();
        for mode in [Mode::Exact, Mode::BitAccurate] {
            let (m, a, c) = (mixed.build(mode), a.build(mode), c.build(mode));
            assert_eq!(m.codes[..20], a.codes[..20]);
            assert_eq!(m.codes[20..], c.codes[20..]);
            assert_ne!(m.codes[20..], a.codes[20..]);
        }
        assert_eq!(mixed.cycles_per_frame(), 10 + 22 * 2);
        // intervals must cover the table in order
        let bad = |m: Vec<(Range<usize>, LightingFn)>| {
            PaletteBuilder::new(random_normals(8, 1), m, f, 1).is_err()
        };
        assert!(bad(vec![(0..4, lambert())]));
        assert!(bad(vec![(0..4, lambert()), (5..8, lambert())]));
        assert!(bad(vec![(0..0, lambert()), (0..8, lambert())]));
        assert!(!bad(vec![(0..4, lambert()), (4..8, lambert())]));
    }

    #[test]
    fn palette_builder_output_loads_into_the_lut() {
        use crate::unit::Unit;
        let f = formats();
        let b = PaletteBuilder::single(random_normals(256, 2), lambert(), f, 1).unwrap();
        let mut lut = PaletteLut::new(
            Encoding::fixed(Format::u(8, 0)),
            f.entry,
            vec![[0.0; 4]; 256],
            1,
        )
        .unwrap();
        lut.load(b.build(Mode::BitAccurate)).unwrap();
        assert_eq!(lut.frame_cycles(), 256);
    }

    #[test]
    fn palette_builder_and_lut_numbers_for_256_2048_16384_entries() {
        let t = CostTable::default();
        let f = formats();
        for (n, bits) in [(256usize, 8u8), (2048, 11), (16384, 14)] {
            for (name, func) in [
                ("lambert", lambert()),
                ("specular", specular([0.0, 0.0, 1.0])),
            ] {
                let b = PaletteBuilder::single(random_normals(n, 1), func, f, 1).unwrap();
                let lut = PaletteLut::new(
                    Encoding::fixed(Format::u(bits, 0)),
                    f.entry,
                    vec![[0.0; 4]; n],
                    1,
                )
                .unwrap();
                use crate::unit::Unit;
                println!(
                    "entries {n} {name}: builder {:.0} GE {} cycles; lut {:.0} GE {} load cycles {} bits",
                    b.gates(&t).total(),
                    b.cycles_per_frame(),
                    lut.gates(&t).total(),
                    lut.frame_cycles(),
                    lut.load_bits()
                );
                assert_eq!(
                    b.cycles_per_frame(),
                    n as u64 * b.materials[0].1.cycles_per_entry()
                );
            }
        }
    }

    /// The bit-accurate sphere-map address against the f64 formula on the same exact
    /// reflection: within one texel per axis wherever `q >= 1/16` (the table's relative error
    /// `2^-table_bits` moves `n (1 + c) / 2` by at most `n 2^-(table_bits+1)`, half a texel at
    /// n = 2^table_bits), equal for 94 %; `q = 0` is the centre.
    #[test]
    fn sphere_address_is_the_formula_within_a_texel() {
        let rs = Rsqrt::new(10, 16).unwrap();
        let (mut seed, mut equal, mut n) = (7u64, 0, 0);
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as i128 - (1 << 30)
        };
        for _ in 0..20_000 {
            // R with 30 fraction bits, |R| up to 2
            let r: [Acc; 3] = std::array::from_fn(|_| Acc::new(rnd(), 29));
            let rf = r.map(|x| x.to_f64());
            let q = rf[0] * rf[0] + rf[1] * rf[1] + (rf[2] + 1.0) * (rf[2] + 1.0);
            if q < 1.0 / 16.0 {
                continue;
            }
            for (w, h) in [(256, 256), (1000, 37)] {
                let (i, j) = sphere_address(&rs, r, w, h);
                let k = sphere_texel(rf, w, h);
                let (fi, fj) = (k % w as usize, k / w as usize);
                assert!(
                    i.abs_diff(fi) <= 1 && j.abs_diff(fj) <= 1,
                    "{rf:?}: {i} {j} {fi} {fj}"
                );
                n += 1;
                equal += usize::from((i, j) == (fi, fj));
            }
        }
        // measured: 37,916 of 39,972 (94.9 %)
        assert!(equal * 100 > n * 94, "{equal} of {n} equal");
        let back = [Acc::ZERO, Acc::ZERO, Acc::new(-1, 0)];
        assert_eq!(sphere_address(&rs, back, 256, 255), (128, 127));
    }

    /// Words whose reflection would overflow 128 bits, and reflection words outside 2 to 30
    /// fraction bits, are refused when the builder is built; symmetric 10-bit words are not.
    #[test]
    fn sphere_words_too_wide_are_refused() {
        let wide = Encoding::fixed(Format::s(32, 30));
        let f = BuilderFormats {
            normal: wide,
            vector: wide,
            ..formats()
        };
        let env = LightingFn::EnvMap {
            view: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            image: vec![[0.5; 3]; 4],
            width: 2,
            height: 2,
        };
        let e = PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], env.clone(), f, 1).unwrap_err();
        assert!(e.contains("128-bit"), "{e}");
        let sym = Encoding::texel(Codec::UnitSymmetric, true, 10);
        let f = BuilderFormats {
            normal: sym,
            vector: sym,
            ..formats()
        };
        assert!(PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], env.clone(), f, 1).is_ok());
        for r_frac in [1, 31] {
            let mut f = formats();
            f.sphere.r_frac = r_frac;
            let e = PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], env.clone(), f, 1).unwrap_err();
            assert!(e.contains("r_frac"), "{e}");
        }
        assert!(PaletteBuilder::single(vec![[0.0, 0.0, 1.0]], env, formats(), 1).is_ok());
    }
}
