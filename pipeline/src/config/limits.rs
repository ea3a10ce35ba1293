//! Ranges that bound work and memory, checked when a config is loaded, before any work
//! (allocation, baking, quantization) starts: hard limits on the fields of the units
//! ([`check_units`]) and an up-front estimate of a run's work and memory ([`estimate`])
//! against a budget ([`BUDGET_SECONDS`], [`BUDGET_BYTES`]), which `--force` may exceed.
//! `docs/configs.md` ("Input limits and ranges") lists them.

use super::InputError;
use super::{Config, Loaded};
use crate::engine::units::{TextureSource, UnitSpec};
use crate::quantize::Quantizer;
use crate::scene::{MeshSpec, MAX_LIGHTS};
use bumpsim_hw::units::SpecGen;

/// Largest memory latency of a texture unit, in cycles.
pub const MAX_MEM_LATENCY: u32 = 1024;
/// Largest vector or input count of `Dot3` and `PowerTable`.
pub const MAX_COUNT: u32 = 8;
/// Largest texture side of a unit.
pub const MAX_TEXTURE_SIDE: u32 = 4096;
/// Largest bump-normal palette of `TexFetch`.
pub const MAX_PALETTE: u32 = 65536;
/// Largest `index_bits` of a power table or specular generator (a table of 65536 words).
pub const MAX_TABLE_BITS: u32 = 16;

/// The time budget of the estimate: 600 s (ten minutes) of wall time on the reference
/// machine, two cores and 24 GB.
pub const BUDGET_SECONDS: f64 = 600.0;
/// The memory budget of the estimate: 8 GiB, a third of the reference machine's 24 GB (the
/// estimate is rough: the rest is its margin).
pub const BUDGET_BYTES: f64 = 8.0 * (1u64 << 30) as f64;

/// A unit field out of range: `(field below the unit, message)`.
type Bad = (String, String);

fn range(field: &str, x: u32, lo: u32, hi: u32, what: &str) -> Result<(), Bad> {
    if (lo..=hi).contains(&x) {
        Ok(())
    } else {
        Err((
            field.to_string(),
            format!("{field} {x}: expected {lo} to {hi}{what}"),
        ))
    }
}

fn side(field: &str, size: u32) -> Result<(), Bad> {
    if size.is_power_of_two() && size <= MAX_TEXTURE_SIDE {
        Ok(())
    } else {
        Err((
            field.to_string(),
            format!("size {size}: expected a power of two from 1 to {MAX_TEXTURE_SIDE}"),
        ))
    }
}

/// The side of an NDF table (`crate::ndf::sources`: L and the NDF texture, at most 1024).
fn ndf_side(field: &str, size: u32) -> Result<(), Bad> {
    let max = crate::ndf::sources::MAX_LOOKUP_SIDE;
    if size.is_power_of_two() && size <= max {
        Ok(())
    } else {
        Err((
            field.to_string(),
            format!("size {size}: expected a power of two from 1 to {max} (an NDF table)"),
        ))
    }
}

fn mem_latency(x: u32) -> Result<(), Bad> {
    range("mem_latency", x, 1, MAX_MEM_LATENCY, " cycles")
}

fn spec_gen(field: &str, g: &SpecGen) -> Result<(), Bad> {
    match *g {
        SpecGen::Table { index_bits, .. } | SpecGen::TableLerp { index_bits, .. } => range(
            &format!("{field}.index_bits"),
            index_bits,
            1,
            MAX_TABLE_BITS,
            " bits",
        ),
        SpecGen::Squaring { .. } => Ok(()),
    }
}

fn texture_source(s: &TextureSource) -> Result<(), Bad> {
    match *s {
        TextureSource::BumpNormals { size, .. }
        | TextureSource::BumpHilo { size, .. }
        | TextureSource::BumpHeights { size }
        | TextureSource::BumpGradient { size, .. }
        | TextureSource::ObjectNormals { size }
        | TextureSource::LightingTable { size, .. }
        | TextureSource::SphereLighting { size, .. }
        | TextureSource::NdfNoise { size, .. } => side("source.size", size),
        TextureSource::NdfLookup { size, .. }
        | TextureSource::NdfShading { size, .. }
        | TextureSource::NdfShading2d { size, .. } => ndf_side("source.size", size),
        TextureSource::CubeLighting { size, .. } => {
            let max = crate::engine::units::MAX_CUBE_SIDE;
            if size.is_power_of_two() && size <= max {
                Ok(())
            } else {
                Err((
                    "source.size".into(),
                    format!(
                        "size {size}: expected a power of two from 1 to {max} (a cube map's face)"
                    ),
                ))
            }
        }
        TextureSource::ColorTexture => Ok(()),
    }
}

/// The hard limits of one unit's fields that bound its work, memory and timing (the unit's
/// build checks the rest): `(field below engine.units[i].unit, message)`.
fn check_unit(u: &UnitSpec) -> Result<(), Bad> {
    match u {
        UnitSpec::TexFetch(s) => {
            texture_source(&s.source)?;
            range("ports", s.ports, 1, 4, " texels per clock")?;
            range("weight_bits", s.weight_bits, 1, 16, " bits")?;
            mem_latency(s.mem_latency)?;
            if let Some(n) = s.palette {
                range("palette", n, 2, MAX_PALETTE, " entries")?;
            }
            Ok(())
        }
        UnitSpec::EmbossFilter(s) => {
            side("size", s.size)?;
            range("ports", s.ports, 1, 9, " texels per clock")?;
            mem_latency(s.mem_latency)?;
            if let Some(w) = s.bevel_w {
                if !(w.is_finite() && w > 0.0 && w <= 1e12) {
                    return Err((
                        "bevel_w".into(),
                        format!("bevel_w {w}: expected a number above 0, at most 1e12"),
                    ));
                }
            }
            Ok(())
        }
        UnitSpec::Dot3(s) => range("count", s.count, 1, MAX_COUNT, " vectors"),
        UnitSpec::PowerTable(s) => {
            range("count", s.count, 1, MAX_COUNT, " inputs")?;
            range("index_bits", s.index_bits, 1, MAX_TABLE_BITS, "")
        }
        UnitSpec::Normalize(s) => range("table_bits", s.table_bits, 2, MAX_TABLE_BITS, ""),
        UnitSpec::TexramFrame(s) => range("table_bits", s.table_bits, 2, MAX_TABLE_BITS, ""),
        UnitSpec::QuatFrame(s) => range("table_bits", s.table_bits, 2, MAX_TABLE_BITS, ""),
        UnitSpec::TextureShader(s) => {
            for (i, p) in s.programs.iter().enumerate() {
                if let Some(t) = &p.texture {
                    texture_source(&t.source)
                        .map_err(|(f, m)| (format!("programs[{i}].texture.{f}"), m))?;
                }
            }
            range(
                "programs",
                s.programs.len().min(u32::MAX as usize) as u32,
                1,
                bumpsim_hw::units::texture_shader::MAX_STAGES as u32,
                " stages",
            )
        }
        UnitSpec::BumpBlend(s) => spec_gen("spec", &s.spec),
        UnitSpec::QuantizedNormals(s) => {
            side("size", s.size)?;
            let max_bits = bumpsim_hw::units::MAX_INDEX_BITS;
            range("index_bits", s.index_bits, 8, max_bits, "")?;
            let most = 1u32 << s.index_bits;
            if !(1..=most).contains(&s.s_n) {
                let m = format!("s_n {}: expected 1 to 2^index_bits = {most}", s.s_n);
                return Err(("s_n".into(), m));
            }
            let table = s.quantizer.max_entries();
            if s.s_n as usize > table {
                let m = format!(
                    "s_n {}: expected at most {table} for {:?} (Exact keeps up to {})",
                    s.s_n,
                    s.quantizer,
                    crate::quantize::MAX_EXACT
                );
                return Err(("s_n".into(), m));
            }
            range("entries_per_clock", s.entries_per_clock, 1, 64, "")?;
            range("load_width", s.load_width, 1, 64, "")?;
            spec_gen("datapath.power", &s.datapath.power)?;
            let sphere = &s.datapath.sphere;
            range(
                "datapath.sphere.r_frac",
                sphere.r_frac,
                2,
                30,
                " fraction bits",
            )?;
            range(
                "datapath.sphere.table_bits",
                sphere.table_bits,
                2,
                MAX_TABLE_BITS,
                " bits",
            )?;
            range(
                "datapath.sphere.value_bits",
                sphere.value_bits,
                4,
                32,
                " bits",
            )?;
            match s.quantizer {
                Quantizer::NeuQuant { sample_factor } => {
                    range("quantizer.sample_factor", sample_factor, 1, 30, "")
                }
                Quantizer::KMeans { max_iterations, .. } => range(
                    "quantizer.max_iterations",
                    max_iterations,
                    1,
                    crate::quantize::MAX_KMEANS_ITERATIONS,
                    "",
                ),
                Quantizer::MedianCut | Quantizer::Exact => Ok(()),
            }
        }
        _ => Ok(()),
    }
}

/// Check every unit's hard limits; the error names `engine.units[i].unit.<field>`.
pub fn check_units(l: &Loaded) -> Result<(), InputError> {
    for (i, u) in l.config.engine.units.iter().enumerate() {
        if let Err((field, message)) = check_unit(&u.unit) {
            return Err(l.error(
                &format!("engine.units[{i}].unit.{field}"),
                &format!("\"{}\"", u.name),
                message,
            ));
        }
    }
    let n = l.config.scene.lights.len();
    if n > MAX_LIGHTS {
        return Err(l.error(
            "scene.lights",
            "lights:",
            format!("{n} lights: expected at most {MAX_LIGHTS}"),
        ));
    }
    Ok(())
}

/// One term of the estimate: what it counts (naming the fields) and its cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    pub what: String,
    pub seconds: f64,
    pub bytes: f64,
}

/// An up-front estimate of a run's wall time on the reference machine (two cores) and its
/// peak memory, from the config alone (no file is read). Rough by design: each term is a
/// count of the work the fields ask for times a per-item cost measured on the bundled
/// configs (release build), so that a config ten times over the budget is caught, not one
/// 10% over it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Estimate {
    pub terms: Vec<Term>,
}

impl Estimate {
    pub fn seconds(&self) -> f64 {
        self.terms.iter().map(|t| t.seconds).sum()
    }
    pub fn bytes(&self) -> f64 {
        self.terms.iter().map(|t| t.bytes).sum()
    }
    fn add(&mut self, what: String, seconds: f64, bytes: f64) {
        self.terms.push(Term {
            what,
            seconds,
            bytes,
        });
    }
    /// The term with the largest time (or memory) share, for the error message.
    fn largest(&self, by: impl Fn(&Term) -> f64) -> Option<&Term> {
        self.terms.iter().max_by(|a, b| by(a).total_cmp(&by(b)))
    }
}

/// Per-item costs (seconds of wall time on two cores, bytes).
mod cost {
    /// Per pixel: the rasterizer's fragments, tokens, two engine evaluations, the images.
    pub const PIXEL_BYTES: f64 = 400.0;
    /// Per pixel and unit, both modes (parallel).
    pub const PIXEL_UNIT_S: f64 = 40e-9;
    /// Per reference sample and light (parallel).
    pub const SAMPLE_LIGHT_S: f64 = 60e-9;
    /// Per simulated cycle and stage (the timing model is single-threaded).
    pub const CYCLE_STAGE_S: f64 = 4e-9;
    /// Per texel of a baked or built texture (bake, encoding, the stored words).
    pub const TEXEL_S: f64 = 100e-9;
    pub const TEXEL_BYTES: f64 = 96.0;
    /// Per texel of an object-space bake and unit of uv area (claims, gutter, normals).
    pub const OBJECT_TEXEL_S: f64 = 300e-9;
    pub const OBJECT_TEXEL_BYTES: f64 = 200.0;
    /// Per texel and palette entry of a nearest-entry search (single-threaded).
    pub const NEAREST_S: f64 = 1.5e-9;
    /// Per texel, entry and iteration of k-means (parallel; about 2 s for 256 x 256 texels
    /// and 16384 entries on two cores).
    pub const KMEANS_S: f64 = 2e-9;
    /// Per mesh vertex (vertices, geometry, packets).
    pub const VERTEX_BYTES: f64 = 600.0;
    pub const VERTEX_S: f64 = 2e-6;
    /// Per sample of a baked map (`MeshSpec::Baked`) and view: the projection, the depth
    /// test and the update (measured on the bunny at 2048² samples: about 85 ns a sample and
    /// view on a loaded 2-core machine), and the sample's state.
    pub const BAKE_SAMPLE_VIEW_S: f64 = 100e-9;
    pub const BAKE_SAMPLE_BYTES: f64 = 128.0;
    /// Per pixel of a baking view and view: clearing, rasterising the detailed mesh, reading
    /// back (about 180 ns on the bunny at 2048² a view), and the view's buffers.
    pub const BAKE_VIEW_PIXEL_S: f64 = 200e-9;
    pub const BAKE_VIEW_PIXEL_BYTES: f64 = 48.0;
}

/// The mesh's vertex count and its uv area (in periods of the bump map) as far as the config
/// tells: a file mesh counts as one period times its `uv_repeat`, its vertices unknown (0).
fn mesh_size(m: &MeshSpec) -> (f64, f64) {
    let rep = |r: &[f64; 2]| r[0].abs() * r[1].abs();
    let grid = |a: u32, b: u32| (f64::from(a) + 1.0) * (f64::from(b) + 1.0);
    match m {
        MeshSpec::Quad {
            subdivisions,
            uv_repeat,
            ..
        } => (grid(*subdivisions, *subdivisions), rep(uv_repeat)),
        MeshSpec::Sphere {
            slices,
            stacks,
            uv_repeat,
            ..
        }
        | MeshSpec::Cylinder {
            slices,
            stacks,
            uv_repeat,
            ..
        }
        | MeshSpec::Lathe {
            slices,
            stacks,
            uv_repeat,
            ..
        } => (grid(*slices, *stacks), rep(uv_repeat)),
        MeshSpec::Torus {
            slices,
            rings,
            uv_repeat,
            ..
        } => (grid(*slices, *rings), rep(uv_repeat)),
        MeshSpec::Teapot {
            subdivisions,
            uv_repeat,
        } => (
            32.0 * grid(*subdivisions, *subdivisions),
            32.0 * rep(uv_repeat),
        ),
        MeshSpec::Fold {
            columns, uv_repeat, ..
        } => (grid(2 * columns, 2 * columns), rep(uv_repeat)),
        MeshSpec::Obj { uv_repeat, .. } | MeshSpec::Ply { uv_repeat, .. } => (0.0, rep(uv_repeat)),
        MeshSpec::Baked { .. } => (0.0, 1.0),
    }
}

/// The estimate of a config's run (see [`Estimate`]).
pub fn estimate(c: &Config) -> Estimate {
    let mut e = Estimate::default();
    let s = &c.scene;
    let pixels = f64::from(s.width.0) * f64::from(s.height.0);
    let samples = f64::from(c.reference.samples).powi(2);
    let lights = c.scene.lights.len() as f64;
    let units = c.engine.units.len() as f64;
    e.add(
        format!(
            "scene.width x scene.height = {} pixels x {} engine units",
            pixels, units
        ),
        pixels * units.max(1.0) * cost::PIXEL_UNIT_S,
        pixels * cost::PIXEL_BYTES,
    );
    e.add(
        format!(
            "the reference: {pixels} pixels x reference.samples^2 = {samples} x (1 + {lights} \
             scene.lights)"
        ),
        pixels * samples * (1.0 + lights) * cost::SAMPLE_LIGHT_S,
        0.0,
    );
    // cycles: about one per fragment per clock of the slowest unit (at most one per light)
    e.add(
        format!("the timing model: {pixels} pixels x {units} stages"),
        pixels * (1.0 + lights) * (units + 2.0) * cost::CYCLE_STAGE_S,
        0.0,
    );
    // every pass after the first evaluates the engine again in both modes and keeps its
    // outputs until the ROP has written them
    let passes = c.engine.passes.len() as f64;
    if passes > 0.0 {
        e.add(
            format!(
                "engine.passes: {passes} more x {pixels} pixels x {units} engine units x 2 modes"
            ),
            2.0 * passes * pixels * units.max(1.0) * cost::PIXEL_UNIT_S,
            passes * pixels * cost::PIXEL_BYTES,
        );
    }
    // the texture cache evaluates the engine once more (in parallel chunks, its reads held a
    // window of fragments at a time) and keeps each fragment's misses per stage for the
    // timing model
    if c.engine.texture_cache.is_some() {
        e.add(
            format!("engine.texture_cache: {pixels} pixels x {units} engine units"),
            pixels * units.max(1.0) * cost::PIXEL_UNIT_S,
            pixels * units * 4.0,
        );
    }
    let (vertices, uv_area) = mesh_size(&s.mesh);
    e.add(
        "scene.mesh".into(),
        vertices * cost::VERTEX_S,
        vertices * cost::VERTEX_BYTES,
    );
    if let MeshSpec::Baked {
        map_size,
        views,
        view_size,
        evaluate,
        ..
    } = &s.mesh
    {
        if let Some(ev) = evaluate {
            // two renders a view (the detailed and the simplified mesh) and the comparison
            let px = f64::from(ev.size.min(crate::wang::scene::MAX_VIEW)).powi(2);
            let n = crate::wang::views::evaluation().len() as f64;
            e.add(
                format!("scene.mesh.Baked.evaluate: {n} views x size^2 = {px} pixels"),
                n * 2.0 * px * cost::BAKE_VIEW_PIXEL_S,
                n * 2.0 * px * cost::BAKE_VIEW_PIXEL_BYTES,
            );
        }
        // the detailed mesh itself is bounded by the file cap of the mesh readers; values
        // past the caps are priced at the caps and rejected, naming the field, by the bake
        let (map, view) = (
            (*map_size).min(crate::wang::scene::MAX_MAP),
            (*view_size).min(crate::wang::scene::MAX_VIEW),
        );
        let (samples, view_px) = (f64::from(map).powi(2), f64::from(view).powi(2));
        let views = (*views).min(64) as f64;
        e.add(
            format!(
                "scene.mesh.Baked: map_size^2 = {samples} samples x {views} views, view_size^2 \
                 = {view_px} pixels a view"
            ),
            views * (samples * cost::BAKE_SAMPLE_VIEW_S + view_px * cost::BAKE_VIEW_PIXEL_S),
            samples * cost::BAKE_SAMPLE_BYTES + view_px * cost::BAKE_VIEW_PIXEL_BYTES,
        );
    }
    if let Some(crate::config::TextureSpec::Checker { size, .. }) = &s.color_texture {
        let t = f64::from(*size).powi(2);
        e.add(
            "scene.color_texture.size^2".into(),
            t * cost::TEXEL_S,
            t * cost::TEXEL_BYTES,
        );
    }
    for (i, u) in c.engine.units.iter().enumerate() {
        let f = format!("engine.units[{i}].unit");
        match &u.unit {
            UnitSpec::TexFetch(t) => {
                let size = match t.source {
                    TextureSource::BumpNormals { size, .. }
                    | TextureSource::BumpHilo { size, .. }
                    | TextureSource::BumpHeights { size }
                    | TextureSource::BumpGradient { size, .. }
                    | TextureSource::LightingTable { size, .. }
                    | TextureSource::SphereLighting { size, .. }
                    | TextureSource::NdfNoise { size, .. }
                    | TextureSource::NdfLookup { size, .. }
                    | TextureSource::NdfShading { size, .. }
                    | TextureSource::NdfShading2d { size, .. } => f64::from(size),
                    TextureSource::ObjectNormals { size } => {
                        let texels = f64::from(size).powi(2);
                        e.add(
                            format!(
                                "{f}.source.size^2 = {texels} texels baked x uv area {uv_area} \
                                 (scene.mesh uv_repeat)"
                            ),
                            texels * uv_area.max(1.0) * cost::OBJECT_TEXEL_S,
                            texels * cost::OBJECT_TEXEL_BYTES,
                        );
                        f64::from(size)
                    }
                    // at most 4096 a side (the PNG limit), counted when it is read
                    TextureSource::ColorTexture => 0.0,
                    // six faces (a fetch unit rejects a cube map when it builds)
                    TextureSource::CubeLighting { size, .. } => f64::from(size) * 6f64.sqrt(),
                };
                let texels = size * size;
                e.add(
                    format!("{f}.source.size^2 = {texels} texels"),
                    texels * cost::TEXEL_S,
                    texels * cost::TEXEL_BYTES,
                );
                if let Some(n) = t.palette {
                    e.add(
                        format!("{f}.source.size^2 = {texels} texels x {f}.palette = {n}"),
                        texels * f64::from(n) * cost::NEAREST_S,
                        0.0,
                    );
                }
            }
            UnitSpec::EmbossFilter(t) => {
                let texels = f64::from(t.size).powi(2);
                e.add(
                    format!("{f}.size^2 = {texels} texels"),
                    2.0 * texels * cost::TEXEL_S,
                    2.0 * texels * cost::TEXEL_BYTES,
                );
            }
            UnitSpec::QuantizedNormals(q) => {
                let texels = f64::from(q.size).powi(2);
                let n = f64::from(q.s_n);
                e.add(
                    format!(
                        "{f}.size^2 = {texels} texels baked x uv area {uv_area} (scene.mesh \
                         uv_repeat)"
                    ),
                    texels * uv_area.max(1.0) * cost::OBJECT_TEXEL_S,
                    texels * cost::OBJECT_TEXEL_BYTES,
                );
                if let Quantizer::KMeans { max_iterations, .. } = q.quantizer {
                    let it = f64::from(max_iterations);
                    e.add(
                        format!(
                            "k-means: {f}.size^2 = {texels} texels x {f}.s_n = {n} x \
                             {f}.quantizer.max_iterations = {it}"
                        ),
                        texels * n * it * cost::KMEANS_S,
                        texels * 64.0,
                    );
                }
                // dithering and index mipmaps search the table per texel
                let searches =
                    f64::from(u8::from(q.dither)) + f64::from(u8::from(q.mipmap.is_some()));
                if searches > 0.0 {
                    e.add(
                        format!(
                            "{f}.dither / mipmap: {f}.size^2 = {texels} texels x {f}.s_n = {n}"
                        ),
                        searches * texels * n * cost::NEAREST_S,
                        2.0 * texels * 24.0,
                    );
                }
            }
            _ => {}
        }
    }
    // each frame of an animation is a run of its own (its assets shared when they are the
    // same), and its image is kept until the outputs are written
    let frames = c.frames.len() as f64;
    if frames > 0.0 {
        let secs = e.seconds();
        e.add(
            format!("frames: {frames} more frames of {pixels} pixels"),
            frames * secs,
            frames * pixels * 3.0,
        );
    }
    e
}

/// Check [`estimate`] against the budget unless `force`; the error names the largest term's
/// fields, both figures and the budget.
pub fn check_budget(l: &Loaded, force: bool) -> Result<(), InputError> {
    if force {
        return Ok(());
    }
    let e = estimate(&l.config);
    let (secs, bytes) = (e.seconds(), e.bytes());
    let gib = |b: f64| b / (1u64 << 30) as f64;
    let over = if secs > BUDGET_SECONDS {
        e.largest(|t| t.seconds).map(|t| {
            format!(
                "the run is estimated at {secs:.0} s, over the budget of {BUDGET_SECONDS:.0} s \
                 on a 2-core, 24 GB machine; the largest part is {} ({:.0} s)",
                t.what, t.seconds
            )
        })
    } else if bytes > BUDGET_BYTES {
        e.largest(|t| t.bytes).map(|t| {
            format!(
                "the run is estimated to need {:.1} GiB, over the budget of {:.0} GiB on a \
                 2-core, 24 GB machine; the largest part is {} ({:.1} GiB)",
                gib(bytes),
                gib(BUDGET_BYTES),
                t.what,
                gib(t.bytes)
            )
        })
    } else {
        None
    };
    match over {
        None => Ok(()),
        Some(m) => Err(InputError::new(
            l.path.display().to_string(),
            "",
            format!("{m}: lower it, or pass --force to run past the estimate"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bake_is_priced_by_samples_views_and_view_pixels_and_its_caps_fit_the_budget() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs");
        let bake = |sets: &[&str]| {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            let l = crate::config::load(&dir.join("wang-bunny.ron"), &sets)
                .unwrap_or_else(|e| panic!("{e}"));
            let e = estimate(&l.config);
            let t = e
                .terms
                .iter()
                .find(|t| t.what.starts_with("scene.mesh.Baked"))
                .unwrap_or_else(|| panic!("no bake term: {:?}", e.terms))
                .clone();
            (t.seconds, t.bytes)
        };
        // wang-bunny: 512² samples, 12 views of 512²: 0.94 s, 44 MB
        let (s0, b0) = bake(&[]);
        assert!((s0 - 12.0 * 262144.0 * 300e-9).abs() < 1e-9, "{s0}");
        assert!((b0 - 262144.0 * 176.0).abs() < 1e-3, "{b0}");
        // the caps (4096² map, 64 views of 4096²): 322 s and 2.8 GB, inside the budget
        let (s1, b1) = bake(&[
            "scene.mesh.map_size=4096",
            "scene.mesh.view_size=4096",
            "scene.mesh.views=64",
        ]);
        assert!(s1 > 300.0 && s1 < BUDGET_SECONDS, "{s1}");
        assert!(b1 > 2.5e9 && b1 < BUDGET_BYTES, "{b1}");
    }

    #[test]
    fn every_bundled_config_is_within_the_budget() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs");
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.extension().is_some_and(|x| x == "ron") {
                let l = crate::config::load(&p, &[]).unwrap_or_else(|e| panic!("{e}"));
                let e = estimate(&l.config);
                assert!(
                    e.seconds() < BUDGET_SECONDS / 10.0 && e.bytes() < BUDGET_BYTES / 4.0,
                    "{}: {} s, {} bytes: {:?}",
                    p.display(),
                    e.seconds(),
                    e.bytes(),
                    e.terms
                );
            }
        }
    }
}
